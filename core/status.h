// Outcome of a kinematic solve. Every solver in core reports one of these
// instead of returning NaN or throwing for a target it cannot serve.
#pragma once

#include <string_view>

namespace linkscape {

enum class Status {
  Ok,            // solution meets the method's tolerance
  Unreachable,   // target lies outside the geometric reach
  Singular,      // target on (within tolerance of) a singular set
  NotConverged,  // iterative method ran out of iterations, or no closed-form
                 // candidate met the residual tolerance
  OutOfLimits,   // solution exists but violates an actuator or joint range
};

std::string_view to_string(Status status);

}  // namespace linkscape
