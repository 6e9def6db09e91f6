// A described mechanism (a preset with a "description") behind the generic
// interface (core/mechanism.h). Registered as "described".
#pragma once

#include <memory>

#include "core/mechanism.h"

namespace linkscape::described {

inline constexpr const char* kMechanismName = "described";

// Throws std::invalid_argument naming the place in the description.
std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset);

}  // namespace linkscape::described
