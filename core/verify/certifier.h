// One device's enclosures for certified checks: whether a box of positions
// certainly meets the criteria, and whether a point certainly fails one.
// Built from a preset (the models' own values), used by verify.cpp.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/preset.h"
#include "core/range.h"
#include "core/verify/kernels.h"

namespace linkscape::verify {

class LegsCertifier;  // legs.h

enum class Device { Parallel12r, Delta, Described };

// Whether every angle atan2(s, c) of the enclosures is certainly within a
// range of actuator angles (rad), or certainly outside it; `wraps`: an angle
// counts as inside if some q + 2 pi k is.
bool certainly_within(Interval c, Interval s, const Range& range, bool wraps);
// A range that cuts nothing (the whole line: one the device's angles never leave).
inline bool cuts_nothing(const Range& range) { return range.lo == -kInf && range.hi == kInf; }
bool certainly_outside(Interval c, Interval s, const Range& range, bool wraps);

struct Certifier {
  Device device = Device::Parallel12r;
  double L1 = 0, L2 = 0;  // 12R
  DeltaGeometry delta;    // Delta
  std::shared_ptr<const LegsCertifier> legs;  // Described (legs.h)
  int branch = 0;
  // Actuator ranges (rad) checked on the solution, when some range cuts the
  // workspace; `wraps`: an angle counts as inside if some q + 2 pi k is (Delta).
  bool check_ranges = false, wraps = false;
  std::array<Range, 3> ranges{};
  // c(J) must stay below this (the cond criterion, or where the device
  // itself reports J singular when only reach is asked).
  double cond_bound = 0;

  // A haptic criterion on the lengths of J's columns (docs/haptic-measures.md):
  // force_iso = min_i scale_i / |J e_i| must exceed the threshold (N), or
  // resolution = max_i scale_i |J e_i| must stay below it (mm), with
  // scale_i = tau_i / m_i or 1000 (2 pi / counts_i) m_i, m_i the metres per
  // length unit of actuator i's column.
  struct ColumnCriterion {
    std::string text;
    bool force = true;  // force_iso (else resolution)
    double threshold = 0;
    std::array<Interval, 3> scale{};
  };
  std::vector<ColumnCriterion> columns;

  // From a parallel-12r, delta or described preset (legs.h says which
  // described devices); throws Uncertifiable otherwise and
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

  // Whether the point certainly fails: out of reach, outside the ranges,
  // c(J) >= cond_bound or a column criterion failing. `column` is the
  // failing column criterion's index (-1: reach or c(J)); `bound` a
  // certified bound on the failing measure there (c(J) or resolution at
  // least it, force_iso at most it; +inf out of reach), `reason` the words.
  struct PointFailure {
    int column = -1;
    double bound = 0;
    std::string reason;
  };
  std::optional<PointFailure> certain_failure(const Eigen::Vector3d& p) const;

  // How far a point is from meeting the criteria, in double (the kernel
  // without enclosures): the largest ratio of a measure to its bound (for
  // force_iso, of the bound to it), >= 1 where one fails; +inf where it does
  // not reach or leaves the ranges. The counterexample search's score.
  double badness(const Eigen::Vector3d& p) const;
};

// J at p evaluated independently of the kernels, in long double: the 12R's
// planar angles and the paper's J (Eqs. 11-13); the Delta's tangent
// half-angle leg solution and J = -Jx^-1 Jq. nullopt where the point is out
// of reach (or the ranges) or J is singular, and for described devices,
// whose reference is their measure in long double (LegsCertifier).
std::optional<Eigen::Matrix<long double, 3, 3>> reference_jacobian(const Certifier& certifier, const Eigen::Vector3d& p);
// From it: c(J) (by an SVD; +inf without J), and a column criterion's measure
// (force_iso 0, resolution +inf without J).
long double reference_condition(const Certifier& certifier, const Eigen::Vector3d& p);
long double reference_value(const Certifier& certifier, const Certifier::ColumnCriterion& criterion,
                            const Eigen::Vector3d& p);

}  // namespace linkscape::verify
