#include "core/mechanisms/delta/delta.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "core/conditioning.h"
#include "core/mechanisms/delta/delta_checks.h"
#include "core/mechanisms/delta/field.h"

namespace linkscape::delta {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Closure error above which (q, p) is not a configuration of the model.
constexpr double kClosureCheck = 1e-6;

}  // namespace

std::string checks::format_vector(const Vector3d& v) {
  std::ostringstream out;
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

namespace {

using checks::format_vector;

void require_finite(const Vector3d& v, const char* what) {
  if (!v.allFinite())
    throw std::invalid_argument(std::string("delta: ") + what + " must be finite, got " + format_vector(v));
}

void require_leg(int leg) {
  if (leg < 0 || leg >= kLegCount)
    throw std::invalid_argument("delta: leg index must be 0, 1 or 2, got " + std::to_string(leg));
}

void require_branch(int branch) {
  if (branch < 0 || branch >= kBranchCount)
    throw std::invalid_argument("delta: branch must be in 0..7 (bit i: leg i elbow in), got " +
                                std::to_string(branch));
}

double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * kPi);  // [-pi, pi]
  return a <= -kPi ? a + 2.0 * kPi : a;
}

// Angle to the nearer end of a range, for the representative q + 2 pi k
// nearest the range's centre; negative outside.
double range_margin(const Interval& range, double q) {
  const double centre = 0.5 * (range.lo + range.hi);
  const double q_near = centre + std::remainder(q - centre, 2.0 * kPi);
  return std::min(q_near - range.lo, range.hi - q_near);
}

bool within_ranges(const Model& m, const Vector3d& q) {
  for (int i = 0; i < kLegCount; ++i)
    if (range_margin(m.q_limits[i], q(i)) < 0.0) return false;
  return true;
}

// The platform joint seen from the motor, in the leg's frame (e_i, t_i, z):
// d = C_i - A_i = p - (R - r) e_i, u = d.e_i, v = d.t_i, w = d.z.
struct LegCoordinates {
  double u = 0.0, v = 0.0, w = 0.0;
};

LegCoordinates leg_coordinates(const Model& m, int leg, const Vector3d& p) {
  const double c = std::cos(leg_angle(leg)), s = std::sin(leg_angle(leg));
  const double px = p.x() - (m.R - m.r) * c, py = p.y() - (m.R - m.r) * s;
  return {c * px + s * py, -s * px + c * py, p.z()};
}

// Nearest and farthest distance from the platform joint to the elbow circle.
struct LegReach {
  double d_min = 0.0, d_max = 0.0, margin = 0.0;
};

LegReach leg_reach(const Model& m, const LegCoordinates& c) {
  const double rho = std::hypot(c.u, c.w);  // in-plane distance from the motor axis
  LegReach r;
  r.d_min = std::hypot(rho - m.La, c.v);
  r.d_max = std::hypot(rho + m.La, c.v);
  r.margin = std::min(m.Lb - r.d_min, r.d_max - m.Lb);
  return r;
}

// Closure of one leg as A cos q + B sin q = C with A = 2 La u, B = -2 La w,
// C = |d|^2 + La^2 - Lb^2 (docs: "IK per leg").
LegSolution solve_leg(const Model& m, const LegCoordinates& c, bool elbow_in, double tol) {
  const LegReach reach = leg_reach(m, c);
  const double A = 2.0 * m.La * c.u, B = -2.0 * m.La * c.w;
  LegSolution s;
  s.margin = reach.margin;
  if (reach.margin < -tol) {
    // Closest approach: elbow towards the joint (too far) or away (too near).
    s.status = Status::Unreachable;
    const double towards = std::atan2(B, A);
    s.q = wrap_angle(m.Lb < reach.d_min ? towards : towards + kPi);
    return s;
  }
  const double C = c.u * c.u + c.v * c.v + c.w * c.w + m.La * m.La - m.Lb * m.Lb;
  // A^2 + B^2 - C^2 in factored form: exact to rounding near the boundary.
  const double disc = (m.Lb - reach.d_min) * (m.Lb + reach.d_min) * (reach.d_max - m.Lb) * (reach.d_max + m.Lb);
  const double root = std::sqrt(std::max(0.0, disc));
  const double sigma = elbow_in ? 1.0 : -1.0;
  // tan(q/2) = (B + sigma root) / (C + A) = (C - A) / (B - sigma root); the
  // pair with the larger norm avoids 0/0.
  const double n1 = B + sigma * root, d1 = C + A;
  const double n2 = C - A, d2 = B - sigma * root;
  const double half = std::hypot(n1, d1) >= std::hypot(n2, d2) ? std::atan2(n1, d1) : std::atan2(n2, d2);
  s.q = wrap_angle(2.0 * half);
  s.status = std::abs(reach.margin) <= tol ? Status::Singular : Status::Ok;
  return s;
}

// Newton on f(q) = (C - A cos q - B sin q) / 2, the leg's closure.
struct LegNewton {
  double q = 0.0;
  int iterations = 0;
};

LegNewton newton_leg(const Model& m, const LegCoordinates& c, double q, int max_iterations) {
  const double A = 2.0 * m.La * c.u, B = -2.0 * m.La * c.w;
  const double C = c.u * c.u + c.v * c.v + c.w * c.w + m.La * m.La - m.Lb * m.Lb;
  auto f = [&](double x) { return 0.5 * (C - A * std::cos(x) - B * std::sin(x)); };
  // f = (|s|^2 - Lb^2) / 2, so |f| / Lb is the closure error to first order.
  const double stop = 1e-15 * m.size() * m.Lb;
  double fq = f(q);
  int it = 0;
  for (; it < max_iterations && std::abs(fq) > stop; ++it) {
    const double slope = 0.5 * (A * std::sin(q) - B * std::cos(q));
    if (slope == 0.0) break;  // serial singularity at the iterate
    const double step = -fq / slope;
    // Backtracking keeps a step from jumping to the other elbow.
    double t = 1.0;
    bool improved = false;
    for (int k = 0; k < 30; ++k, t *= 0.5) {
      const double trial = q + t * step;
      const double ft = f(trial);
      if (std::abs(ft) < std::abs(fq)) {
        q = trial;
        fq = ft;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  return {wrap_angle(q), it};
}

// The three sphere centres c_i = B_i - r e_i of a configuration and their
// circumcircle: the closed-form FK places p on its axis.
struct Spheres {
  std::array<Vector3d, kLegCount> c;
  Vector3d normal = Vector3d::UnitZ();  // unit (c1 - c0) x (c2 - c0)
  Vector3d circumcentre = Vector3d::Zero();
  double gap = 0.0;  // Lb - circumradius; the FK discriminant is gap (Lb + circumradius)
  bool degenerate = false;  // collinear or coincident centres
};

Spheres spheres_from_centres(const Model& m, const std::array<Vector3d, kLegCount>& centres) {
  Spheres s;
  s.c = centres;
  const Vector3d a = s.c[0] - s.c[2], b = s.c[1] - s.c[2];
  const Vector3d n = a.cross(b);  // = (c1 - c0) x (c2 - c0)
  const double n2 = n.squaredNorm(), a2 = a.squaredNorm(), b2 = b.squaredNorm();
  // sin of the triangle's angle at c2 below 1e-12: no plane to speak of.
  if (!(n2 > 1e-24 * a2 * b2)) {
    s.degenerate = true;
    s.circumcentre = (s.c[0] + s.c[1] + s.c[2]) / 3.0;
    s.gap = -kInf;
    return s;
  }
  s.normal = n / std::sqrt(n2);
  s.circumcentre = s.c[2] + (a2 * b - b2 * a).cross(n) / (2.0 * n2);
  const double circumradius = std::sqrt(a2 * b2 * (a - b).squaredNorm()) / (2.0 * std::sqrt(n2));
  s.gap = m.Lb - circumradius;
  return s;
}

Spheres spheres_of(const Model& m, const Vector3d& q) {
  std::array<Vector3d, kLegCount> c;
  for (int i = 0; i < kLegCount; ++i) c[i] = sphere_centre(m, i, q(i));
  return spheres_from_centres(m, c);
}

double closure_error(const Model& m, const Vector3d& q, const Vector3d& p) {
  double worst = 0.0;
  for (int i = 0; i < kLegCount; ++i)
    worst = std::max(worst, std::abs((p - sphere_centre(m, i, q(i))).norm() - m.Lb));
  return worst;
}

}  // namespace

void checks::require_closure(const Model& m, const Vector3d& q, const Vector3d& p, const char* who) {
  require_finite(q, "actuator angles");
  require_finite(p, "platform position");
  const double e = closure_error(m, q, p);
  if (!(e <= kClosureCheck * m.size())) {
    std::ostringstream msg;
    msg << "delta: " << who << ": q = " << format_vector(q) << " and p = " << format_vector(p)
        << " do not close the legs (error " << e << " " << m.length_unit << ")";
    throw std::invalid_argument(msg.str());
  }
}

namespace {

using checks::require_closure;

// Unit direction in which the elbow moves as q_i grows, over La.
Vector3d elbow_motion(int leg, double q) {
  return -(std::sin(q) * leg_radial(leg) + std::cos(q) * Vector3d::UnitZ());
}

void check_options(int max_iterations, double tolerance) {
  if (!(tolerance > 0.0) || max_iterations < 0)
    throw std::invalid_argument("delta: options need tolerance > 0 and max_iterations >= 0");
}

}  // namespace

// ---- Model --------------------------------------------------------------------

void Model::validate() const {
  auto fail = [](const std::string& what, double v) {
    std::ostringstream msg;
    msg << "delta: " << what << ", got " << v;
    throw std::invalid_argument(msg.str());
  };
  if (!std::isfinite(R) || R <= 0.0) fail("R must be a positive finite length", R);
  if (!std::isfinite(r) || r < 0.0) fail("r must be a finite length >= 0", r);
  if (!std::isfinite(La) || La <= 0.0) fail("La must be a positive finite length", La);
  if (!std::isfinite(Lb) || Lb <= 0.0) fail("Lb must be a positive finite length", Lb);
  for (int i = 0; i < kLegCount; ++i) {
    const Interval& range = q_limits[i];
    if (!(std::isfinite(range.lo) && std::isfinite(range.hi) && range.lo < range.hi &&
          range.hi - range.lo <= 2.0 * kPi)) {
      std::ostringstream msg;
      msg << "delta: range of q" << i + 1 << " must be finite with lo < hi <= lo + 2 pi, got [" << range.lo
          << ", " << range.hi << "] rad";
      throw std::invalid_argument(msg.str());
    }
  }
  if (!std::isfinite(elbow_axis) || !std::isfinite(wrist_axis)) fail("a ball joint's cone axis must be finite", elbow_axis + wrist_axis);
  if (!(elbow_cone > 0.0 && elbow_cone <= kPi)) fail("the elbow's cone must be in (0, pi] rad", elbow_cone);
  if (!(wrist_cone > 0.0 && wrist_cone <= kPi)) fail("the wrist's cone must be in (0, pi] rad", wrist_cone);
}

Model Model::from_parameters(const std::map<std::string, double>& parameters,
                             const std::map<std::string, Interval>& limits_deg, std::string length_unit) {
  Model m;
  m.length_unit = std::move(length_unit);
  for (const auto& [name, value] : parameters) {
    if (name == "R") m.R = value;
    else if (name == "r") m.r = value;
    else if (name == "La") m.La = value;
    else if (name == "Lb") m.Lb = value;
    else throw std::invalid_argument("delta: unknown parameter '" + name + "' (known: R, r, La, Lb)");
  }
  constexpr double deg = kPi / 180.0;
  for (const auto& [name, range] : limits_deg) {
    const Interval rad{range.lo * deg, range.hi * deg};
    if (name == "q1") m.q_limits[0] = rad;
    else if (name == "q2") m.q_limits[1] = rad;
    else if (name == "q3") m.q_limits[2] = rad;
    else throw std::invalid_argument("delta: unknown actuator '" + name + "' (known: q1, q2, q3)");
  }
  m.validate();
  return m;
}

std::map<std::string, double> Model::to_parameters() const {
  return {{"R", R}, {"r", r}, {"La", La}, {"Lb", Lb}};
}

// ---- Leg geometry -----------------------------------------------------------

double leg_angle(int leg) {
  require_leg(leg);
  return leg * (2.0 * kPi / 3.0);
}

Vector3d leg_radial(int leg) { return {std::cos(leg_angle(leg)), std::sin(leg_angle(leg)), 0.0}; }
Vector3d leg_motor_axis(int leg) { return {-std::sin(leg_angle(leg)), std::cos(leg_angle(leg)), 0.0}; }
Vector3d motor_position(const Model& m, int leg) { return m.R * leg_radial(leg); }

Vector3d elbow_position(const Model& m, int leg, double q) {
  return motor_position(m, leg) + m.La * (std::cos(q) * leg_radial(leg) - std::sin(q) * Vector3d::UnitZ());
}

Vector3d sphere_centre(const Model& m, int leg, double q) { return elbow_position(m, leg, q) - m.r * leg_radial(leg); }

double leg_margin(const Model& m, int leg, const Vector3d& p) {
  require_finite(p, "platform position");
  return leg_reach(m, leg_coordinates(m, leg, p)).margin;
}

LegSolution leg_inverse(const Model& m, int leg, const Vector3d& p, bool elbow_in) {
  require_leg(leg);
  require_finite(p, "IK target");
  return solve_leg(m, leg_coordinates(m, leg, p), elbow_in, kSingularTolerance * m.size());
}

// ---- Inverse kinematics -----------------------------------------------------

std::string_view to_string(IkMethod method) {
  switch (method) {
    case IkMethod::Closed: return "closed";
    case IkMethod::Newton: return "newton";
  }
  return "unknown";
}

IkMethod parse_ik_method(std::string_view name) {
  for (IkMethod m : {IkMethod::Closed, IkMethod::Newton})
    if (name == to_string(m)) return m;
  throw std::invalid_argument("delta: unknown IK method '" + std::string(name) + "' (expected closed or newton)");
}

int branch_of(const Model& m, const Vector3d& q, const Vector3d& p) {
  require_finite(q, "actuator angles");
  require_finite(p, "platform position");
  int branch = 0;
  for (int i = 0; i < kLegCount; ++i) {
    const Vector3d s = p + m.r * leg_radial(i) - elbow_position(m, i, q(i));
    // dF_i/dq_i = -La s . elbow_motion > 0: the elbow is on the inner side.
    if (-m.La * s.dot(elbow_motion(i, q(i))) > 0.0) branch |= 1 << i;
  }
  return branch;
}

IkResult inverse(const Model& m, const Vector3d& p, IkMethod method, const IkOptions& options) {
  m.validate();
  require_finite(p, "IK target");
  require_branch(options.branch);
  check_options(options.max_iterations, options.tolerance);
  const double tol = kSingularTolerance * m.size();

  IkResult result;
  result.method = method;
  std::array<LegCoordinates, kLegCount> coords;
  bool unreachable = false, singular = false;
  for (int i = 0; i < kLegCount; ++i) {
    coords[i] = leg_coordinates(m, i, p);
    const LegSolution s = solve_leg(m, coords[i], (options.branch >> i) & 1, tol);
    result.leg_status[i] = s.status;
    result.q_actuated(i) = s.q;
    unreachable = unreachable || s.status == Status::Unreachable;
    singular = singular || s.status == Status::Singular;
  }
  result.branch = options.branch;

  if (method == IkMethod::Newton && !unreachable) {
    Vector3d seed = home_pose(m);
    if (options.seed) {
      require_finite(*options.seed, "IK seed");
      seed = *options.seed;
    }
    for (int i = 0; i < kLegCount; ++i) {
      const LegNewton n = newton_leg(m, coords[i], seed(i), options.max_iterations);
      result.q_actuated(i) = n.q;
      result.iterations = std::max(result.iterations, n.iterations);
    }
    result.branch = branch_of(m, result.q_actuated, p);
  }

  result.residual = closure_error(m, result.q_actuated, p);
  const bool closed = result.residual <= options.tolerance * m.size();
  if (!result.q_actuated.allFinite() || !std::isfinite(result.residual)) {
    result.q_actuated.setZero();
    result.residual = closure_error(m, result.q_actuated, p);
    result.status = unreachable ? Status::Unreachable : Status::NotConverged;
  } else if (unreachable) {
    result.status = Status::Unreachable;
  } else if (singular) {
    result.status = Status::Singular;  // Newton slows to a crawl at the double root
  } else if (!closed) {
    result.status = Status::NotConverged;
  } else {
    result.status = within_ranges(m, result.q_actuated) ? Status::Ok : Status::OutOfLimits;
  }
  return result;
}

// ---- Forward kinematics -----------------------------------------------------

std::string_view to_string(FkMethod method) {
  switch (method) {
    case FkMethod::Closed: return "closed";
    case FkMethod::Newton: return "newton";
  }
  return "unknown";
}

FkMethod parse_fk_method(std::string_view name) {
  for (FkMethod m : {FkMethod::Closed, FkMethod::Newton})
    if (name == to_string(m)) return m;
  throw std::invalid_argument("delta: unknown FK method '" + std::string(name) + "' (expected closed or newton)");
}

FkResult forward(const Model& m, const Vector3d& q, FkMethod method, const FkOptions& options) {
  m.validate();
  require_finite(q, "actuator angles");
  check_options(options.max_iterations, options.tolerance);
  const double tol = kSingularTolerance * m.size();
  const Spheres sp = spheres_of(m, q);

  FkResult result;
  result.method = method;
  result.p_base_platform = result.p_other_mode = sp.circumcentre;
  if (sp.degenerate) {
    // Coincident centres leave a circle or sphere of solutions; distinct
    // collinear centres of equal spheres have no common point.
    double closest = kInf;
    for (int i = 0; i < kLegCount; ++i) closest = std::min(closest, (sp.c[i] - sp.c[(i + 1) % 3]).norm());
    result.status = closest <= tol ? Status::Singular : Status::Unreachable;
    // Coincident centres (every forearm parallel): the platform anywhere on
    // the sphere of radius Lb about them; the point below them, which closes
    // every leg, stands for it.
    if (result.status == Status::Singular) {
      result.p_base_platform = sp.circumcentre - m.Lb * Vector3d::UnitZ();
      result.p_other_mode = sp.circumcentre + m.Lb * Vector3d::UnitZ();
    }
    result.residual = closure_error(m, q, result.p_base_platform);
    return result;
  }
  if (sp.gap < -tol) {
    result.status = Status::Unreachable;
    result.residual = closure_error(m, q, result.p_base_platform);
    return result;
  }
  const bool singular = sp.gap <= tol;

  if (method == FkMethod::Closed) {
    const double circumradius = m.Lb - sp.gap;
    const double height = std::sqrt(std::max(0.0, sp.gap * (m.Lb + circumradius)));
    result.p_base_platform = sp.circumcentre - height * sp.normal;
    result.p_other_mode = sp.circumcentre + height * sp.normal;
  } else {
    Vector3d p = home_position(m);
    if (options.seed) {
      require_finite(*options.seed, "FK seed");
      p = *options.seed;
    }
    auto closure = [&](const Vector3d& x) {
      Vector3d f;
      for (int i = 0; i < kLegCount; ++i) f(i) = 0.5 * ((x - sp.c[i]).squaredNorm() - m.Lb * m.Lb);
      return f;
    };
    const double stop = 1e-15 * m.size() * m.Lb;  // on |f|, as in newton_leg
    Vector3d f = closure(p);
    int it = 0;
    for (; it < options.max_iterations && f.lpNorm<Eigen::Infinity>() > stop; ++it) {
      const Vector3d s0 = p - sp.c[0], s1 = p - sp.c[1], s2 = p - sp.c[2];
      const double det = s0.dot(s1.cross(s2));
      if (det == 0.0) break;  // type II at the iterate
      Matrix3d inverse_Jx;
      inverse_Jx << s1.cross(s2), s2.cross(s0), s0.cross(s1);
      const Vector3d step = -(inverse_Jx * f) / det;
      double t = 1.0;
      bool improved = false;
      for (int k = 0; k < 30; ++k, t *= 0.5) {
        const Vector3d trial = p + t * step;
        const Vector3d ft = closure(trial);
        if (ft.lpNorm<Eigen::Infinity>() < f.lpNorm<Eigen::Infinity>()) {
          p = trial;
          f = ft;
          improved = true;
          break;
        }
      }
      if (!improved) break;
    }
    result.iterations = it;
    result.p_base_platform = p;
    const double h = (p - sp.c[0]).dot(sp.normal);
    result.p_other_mode = p - 2.0 * h * sp.normal;
    result.assembly_mode = h < 0.0 ? 0 : 1;
  }

  result.residual = closure_error(m, q, result.p_base_platform);
  const bool closed = result.residual <= options.tolerance * m.size();
  if (!result.p_base_platform.allFinite() || !std::isfinite(result.residual)) {
    result.p_base_platform = result.p_other_mode = sp.circumcentre;
    result.residual = closure_error(m, q, result.p_base_platform);
    result.status = Status::NotConverged;
  } else if (singular) {
    result.status = Status::Singular;
  } else if (!closed) {
    result.status = Status::NotConverged;
  } else {
    result.status = within_ranges(m, q) ? Status::Ok : Status::OutOfLimits;
  }
  return result;
}

// ---- Jacobian -----------------------------------------------------------------

JacobianResult jacobian(const Model& m, const Vector3d& q, const Vector3d& p) {
  m.validate();
  require_closure(m, q, p, "jacobian");
  const double tol = kSingularTolerance * m.size();
  JacobianResult r;
  std::array<Vector3d, kLegCount> s;
  bool serial = false;
  for (int i = 0; i < kLegCount; ++i) {
    s[i] = p + m.r * leg_radial(i) - elbow_position(m, i, q(i));
    r.Jx.row(i) = s[i].transpose();
    r.Jq_diagonal(i) = -m.La * s[i].dot(elbow_motion(i, q(i)));
    serial = serial || r.Jq_diagonal(i) == 0.0 || std::abs(leg_margin(m, i, p)) <= tol;
  }
  r.det_Jx = s[0].dot(s[1].cross(s[2]));
  r.det_Jq = r.Jq_diagonal.prod();
  const Spheres sp = spheres_of(m, q);
  const bool parallel = r.det_Jx == 0.0 || sp.degenerate || sp.gap <= tol;

  if (r.det_Jx != 0.0) {
    // Jx^-1 has columns (s1 x s2, s2 x s0, s0 x s1) / det Jx; J = -Jx^-1 Jq.
    r.J_task_from_actuated << s[1].cross(s[2]), s[2].cross(s[0]), s[0].cross(s[1]);
    r.J_task_from_actuated *= (-r.Jq_diagonal).asDiagonal();
    r.J_task_from_actuated /= r.det_Jx;
    r.det_J = -r.det_Jq / r.det_Jx;
  }
  if (r.det_Jq != 0.0) {
    for (int i = 0; i < kLegCount; ++i) r.J_actuated_from_task.row(i) = -r.Jx.row(i) / r.Jq_diagonal(i);
  }
  if (serial || parallel) {
    r.status = Status::Singular;
    r.cond = kInf;
  } else {
    // cond(J) = cond(J^-1), and J^-1 stays finite up to type II. Beyond
    // kSingularCondition the rounding of the pose decides its digits: every
    // forearm parallel (coincident sphere centres) passes the gap's test.
    r.cond = condition_number_closed_form(r.J_actuated_from_task);
    r.status = r.cond <= kSingularCondition ? Status::Ok : Status::Singular;
    if (r.status == Status::Singular) r.cond = kInf;
  }
  return r;
}

JacobianResult jacobian(const Model& m, const Vector3d& q) {
  const FkResult fk = forward(m, q);
  if (fk.status == Status::Unreachable || fk.status == Status::NotConverged) {
    JacobianResult r;
    r.status = fk.status;
    return r;
  }
  return jacobian(m, q, fk.p_base_platform);
}

Matrix3d jacobian_central_difference(const Model& m, const Vector3d& q, double step) {
  Matrix3d J;
  for (int k = 0; k < 3; ++k) {
    Vector3d dq = Vector3d::Zero();
    dq(k) = step;
    const FkResult plus = forward(m, q + dq), minus = forward(m, q - dq);
    for (const FkResult* f : {&plus, &minus})
      if (f->status == Status::Unreachable || f->status == Status::NotConverged)
        throw std::invalid_argument("delta: central difference step leaves the workspace at q = " + format_vector(q));
    J.col(k) = (plus.p_base_platform - minus.p_base_platform) / (2.0 * step);
  }
  return J;
}

// ---- Singular sets ------------------------------------------------------------

std::string_view to_string(SingularSet set) {
  switch (set) {
    case SingularSet::Leg1Serial: return "leg-1-serial";
    case SingularSet::Leg2Serial: return "leg-2-serial";
    case SingularSet::Leg3Serial: return "leg-3-serial";
    case SingularSet::Parallel: return "parallel";
  }
  return "unknown";
}

SingularityReport nearest_singularity(const Model& m, const Vector3d& q, const Vector3d& p) {
  m.validate();
  require_closure(m, q, p, "nearest_singularity");
  SingularityReport report;
  std::array<Vector3d, kLegCount> unit_forearm;
  for (int i = 0; i < kLegCount; ++i) {
    report.distances[i] = std::abs(leg_margin(m, i, p));
    const Vector3d s = p + m.r * leg_radial(i) - elbow_position(m, i, q(i));
    unit_forearm[i] = s.normalized();
    report.serial_index[i] = std::abs(unit_forearm[i].dot(elbow_motion(i, q(i))));
  }
  const Spheres sp = spheres_of(m, q);
  report.distances[3] = sp.degenerate ? 0.0 : std::abs((p - sp.c[0]).dot(sp.normal));
  report.parallel_index = std::abs(unit_forearm[0].dot(unit_forearm[1].cross(unit_forearm[2])));
  const auto it = std::min_element(report.distances.begin(), report.distances.end());
  report.nearest = static_cast<SingularSet>(it - report.distances.begin());
  report.distance = *it;
  return report;
}

SingularityReport nearest_singularity(const Model& m, const Vector3d& q) {
  const FkResult fk = forward(m, q);
  if (fk.status == Status::Unreachable || fk.status == Status::NotConverged)
    throw std::invalid_argument("delta: nearest_singularity: no platform position for q = " + format_vector(q));
  return nearest_singularity(m, q, fk.p_base_platform);
}

// ---- Reach margin and home ----------------------------------------------------

ReachMargin reach_margin(const Model& m, const Vector3d& p, int branch) {
  m.validate();
  require_finite(p, "platform position");
  require_branch(branch);
  ReachMargin r;
  r.geometric = kInf;
  for (int i = 0; i < kLegCount; ++i) {
    // Beyond reach the closest-approach angle, which the branch's angle
    // meets on the boundary: the margin stays continuous.
    const LegSolution s = solve_leg(m, leg_coordinates(m, i, p), (branch >> i) & 1, 0.0);
    r.geometric = std::min(r.geometric, s.margin);
    r.limits = std::min(r.limits, m.La * range_margin(m.q_limits[i], s.q));
  }
  r.value = std::min(r.geometric, r.limits);
  return r;
}

Vector3d home_position(const Model& m) {
  m.validate();
  const double offset = m.R - m.r, rho = std::max(m.La, m.Lb);
  return {0.0, 0.0, -std::sqrt(std::max(0.0, rho * rho - offset * offset))};
}

Vector3d home_pose(const Model& m) {
  const Vector3d p = home_position(m);
  Vector3d q;
  for (int i = 0; i < kLegCount; ++i)
    q(i) = solve_leg(m, leg_coordinates(m, i, p), false, kSingularTolerance * m.size()).q;
  return q;
}

// ---- Field kernel -------------------------------------------------------------

FieldLegs field_legs(const Model& m) {
  m.validate();
  FieldLegs legs;
  for (int i = 0; i < kLegCount; ++i) {
    legs.cos_phi[i] = std::cos(leg_angle(i));
    legs.sin_phi[i] = std::sin(leg_angle(i));
    const Interval& range = m.q_limits[i];
    const double centre = 0.5 * (range.lo + range.hi), half_width = 0.5 * (range.hi - range.lo);
    legs.cos_centre[i] = std::cos(centre);
    legs.sin_centre[i] = std::sin(centre);
    legs.cos_half_width[i] = std::cos(half_width);
    legs.sin_half_width[i] = std::sin(half_width);
  }
  return legs;
}

}  // namespace linkscape::delta
