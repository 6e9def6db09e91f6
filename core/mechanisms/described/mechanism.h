// A described mechanism (a preset with a "description") behind the generic
// interface (core/mechanism.h). Registered as "described".
#pragma once

#include <memory>
#include <string>

#include "core/mechanism.h"

namespace linkscape::described {

inline constexpr const char* kMechanismName = "described";

// Throws std::invalid_argument naming the place in the description.
std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset);

// How the described device is solved, as text for `linkscape describe FILE`:
// its mobility, then per leg the pattern it was recognised as (or
// "numeric"), its actuator and travel, its branch rules and its reach
// bounds. Throws std::invalid_argument as make_mechanism does (a preset
// without a description included).
std::string describe(const Preset& preset);

}  // namespace linkscape::described
