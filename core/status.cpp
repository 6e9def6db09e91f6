#include "core/status.h"

namespace linkscape {

std::string_view to_string(Status status) {
  switch (status) {
    case Status::Ok: return "ok";
    case Status::Unreachable: return "unreachable";
    case Status::Singular: return "singular";
    case Status::NotConverged: return "not-converged";
    case Status::OutOfLimits: return "out-of-limits";
  }
  return "unknown";
}

}  // namespace linkscape
