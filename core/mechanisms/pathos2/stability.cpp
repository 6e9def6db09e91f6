#include "core/mechanisms/pathos2/stability.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "core/mechanisms/pathos2/methods.h"

namespace linkscape::stability {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;
constexpr double kUnitRoundoff = 1.1102230246251565e-16;  // 2^-53
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

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
  const std::vector<double> eps_values = sweep_eps(o);
  const pathos2::Geometry g = pathos2::make_geometry(model);
  const pathos2::Model& m = g.model;
  const double L = m.l2 + m.l3;
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

}  // namespace linkscape::stability
