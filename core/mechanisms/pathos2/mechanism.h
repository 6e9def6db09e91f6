// PATHOS-II behind the generic interface (core/mechanism.h).
#pragma once

#include <memory>

#include "core/mechanism.h"
#include "core/mechanisms/pathos2/pathos2.h"

namespace linkscape::pathos2 {

// Throws std::invalid_argument for an invalid model.
std::shared_ptr<const Mechanism> make_mechanism(const Model& model);
std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset);

}  // namespace linkscape::pathos2

namespace linkscape {

// The model a preset describes; throws std::invalid_argument if the preset is
// of another mechanism, has actuator_limits_deg or invalid values.
pathos2::Model make_pathos2(const Preset& preset);

}  // namespace linkscape
