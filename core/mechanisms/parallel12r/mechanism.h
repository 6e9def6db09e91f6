// The 12R hand controller behind the generic interface (core/mechanism.h).
#pragma once

#include <memory>

#include "core/mechanism.h"
#include "core/mechanisms/parallel12r/parallel12r.h"

namespace linkscape::parallel12r {

// Throws std::invalid_argument for an invalid model.
std::shared_ptr<const Mechanism> make_mechanism(const Model& model);
std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset);

}  // namespace linkscape::parallel12r

namespace linkscape {

// The model a preset describes; throws std::invalid_argument if the preset is
// of another mechanism or its values are invalid.
parallel12r::Model make_parallel12r(const Preset& preset);

}  // namespace linkscape
