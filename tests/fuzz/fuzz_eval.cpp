// Fuzz target for the `eval` paths: rows of numbers through the 12R IK (every
// method) and FK, and the PATHOS-II pose IK and numerical FK, with the
// presets' models. The input is CSV as `linkscape eval` reads it; the header
// picks what runs (every group whose columns are all present):
//
//   x,y,z                   12R IK, each of paper, planar, newton, dls, fallback
//   alpha,beta,gamma        12R FK, conditioning, and IK of the FK (round trip)
//   x,y,z,rx,ry,rz,h0       PATHOS-II pose IK, Jacobian, numerical and nine-sensor FK
//   q1,q2,q3,q4,q5,q6,h0    PATHOS-II numerical FK, tracking row to row as eval does
//   device,<task names>     any registered device through the Mechanism interface (the
//   device,<actuator names>   code `eval` runs): IK by each method, FK by each method;
//                           `device` picks registered_mechanisms()[device mod count], and
//                           columns named after its design parameters change its model
//
// Optional columns change a row's model (12R: L1, L2; PATHOS-II: any preset
// parameter name but h0, which is the pose's grip) or the 12R IK options (seed_alpha, seed_beta, seed_gamma,
// tolerance, max_iterations).
//
// What a user relies on, checked against independent computations (long
// double 12R forward, the PATHOS-II frames rebuilt from the conventions in
// core/mechanisms/pathos2/pathos2.h, finite differences): no crash; std::invalid_argument exactly
// for the inputs the headers name; statuses valid; an Ok IK solution's forward
// is within the tolerance of the target and inside the actuator limits; no
// NaN in a result with status Ok.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <memory>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "core/conditioning.h"
#include "core/csv.h"
#include "core/mechanism.h"
#include "core/mechanisms/parallel12r/mechanism.h"
#include "core/mechanisms/pathos2/pathos2.h"
#include "core/preset.h"
#include "fuzz_check.h"

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using linkscape::Status;
using linkscape::Table;
namespace p12 = linkscape::parallel12r;
namespace p2 = linkscape::pathos2;
constexpr double kPi = std::numbers::pi;
// Core reduces angles with std::remainder(a, fl(2 pi)), which drifts from the
// true angle by |a| (2 pi - fl(2 pi)) / (2 pi) < 4e-17 |a|: nothing at a few
// turns, the whole circle at 1e16 rad. Checks that compare angles allow it.
constexpr double kReductionDrift = 4e-17;

// Rows per group: enough to chain FK tracking, few enough for speed.
constexpr std::size_t kMaxRows = 16;

bool valid(Status s) { return static_cast<int>(s) >= 0 && static_cast<int>(s) <= static_cast<int>(Status::OutOfLimits); }

double wrap(double a) {
  a = std::remainder(a, 2.0 * kPi);
  return a <= -kPi ? a + 2.0 * kPi : a;
}

// |a - b| as an angle in [0, pi], from sines and cosines: exact even for huge
// angles, where remainder(a - b, fl(2 pi)) drifts by (a / 2 pi)(2 pi - fl(2 pi)).
double angle_between(double a, double b) {
  const double sa = std::sin(a), ca = std::cos(a), sb = std::sin(b), cb = std::cos(b);
  return std::abs(std::atan2(sa * cb - ca * sb, ca * cb + sa * sb));
}

std::optional<std::size_t> find_column(const Table& t, const std::string& name) {
  for (std::size_t i = 0; i < t.columns.size(); ++i)
    if (t.columns[i] == name) return i;
  return std::nullopt;
}

struct Presets {
  p12::Model r12;
  std::map<std::string, double> pathos2_parameters;
};

// The models `eval` uses by default, read once.
const Presets& presets() {
  static const Presets p = [] {
    Presets out;
    out.r12 = linkscape::make_parallel12r(linkscape::load_preset("parallel-12r"));
    out.pathos2_parameters = linkscape::load_preset("pathos2").parameters;
    return out;
  }();
  return p;
}

// ---- 12R ---------------------------------------------------------------------

// Endpoint D = L1 u(a, b) + L2 u(a, g) of core/mechanisms/parallel12r/parallel12r.h in long double,
// u = (-sin a cos t, cos a cos t, cos a sin t) / sqrt(cos^2 a + sin^2 a cos^2 t).
Eigen::Matrix<long double, 3, 1> forward_long(const p12::Model& m, const Vector3d& q) {
  const long double sa = std::sin(static_cast<long double>(q.x())), ca = std::cos(static_cast<long double>(q.x()));
  auto u = [&](double t_double) {
    const long double t = t_double, st = std::sin(t), ct = std::cos(t);
    const long double d = std::sqrt(ca * ca + sa * sa * ct * ct);
    return Eigen::Matrix<long double, 3, 1>(-sa * ct / d, ca * ct / d, ca * st / d);
  };
  return static_cast<long double>(m.L1) * u(q.y()) + static_cast<long double>(m.L2) * u(q.z());
}

double distance_long(const p12::Model& m, const Vector3d& q, const Vector3d& p) {
  return static_cast<double>((forward_long(m, q) - p.cast<long double>()).norm());
}

// Largest angle difference between an IK solution (angles within a turn) and
// any q, allowing the other representation of the same pose, (a + pi, b + pi, g + pi).
double angle_distance(const Vector3d& solution, const Vector3d& q) {
  double same = 0.0, other = 0.0;
  for (int k = 0; k < 3; ++k) {
    same = std::max(same, angle_between(solution(k), q(k)));
    other = std::max(other, angle_between(solution(k) + kPi, q(k)));
  }
  return std::min(same, other);
}

bool inside_limits(const p12::Model& m, const Vector3d& q) {
  return m.alpha_limits.contains(q.x()) && m.beta_limits.contains(q.y()) && m.gamma_limits.contains(q.z());
}

constexpr std::array kMethods = {p12::IkMethod::Paper, p12::IkMethod::Planar, p12::IkMethod::Newton,
                                 p12::IkMethod::DampedLeastSquares, p12::IkMethod::Fallback};

void check_ik_result(const p12::Model& m, const Vector3d& p, p12::IkMethod method, const p12::IkOptions& o,
                     const p12::IkResult& r) {
  const std::string where = std::string(p12::to_string(method)) + " IK of (" + std::to_string(p.x()) + ", " +
                            std::to_string(p.y()) + ", " + std::to_string(p.z()) + ")";
  FUZZ_CHECK(valid(r.status), where << ": status " << static_cast<int>(r.status));
  FUZZ_CHECK(r.solutions.size() <= 2, where << ": " << r.solutions.size() << " solutions");
  bool any_ok = false;
  int previous_branch = -1;
  for (const p12::IkSolution& s : r.solutions) {
    FUZZ_CHECK(valid(s.status), where << ": solution status " << static_cast<int>(s.status));
    FUZZ_CHECK(s.branch > previous_branch && s.branch <= 1, where << ": branch " << s.branch << " after " << previous_branch);
    previous_branch = s.branch;
    FUZZ_CHECK(s.q_actuated.allFinite(), where << ": q " << s.q_actuated.transpose());
    FUZZ_CHECK(s.branch == p12::branch_of(s.q_actuated), where << ": branch " << s.branch << " of q " << s.q_actuated.transpose());
    FUZZ_CHECK(s.residual >= 0.0, where << ": residual " << s.residual);  // also rejects NaN
    if (method == p12::IkMethod::Fallback)
      FUZZ_CHECK(s.method == p12::IkMethod::Planar || s.method == p12::IkMethod::Newton, where << ": produced by " << p12::to_string(s.method));
    else
      FUZZ_CHECK(s.method == method, where << ": produced by " << p12::to_string(s.method));
    // planar is iteration-free; paper ends with one Newton step per branch.
    const int closed_form_steps = s.method == p12::IkMethod::Planar ? 0 : s.method == p12::IkMethod::Paper ? 1 : -1;
    FUZZ_CHECK(s.iterations >= 0 && s.iterations <= (closed_form_steps >= 0 ? closed_form_steps : o.max_iterations),
               where << ": " << s.iterations << " iterations");
    if (s.status != Status::Ok) continue;
    any_ok = true;
    // Within the tolerance, up to rounding of the long double reference.
    const double error = distance_long(m, s.q_actuated, p);
    FUZZ_CHECK(error <= o.tolerance * m.reach() + 1e-14 * (m.reach() + p.norm()),
               where << ": Ok solution " << s.q_actuated.transpose() << " misses the target by " << error
                     << " (tolerance " << o.tolerance * m.reach() << ", reported residual " << s.residual << ")");
    FUZZ_CHECK(inside_limits(m, s.q_actuated), where << ": Ok solution " << s.q_actuated.transpose() << " outside the actuator ranges");
  }
  FUZZ_CHECK(any_ok == (r.status == Status::Ok), where << ": status " << linkscape::to_string(r.status) << " but an Ok solution " << (any_ok ? "exists" : "does not exist"));
  // A target clearly outside the reach shell is Unreachable, whatever the method.
  const double radius = p.norm();
  if (radius > m.reach() * (1.0 + 1e-9) || radius < m.inner_reach() - 1e-9 * m.reach())
    FUZZ_CHECK(r.status == Status::Unreachable, where << ": |D| = " << radius << " outside [" << m.inner_reach() << ", "
                                                      << m.reach() << "] but status " << linkscape::to_string(r.status));
}

// The row's 12R model: the preset with L1, L2 from the row where given.
p12::Model r12_model(const Table& t, const std::vector<double>& row) {
  p12::Model m = presets().r12;
  if (const auto c = find_column(t, "L1")) m.L1 = row[*c];
  if (const auto c = find_column(t, "L2")) m.L2 = row[*c];
  return m;
}

bool model_valid(const p12::Model& m) {
  try {
    m.validate();
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

void run_12r_ik(const Table& t) {
  const auto cx = find_column(t, "x"), cy = find_column(t, "y"), cz = find_column(t, "z");
  if (!cx || !cy || !cz) return;
  const auto sa = find_column(t, "seed_alpha"), sb = find_column(t, "seed_beta"), sg = find_column(t, "seed_gamma");
  const auto ctol = find_column(t, "tolerance"), citer = find_column(t, "max_iterations");
  for (std::size_t r = 0; r < std::min(t.rows.size(), kMaxRows); ++r) {
    const auto& row = t.rows[r];
    const p12::Model m = r12_model(t, row);
    const Vector3d p(row[*cx], row[*cy], row[*cz]);
    p12::IkOptions o;
    if (sa && sb && sg) o.seed = Vector3d(row[*sa], row[*sb], row[*sg]);
    if (ctol) o.tolerance = row[*ctol];
    if (citer) {
      if (!(row[*citer] >= -5.0 && row[*citer] <= 200.0)) continue;  // keeps each input fast
      o.max_iterations = static_cast<int>(row[*citer]);
    }
    const bool must_throw = !model_valid(m) || !p.allFinite() || !(o.tolerance > 0.0) || o.max_iterations < 0;
    const bool may_throw = must_throw || (o.seed && !o.seed->allFinite());  // the seed is checked where used
    for (const p12::IkMethod method : kMethods) {
      p12::IkResult result;
      try {
        result = p12::inverse(m, p, method, o);
      } catch (const std::invalid_argument& e) {
        FUZZ_CHECK(may_throw, p12::to_string(method) << " IK threw for valid input: " << e.what());
        continue;
      }
      FUZZ_CHECK(!must_throw, p12::to_string(method) << " IK accepted a non-finite target, invalid model or options: target "
                                                      << p.transpose() << " L1 " << m.L1 << " L2 " << m.L2 << " tolerance "
                                                      << o.tolerance << " max_iterations " << o.max_iterations);
      check_ik_result(m, p, method, o, result);
    }
  }
}

void run_12r_fk(const Table& t) {
  const auto ca = find_column(t, "alpha"), cb = find_column(t, "beta"), cg = find_column(t, "gamma");
  if (!ca || !cb || !cg) return;
  for (std::size_t r = 0; r < std::min(t.rows.size(), kMaxRows); ++r) {
    const auto& row = t.rows[r];
    const p12::Model m = r12_model(t, row);
    if (!model_valid(m)) continue;  // presets reject it before eval runs
    const Vector3d q(row[*ca], row[*cb], row[*cg]);
    if (!q.allFinite()) {
      bool forward_threw = false, conditioning_threw = false;
      try { p12::forward(m, q); } catch (const std::invalid_argument&) { forward_threw = true; }
      try { p12::conditioning(m, q); } catch (const std::invalid_argument&) { conditioning_threw = true; }
      FUZZ_CHECK(forward_threw && conditioning_threw, "non-finite angles " << q.transpose() << " accepted");
      continue;
    }
    const Vector3d p = p12::forward(m, q);
    FUZZ_CHECK(p.allFinite(), "forward " << q.transpose() << " = " << p.transpose());
    const double scale = m.reach();
    FUZZ_CHECK(distance_long(m, q, p) <= 1e-12 * scale, "forward " << q.transpose() << " = " << p.transpose()
                                                                   << ", long double differs by " << distance_long(m, q, p));
    FUZZ_CHECK(p.norm() <= scale * (1 + 1e-12) && p.norm() >= m.inner_reach() - 1e-12 * scale,
               "|forward " << q.transpose() << "| = " << p.norm() << " outside [" << m.inner_reach() << ", " << scale << "]");
    const p12::Conditioning c = p12::conditioning(m, q);
    FUZZ_CHECK(c.cond >= 1.0 - 1e-12 && std::isfinite(c.det), "conditioning at " << q.transpose() << ": cond " << c.cond << " det " << c.det);
    const double cond_svd = linkscape::condition_number_svd(p12::jacobian(m, q));
    if (c.cond < 1e6)
      FUZZ_CHECK(std::abs(c.cond - cond_svd) <= 1e-6 * cond_svd, "cond at " << q.transpose() << ": closed form " << c.cond << ", SVD " << cond_svd);

    // Round trip, away from singular sets and with comparable links: the
    // planar and fallback IK find q again, and Newton and DLS seeded at q stay.
    const double ratio = m.L1 / m.L2;
    const bool well_posed = c.cond < 1e6 && cond_svd < 1e6 && ratio > 1e-3 && ratio < 1e3 &&
                            p12::nearest_singularity(m, q).distance > 1e-6 * scale;
    if (!well_posed) continue;
    const double angle_tolerance = 1e-9 * c.cond + 1e-12;
    for (const p12::IkMethod method : kMethods) {
      if (method == p12::IkMethod::Paper) continue;  // its accuracy is studied in docs/methods.md, not promised
      p12::IkOptions o;
      if (method == p12::IkMethod::Newton || method == p12::IkMethod::DampedLeastSquares) {
        // A seed reduced more than a tracking step away from q is another seed.
        if (kReductionDrift * q.cwiseAbs().maxCoeff() > 1e-9) continue;
        o.seed = q;
      }
      const p12::IkResult result = p12::inverse(m, p, method, o);
      check_ik_result(m, p, method, o, result);
      double best = kPi;
      for (const auto& s : result.solutions)
        if (s.status == Status::Ok) best = std::min(best, angle_distance(s.q_actuated, q));
      FUZZ_CHECK(best <= angle_tolerance, p12::to_string(method) << " IK of forward(" << q.transpose() << ") = "
                                                                 << p.transpose() << " (cond " << c.cond << "): status "
                                                                 << linkscape::to_string(result.status)
                                                                 << ", nearest Ok solution " << best << " rad away");
    }
  }
}

// ---- PATHOS-II ---------------------------------------------------------------

Matrix3d rot_x(double a) { return Eigen::AngleAxisd(a, Vector3d::UnitX()).toRotationMatrix(); }
Matrix3d rot_y(double a) { return Eigen::AngleAxisd(a, Vector3d::UnitY()).toRotationMatrix(); }
Matrix3d rot_z(double a) { return Eigen::AngleAxisd(a, Vector3d::UnitZ()).toRotationMatrix(); }

// The row's PATHOS-II model (preset values, then the row's parameter
// columns), or nothing if the preset validation would refuse it.
std::optional<p2::Model> pathos2_model(const Table& t, const std::vector<double>& row) {
  std::map<std::string, double> parameters = presets().pathos2_parameters;
  for (const std::string& name : p2::Model::parameter_names())
    if (name != "h0")  // the h0 column is the pose's grip
      if (const auto c = find_column(t, name)) parameters[name] = row[*c];
  try {
    return p2::Model::from_parameters(parameters);
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
}

// Size of the whole device (tolerances) and of a leg (steps that move the plate).
double length_scale(const p2::Model& m) {
  return m.l0 + m.lb + m.l1 + m.l2 + m.l3 + m.lp + m.h0 + std::abs(m.db) + std::abs(m.lx);
}
double leg_scale(const p2::Model& m) { return m.l1 + m.l2 + m.l3; }

double max_angle_between(const p2::Vector6d& a, const p2::Vector6d& b) {
  double worst = 0.0;
  for (int i = 0; i < p2::kLegCount; ++i) worst = std::max(worst, angle_between(a(i), b(i)));
  return worst;
}

double rotation_distance(const Matrix3d& a, const Matrix3d& b) { return (a - b).cwiseAbs().maxCoeff(); }

// Each Ok leg, rebuilt from the conventions in core/mechanisms/pathos2/pathos2.h: the chain
// B_i Rz(t1) Tz(l1) Ry(t2) Tz(l2) Rx(t3) Tz(l3) Rz(t4) Ry(t5) Rz(t6) ends at
// the attachment A_i of the pose, in position and orientation, within the
// joint limits.
void check_legs_close(const p2::Model& m, const p2::Pose& pose, const p2::PoseIkResult& ik, const std::string& where) {
  const double scale = length_scale(m) + pose.p_world_E.norm();
  for (int i = 0; i < p2::kLegCount; ++i) {
    const p2::LegSolution& leg = ik.legs[i];
    if (leg.status != Status::Ok) continue;
    const bool upper = i >= 3;
    const double theta_b1 = upper ? kPi : 0.0, k = i % 3;
    const Matrix3d R_around = rot_x(theta_b1) * rot_z(m.base_phase + 2.0 * kPi / 3.0 * k);
    const Matrix3d R_world_B = R_around * rot_y(m.tilt_sign * m.theta_t);
    const Vector3d p_world_B = Vector3d(0, 0, upper ? m.l0 : 0.0) +
                               R_around * (Vector3d(0, 0, m.db) + rot_y(m.tilt_sign * m.theta_t) * Vector3d(m.lx, 0, 0));
    const Vector3d p_B_end = rot_z(leg.t1) * (Vector3d(0, 0, m.l1) + rot_y(leg.t2) * (Vector3d(0, 0, m.l2) + rot_x(leg.t3) * Vector3d(0, 0, m.l3)));
    const Matrix3d R_world_end = R_world_B * rot_z(leg.t1) * rot_y(leg.t2) * rot_x(leg.t3) * rot_z(leg.t4) * rot_y(leg.t5) * rot_z(leg.t6);
    const Matrix3d R_E_plate = rot_x(theta_b1) * rot_z(m.plate_phase + 2.0 * kPi / 3.0 * k);
    const Vector3d p_E_A = rot_x(theta_b1) * Vector3d(0, 0, -pose.h0) + R_E_plate * Vector3d(m.lp, 0, 0);
    const Vector3d p_world_A = pose.p_world_E + pose.R_world_E * p_E_A;
    const Matrix3d R_world_A = pose.R_world_E * R_E_plate * rot_y(m.theta_g);
    const double miss = (p_world_B + R_world_B * p_B_end - p_world_A).norm();
    FUZZ_CHECK(miss <= 1e-9 * scale, where << ": leg " << i + 1 << " ends " << miss << " cm from its globular joint");
    FUZZ_CHECK((ik.p_world_globular[i] - p_world_A).norm() <= 1e-9 * scale, where << ": leg " << i + 1 << " reports globular centre "
                                                                              << ik.p_world_globular[i].transpose() << ", expected "
                                                                              << p_world_A.transpose());
    const double turn = rotation_distance(R_world_end, R_world_A);
    FUZZ_CHECK(turn <= 1e-9, where << ": leg " << i + 1 << " globular angles (" << leg.t4 << ", " << leg.t5 << ", " << leg.t6
                                   << ") miss the plate orientation by " << turn);
    FUZZ_CHECK(std::abs(leg.t2) <= m.t2_limit + 1e-9 && std::abs(leg.t3) <= m.t3_limit + 1e-9 && leg.t5 <= m.cone_limit + 1e-9,
               where << ": leg " << i + 1 << " Ok outside its limits: t2 " << leg.t2 << " t3 " << leg.t3 << " t5 " << leg.t5);
  }
}

// The pose IK of `pose` and what follows from it when it is Ok.
void check_pose(const p2::Model& m, const p2::Geometry& g, const p2::Pose& pose, const std::string& where) {
  const p2::PoseIkResult ik = p2::inverse(g, pose);
  FUZZ_CHECK(valid(ik.status), where << ": status " << static_cast<int>(ik.status));
  FUZZ_CHECK((ik.failing_leg == -1) == (ik.status == Status::Ok) && ik.failing_leg >= -1 && ik.failing_leg < p2::kLegCount,
             where << ": failing leg " << ik.failing_leg << " with status " << linkscape::to_string(ik.status));
  for (int i = 0; i < p2::kLegCount; ++i) {
    FUZZ_CHECK(valid(ik.legs[i].status), where << ": leg status " << static_cast<int>(ik.legs[i].status));
    FUZZ_CHECK(ik.q_active(i) == ik.legs[i].t1 || (std::isnan(ik.q_active(i)) && std::isnan(ik.legs[i].t1)), where << ": q_active");
    if (ik.failing_leg < 0 || i < ik.failing_leg) FUZZ_CHECK(ik.legs[i].status == Status::Ok, where << ": leg " << i + 1 << " before the failing one");
  }
  if (ik.failing_leg >= 0) FUZZ_CHECK(ik.legs[ik.failing_leg].status == ik.status, where << ": failing leg's status");

  // ActiveOnly: same angles and statuses, up to rounding of the cone test at its limit.
  const p2::PoseIkResult active = p2::inverse(g, pose, p2::IkDetail::ActiveOnly);
  for (int i = 0; i < p2::kLegCount; ++i) {
    const Status a = active.legs[i].status, b = ik.legs[i].status;
    const bool cone_rounding = m.cone_limit < kPi && (a == Status::Ok || a == Status::OutOfLimits) &&
                               (b == Status::Ok || b == Status::OutOfLimits);
    FUZZ_CHECK(a == b || cone_rounding, where << ": leg " << i + 1 << " ActiveOnly " << linkscape::to_string(a) << ", Full "
                                              << linkscape::to_string(b));
    if (a != Status::Unreachable)
      FUZZ_CHECK(active.q_active(i) == ik.q_active(i), where << ": leg " << i + 1 << " t1 ActiveOnly " << active.q_active(i)
                                                             << ", Full " << ik.q_active(i));
  }
  if (ik.status != Status::Ok) return;

  FUZZ_CHECK(ik.q_active.allFinite(), where << ": Ok with q_active " << ik.q_active.transpose());
  for (const auto& leg : ik.legs)
    FUZZ_CHECK(std::isfinite(leg.t2) && std::isfinite(leg.t3) && std::isfinite(leg.t4) && std::isfinite(leg.t5) &&
                   std::isfinite(leg.t6) && std::isfinite(leg.det),
               where << ": Ok leg with a non-finite angle");
  check_legs_close(m, pose, ik, where);

  const p2::JacobianResult J = p2::jacobian(g, pose, ik);
  FUZZ_CHECK(J.status == Status::Ok || J.status == Status::Singular, where << ": Jacobian status " << linkscape::to_string(J.status));
  FUZZ_CHECK(J.cond_p >= 1.0 - 1e-9 && J.cond_o >= 1.0 - 1e-9, where << ": cond_p " << J.cond_p << " cond_o " << J.cond_o);
  if (J.status != Status::Ok) return;
  const p2::Matrix6d& M = J.J_qdot_from_twist;
  FUZZ_CHECK(M.allFinite() && J.J_twist_from_qdot.allFinite(), where << ": Ok Jacobian not finite");
  const double product_error = (J.J_twist_from_qdot * M - p2::Matrix6d::Identity()).cwiseAbs().maxCoeff();
  FUZZ_CHECK(product_error <= 1e-8 * J.J_twist_from_qdot.norm() * M.norm(), where << ": J * J^-1 - I = " << product_error);

  // Legs well away from their singularity: the Jacobian against central
  // differences of the IK, numerical FK from a nearby seed, nine-sensor FK.
  double leg_measure = kPi;
  for (const auto& leg : ik.legs) leg_measure = std::min(leg_measure, std::abs(leg.det) / (m.l2 * (m.l2 + m.l3) * (m.l2 + m.l3)));
  const double scale = length_scale(m) + pose.p_world_E.norm();
  if (J.cond_p < 1e4 && J.cond_o < 1e4 && leg_measure > 1e-4) {
    // Central differences at h and h/2, extrapolated (Richardson) to cancel
    // the h^2 term, with h shrunk until the two agree: within a step of an
    // actuator's turning point (a leg near its limit) q(x) bends like a
    // square root and a difference at a fixed h misses by percents (found by
    // fuzzing; as h -> 0 the differences converge to the analytic column).
    const auto central = [&](int k, double h) -> std::optional<p2::Vector6d> {
      const p2::Vector6d step = p2::Vector6d::Unit(k) * h;
      const p2::PoseIkResult plus = p2::inverse(g, p2::step_pose(pose, step), p2::IkDetail::ActiveOnly);
      const p2::PoseIkResult minus = p2::inverse(g, p2::step_pose(pose, -step), p2::IkDetail::ActiveOnly);
      if (plus.status != Status::Ok || minus.status != Status::Ok) return std::nullopt;
      p2::Vector6d d;
      for (int i = 0; i < 6; ++i) d(i) = wrap(plus.q_active(i) - minus.q_active(i)) / (2.0 * h);
      return d;
    };
    for (int k = 0; k < 6; ++k) {
      const double column_scale = (k < 3 ? M.leftCols<3>() : M.rightCols<3>()).cwiseAbs().maxCoeff();
      std::optional<p2::Vector6d> difference;
      for (double h = k < 3 ? 1e-5 * leg_scale(m) : 1e-5; h >= 1e-9 * (k < 3 ? leg_scale(m) : 1.0); h /= 8) {
        const auto coarse = central(k, h), fine = central(k, h / 2);
        if (coarse && fine && (*fine - *coarse).cwiseAbs().maxCoeff() <= 1e-5 * column_scale) {
          difference = *fine + (*fine - *coarse) / 3.0;
          break;
        }
      }
      if (!difference) continue;  // no step resolves the column: nothing to compare
      const double error = (*difference - M.col(k)).cwiseAbs().maxCoeff();
      FUZZ_CHECK(error <= 1e-4 * column_scale, where << ": Jacobian column " << k << " " << M.col(k).transpose()
                                                     << ", central difference " << difference->transpose());
    }
  }
  if (J.cond_p < 100 && J.cond_o < 100 && leg_measure > 1e-2) {
    p2::Vector6d nudge;
    const double step = 1e-4 * leg_scale(m);
    nudge << step, -step, step, 1e-4, 1e-4, -1e-4;
    const p2::Pose seed = p2::step_pose(pose, nudge);
    const p2::PoseIkResult seed_ik = p2::inverse(g, seed, p2::IkDetail::ActiveOnly);
    if (seed_ik.status != Status::Unreachable && seed_ik.status != Status::Singular) {
      const p2::FkResult fk = p2::forward_numeric(g, ik.q_active, pose.h0, seed);
      FUZZ_CHECK(fk.status == Status::Ok, where << ": numerical FK from a nearby seed: " << linkscape::to_string(fk.status)
                                                << " after " << fk.iterations << " iterations, residual " << fk.residual);
      FUZZ_CHECK((fk.pose.p_world_E - pose.p_world_E).norm() <= 1e-6 * scale && rotation_distance(fk.pose.R_world_E, pose.R_world_E) <= 1e-6,
                 where << ": numerical FK from a nearby seed found another pose, p " << fk.pose.p_world_E.transpose());
    }
  }
  if (m.lp > 1e-3 * scale && pose.h0 > 1e-3 * scale) {
    const p2::FkResult fk = p2::forward_nine_sensors(g, p2::sensors_of(ik));
    FUZZ_CHECK(fk.status == Status::Ok, where << ": nine-sensor FK of a solved pose: " << linkscape::to_string(fk.status)
                                              << ", residual " << fk.residual);
    FUZZ_CHECK((fk.pose.p_world_E - pose.p_world_E).norm() <= 1e-6 * scale && rotation_distance(fk.pose.R_world_E, pose.R_world_E) <= 1e-6 &&
                   std::abs(fk.pose.h0 - pose.h0) <= 1e-6 * scale,
               where << ": nine-sensor FK found p " << fk.pose.p_world_E.transpose() << " h0 " << fk.pose.h0);
  }
}

void run_pathos2_ik(const Table& t) {
  const char* names[] = {"x", "y", "z", "rx", "ry", "rz", "h0"};
  std::array<std::size_t, 7> col{};
  for (int k = 0; k < 7; ++k) {
    const auto c = find_column(t, names[k]);
    if (!c) return;
    col[k] = *c;
  }
  for (std::size_t r = 0; r < std::min(t.rows.size(), kMaxRows); ++r) {
    const auto& row = t.rows[r];
    const auto m = pathos2_model(t, row);
    if (!m) continue;
    const p2::Geometry g = p2::make_geometry(*m);
    std::array<double, 7> v;
    for (int k = 0; k < 7; ++k) v[k] = row[col[k]];
    const bool must_throw = !std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }) || !(v[6] > 0.0);
    const p2::Pose pose = p2::Pose::from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
    std::ostringstream where;
    where << std::setprecision(17) << "pathos2 pose (" << v[0] << ", " << v[1] << ", " << v[2] << ", " << v[3] << ", " << v[4]
          << ", " << v[5] << ", h0 " << v[6] << ")";
    try {
      check_pose(*m, g, pose, where.str());
    } catch (const std::invalid_argument& e) {
      FUZZ_CHECK(must_throw, where.str() << ": threw " << e.what());
      continue;
    }
    FUZZ_CHECK(!must_throw, where.str() << ": accepted");
  }
}

void run_pathos2_fk(const Table& t) {
  const char* names[] = {"q1", "q2", "q3", "q4", "q5", "q6", "h0"};
  std::array<std::size_t, 7> col{};
  for (int k = 0; k < 7; ++k) {
    const auto c = find_column(t, names[k]);
    if (!c) return;
    col[k] = *c;
  }
  std::optional<p2::Pose> last;  // the previous row's pose, as eval tracks
  for (std::size_t r = 0; r < std::min(t.rows.size(), kMaxRows); ++r) {
    const auto& row = t.rows[r];
    const auto m = pathos2_model(t, row);
    if (!m) continue;
    const p2::Geometry g = p2::make_geometry(*m);
    p2::Vector6d q;
    for (int i = 0; i < 6; ++i) q(i) = row[col[i]];
    const double h0 = row[col[6]];
    p2::Pose seed = last ? *last : p2::home_pose(*m);
    seed.h0 = h0 > 0.0 ? h0 : seed.h0;
    const bool must_throw = !q.allFinite() || !(h0 > 0.0) || !std::isfinite(h0);
    std::ostringstream where;
    where << std::setprecision(17) << "pathos2 FK of q (" << q.transpose() << "), h0 " << h0;
    p2::FkResult fk;
    try {
      fk = p2::forward_numeric(g, q, h0, seed);
    } catch (const std::invalid_argument& e) {
      FUZZ_CHECK(must_throw, where.str() << ": threw " << e.what());
      last.reset();
      continue;
    }
    FUZZ_CHECK(!must_throw, where.str() << ": accepted");
    const p2::FkOptions options;
    FUZZ_CHECK(fk.status == Status::Ok || fk.status == Status::NotConverged, where.str() << ": status " << linkscape::to_string(fk.status));
    FUZZ_CHECK(!std::isnan(fk.residual) && fk.iterations >= 0 && fk.iterations <= options.max_iterations,
               where.str() << ": residual " << fk.residual << ", " << fk.iterations << " iterations");
    if (fk.status != Status::Ok) {
      last.reset();
      continue;
    }
    const p2::Pose& pose = fk.pose;
    FUZZ_CHECK(pose.p_world_E.allFinite() && pose.R_world_E.allFinite() && pose.h0 == h0 && pose.rpy().allFinite(),
               where.str() << ": Ok pose not finite or grip changed");
    FUZZ_CHECK(rotation_distance(pose.R_world_E.transpose() * pose.R_world_E, Matrix3d::Identity()) <= 1e-12 &&
                   pose.R_world_E.determinant() > 0.0,
               where.str() << ": Ok orientation is not a rotation");
    // The documented promise: never a pose whose actuator angles miss the tolerance.
    const p2::PoseIkResult ik = p2::inverse(g, pose);
    FUZZ_CHECK(ik.status != Status::Unreachable && ik.status != Status::Singular,
               where.str() << ": Ok pose has IK status " << linkscape::to_string(ik.status));
    const double miss = max_angle_between(ik.q_active, q);
    FUZZ_CHECK(miss <= options.tolerance + kReductionDrift * q.cwiseAbs().maxCoeff() + 1e-15, where.str() << ": Ok pose p (" << pose.p_world_E.transpose() << ") reproduces q only to "
                                                       << miss << " rad (tolerance " << options.tolerance << ")");
    last = pose;
  }
}


// ---- Every device, through the interface ------------------------------------

// The row's device: the registered one its `device` column picks, with the
// row's parameter columns applied; nothing if the preset checks refuse them.
std::shared_ptr<const linkscape::Mechanism> interface_device(const Table& t, const std::vector<double>& row, std::size_t device_col) {
  const std::vector<std::string> names = linkscape::registered_mechanisms();
  const double pick = row[device_col];
  if (!std::isfinite(pick) || pick < 0.0 || pick > 1e6) return nullptr;
  // The shipped presets, read once (a copy per row, as overrides change it).
  static const std::vector<linkscape::Preset> shipped = [&] {
    std::vector<linkscape::Preset> out;
    for (const std::string& name : names) out.push_back(linkscape::load_preset(name));
    return out;
  }();
  linkscape::Preset preset = shipped[std::size_t(pick) % shipped.size()];
  std::vector<std::string> overrides;
  for (const std::string& name : linkscape::parameter_names(preset))
    if (const auto c = find_column(t, name)) overrides.push_back(name + "=" + linkscape::format_number(row[*c]));
  try {
    linkscape::apply_overrides(preset, overrides);
    return linkscape::make_mechanism(preset);
  } catch (const std::invalid_argument&) {
    return nullptr;
  }
}

// The row's values of the named columns, or nothing if a column is missing.
std::optional<Eigen::VectorXd> named_values(const Table& t, const std::vector<double>& row,
                                            const std::vector<linkscape::Quantity>& quantities) {
  Eigen::VectorXd v(Eigen::Index(quantities.size()));
  for (std::size_t k = 0; k < quantities.size(); ++k) {
    const auto c = find_column(t, quantities[k].name);
    if (!c) return std::nullopt;
    v(Eigen::Index(k)) = row[*c];
  }
  return v;
}

void check_measures(const linkscape::Mechanism& m, const Eigen::VectorXd& q, const Eigen::VectorXd& x, const std::string& where) {
  const linkscape::Measures measures = m.measures(q, x);
  FUZZ_CHECK(valid(measures.status), where << ": measures status");
  FUZZ_CHECK(measures.values.size() == m.info().measures.size(), where << ": " << measures.values.size() << " measures");
  for (double v : measures.values) {
    FUZZ_CHECK(!std::isnan(v) && v >= 1.0 - 1e-9, where << ": measure " << v);
    if (measures.status == Status::Ok) FUZZ_CHECK(std::isfinite(v), where << ": Ok measures hold " << v);
  }
  FUZZ_CHECK(!std::isnan(measures.det), where << ": det is NaN");
}

void run_interface(const Table& t) {
  const auto device_col = find_column(t, "device");
  if (!device_col) return;
  for (std::size_t r = 0; r < std::min(t.rows.size(), kMaxRows); ++r) {
    const auto& row = t.rows[r];
    const auto m = interface_device(t, row, *device_col);
    if (!m) continue;
    const linkscape::MechanismInfo& info = m->info();
    const double size = m->size();
    FUZZ_CHECK(std::isfinite(size) && size > 0.0, info.name << ": size " << size);
    if (const auto x = named_values(t, row, info.task)) {
      const bool must_throw = !x->allFinite();
      for (const linkscape::NamedItem& method : info.ik_methods) {
        std::ostringstream where;
        where << std::setprecision(17) << info.name << " IK (" << method.name << ") of (" << x->transpose() << ")";
        linkscape::IkOptions options;
        options.method = method.name;
        linkscape::IkResult ik;
        try {
          ik = m->inverse(*x, options);
        } catch (const std::invalid_argument& e) {
          FUZZ_CHECK(must_throw, where.str() << ": threw " << e.what());
          continue;
        }
        FUZZ_CHECK(!must_throw, where.str() << ": accepted");
        FUZZ_CHECK(valid(ik.status), where.str() << ": status");
        bool any_ok = false;
        for (const linkscape::IkSolution& s : ik.solutions) {
          FUZZ_CHECK(valid(s.status) && !std::isnan(s.residual) && s.iterations >= 0, where.str() << ": solution status or residual");
          if (s.status != Status::Ok) continue;
          any_ok = true;
          FUZZ_CHECK(s.q.size() == Eigen::Index(info.actuators.size()) && s.q.allFinite(), where.str() << ": Ok q not finite");
          FUZZ_CHECK(s.residual <= options.tolerance * size, where.str() << ": Ok with residual " << s.residual);
          check_measures(*m, s.q, *x, where.str() + " branch " + std::to_string(s.branch));
        }
        FUZZ_CHECK(any_ok == (ik.status == Status::Ok), where.str() << ": overall status disagrees with the solutions");
      }
    }
    if (const auto q = named_values(t, row, info.actuators)) {
      const bool must_throw = !q->allFinite();
      for (const linkscape::NamedItem& method : info.fk_methods) {
        std::ostringstream where;
        where << std::setprecision(17) << info.name << " FK (" << method.name << ") of (" << q->transpose() << ")";
        linkscape::FkOptions options;
        options.method = method.name;
        linkscape::FkResult fk;
        try {
          fk = m->forward(*q, options);
        } catch (const std::invalid_argument& e) {
          FUZZ_CHECK(must_throw, where.str() << ": threw " << e.what());
          continue;
        }
        FUZZ_CHECK(!must_throw, where.str() << ": accepted");
        FUZZ_CHECK(valid(fk.status) && !std::isnan(fk.residual), where.str() << ": status or residual");
        if (fk.status != Status::Ok) continue;
        FUZZ_CHECK(fk.x.size() == Eigen::Index(info.task.size()) && fk.x.allFinite(), where.str() << ": Ok pose not finite");
        check_measures(*m, *q, fk.x, where.str());
        // The pose found gives the actuator values back: some IK branch lands
        // on q. Only for q within the travel: outside it a device may have
        // several actuator values per configuration (the 12R's (a + pi, b + pi,
        // g + pi) is (a, b, g)) and IK reports the one in the travel.
        bool in_travel = true;
        for (std::size_t k = 0; k < info.actuators.size(); ++k) in_travel = in_travel && info.actuators[k].range.contains((*q)(Eigen::Index(k)));
        if (!in_travel) continue;
        const linkscape::IkResult ik = m->inverse(fk.x);
        const linkscape::Measures measures = m->measures(*q, fk.x);
        if (measures.status != Status::Ok || measures.values.front() > 1e6) continue;  // IK of near-singular poses may pick a twin
        double closest = std::numeric_limits<double>::infinity();
        for (const linkscape::IkSolution& s : ik.solutions) {
          if (s.q.size() != q->size()) continue;
          double worst = 0.0;
          for (Eigen::Index k = 0; k < q->size(); ++k) worst = std::max(worst, angle_between(s.q(k), (*q)(k)));
          closest = std::min(closest, worst);
        }
        FUZZ_CHECK(closest <= 1e-6 + kReductionDrift * q->cwiseAbs().maxCoeff(),
                   where.str() << ": x (" << fk.x.transpose() << "), c " << measures.values.front()
                               << ": no IK branch gives q back (closest " << closest << " rad)");
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  presets();  // read before any input, outside the timing of the first one
  Table table;
  try {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    table = linkscape::read_csv(in, "fuzz.csv");
  } catch (const std::invalid_argument&) {
    return 0;  // the CSV target covers malformed text
  }
  run_12r_ik(table);
  run_12r_fk(table);
  run_pathos2_ik(table);
  run_pathos2_fk(table);
  run_interface(table);
  return 0;
}
