// Helpers of the tests that compare a vectorised field kernel with its scalar
// reference on every SIMD target (core/simd.h).
#pragma once

#include <cmath>
#include <string>

#include "core/simd.h"

namespace linkscape::simd_test {

// Dispatch limited to one target for the lifetime of the object.
class TargetLimit {
 public:
  explicit TargetLimit(const std::string& target) { simd::limit_targets(target); }
  ~TargetLimit() { simd::limit_targets(""); }
  TargetLimit(const TargetLimit&) = delete;
  TargetLimit& operator=(const TargetLimit&) = delete;
};

// Whether the float v is the rounding of a value within rel * |d| of d
// (rounding is monotonic, so the ends of that interval bound it); infinities
// must be equal.
inline bool rounds_near(float v, double d, double rel) {
  if (std::isinf(d) || std::isinf(v)) return v == d;
  const double slack = rel * std::abs(d);
  return float(d - slack) <= v && v <= float(d + slack);
}

// The same within an absolute slack.
inline bool rounds_within(float v, double d, double absolute) {
  if (std::isinf(d) || std::isinf(v)) return v == d;
  return float(d - absolute) <= v && v <= float(d + absolute);
}

}  // namespace linkscape::simd_test
