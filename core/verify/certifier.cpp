#include "core/verify/certifier.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/conditioning.h"
#include "core/mechanisms/delta/delta.h"
#include "core/mechanisms/parallel12r/mechanism.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/verify/legs.h"
#include "core/verify/verify.h"

namespace linkscape::verify {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;
// atan2 is not correctly rounded (glibc: within 1 ulp); angles here are
// compared with this margin, far above its error and that of 2 pi.
constexpr double kAngleMargin = 1e-12;

// ---- Actuator ranges -----------------------------------------------------------------

// The angles atan2(s, c) over a box of (c, s) away from the origin, as an
// interval of width below 2 pi (within (-pi, pi], or around pi within
// (0, 2 pi) where the box straddles the negative c axis); nullopt where the
// box holds the origin (any angle).
std::optional<Interval> angle_enclosure(Interval c, Interval s) {
  if (c.lo <= 0 && c.hi >= 0 && s.lo <= 0 && s.hi >= 0) return std::nullopt;
  const bool across_pi = c.hi < 0 && s.lo <= 0 && s.hi >= 0;
  double lo = kInf, hi = -kInf;
  for (double cc : {c.lo, c.hi})
    for (double ss : {s.lo, s.hi}) {
      double a = std::atan2(ss, cc);
      if (across_pi && a < 0) a += 2 * kPi;
      lo = std::min(lo, a), hi = std::max(hi, a);
    }
  return Interval(lo - kAngleMargin, hi + kAngleMargin);
}

// The shifts by whole turns that may bring angles `a` into a range (any
// number of turns away: ranges may lie anywhere, e.g. 300 to 400 deg).
std::vector<double> turns(bool wraps, const Interval& a, const Range& range) {
  if (!wraps) return {0.0};
  const double base = 2 * kPi * std::round((0.5 * (range.lo + range.hi) - a.mid()) / (2 * kPi));
  return {base - 2 * kPi, base, base + 2 * kPi};
}

}  // namespace

bool certainly_within(Interval c, Interval s, const Range& range, bool wraps) {
  if (cuts_nothing(range)) return true;
  const std::optional<Interval> a = angle_enclosure(c, s);
  if (!a) return false;
  const auto holds = [&](double lo, double hi) { return lo >= range.lo + kAngleMargin && hi <= range.hi - kAngleMargin; };
  // Without wrapping the device's angle is in (-pi, pi]: an enclosure around
  // pi is two pieces, [lo, pi] and (-pi, hi - 2 pi], and both must hold.
  if (!wraps && a->hi > kPi) return holds(a->lo, kPi) && holds(-kPi, a->hi - 2 * kPi);
  for (double shift : turns(wraps, *a, range))
    if (holds(a->lo + shift, a->hi + shift)) return true;
  return false;
}

bool certainly_outside(Interval c, Interval s, const Range& range, bool wraps) {
  if (cuts_nothing(range)) return false;
  const std::optional<Interval> a = angle_enclosure(c, s);
  if (!a) return false;
  // Without wrapping the device's angle is in (-pi, pi]: an enclosure around pi is both ends.
  const std::vector<double> shifts = turns(wraps || a->hi > kPi, *a, range);
  for (double shift : shifts)
    if (a->hi + shift >= range.lo - kAngleMargin && a->lo + shift <= range.hi + kAngleMargin) return false;
  return true;
}

namespace {

// Each range that holds every angle the device takes (`full`, or, where
// angles wrap, a whole turn) made the whole line, so that it is never
// checked; whether any range is left that cuts the workspace.
bool open_full_ranges(std::array<Range, 3>& ranges, const std::array<Range, 3>& full, bool wraps) {
  bool cuts = false;
  for (int k = 0; k < 3; ++k) {
    if ((ranges[k].lo <= full[k].lo && ranges[k].hi >= full[k].hi) || (wraps && ranges[k].hi - ranges[k].lo >= 2 * kPi))
      ranges[k] = Range{-kInf, kInf};
    else
      cuts = true;
  }
  return cuts;
}

// ---- Singular values of a point matrix ---------------------------------------------------

using IntervalMatrix = Matrix3<Interval>;

// M^T M of a double matrix, enclosed.
IntervalMatrix gram(const Matrix3d& M) {
  IntervalMatrix A;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Interval sum(0.0);
      for (int k = 0; k < 3; ++k) sum += Interval(M(k, i)) * Interval(M(k, j));
      A[i][j] = sum;
    }
  return A;
}

// Whether a symmetric matrix in the enclosure is certainly positive
// definite (Sylvester: every leading principal minor positive).
bool certainly_positive_definite(const IntervalMatrix& B) {
  const Interval m2 = B[0][0] * B[1][1] - sqr(B[0][1]);
  const Interval m3 = B[0][0] * (B[1][1] * B[2][2] - sqr(B[1][2])) - B[0][1] * (B[0][1] * B[2][2] - B[1][2] * B[0][2]) +
                      B[0][2] * (B[0][1] * B[1][2] - B[1][1] * B[0][2]);
  return B[0][0].lo > 0 && m2.lo > 0 && m3.lo > 0;
}

IntervalMatrix shifted(const IntervalMatrix& A, double shift, double sign) {
  IntervalMatrix B;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) B[i][j] = Interval(sign) * A[i][j] - (i == j ? Interval(sign * shift) : Interval(0.0));
  return B;
}

// Certified sigma_max upper and sigma_min lower bounds of a double matrix:
// the eigenvalues of M^T M found in double, moved outward until the shifted
// matrix is certainly positive definite.
struct SingularBounds {
  double largest_upper = kInf, smallest_lower = 0;
};
SingularBounds singular_value_bounds(const Matrix3d& M) {
  const IntervalMatrix A = gram(M);
  Matrix3d A_mid;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) A_mid(i, j) = A[i][j].mid();
  const Eigen::Vector3d eig = Eigen::SelfAdjointEigenSolver<Matrix3d>(A_mid, Eigen::EigenvaluesOnly).eigenvalues();
  SingularBounds b;
  for (double slack : {1e-9, 1e-6, 1e-3}) {
    const double mu = eig(2) * (1 + slack) + kTiny;
    if (certainly_positive_definite(shifted(A, mu, -1.0))) {
      b.largest_upper = up(std::sqrt(up(mu)));
      break;
    }
  }
  for (double slack : {1e-9, 1e-6, 1e-3}) {
    const double nu = eig(0) * (1 - slack);
    if (nu > 0 && certainly_positive_definite(shifted(A, nu, 1.0))) {
      b.smallest_lower = down(std::sqrt(down(nu)));
      break;
    }
  }
  return b;
}

// A bound on the spectral norm from entry magnitudes: the smaller of the
// Frobenius norm and sqrt(|.|_1 |.|_inf).
double norm_bound(const Matrix3d& magnitude) {
  Interval frobenius(0.0);
  double rows = 0, cols = 0;
  for (int i = 0; i < 3; ++i) {
    Interval row(0.0), col(0.0);
    for (int j = 0; j < 3; ++j) {
      frobenius += sqr(Interval(magnitude(i, j)));
      row += Interval(magnitude(i, j));
      col += Interval(magnitude(j, i));
    }
    rows = std::max(rows, row.hi), cols = std::max(cols, col.hi);
  }
  return std::min(sqrt(frobenius).hi, sqrt(Interval(rows) * Interval(cols)).hi);
}

// A certified lower bound on c(M) for M in a thin enclosure: Rayleigh
// quotients of the double midpoint along its singular vectors, less the
// enclosure's radius (Weyl).
double condition_lower_bound(const IntervalMatrix& M) {
  Matrix3d mid, radius;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) mid(i, j) = M[i][j].mid(), radius(i, j) = M[i][j].rad();
  const double r = norm_bound(radius);
  const Eigen::JacobiSVD<Matrix3d> svd(mid, Eigen::ComputeFullV);
  auto rayleigh = [&](const Vector3d& v) {
    Interval mv2(0.0), v2(0.0);
    for (int i = 0; i < 3; ++i) {
      Interval row(0.0);
      for (int j = 0; j < 3; ++j) row += Interval(mid(i, j)) * Interval(v(j));
      mv2 += sqr(row);
      v2 += sqr(Interval(v(i)));
    }
    return sqrt(mv2 / v2);
  };
  const double largest_lower = down(rayleigh(svd.matrixV().col(0)).lo - r);
  const double smallest_upper = up(rayleigh(svd.matrixV().col(2)).hi + r);
  if (!(largest_lower > 0)) return 0;
  return smallest_upper > 0 ? down(largest_lower / smallest_upper) : kInf;
}

// Enclosures of |J(p) e_i| for every p whose M(p) is within `deviation`
// (entry magnitudes, spectral norm at most r) of M_c, whose smallest
// singular value is at least `smallest`. The 12R's M is J; the Delta's is
// J^-1, so J(p) e_i = x - M(p)^-1 (M(p) x - e_i) for x = M_c^-1 e_i found in
// double, with |M(p)^-1| <= 1 / (smallest - r) (Weyl).
std::array<Interval, 3> column_lengths(Device device, const Matrix3d& M_c, const Matrix3d& deviation, double r,
                                       double smallest) {
  auto length = [](const Vector3d& v) {
    Interval sum(0.0);
    for (int k = 0; k < 3; ++k) sum += sqr(Interval(v(k)));
    return sqrt(sum);
  };
  std::array<Interval, 3> out;
  const Eigen::PartialPivLU<Matrix3d> lu(M_c);
  const double inverse_norm = smallest - r > 0 ? up(1.0 / down(smallest - r)) : kInf;
  for (int i = 0; i < 3; ++i) {
    Interval centre;
    double error;
    if (device == Device::Parallel12r) {
      centre = length(M_c.col(i));
      error = length(deviation.col(i)).hi;
    } else {
      const Vector3d x = lu.solve(Vector3d::Unit(i));
      Vector3d residual;
      for (int j = 0; j < 3; ++j) {
        Interval row(j == i ? -1.0 : 0.0);
        for (int k = 0; k < 3; ++k) row += Interval(M_c(j, k)) * Interval(x(k));
        residual(j) = row.mag();
      }
      centre = length(x);
      error = up(inverse_norm * up(length(residual).hi + up(r * centre.hi)));
    }
    out[i] = {std::max(0.0, down(centre.lo - error)), up(centre.hi + error)};
  }
  return out;
}

// A column criterion's measure bounded from the column lengths: at best
// (from their upper bounds: force_iso at least, resolution at most) or at
// worst (from their lower bounds).
double column_measure(const Certifier::ColumnCriterion& c, const std::array<Interval, 3>& lengths, bool best) {
  double value = c.force ? kInf : 0;
  for (int i = 0; i < 3; ++i) {
    const Interval length = best ? Interval(lengths[i].hi) : Interval(lengths[i].lo);
    if (c.force) {
      const Interval force = length.hi > 0 ? c.scale[i] / length : Interval::entire();
      value = std::min(value, best ? force.lo : force.hi);
    } else {
      const Interval resolution = c.scale[i] * length;
      value = std::max(value, best ? resolution.hi : resolution.lo);
    }
  }
  return value;
}

bool column_criteria_hold(const Certifier& c, const std::array<Interval, 3>& lengths) {
  for (const Certifier::ColumnCriterion& criterion : c.columns) {
    const double value = column_measure(criterion, lengths, true);
    if (criterion.force ? !(value > criterion.threshold) : !(value < criterion.threshold)) return false;
  }
  return true;
}

std::string measure_text(const char* name, const char* relation, double value, const char* unit) {
  std::ostringstream out;
  out.precision(6);
  out << name << " " << relation << " " << value << unit;
  return out.str();
}

const char* kActuatorNames12r[] = {"alpha", "beta", "gamma"};
const char* kActuatorNamesDelta[] = {"q1", "q2", "q3"};

}  // namespace

Certifier Certifier::from_preset(const Preset& preset, int branch, double cond_bound) {
  Certifier c;
  c.branch = branch;
  c.cond_bound = cond_bound;
  if (preset.mechanism == parallel12r::kMechanismName) {
    const parallel12r::Model m = make_parallel12r(preset);
    if (branch != 0 && branch != 1)
      throw std::invalid_argument("verify: parallel-12r has branches 0 and 1, got " + std::to_string(branch));
    c.device = Device::Parallel12r;
    c.L1 = m.L1, c.L2 = m.L2;
    c.ranges = {Range{m.alpha_limits.lo, m.alpha_limits.hi}, Range{m.beta_limits.lo, m.beta_limits.hi},
                Range{m.gamma_limits.lo, m.gamma_limits.hi}};
    c.check_ranges = open_full_ranges(c.ranges, {Range{-kPi / 2, kPi / 2}, Range{-kPi, kPi}, Range{-kPi, kPi}}, false);
    return c;
  }
  if (preset.mechanism == delta::kMechanismName) {
    std::map<std::string, delta::Interval> limits;
    for (const auto& [name, range] : preset.limits_deg) limits[name] = {range.lo, range.hi};
    const delta::Model m = delta::Model::from_parameters(preset.parameters, limits, preset.length_unit);
    if (branch < 0 || branch >= delta::kBranchCount)
      throw std::invalid_argument("verify: delta has branches 0..7, got " + std::to_string(branch));
    c.device = Device::Delta;
    c.delta = {m.R, m.r, m.La, m.Lb, branch};
    for (int k = 0; k < 3; ++k) c.ranges[k] = {m.q_limits[k].lo, m.q_limits[k].hi};
    c.wraps = true;
    c.check_ranges = open_full_ranges(c.ranges, {Range{-kPi, kPi}, Range{-kPi, kPi}, Range{-kPi, kPi}}, true);
    return c;
  }
  if (preset.mechanism == described::kMechanismName) {
    c.device = Device::Described;
    c.legs = LegsCertifier::from_preset(preset, branch);
    return c;
  }
  throw Uncertifiable("verify: '" + preset.mechanism +
                      "' cannot be certified (certified checks need closed-form kinematics written for interval "
                      "arithmetic; they exist for parallel-12r, delta and described devices whose legs are "
                      "crank-rod, slide-rod or extensible)");
}

std::optional<double> Certifier::condition_bound(const Vector3d& lo, const Vector3d& hi) const {
  if (legs) return legs->condition_bound(lo, hi, cond_bound);
  const KernelResult<Dual> box = kernel(Dual::variable({lo.x(), hi.x()}, 0), Dual::variable({lo.y(), hi.y()}, 1),
                                        Dual::variable({lo.z(), hi.z()}, 2));
  if (box.failure != KernelFailure::None) return std::nullopt;
  if (check_ranges)
    for (int k = 0; k < 3; ++k)
      if (!certainly_within(box.cos_q[k].v, box.sin_q[k].v, ranges[k], wraps)) return std::nullopt;
  const Vector3d m = (0.5 * lo + 0.5 * hi).cwiseMax(lo).cwiseMin(hi);
  const KernelResult<Interval> at_mid = kernel(Interval(m.x()), Interval(m.y()), Interval(m.z()));
  if (at_mid.failure != KernelFailure::None) return std::nullopt;
  double half_width[3];
  for (int k = 0; k < 3; ++k) half_width[k] = up(std::max(m(k) - lo(k), hi(k) - m(k)));
  // M(p) - M_c over the box, enclosed twice: the box's own enclosure, and the
  // mean value form M(m) + grad(box) (p - m); each holds it, so their intersection does.
  Matrix3d M_c, deviation;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      M_c(i, j) = at_mid.M[i][j].mid();
      const Dual& e = box.M[i][j];
      Interval mean_value = at_mid.M[i][j] - Interval(M_c(i, j));
      for (int k = 0; k < 3; ++k) mean_value += e.d[k] * Interval(-half_width[k], half_width[k]);
      deviation(i, j) = intersect(e.v - Interval(M_c(i, j)), mean_value).mag();
    }
  const double r = norm_bound(deviation);
  const SingularBounds s = singular_value_bounds(M_c);
  // Weyl: every singular value of M(p) is within r of M_c's.
  const double smallest = down(s.smallest_lower - r);
  if (!(smallest > 0)) return std::nullopt;
  const double bound = up(up(s.largest_upper + r) / smallest);
  if (!(bound < cond_bound)) return std::nullopt;
  if (!columns.empty() &&
      !column_criteria_hold(*this, column_lengths(device, M_c, deviation, r, s.smallest_lower)))
    return std::nullopt;
  return bound;
}

std::optional<Certifier::PointFailure> Certifier::certain_failure(const Vector3d& p) const {
  if (legs) {
    const std::optional<LegsCertifier::Failure> f = legs->certain_failure(p, cond_bound);
    if (!f) return std::nullopt;
    return PointFailure{-1, f->value, f->reason};
  }
  if (device == Device::Parallel12r && p.y() == 0.0) return PointFailure{-1, kInf, "on the actuator plane y = 0 (singular)"};
  const KernelResult<Interval> at = kernel(Interval(p.x()), Interval(p.y()), Interval(p.z()));
  if (at.failure == KernelFailure::Unreachable) return PointFailure{-1, kInf, "out of reach"};
  if (at.failure != KernelFailure::None) return std::nullopt;
  if (check_ranges)
    for (int k = 0; k < 3; ++k)
      if (certainly_outside(at.cos_q[k], at.sin_q[k], ranges[k], wraps))
        return PointFailure{-1, kInf, std::string("outside the range of ") +
                                      (device == Device::Parallel12r ? kActuatorNames12r : kActuatorNamesDelta)[k]};
  const double lower = condition_lower_bound(at.M);
  if (lower >= cond_bound) return PointFailure{-1, lower, measure_text("c(J)", ">=", lower, "")};
  if (columns.empty()) return std::nullopt;
  Matrix3d mid, radius;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) mid(i, j) = at.M[i][j].mid(), radius(i, j) = at.M[i][j].rad();
  const std::array<Interval, 3> lengths =
      column_lengths(device, mid, radius, norm_bound(radius), singular_value_bounds(mid).smallest_lower);
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const ColumnCriterion& c = columns[k];
    const double worst = column_measure(c, lengths, false);
    if (c.force ? worst <= c.threshold : worst >= c.threshold)
      return PointFailure{int(k), worst, c.force ? measure_text("force_iso", "<=", worst, " N")
                                                 : measure_text("resolution", ">=", worst, " mm")};
  }
  return std::nullopt;
}

double Certifier::badness(const Vector3d& p) const {
  if (legs) return legs->badness(p, cond_bound);
  const KernelResult<double> at = kernel(p.x(), p.y(), p.z());
  if (at.failure != KernelFailure::None) return kInf;
  if (check_ranges)
    for (int k = 0; k < 3; ++k)
      if (!certainly_within(Interval(at.cos_q[k]), Interval(at.sin_q[k]), ranges[k], wraps)) return kInf;
  Matrix3d M;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M(i, j) = at.M[i][j];
  double worst = condition_number_closed_form(M) / cond_bound;
  if (columns.empty()) return worst;
  const Matrix3d J = device == Device::Parallel12r ? M : Matrix3d(M.inverse());
  for (const ColumnCriterion& c : columns)
    for (int i = 0; i < 3; ++i) {
      const double scale = c.scale[i].mid(), length = J.col(i).norm();
      worst = std::max(worst, c.force ? c.threshold * length / scale : scale * length / c.threshold);
    }
  return worst;
}

}  // namespace linkscape::verify
