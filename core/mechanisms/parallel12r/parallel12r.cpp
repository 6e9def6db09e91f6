#include "core/mechanisms/parallel12r/parallel12r.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "core/conditioning.h"

namespace linkscape::parallel12r {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

std::string format_vector(const Vector3d& v) {
  std::ostringstream out;
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

void require_finite(const Vector3d& v, const char* what) {
  if (!v.allFinite())
    throw std::invalid_argument(std::string(what) + " must be finite, got " + format_vector(v));
}

double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * kPi);  // (-pi, pi]
  return a <= -kPi ? a + 2.0 * kPi : a;
}

// Bring q to alpha in (-pi/2, pi/2] without moving D: u(a + pi, t + pi) = u(a, t).
Vector3d normalise(Vector3d q) {
  q = q.unaryExpr(&wrap_angle);
  if (std::cos(q.x()) < 0.0) {
    q.x() = wrap_angle(q.x() + kPi);
    q.y() = wrap_angle(q.y() + kPi);
    q.z() = wrap_angle(q.z() + kPi);
  }
  return q;
}

// Unit direction of a planar link, u(alpha, t), and its partial derivatives.
struct LinkDirection {
  Vector3d u, du_dalpha, du_dt;
};

LinkDirection link_direction(double sa, double ca, double t) {
  const double st = std::sin(t), ct = std::cos(t);
  // d^2 = 1 - sa^2 st^2 written as ca^2 + sa^2 ct^2: the printed form
  // cancels near the actuator plane (sa, st -> 1) and loses digits like
  // 1/d^2; this one has no subtraction (docs/methods.md).
  const double d2 = ca * ca + sa * sa * ct * ct;
  const double d = std::sqrt(d2), d3 = d2 * d;
  LinkDirection r;
  r.u = Vector3d(-sa * ct, ca * ct, ca * st) / d;
  // Differentiating u = N / d; d^2 + sa^2 st^2 = 1 simplifies every entry.
  r.du_dalpha = Vector3d(-ca * ct, -sa * ct * ct * ct, -sa * st * ct * ct) / d3;
  r.du_dt = ca * Vector3d(sa * ca * st, -ca * ca * st, ct) / d3;
  return r;
}

Status limits_status(const Model& m, const Vector3d& q) { return m.within_limits(q) ? Status::Ok : Status::OutOfLimits; }

// Fills residual, branch and status of a candidate; keeps the best per branch.
void offer(const Model& m, const Vector3d& target, const Vector3d& q, int iterations,
           double tolerance, Status geometric_status, std::array<std::optional<IkSolution>, 2>& best,
           IkMethod produced_by) {
  IkSolution s;
  s.method = produced_by;
  s.q_actuated = normalise(q);
  s.branch = branch_of(s.q_actuated);
  s.residual = (forward(m, s.q_actuated) - target).norm();
  s.iterations = iterations;
  if (!std::isfinite(s.residual)) return;
  if (s.residual > tolerance * m.reach()) {
    // Within the singular band a candidate that misses the tolerance is no
    // answer: drop it, and the result says singular (collect), never a wrong
    // finite configuration.
    if (geometric_status == Status::Singular) return;
    s.status = Status::NotConverged;
  } else if (geometric_status != Status::Ok) {
    s.status = geometric_status;
  } else {
    s.status = limits_status(m, s.q_actuated);
  }
  auto& slot = best[s.branch];
  if (!slot || s.residual < slot->residual) slot = s;
}

// Where a target sits with respect to the workspace, before any method runs.
struct TargetGeometry {
  Status status = Status::Ok;  // Ok, Unreachable or Singular
  double rho = 0.0;            // distance from the z axis
  double radius = 0.0;         // |D|
};

TargetGeometry classify(const Model& m, const Vector3d& p) {
  TargetGeometry g;
  g.rho = std::hypot(p.x(), p.y());
  g.radius = p.norm();
  const double tol = kSingularTolerance * m.reach();
  if (g.radius > m.reach() + tol || g.radius < m.inner_reach() - tol) {
    g.status = Status::Unreachable;
  } else if (std::abs(p.y()) <= tol || g.rho <= tol || m.reach() - g.radius <= tol ||
             g.radius - m.inner_reach() <= tol) {
    g.status = Status::Singular;
  }
  return g;
}

IkResult collect(std::array<std::optional<IkSolution>, 2>& best, Status fallback) {
  IkResult result;
  for (auto& slot : best)
    if (slot) result.solutions.push_back(*slot);
  // Stretched or folded targets have one solution, found under both branches.
  // Distinct branches are never this close unless within ~1e-12 of the sphere.
  if (result.solutions.size() == 2 &&
      (result.solutions[0].q_actuated - result.solutions[1].q_actuated).norm() < 1e-6)
    result.solutions.pop_back();
  // No candidate survived (e.g. Eqs. 11-13 gave NaN): never report Ok then.
  result.status = result.solutions.empty() && fallback == Status::Ok ? Status::NotConverged : fallback;
  for (const auto& s : result.solutions) {
    if (s.status == Status::Ok) {
      result.status = Status::Ok;
      break;
    }
    result.status = s.status;
  }
  return result;
}

// ---- Planar reduction ------------------------------------------------------
// Both link directions are normal to n = (cos a, sin a, 0), so D lies in the
// vertical plane with normal n and the linkage is a planar two-link arm there
// with absolute link angles phi, tan(phi) = cos(a) tan(t).
IkResult inverse_planar(const Model& m, const Vector3d& p, const TargetGeometry& g,
                        double tolerance) {
  std::array<std::optional<IkSolution>, 2> best;
  if (g.status == Status::Unreachable || g.rho == 0.0 || p.y() == 0.0) return collect(best, g.status);
  const double sign_y = p.y() > 0.0 ? 1.0 : -1.0;
  const double ca = std::abs(p.y()) / g.rho;
  const double r = sign_y * g.rho;  // in-plane horizontal coordinate
  const double R = g.radius, L1 = m.L1, L2 = m.L2;
  // Projection a of link 1 on D and its normal offset h, in factored form so
  // that both stay accurate at the outer and inner spheres.
  const double a = (R * R + L1 * L1 - L2 * L2) / (2.0 * R);
  const double h2 = (L1 + L2 - R) * (L2 - L1 + R) * (R + L1 - L2) * (R + L1 + L2) / (4.0 * R * R);
  const double h = std::sqrt(std::max(0.0, h2));
  const double ur = r / R, uz = p.z() / R;  // unit D in the plane
  const double alpha = std::atan2(-p.x() * sign_y, std::abs(p.y()));
  for (int branch = 0; branch < 2; ++branch) {
    const double s = branch == 0 ? 1.0 : -1.0;
    const double l1r = a * ur - s * h * uz, l1z = a * uz + s * h * ur;
    const double l2r = r - l1r, l2z = p.z() - l1z;
    const Vector3d q(alpha, std::atan2(l1z, ca * l1r), std::atan2(l2z, ca * l2r));
    offer(m, p, q, 0, tolerance, g.status, best, IkMethod::Planar);
  }
  return collect(best, g.status);
}

// ---- The paper's closed form, Eqs. 14-16 (corrected) -----------------------
IkResult inverse_paper(const Model& m, const Vector3d& p, const TargetGeometry& g,
                       double tolerance) {
  std::array<std::optional<IkSolution>, 2> best;
  if (g.status == Status::Unreachable || p.y() == 0.0) return collect(best, g.status);
  const double x = p.x(), y = p.y(), z = p.z();
  const double alpha = std::atan(-x / y);  // Eq. 14
  const double rho2 = x * x + y * y;
  // Eq. 15 with W = L2 U in place of the printed U (see docs).
  const double W = (p.squaredNorm() + m.L1 * m.L1 - m.L2 * m.L2) / (2.0 * m.L1);
  const double f = rho2 * rho2 - W * W * x * x - y * y * z * z;
  const double gg = 2.0 * rho2 * y * z;
  const double hh = (z * z - W * W) * y * y;
  const double P = f * f + gg * gg, Q = 2.0 * f * hh - gg * gg, R = hh * hh;
  if (P == 0.0) return collect(best, Status::Singular);
  // Q^2 - 4PR factors (with f + h = rho^2 (rho^2 - W^2)) into
  // 16 rho^6 y^4 z^2 W^2 (|D|^2 - W^2): no cancellation, where Q^2 - 4PR
  // cancels terms of length^16 down to rounding as the roots meet.
  const double radius = p.norm(), rho = std::sqrt(rho2), abs_W = std::abs(W);
  const double sqrt_disc = 4.0 * rho2 * rho * y * y * std::abs(z * W) *
                           std::sqrt(std::max(0.0, (radius - abs_W) * (radius + abs_W)));
  // The roots without cancellation: q / P and R / q.
  const double q_root = -0.5 * (Q + std::copysign(sqrt_disc, Q));
  const double roots[2] = {q_root / P, q_root != 0.0 ? R / q_root : 0.0};
  const double sign_y = y > 0.0 ? 1.0 : -1.0;
  for (double root : roots) {
    const double cos2_beta = std::clamp(root, 0.0, 1.0);
    const double b0 = std::acos(std::sqrt(cos2_beta));
    for (double beta : {b0, -b0, kPi - b0, b0 - kPi}) {
      // Eq. 16 with the sign corrected and V = sign(y) - ... for y < 0.
      const double cb = std::cos(beta);
      const double V = sign_y - m.L1 * cb / std::sqrt(x * x * cb * cb + y * y);
      const double denom = m.L2 * m.L2 - x * x * V * V;
      if (denom <= 0.0) continue;
      const double cos2_gamma = std::clamp(y * y * V * V / denom, 0.0, 1.0);
      const double g0 = std::acos(std::sqrt(cos2_gamma));
      for (double gamma : {g0, -g0, kPi - g0, g0 - kPi})
        offer(m, p, Vector3d(alpha, beta, gamma), 0, tolerance, g.status, best, IkMethod::Paper);
    }
  }
  // One Newton step on Eqs. 11-13 from each branch's best candidate, part of
  // the method: Eqs. 15 and 16 give cos^2 of the angles, which is stationary
  // at 0, pi/2 and pi, so a rounding error e there becomes sqrt(e) in the
  // angle (7e-9 (L1 + L2) at the isotropic point (0, L, L)). The step squares
  // that error away; a solution it improved has iterations = 1.
  for (int branch = 0; branch < 2; ++branch) {
    if (!best[branch]) continue;
    const Vector3d q = best[branch]->q_actuated;
    const Vector3d step = jacobian(m, q).partialPivLu().solve(p - forward(m, q));
    if (step.allFinite()) offer(m, p, q + step, 1, tolerance, g.status, best, IkMethod::Paper);
  }
  return collect(best, g.status);
}

// ---- Iterative methods -----------------------------------------------------
Vector3d default_seed(int branch, const Vector3d& target) {
  Vector3d q = home_pose(branch);
  // Mirror through the x-z plane for targets with y < 0: u(-a, pi - t) flips y.
  if (target.y() < 0.0) q = Vector3d(-q.x(), kPi - q.y(), kPi - q.z());
  return normalise(q);
}

struct IterationOutcome {
  Vector3d q;
  int iterations = 0;
  bool singular = false;
};

IterationOutcome iterate_newton(const Model& m, const Vector3d& target, Vector3d q, int max_iterations) {
  const double stop = 1e-15 * m.reach();
  double residual = (forward(m, q) - target).norm();
  int it = 0;
  for (; it < max_iterations && residual > stop; ++it) {
    const Matrix3d J = jacobian(m, q);
    const Vector3d step = J.partialPivLu().solve(target - forward(m, q));
    if (!step.allFinite()) return {q, it, true};  // exactly singular J
    // Backtracking keeps Newton from jumping across the workspace.
    double t = 1.0;
    bool improved = false;
    for (int k = 0; k < 30; ++k, t *= 0.5) {
      const Vector3d trial = normalise(q + t * step);
      const double r = (forward(m, trial) - target).norm();
      if (r < residual) {
        q = trial;
        residual = r;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  return {q, it, false};
}

IterationOutcome iterate_dls(const Model& m, const Vector3d& target, Vector3d q, int max_iterations) {
  const double stop = 1e-15 * m.reach();
  double lambda = 1e-2 * m.reach();
  double residual = (forward(m, q) - target).norm();
  int it = 0;
  for (; it < max_iterations && residual > stop; ++it) {
    const Matrix3d J = jacobian(m, q);
    const Vector3d e = target - forward(m, q);
    const Matrix3d A = J * J.transpose() + lambda * lambda * Matrix3d::Identity();
    const Vector3d step = J.transpose() * A.ldlt().solve(e);
    const Vector3d trial = normalise(q + step);
    const double r = (forward(m, trial) - target).norm();
    if (r < residual) {
      q = trial;
      residual = r;
      lambda = std::max(lambda * 0.2, 1e-12 * m.reach());
    } else {
      lambda *= 10.0;
      if (lambda > 1e8 * m.reach()) break;  // no direction reduces the residual
    }
  }
  return {q, it, false};
}

IkResult inverse_iterative(const Model& m, const Vector3d& p, const TargetGeometry& g, IkMethod method,
                           const IkOptions& options) {
  std::array<std::optional<IkSolution>, 2> best;
  if (g.status == Status::Unreachable) return collect(best, g.status);
  std::vector<Vector3d> seeds;
  if (options.seed) {
    require_finite(*options.seed, "IK seed");
    seeds.push_back(normalise(*options.seed));
  } else {
    seeds = {default_seed(0, p), default_seed(1, p)};
  }
  bool singular = false;
  for (const Vector3d& seed : seeds) {
    const IterationOutcome out = method == IkMethod::Newton
                                     ? iterate_newton(m, p, seed, options.max_iterations)
                                     : iterate_dls(m, p, seed, options.max_iterations);
    singular = singular || out.singular;
    offer(m, p, out.q, out.iterations, options.tolerance, g.status, best, method);
  }
  return collect(best, singular || g.status == Status::Singular ? Status::Singular : Status::NotConverged);
}

// ---- Fallback policy --------------------------------------------------------
// The planar closed form first (exact wherever it meets the tolerance, and
// cheapest); for each branch whose planar candidate misses the tolerance,
// Newton seeded from that candidate. Targets the geometry already classes as
// unreachable or singular keep the planar answer: no method can do better.
IkResult inverse_fallback(const Model& m, const Vector3d& p, const TargetGeometry& g, const IkOptions& options) {
  IkResult planar = inverse_planar(m, p, g, options.tolerance);
  if (g.status != Status::Ok) return planar;
  std::array<std::optional<IkSolution>, 2> best;
  for (const IkSolution& s : planar.solutions) best[s.branch] = s;
  bool singular = false;
  for (int branch = 0; branch < 2; ++branch) {
    const bool missed = best[branch] && best[branch]->status == Status::NotConverged;
    if (!missed && !planar.solutions.empty()) continue;
    const Vector3d seed = best[branch] ? best[branch]->q_actuated : default_seed(branch, p);
    const IterationOutcome out = iterate_newton(m, p, seed, options.max_iterations);
    singular = singular || out.singular;
    offer(m, p, out.q, out.iterations, options.tolerance, g.status, best, IkMethod::Newton);
  }
  return collect(best, singular ? Status::Singular : Status::NotConverged);
}

// Elementary rotations.
Matrix3d rot_x(double a) { return Eigen::AngleAxisd(a, Vector3d::UnitX()).toRotationMatrix(); }
Matrix3d rot_z(double a) { return Eigen::AngleAxisd(a, Vector3d::UnitZ()).toRotationMatrix(); }

struct StyleValues {
  double r1, r2, motor, side;
};
StyleValues resolve(const Model& m, const SkeletonStyle& s) {
  const double scale = std::min(m.L1, m.L2);
  return {s.inner_radius > 0 ? s.inner_radius : 0.26 * scale,
          s.outer_radius > 0 ? s.outer_radius : 0.36 * scale,
          s.motor_length > 0 ? s.motor_length : 0.14 * scale, s.parallelogram_fraction * m.L1};
}

std::vector<Vector3d> arc(const Vector3d& from, const Vector3d& to, double radius, int samples) {
  std::vector<Vector3d> pts;
  const Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond q1 = Eigen::Quaterniond::FromTwoVectors(from, to);
  for (int i = 0; i <= samples; ++i)
    pts.push_back(radius * (q0.slerp(double(i) / samples, q1) * from.normalized()));
  return pts;
}

}  // namespace

// ---- Model ----------------------------------------------------------------

void Model::validate() const {
  auto check_length = [](const char* name, double v) {
    if (!(v >= kMinLength && v <= kMaxLength)) {
      std::ostringstream msg;
      msg << "parallel-12r: " << name << " must be a length in [" << kMinLength << ", " << kMaxLength
          << "], got " << v;
      throw std::invalid_argument(msg.str());
    }
  };
  check_length("L1", L1);
  check_length("L2", L2);
  auto check_range = [](const char* name, const Interval& r) {
    if (!(std::isfinite(r.lo) && std::isfinite(r.hi) && r.lo < r.hi)) {
      std::ostringstream msg;
      msg << "parallel-12r: range of " << name << " must be finite with lo < hi, got [" << r.lo
          << ", " << r.hi << "]";
      throw std::invalid_argument(msg.str());
    }
  };
  check_range("alpha", alpha_limits);
  check_range("beta", beta_limits);
  check_range("gamma", gamma_limits);
}

Model Model::from_parameters(const std::map<std::string, double>& parameters,
                             const std::map<std::string, Interval>& limits_deg,
                             std::string length_unit) {
  Model m;
  m.length_unit = std::move(length_unit);
  for (const auto& [name, value] : parameters) {
    if (name == "L1") m.L1 = value;
    else if (name == "L2") m.L2 = value;
    else throw std::invalid_argument("parallel-12r: unknown parameter '" + name + "' (known: L1, L2)");
  }
  constexpr double deg = kPi / 180.0;
  for (const auto& [name, r] : limits_deg) {
    const Interval rad{r.lo * deg, r.hi * deg};
    if (name == "alpha") m.alpha_limits = rad;
    else if (name == "beta") m.beta_limits = rad;
    else if (name == "gamma") m.gamma_limits = rad;
    else throw std::invalid_argument("parallel-12r: unknown actuator '" + name + "' (known: alpha, beta, gamma)");
  }
  m.validate();
  return m;
}

// ---- Forward geometry -----------------------------------------------------

Vector3d forward(const Model& m, const Vector3d& q) {
  require_finite(q, "actuator angles");
  const double sa = std::sin(q.x()), ca = std::cos(q.x());
  return m.L1 * link_direction(sa, ca, q.y()).u + m.L2 * link_direction(sa, ca, q.z()).u;
}

void forward(const Model& m, std::span<const Vector3d> q, std::span<Vector3d> p) {
  if (q.size() != p.size())
    throw std::invalid_argument("forward: " + std::to_string(q.size()) + " configurations but " +
                                std::to_string(p.size()) + " output slots");
  for (std::size_t i = 0; i < q.size(); ++i) p[i] = forward(m, q[i]);
}

Matrix3d jacobian(const Model& m, const Vector3d& q) {
  require_finite(q, "actuator angles");
  const double sa = std::sin(q.x()), ca = std::cos(q.x());
  const LinkDirection b = link_direction(sa, ca, q.y());
  const LinkDirection c = link_direction(sa, ca, q.z());
  Matrix3d J;
  J.col(0) = m.L1 * b.du_dalpha + m.L2 * c.du_dalpha;
  J.col(1) = m.L1 * b.du_dt;
  J.col(2) = m.L2 * c.du_dt;
  return J;
}

Matrix3d jacobian_central_difference(const Model& m, const Vector3d& q, double step) {
  Matrix3d J;
  for (int k = 0; k < 3; ++k) {
    Vector3d dq = Vector3d::Zero();
    dq(k) = step;
    J.col(k) = (forward(m, q + dq) - forward(m, q - dq)) / (2.0 * step);
  }
  return J;
}

double jacobian_determinant_eq18(const Model& m, const Vector3d& q) {
  const double sa = std::sin(q.x()), ca = std::cos(q.x());
  const double cb = std::cos(q.y()), cg = std::cos(q.z());
  const double db = std::sqrt(ca * ca + sa * sa * cb * cb);  // no cancellation (see link_direction)
  const double dg = std::sqrt(ca * ca + sa * sa * cg * cg);
  return m.L1 * m.L2 * ca * ca * ca * std::sin(q.y() - q.z()) / (db * db * db * dg * dg * dg) *
         (m.L1 * std::cos(q.y()) / db + m.L2 * std::cos(q.z()) / dg);
}

// ---- Inverse kinematics ---------------------------------------------------

std::string_view to_string(IkMethod method) {
  switch (method) {
    case IkMethod::Paper: return "paper";
    case IkMethod::Planar: return "planar";
    case IkMethod::Newton: return "newton";
    case IkMethod::DampedLeastSquares: return "dls";
    case IkMethod::Fallback: return "fallback";
  }
  return "unknown";
}

IkMethod parse_ik_method(std::string_view name) {
  for (IkMethod m : {IkMethod::Paper, IkMethod::Planar, IkMethod::Newton, IkMethod::DampedLeastSquares,
                     IkMethod::Fallback})
    if (name == to_string(m)) return m;
  throw std::invalid_argument("unknown IK method '" + std::string(name) +
                              "' (expected paper, planar, newton, dls or fallback)");
}

int branch_of(const Vector3d& q) { return std::sin(q.y() - q.z()) >= 0.0 ? 0 : 1; }

Vector3d home_pose(int branch) {
  return branch == 0 ? Vector3d(0.0, kPi / 2, 0.0) : Vector3d(0.0, 0.0, kPi / 2);
}

IkResult inverse(const Model& m, const Vector3d& p, IkMethod method, const IkOptions& options) {
  m.validate();
  require_finite(p, "IK target");
  if (!(options.tolerance > 0.0) || options.max_iterations < 0)
    throw std::invalid_argument("IK options: tolerance must be > 0 and max_iterations >= 0");
  // The angles do not depend on scale: solve with lengths and target divided
  // by a power of two near the reach (exact), so that no intermediate (the
  // paper's quartic has terms of length^16) overflows or underflows, and
  // scale the residuals back.
  const int exponent = std::ilogb(m.reach());
  Model unit = m;
  unit.L1 = std::ldexp(m.L1, -exponent);
  unit.L2 = std::ldexp(m.L2, -exponent);
  const Vector3d p_unit = p * std::ldexp(1.0, -exponent);
  const TargetGeometry g = classify(unit, p_unit);
  IkResult result;
  switch (method) {
    case IkMethod::Paper: result = inverse_paper(unit, p_unit, g, options.tolerance); break;
    case IkMethod::Planar: result = inverse_planar(unit, p_unit, g, options.tolerance); break;
    case IkMethod::Newton:
    case IkMethod::DampedLeastSquares: result = inverse_iterative(unit, p_unit, g, method, options); break;
    case IkMethod::Fallback: result = inverse_fallback(unit, p_unit, g, options); break;
  }
  for (IkSolution& s : result.solutions) s.residual = std::ldexp(s.residual, exponent);
  return result;
}

// ---- Conditioning and singularities ---------------------------------------

std::string_view to_string(SingularSet set) {
  switch (set) {
    case SingularSet::ActuatorPlane: return "actuator-plane";
    case SingularSet::Stretched: return "stretched";
    case SingularSet::Folded: return "folded";
    case SingularSet::ZAxis: return "z-axis";
  }
  return "unknown";
}

SingularityReport nearest_singularity(const Model& m, const Vector3d& q) {
  const Vector3d p = forward(m, q);
  SingularityReport r;
  const double radius = p.norm();
  r.distances = {std::abs(p.y()), std::max(0.0, m.reach() - radius),
                 std::max(0.0, radius - m.inner_reach()), std::hypot(p.x(), p.y())};
  const auto it = std::min_element(r.distances.begin(), r.distances.end());
  r.nearest = static_cast<SingularSet>(it - r.distances.begin());
  r.distance = *it;
  const double sa = std::sin(q.x());
  r.static_measure = std::min(std::sqrt(1.0 - sa * sa * std::sin(q.y()) * std::sin(q.y())),
                              std::sqrt(1.0 - sa * sa * std::sin(q.z()) * std::sin(q.z())));
  return r;
}

Conditioning conditioning(const Model& m, const Vector3d& q) {
  const Matrix3d J = jacobian(m, q);
  const double cond = condition_number_closed_form(J);
  if (!(cond <= kMaxTrustedCondition))
    return {std::numeric_limits<double>::infinity(), 0.0, Status::Singular};
  return {cond, J.determinant(), Status::Ok};
}

// ---- Skeleton -------------------------------------------------------------
// Link frames chain from ground through each loop; the passive angles follow
// from u(alpha, beta) (derivation in docs): the loop I chain through A gives
// link 4 = Rz(alpha) Rx(beta3), the chain through B gives link 3 =
// Rx(beta) Rz(beta1), and closure means both carry joint 3-4 on the same axis.

std::array<JointDefinition, kJointCount> joint_definitions(const Model& m, const SkeletonStyle& style) {
  const StyleValues s = resolve(m, style);
  const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
  auto same = [](std::string name, int a, int b, Vector3d point, Vector3d axis) {
    return JointDefinition{std::move(name), a, b, point, axis, point, axis};
  };
  return {{
      same("A", 1, 5, -s.r1 * Z, Z),
      same("B", 1, 2, s.r1 * X, X),
      same("C", 1, 8, -s.r2 * X, X),
      same("2-3", 2, 3, s.r1 * Z, Z),
      same("3-4", 3, 4, -s.r1 * Y, Y),
      same("4-5", 4, 5, -s.r1 * X, X),
      same("5-6", 5, 6, s.r2 * X, X),
      same("6-7", 6, 7, -s.r2 * Y, Y),
      same("7-8", 7, 8, s.r2 * Z, Z),
      JointDefinition{"6-10", 6, 10, m.L2 * Y, X, Vector3d::Zero(), X},
      JointDefinition{"10-9", 10, 9, s.side * Y, X, m.L2 * Y, X},
      JointDefinition{"9-4", 9, 4, Vector3d::Zero(), X, s.side * Y, X},
  }};
}

std::array<LinkShape, kLinkCount> link_shapes(const Model& m, const SkeletonStyle& style) {
  const StyleValues s = resolve(m, style);
  const int n = std::max(2, style.arc_samples);
  const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
  const double base = s.r2 + s.motor;
  std::array<LinkShape, kLinkCount> shapes;
  // Link 1, ground: three motor shafts and the frame joining their housings.
  shapes[0].polylines = {{-s.r1 * Z, -base * Z},
                         {s.r1 * X, base * X},
                         {-s.r2 * X, -base * X},
                         {base * X, base * (X - Z), -base * Z, base * (-X - Z), -base * X}};
  shapes[4].polylines = {arc(-Z, -X, s.r1, n), arc(-Z, X, s.r2, n), {-s.r1 * Z, -s.r2 * Z}};  // 5
  shapes[1].polylines = {arc(X, Z, s.r1, n)};                                                   // 2
  shapes[2].polylines = {arc(Z, -Y, s.r1, n)};                                                  // 3
  shapes[3].polylines = {arc(-Y, -X, s.r1, n), {-s.r1 * Y, s.side * Y}};                        // 4
  shapes[7].polylines = {arc(-X, Z, s.r2, n)};                                                  // 8
  shapes[6].polylines = {arc(Z, -Y, s.r2, n)};                                                  // 7
  shapes[5].polylines = {arc(-Y, X, s.r2, n), {-s.r2 * Y, m.L2 * Y}};                           // 6
  shapes[9].polylines = {{Vector3d::Zero(), m.L1 * Y}};                                         // 10
  shapes[8].polylines = {{Vector3d::Zero(), m.L2 * Y}};                                         // 9
  return shapes;
}

Vector3d endpoint_in_link10(const Model& m) { return m.L1 * Vector3d::UnitY(); }

Skeleton skeleton(const Model& m, const Vector3d& q, const SkeletonStyle& style) {
  require_finite(q, "actuator angles");
  const StyleValues s = resolve(m, style);
  const double alpha = q.x(), beta = q.y(), gamma = q.z();
  const double sa = std::sin(alpha), ca = std::cos(alpha);
  // Passive angles: beta3 at joint 4-5 (the planar angle phi_beta), beta1 at 2-3.
  const double beta3 = std::atan2(ca * std::sin(beta), std::cos(beta));
  const double beta1 = std::atan2(sa * std::cos(beta), ca);
  const double gamma3 = std::atan2(ca * std::sin(gamma), std::cos(gamma));
  const double gamma1 = std::atan2(sa * std::cos(gamma), ca);

  std::array<Matrix3d, kLinkCount> R;
  R[0] = Matrix3d::Identity();
  R[4] = rot_z(alpha);                // 5: shaft of A
  R[3] = R[4] * rot_x(beta3);         // 4
  R[1] = rot_x(beta);                 // 2: shaft of B
  R[2] = R[1] * rot_z(beta1);         // 3
  R[7] = rot_x(gamma);                // 8: shaft of C
  R[6] = R[7] * rot_z(gamma1);        // 7
  R[5] = R[4] * rot_x(gamma3);        // 6
  R[9] = R[5] * rot_x(beta3 - gamma3);  // 10, parallel to link 4
  R[8] = R[3] * rot_x(gamma3 - beta3);  // 9, parallel to link 6

  Skeleton sk;
  for (int k = 0; k < kLinkCount; ++k) {
    sk.link_frames[k].setIdentity();
    sk.link_frames[k].linear() = R[k];
  }
  sk.link_frames[9].translation() = m.L2 * (R[5] * Vector3d::UnitY());   // joint 6-10
  sk.link_frames[8].translation() = s.side * (R[3] * Vector3d::UnitY());  // joint 9-4
  const auto defs = joint_definitions(m, style);
  for (int j = 0; j < kJointCount; ++j) {
    const Eigen::Isometry3d& T = sk.link_frames[defs[j].link_a - 1];
    sk.joint_positions[j] = T * defs[j].point_in_a;
    sk.joint_axes[j] = T.linear() * defs[j].axis_in_a;
  }
  sk.endpoint = sk.link_frames[9] * endpoint_in_link10(m);
  return sk;
}

}  // namespace linkscape::parallel12r
