#include "core/stability.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

#include "core/conditioning.h"
#include "core/mechanisms/parallel12r/methods.h"
#include "core/mechanisms/pathos2/methods.h"

namespace linkscape::stability {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using parallel12r::IkMethod;
using parallel12r::Model;
constexpr double kPi = std::numbers::pi;
constexpr double kUnitRoundoff = 1.1102230246251565e-16;  // 2^-53
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A generic unit direction with y >= 0.3 and rho >= 0.4: away from the
// actuator plane and the z axis.
Vector3d generic_direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  for (;;) {
    const Vector3d d = Vector3d(u(rng), u(rng), u(rng));
    if (d.norm() < 0.2 || d.norm() > 1) continue;
    const Vector3d n = d.normalized();
    if (n.y() >= 0.3 && std::hypot(n.x(), n.y()) >= 0.4 && std::abs(n.z()) >= 0.2) return n;
  }
}

Vector3d planar_guess(const Model& m, const Vector3d& target, int branch) {
  parallel12r::IkOptions loose;
  loose.tolerance = 1e300;
  const parallel12r::IkResult r = parallel12r::inverse(m, target, IkMethod::Planar, loose);
  for (const auto& s : r.solutions)
    if (s.branch == branch) return s.q_actuated;
  return r.solutions.empty() ? parallel12r::home_pose(branch) : r.solutions.front().q_actuated;
}

}  // namespace

std::string_view to_string(SweepPath path) {
  switch (path) {
    case SweepPath::CosAlpha: return "cos-alpha";
    case SweepPath::BetaGamma: return "beta=gamma";
    case SweepPath::BetaGammaPi: return "beta=gamma+pi";
    case SweepPath::ZAxis: return "z-axis";
    case SweepPath::OuterSphere: return "outer-sphere";
    case SweepPath::InnerSphere: return "inner-sphere";
    case SweepPath::LegStretched: return "leg-stretched";
    case SweepPath::LegFolded: return "leg-folded";
    case SweepPath::LegElbow: return "leg-elbow";
    case SweepPath::Reach: return "reach-boundary";
    case SweepPath::ActuatedSingular: return "J-singular";
  }
  return "unknown";
}

bool is_joint_path(SweepPath path) {
  return path == SweepPath::BetaGamma || path == SweepPath::BetaGammaPi || path == SweepPath::LegStretched ||
         path == SweepPath::LegFolded || path == SweepPath::LegElbow;
}

SweepPoint sweep_point(const Model& m, SweepPath path, double eps, int base_point, unsigned seed) {
  m.validate();
  if (!(eps > 0) || !(eps < 1)) throw std::invalid_argument("sweep: expected 0 < eps < 1, got " + std::to_string(eps));
  std::mt19937_64 rng(seed * 1000003ULL + unsigned(path) * 101ULL + unsigned(base_point));
  std::uniform_real_distribution<double> unit(0, 1);
  const double R = m.reach(), r_in = m.inner_reach();
  const double shell = R - r_in;
  SweepPoint p;
  switch (path) {
    case SweepPath::CosAlpha: {
      // (x0, eps R, z0) with (x0, z0) well inside the shell and |x0| >= 0.3 R.
      for (;;) {
        const double radius = r_in + shell * (0.25 + 0.5 * unit(rng));
        const double phi = 2 * kPi * unit(rng);
        const Vector3d c(radius * std::cos(phi), 0, radius * std::sin(phi));
        if (std::abs(c.x()) >= 0.3 * R) {
          p.target = c + Vector3d(0, eps * R, 0);
          break;
        }
      }
      p.distance = p.target.y();
      break;
    }
    case SweepPath::BetaGamma:
    case SweepPath::BetaGammaPi: {
      // alpha in [-0.9, 0.9], beta generic; gamma = beta - eps (stretched)
      // or beta - pi + eps (folded); both have sin(beta - gamma) > 0: branch 0.
      const double alpha = -0.9 + 1.8 * unit(rng);
      const double beta = -2.5 + 5.0 * unit(rng);
      const double gamma = path == SweepPath::BetaGamma ? beta - eps : beta - kPi + eps;
      p.q_path = Vector3d(alpha, beta, gamma);
      p.target = parallel12r::forward(m, p.q_path);
      const double radius = p.target.norm();
      p.distance = path == SweepPath::BetaGamma ? R - radius : radius - r_in;
      return p;
    }
    case SweepPath::ZAxis: {
      const double theta = 0.3 + 2.5 * unit(rng);  // y > 0
      const double z = (r_in + shell * (0.2 + 0.6 * unit(rng))) * (unit(rng) < 0.5 ? -1 : 1);
      p.target = Vector3d(eps * R * std::cos(theta), eps * R * std::sin(theta), z);
      p.distance = eps * R;
      break;
    }
    case SweepPath::OuterSphere:
      p.target = (1 - eps) * R * generic_direction(rng);
      p.distance = eps * R;
      break;
    case SweepPath::InnerSphere:
      p.target = (r_in + eps * R) * generic_direction(rng);
      p.distance = eps * R;
      break;
    default:
      throw std::invalid_argument("sweep: " + std::string(to_string(path)) + " is a PATHOS-II path (run_pathos2_sweeps)");
  }
  p.q_path = planar_guess(m, p.target, 0);
  return p;
}

std::vector<SweepRow> run_stability_sweeps(const Model& m, const SweepOptions& o) {
  m.validate();
  if (!(o.eps_max > o.eps_min) || !(o.eps_min > 0) || !(o.eps_max < 1) || o.steps_per_decade < 1 ||
      o.base_points < 1)
    throw std::invalid_argument("sweep: expected 0 < eps_min < eps_max < 1, steps_per_decade >= 1, base_points >= 1");
  std::vector<double> eps_values;
  const double decades = std::log10(o.eps_max / o.eps_min);
  const int steps = int(std::lround(decades * o.steps_per_decade));
  for (int k = 0; k <= steps; ++k) eps_values.push_back(o.eps_max * std::pow(10.0, -double(k) / o.steps_per_decade));

  const std::pair<const char*, IkMethod> ik_methods[] = {
      {"paper", IkMethod::Paper},   {"planar", IkMethod::Planar},
      {"newton", IkMethod::Newton}, {"dls", IkMethod::DampedLeastSquares},
      {"fallback", IkMethod::Fallback},
  };
  const std::vector<std::pair<const char*, std::function<Matrix3d(const Vector3d&)>>> jacobians = {
      {"analytic", [&](const Vector3d& q) { return parallel12r::jacobian(m, q); }},
      {"central-difference",
       [&](const Vector3d& q) { return parallel12r::jacobian_central_difference(m, q, methods::kCentralDifferenceStep); }},
      {"forward-difference",
       [&](const Vector3d& q) { return methods::jacobian_forward_difference(m, q, methods::kForwardDifferenceStep); }},
      {"complex-step", [&](const Vector3d& q) { return methods::jacobian_complex_step(m, q); }},
  };
  const std::pair<const char*, double (*)(const Matrix3d&)> conditioners[] = {
      {"closed-form", &condition_number_closed_form},
      {"closed-form-fast", &condition_number_fast},
      {"svd", &condition_number_svd},
      {"normal-equations", &methods::condition_number_normal_equations},
  };

  std::vector<SweepRow> rows;
  for (SweepPath path : kAllPaths)
    for (int b = 0; b < o.base_points; ++b)
      for (double eps : eps_values) {
        const SweepPoint point = sweep_point(m, path, eps, b, o.seed);
        const methods::IkReference ref = methods::reference_ik(m, point.target, point.q_path);
        const auto& r0 = ref.branch[0] ? ref.branch[0] : ref.branch[1];
        SweepRow base;
        base.path = path;
        base.base_point = b;
        base.eps = eps;
        base.distance = point.distance;
        base.cond = std::numeric_limits<double>::infinity();
        double sigma_min = 0, backward = 0;
        Matrix3d J_ref = Matrix3d::Zero();
        if (r0) {
          J_ref = methods::reference_jacobian(m, r0->q_actuated);
          const Vector3d sv = methods::reference_singular_values(J_ref);
          sigma_min = sv(2);
          base.sigma_min = sigma_min;
          backward = methods::backward_error_scale(m, r0->q_actuated);
          base.cond = sv(2) > 0 ? sv(0) / sv(2) : std::numeric_limits<double>::infinity();
        }
        // IK.
        auto add_ik = [&](const std::string& name, IkMethod method, const parallel12r::IkOptions& options) {
          SweepRow row = base;
          row.family = "ik";
          row.method = name;
          // A backward-stable solver's error: the rounding of target, angles
          // and Eqs. 11-13 in double, divided by the smallest singular value.
          row.predicted = sigma_min > 0 ? kUnitRoundoff * backward / sigma_min : kNaN;
          const methods::IkMeasurement meas = methods::measure_ik(m, point.target, ref, method, options);
          row.status = meas.status;
          row.error = meas.status == Status::Ok ? meas.error : kNaN;
          row.residual = meas.residual;
          row.iterations = meas.iterations;
          rows.push_back(row);
        };
        for (const auto& [name, method] : ik_methods) add_ik(name, method, o.ik);
        {
          parallel12r::IkOptions near = o.ik;
          near.seed = (r0 ? r0->q_actuated : point.q_path) + Vector3d::Constant(1e-3);
          add_ik("newton-near", IkMethod::Newton, near);
        }
        // Jacobian and conditioning at the reference configuration.
        for (const auto& [name, fn] : jacobians) {
          SweepRow row = base;
          row.family = "jacobian";
          row.method = name;
          row.predicted = kNaN;
          row.status = r0 ? Status::Ok : Status::NotConverged;
          row.error = r0 ? (fn(r0->q_actuated) - J_ref).norm() / J_ref.norm() : kNaN;
          rows.push_back(row);
        }
        const Matrix3d J = r0 ? parallel12r::jacobian(m, r0->q_actuated) : Matrix3d::Zero();
        const Vector3d sv = methods::reference_singular_values(J);
        const double c_ref = sv(2) > 0 ? sv(0) / sv(2) : std::numeric_limits<double>::infinity();
        for (const auto& [name, fn] : conditioners) {
          SweepRow row = base;
          row.family = "conditioning";
          row.method = name;
          row.predicted = kUnitRoundoff * c_ref;
          const double c = fn(J);
          row.status = r0 && std::isfinite(c) ? Status::Ok : Status::Singular;
          row.error = row.status == Status::Ok ? std::abs(c - c_ref) / c_ref : kNaN;
          rows.push_back(row);
        }
      }
  return rows;
}

// ---- PATHOS-II ------------------------------------------------------------------

namespace {

using pathos2::Pose;
using pathos2::Vector6d;
using pathos2::Matrix6d;

Pose along(const Pose& home, const Vector6d& d, double s) {
  Pose p = home;
  p.p_world_E += s * d.head<3>();
  const Vector3d w = s * d.tail<3>();
  if (w.norm() > 0) p.R_world_E = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * home.R_world_E;
  return p;
}

// The first crossing along a direction: the IK failing (Reach) or det M
// changing sign with all legs Ok (ActuatedSingular). 0 if the other comes first.
double first_crossing(const pathos2::Geometry& g, const Pose& home, const Vector6d& d, SweepPath path) {
  auto state = [&](double s, double& det) {
    const Pose p = along(home, d, s);
    const pathos2::PoseIkResult ik = pathos2::inverse(g, p, pathos2::IkDetail::ActiveOnly);
    if (ik.status != Status::Ok) return false;
    det = pathos2::jacobian(g, p, ik).J_qdot_from_twist.determinant();
    return true;
  };
  double det0 = 0;
  if (!state(0, det0)) return 0;
  double lo = 0, hi = 0;
  for (double s = 0.05;; s += 0.05) {
    if (s > 60) return 0;
    double det = 0;
    const bool ok = state(s, det);
    if (!ok || !std::isfinite(det)) {
      if (path != SweepPath::Reach) return 0;
      hi = s;
      break;
    }
    if (det * det0 < 0) {
      if (path != SweepPath::ActuatedSingular) return 0;
      hi = s;
      break;
    }
    lo = s;
  }
  for (int k = 0; k < 200 && hi - lo > 4e-16 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    double det = 0;
    const bool ok = state(mid, det);
    const bool before = path == SweepPath::Reach ? ok : (ok && det * det0 > 0);
    (before ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

std::vector<SweepRow> run_pathos2_sweeps(const pathos2::Model& model, const SweepOptions& o) {
  if (!(o.eps_max > o.eps_min) || !(o.eps_min > 0) || !(o.eps_max < 1) || o.steps_per_decade < 1 ||
      o.base_points < 1)
    throw std::invalid_argument("sweep: expected 0 < eps_min < eps_max < 1, steps_per_decade >= 1, base_points >= 1");
  const pathos2::Geometry g = pathos2::make_geometry(model);
  const pathos2::Model& m = g.model;
  const double L = m.l2 + m.l3;
  std::vector<double> eps_values;
  const int steps = int(std::lround(std::log10(o.eps_max / o.eps_min) * o.steps_per_decade));
  for (int k = 0; k <= steps; ++k) eps_values.push_back(o.eps_max * std::pow(10.0, -double(k) / o.steps_per_decade));
  const Pose home = pathos2::home_pose(m);
  const pathos2::PoseIkResult home_ik = pathos2::inverse(g, home);
  std::vector<SweepRow> rows;

  for (SweepPath path : kPathos2Paths) {
    std::mt19937_64 rng(o.seed * 1000003ULL + unsigned(path) * 101ULL);
    std::uniform_real_distribution<double> unit(0, 1);
    std::normal_distribution<double> normal;
    if (is_joint_path(path)) {
      for (int b = 0; b < o.base_points; ++b) {
        const double t1 = -kPi + 2 * kPi * unit(rng);
        const double t2 = 0.3 + 2.2 * unit(rng), t3 = -(0.3 + 2.2 * unit(rng));
        for (double eps : eps_values) {
          const Vector3d t = path == SweepPath::LegStretched ? Vector3d(t1, t2, -eps)
                             : path == SweepPath::LegFolded  ? Vector3d(t1, t2, -(kPi - eps))
                                                             : Vector3d(t1, eps, t3);
          const Vector3d a = pathos2::leg_forward(m.l1, m.l2, m.l3, t.x(), t.y(), t.z());
          const pathos2_methods::LegReference ref = pathos2_methods::reference_leg_inverse(m.l1, m.l2, m.l3, a, t);
          const Vector3d t_ref(double(ref.t[0]), double(ref.t[1]), double(ref.t[2]));
          SweepRow base;
          base.mechanism = "pathos2";
          base.path = path;
          base.base_point = b;
          base.eps = eps;
          const double rho = (a - Vector3d(0, 0, m.l1)).norm();
          base.distance = path == SweepPath::LegStretched ? L - rho
                          : path == SweepPath::LegFolded  ? rho - std::abs(m.l2 - m.l3)
                                                          : std::abs(std::sin(t.y()) * (m.l2 + m.l3 * std::cos(t.z())));
          const Matrix3d J = pathos2_methods::leg_jacobian(m.l1, m.l2, m.l3, t_ref);
          const Vector3d sv = methods::reference_singular_values(J);
          base.sigma_min = sv(2);
          base.cond = sv(2) > 0 ? sv(0) / sv(2) : std::numeric_limits<double>::infinity();
          base.family = "ik";
          base.predicted = ref.converged && sv(2) > 0 ? kUnitRoundoff * (m.l1 + L + kPi * J.norm()) / sv(2) : kNaN;
          const int branch = -std::sin(t.z()) >= 0 ? 1 : -1;
          auto add = [&](const char* name, Status status, const Vector3d& q, double residual, int iterations) {
            SweepRow row = base;
            row.method = name;
            row.status = status;
            row.error = status == Status::Ok && ref.converged ? pathos2_methods::leg_joint_error(q, ref) : kNaN;
            row.residual = residual;
            row.iterations = iterations;
            rows.push_back(row);
          };
          const pathos2::LegSolution closed = pathos2::leg_inverse(m.l1, m.l2, m.l3, a, branch);
          add("closed-form", closed.status, Vector3d(closed.t1, closed.t2, closed.t3),
              (pathos2::leg_forward(m.l1, m.l2, m.l3, closed.t1, closed.t2, closed.t3) - a).norm(), 0);
          const auto& h = home_ik.legs[0];
          const auto newton =
              pathos2_methods::leg_inverse_newton(m.l1, m.l2, m.l3, a, branch, Vector3d(h.t1, h.t2, h.t3));
          add("newton", newton.status, newton.t, newton.residual, newton.iterations);
          // 1e-3 rad off, never onto the singular set itself (t3 = 0 or pi, t2 = 0).
          const auto near =
              pathos2_methods::leg_inverse_newton(m.l1, m.l2, m.l3, a, branch, t_ref + Vector3d(1e-3, 1e-3, -1e-3));
          add("newton-near", near.status, near.t, near.residual, near.iterations);
        }
      }
      continue;
    }
    // Pose paths: seeded directions whose first crossing is of this kind.
    int found = 0;
    for (int attempt = 0; attempt < 400 && found < o.base_points; ++attempt) {
      Vector6d d;
      for (int k = 0; k < 6; ++k) d(k) = normal(rng);
      d.tail<3>() *= 0.1;
      d.normalize();
      const double s_star = first_crossing(g, home, d, path);
      if (!(s_star > 0)) continue;
      const int b = found++;
      for (double eps : eps_values) {
        const Pose P = along(home, d, s_star * (1 - eps));
        SweepRow base;
        base.mechanism = "pathos2";
        base.path = path;
        base.base_point = b;
        base.eps = eps;
        base.distance = s_star * eps;
        base.cond = std::numeric_limits<double>::infinity();
        const pathos2::PoseIkResult ik = pathos2::inverse(g, P);
        const pathos2::JacobianResult jr = pathos2::jacobian(g, P, ik);
        Matrix6d J_ref;
        const bool have_ref = ik.status == Status::Ok && pathos2_methods::reference_jacobian(g, P, J_ref);
        double scaled_norm = 0, m_norm = 0, cond_J = std::numeric_limits<double>::infinity();
        if (have_ref) {
          const Eigen::Matrix<long double, 6, 6> JL = J_ref.cast<long double>();
          const auto sv = Eigen::JacobiSVD<Eigen::Matrix<long double, 6, 6>>(JL).singularValues();
          cond_J = double(sv(0) / sv(5));
          Matrix6d SJ = J_ref;
          SJ.topRows<3>() /= L;
          scaled_norm = Eigen::JacobiSVD<Matrix6d>(SJ).singularValues()(0);
          m_norm = J_ref.inverse().norm();
          base.cond = cond_J;
          base.sigma_min = 1.0 / scaled_norm;
        }
        const Status pose_status = ik.status == Status::Ok && !have_ref ? Status::Singular : ik.status;
        // FK: inputs are the double sensors of this pose.
        {
          SweepRow fk = base;
          fk.family = "fk";
          fk.predicted = have_ref ? kUnitRoundoff * std::sqrt(6.0) * (kPi + (m.l0 + L) * m_norm) * scaled_norm : kNaN;
          const pathos2_methods::PoseReference ref_nine =
              ik.status == Status::Ok ? pathos2_methods::reference_nine_sensors(g, pathos2::sensors_of(ik))
                                      : pathos2_methods::PoseReference{};
          const pathos2_methods::PoseReference ref_num =
              ik.status == Status::Ok ? pathos2_methods::reference_forward(g, ik.q_active, P.h0, P)
                                      : pathos2_methods::PoseReference{};
          auto add = [&](const char* name, const pathos2::FkResult* r, const pathos2_methods::PoseReference& ref,
                         bool numeric) {
            SweepRow row = fk;
            row.method = name;
            if (!r) {
              row.status = pose_status;
              row.error = kNaN;
            } else {
              row.status = r->status;
              row.residual = r->residual;
              row.iterations = r->iterations;
              row.error = kNaN;
              if (r->status == Status::Ok && ref.converged) {
                double e = pathos2_methods::pose_error(r->pose, ref, L);
                if (numeric && e > 1e-6) {
                  // Another assembly with the same actuator angles: compare with it.
                  const auto other = pathos2_methods::reference_forward(g, ik.q_active, P.h0, r->pose);
                  if (other.converged) e = std::min(e, pathos2_methods::pose_error(r->pose, other, L));
                }
                row.error = e;
              }
            }
            rows.push_back(row);
          };
          if (ik.status != Status::Ok) {
            for (const char* name : {"nine-sensor", "numeric", "numeric-near"}) add(name, nullptr, ref_nine, false);
          } else {
            const pathos2::FkResult nine = pathos2::forward_nine_sensors(g, pathos2::sensors_of(ik));
            add("nine-sensor", &nine, ref_nine, false);
            const pathos2::FkResult num = pathos2::forward_numeric(g, ik.q_active, P.h0, home);
            add("numeric", &num, ref_num, true);
            Vector6d off = Vector6d::Constant(1e-3);
            const pathos2::FkResult num_near = pathos2::forward_numeric(g, ik.q_active, P.h0, along(P, off, 1.0));
            add("numeric-near", &num_near, ref_num, true);
          }
        }
        // Jacobian and conditioning.
        const std::pair<const char*, double> jac_methods[] = {
            {"analytic", 0}, {"central-difference", methods::kCentralDifferenceStep},
            {"forward-difference", methods::kForwardDifferenceStep}};
        for (const auto& [name, step] : jac_methods) {
          SweepRow row = base;
          row.family = "jacobian";
          row.method = name;
          row.predicted = have_ref ? kUnitRoundoff * cond_J : kNaN;
          Matrix6d J = Matrix6d::Zero();
          bool ok = false;
          if (have_ref) {
            if (step == 0) J = jr.J_twist_from_qdot, ok = jr.status == Status::Ok;
            else ok = pathos2_methods::jacobian_finite_difference(g, P, step, std::string(name) == "central-difference", J);
          }
          row.status = !have_ref ? pose_status : ok ? Status::Ok : Status::Singular;
          row.error = row.status == Status::Ok ? (J - J_ref).norm() / J_ref.norm() : kNaN;
          rows.push_back(row);
        }
        const std::array<double, 2> c_ref =
            have_ref ? pathos2_methods::reference_condition_numbers(jr.J_twist_from_qdot) : std::array<double, 2>{};
        for (const char* name : {"closed-form", "svd"}) {
          SweepRow row = base;
          row.family = "conditioning";
          row.method = name;
          row.predicted = have_ref ? kUnitRoundoff * std::max(c_ref[0], c_ref[1]) : kNaN;
          std::array<double, 2> c{kNaN, kNaN};
          if (have_ref && jr.status == Status::Ok)
            c = std::string(name) == "svd" ? pathos2_methods::condition_numbers_svd(jr.J_twist_from_qdot)
                                           : std::array<double, 2>{jr.cond_p, jr.cond_o};
          const bool ok = std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c_ref[0]) && std::isfinite(c_ref[1]);
          row.status = !have_ref ? pose_status : ok ? Status::Ok : Status::Singular;
          row.error = ok ? std::max(std::abs(c[0] - c_ref[0]) / c_ref[0], std::abs(c[1] - c_ref[1]) / c_ref[1]) : kNaN;
          rows.push_back(row);
        }
      }
    }
  }
  return rows;
}

std::string path_label(const SweepRow& row) {
  return row.path_name.empty() ? std::string(to_string(row.path)) : row.path_name;
}

}  // namespace linkscape::stability
