// Outcome of a kinematic solve. Every solver in core reports one of these
// instead of returning NaN or throwing for a target it cannot serve.
#pragma once

#include <string>
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

// The legend of status codes as files store them (a field's status array):
// "0 ok, 1 unreachable, 2 singular, 3 not-converged, 4 out-of-limits".
std::string status_codes();

}  // namespace linkscape
