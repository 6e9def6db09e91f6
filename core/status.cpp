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

std::string status_codes() {
  std::string out;
  for (Status s : {Status::Ok, Status::Unreachable, Status::Singular, Status::NotConverged, Status::OutOfLimits})
    out += (out.empty() ? "" : ", ") + std::to_string(int(s)) + " " + std::string(to_string(s));
  return out;
}

}  // namespace linkscape
