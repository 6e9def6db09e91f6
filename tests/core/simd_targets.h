// Helpers of the tests that compare a vectorised field kernel with its scalar
// reference on every SIMD target (core/simd.h).
#pragma once

#include <Eigen/Core>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/field.h"
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

inline constexpr double kUlp = 0x1p-53;

// A case of an agreement test: a design, its field request (grid included)
// and a name for the reports.
template <class Model, class Request>
struct FieldCase {
  std::string name;
  Model model;
  Request request;
};

// The field of case c with `kernel` (the device's compute_field, found by
// argument-dependent lookup).
template <class Case, class Kernel>
Field field_of(const Case& c, Kernel kernel) {
  auto request = c.request;
  request.kernel = kernel;
  return *compute_field(c.model, request);
}

// Halves [a, b] towards where same_as_a stops holding: at most `steps`
// times, while |b - a| > min_length and the midpoint is neither end.
template <class SameAsA>
void bisect(Eigen::Vector3d& a, Eigen::Vector3d& b, SameAsA&& same_as_a, int steps, double min_length = 0.0) {
  for (int k = 0; k < steps && (b - a).norm() > min_length; ++k) {
    const Eigen::Vector3d mid = 0.5 * (a + b);
    if (mid == a || mid == b) return;
    (same_as_a(mid) ? a : b) = mid;
  }
}

// One row of n samples along `axis` through `centre`, spacing `step`.
inline Grid row_through(const Eigen::Vector3d& centre, int axis, double step, int n) {
  Grid g;
  g.dims = {1, 1, 1};
  g.dims[axis] = n;
  g.spacing = Eigen::Vector3d::Constant(step);
  g.origin = centre - Eigen::Vector3d::Constant(0.5 * step);
  g.origin(axis) = centre(axis) - 0.5 * n * step;
  return g;
}

// The relative c(J) allowance where two eigenvalues l_i > l_j of J^T J nearly
// coincide: 64 ulps times (l_i + l_j) / (l_i - l_j), capped at 1e-7 (the
// closed form's cos(acos(r) / 3) is flat in r where l1 = l2, and l2 is a
// quadratic's double root where l2 = l3).
inline double coincident_eigenvalue_allowance(const Eigen::Matrix3d& J) {
  const Eigen::Vector3d sv = J.jacobiSvd().singularValues();
  const double l1 = sv(0) * sv(0), l2 = sv(1) * sv(1), l3 = sv(2) * sv(2);
  return std::min(1e-7, 64 * kUlp * std::max((l1 + l2) / (l1 - l2), (l2 + l3) / (l2 - l3)));
}

// Counts of the samples compared, by status, and of those whose stored c(J)
// differed from the reference's.
struct Tally {
  long samples = 0, by_status[5] = {0, 0, 0, 0, 0}, wide_cond = 0;
};

}  // namespace linkscape::simd_test
