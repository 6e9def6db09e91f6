// The Delta behind the generic interface (core/mechanism.h).
#pragma once

#include <memory>

#include "core/mechanism.h"
#include "core/mechanisms/delta/delta.h"

namespace linkscape::delta {

// Throws std::invalid_argument for an invalid model.
std::shared_ptr<const Mechanism> make_mechanism(const Model& model);
std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset);
// The model a preset describes, with the ball-joint cones its "stops" block
// states (stops.h) unless preset.checks turns them off. Throws
// std::invalid_argument for a bad value or key.
Model make_delta_model(const Preset& preset);

}  // namespace linkscape::delta
