// One device's enclosures for certified checks: whether a box of positions
// certainly meets the criteria, and whether a point certainly fails one.
// Built from a preset (the models' own values), used by verify.cpp.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>

#include "core/preset.h"
#include "core/range.h"
#include "core/verify/kernels.h"

namespace linkscape::verify {

enum class Device { Parallel12r, Delta };

struct Certifier {
  Device device = Device::Parallel12r;
  double L1 = 0, L2 = 0;  // 12R
  DeltaGeometry delta;    // Delta
  int branch = 0;
  // Actuator ranges (rad) checked on the solution, when some range cuts the
  // workspace; `wraps`: an angle counts as inside if some q + 2 pi k is (Delta).
  bool check_ranges = false, wraps = false;
  std::array<Range, 3> ranges{};
  // c(J) must stay below this (the cond criterion, or where the device
  // itself reports J singular when only reach is asked).
  double cond_bound = 0;

  // From a parallel-12r or delta preset; throws Uncertifiable otherwise and
  // std::invalid_argument for a branch the device does not have.
  static Certifier from_preset(const Preset& preset, int branch, double cond_bound);

  template <typename T>
  KernelResult<T> kernel(const T& x, const T& y, const T& z) const {
    return device == Device::Parallel12r ? kernel_12r(L1, L2, branch, x, y, z) : kernel_delta(delta, x, y, z);
  }

  // A certified upper bound on c(J) over the box, when every point of it is
  // reachable in the branch within the ranges; nullopt otherwise (or when
  // the enclosure is too wide to tell).
  std::optional<double> condition_bound(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const;

  // Whether the point certainly fails: out of reach, outside the ranges, or
  // c(J) >= cond_bound; `lower_bound` gets a certified lower bound on c(J)
  // (+inf out of reach), `reason` the words.
  struct PointFailure {
    double lower_bound = 0;
    std::string reason;
  };
  std::optional<PointFailure> certain_failure(const Eigen::Vector3d& p) const;

  // c(J) at a point in double (the kernel without enclosures), +inf where
  // it does not reach or leaves the ranges: the counterexample search's score.
  double condition_estimate(const Eigen::Vector3d& p) const;
};

// c(J) at p evaluated independently of the kernels, in long double: the
// 12R's planar angles, the paper's J (Eqs. 11-13) and an SVD; the Delta's
// tangent half-angle leg solution, J^-1 = -Jq^-1 Jx and an SVD. +inf where
// the point is out of reach (or the ranges) or J is singular.
long double reference_condition(const Certifier& certifier, const Eigen::Vector3d& p);

}  // namespace linkscape::verify
