// PATHOS-II's methods measured against their references (the harness of
// `linkscape bench` and the Methods tab; core/mechanisms/pathos2/methods.h).
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>

#include "core/mechanisms/pathos2/methods.h"

namespace linkscape::pathos2_methods {
namespace {

using methods::fill_statistics;
using methods::median_pass_seconds;
using Eigen::Vector3d;
volatile double g_sink = 0;  // keeps timed results alive

}  // namespace

// ---- Harness --------------------------------------------------------------------------------

std::vector<Pose> workspace_poses(const Geometry& g, std::size_t count, unsigned seed, double radius_cm,
                                  double max_rotation_rad) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const Pose home = pathos2::home_pose(g.model);
  std::vector<Pose> out;
  out.reserve(count);
  for (std::size_t attempts = 0; out.size() < count && attempts < 100 * count + 1000; ++attempts) {
    const Vector3d d(u(rng), u(rng), u(rng));
    Vector3d axis(u(rng), u(rng), u(rng));
    const double angle = max_rotation_rad * std::abs(u(rng));
    if (d.norm() > 1 || axis.norm() < 0.1 || axis.norm() > 1) continue;
    Pose p = home;
    p.p_world_E += radius_cm * d;
    p.R_world_E = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix() * home.R_world_E;
    if (pathos2::inverse(g, p, pathos2::IkDetail::ActiveOnly).status == Status::Ok) out.push_back(p);
  }
  return out;
}

namespace {

struct PoseSample {
  Pose pose;
  pathos2::PoseIkResult ik;
  pathos2::NineSensors sensors;
  std::array<LegReference, 6> legs;
  PoseReference fk_nine, fk_numeric;
  Matrix6d J_ref;
  std::array<double, 2> cond_ref{};
  bool jacobian_ok = false;
};

}  // namespace

std::vector<methods::MethodRow> run_pathos2_harness(const pathos2::Model& model, const HarnessOptions& o) {
  if (o.samples < 10) throw std::invalid_argument("pathos2 harness: expected at least 10 samples");
  if (o.repeats < 1) throw std::invalid_argument("pathos2 harness: expected repeats >= 1");
  const Geometry g = pathos2::make_geometry(model);
  const pathos2::Model& m = g.model;
  const double L = m.l2 + m.l3;
  const Pose home = pathos2::home_pose(m);
  const pathos2::PoseIkResult home_ik = pathos2::inverse(g, home);
  auto stage = [&](double fraction, const char* name) {
    if (o.cancel && o.cancel->load()) return false;
    if (o.progress) o.progress(fraction, name);
    return true;
  };
  if (!stage(0.0, "references")) return {};
  std::vector<PoseSample> samples;
  for (const Pose& pose : workspace_poses(g, o.samples, o.seed, o.radius_cm, o.max_rotation_rad)) {
    if (o.cancel && o.cancel->load()) return {};
    PoseSample s;
    s.pose = pose;
    s.ik = pathos2::inverse(g, pose);
    s.sensors = pathos2::sensors_of(s.ik);
    for (int i = 0; i < 6; ++i) {
      const auto& leg = s.ik.legs[i];
      s.legs[i] = reference_leg_inverse(m.l1, m.l2, m.l3, leg.p_B_globular, Vector3d(leg.t1, leg.t2, leg.t3));
    }
    s.fk_nine = reference_nine_sensors(g, s.sensors);
    s.fk_numeric = reference_forward(g, s.ik.q_active, pose.h0, pose);
    s.jacobian_ok = reference_jacobian(g, pose, s.J_ref);
    if (s.jacobian_ok) s.cond_ref = reference_condition_numbers(pathos2::jacobian(g, pose, s.ik).J_twist_from_qdot);
    samples.push_back(s);
  }
  if (samples.empty()) throw std::invalid_argument("pathos2 harness: no reachable pose around the home pose");
  const double n = double(samples.size());
  std::vector<methods::MethodRow> rows;
  auto new_row = [&](const std::string& family, const std::string& method, const std::string& unit) {
    methods::MethodRow row;
    row.mechanism = std::string(pathos2::kMechanismName);
    row.family = family;
    row.method = method;
    row.error_unit = unit;
    return row;
  };

  // Leg IK: every leg of every pose.
  if (!stage(0.3, "leg inverse kinematics")) return rows;
  {
    methods::MethodRow closed = new_row("leg-ik", "closed-form", "rad");
    std::vector<double> errors;
    for (const auto& s : samples)
      for (int i = 0; i < 6; ++i) {
        const pathos2::LegSolution r = pathos2::leg_inverse(m.l1, m.l2, m.l3, s.ik.legs[i].p_B_globular, m.branch[i]);
        if (r.status != Status::Ok || !s.legs[i].converged) ++closed.failures;
        else errors.push_back(leg_joint_error(Vector3d(r.t1, r.t2, r.t3), s.legs[i]));
      }
    fill_statistics(closed, errors);
    closed.seconds_per_evaluation = median_pass_seconds(o.repeats, [&] {
                                      double acc = 0;
                                      for (const auto& s : samples)
                                        for (int i = 0; i < 6; ++i)
                                          acc += pathos2::leg_inverse(m.l1, m.l2, m.l3, s.ik.legs[i].p_B_globular, m.branch[i]).t1;
                                      g_sink = acc;
                                    }) / (6 * n);
    rows.push_back(closed);
    methods::MethodRow newton = new_row("leg-ik", "newton", "rad");
    newton.parameter = "home seed";
    errors.clear();
    for (const auto& s : samples)
      for (int i = 0; i < 6; ++i) {
        const auto& h = home_ik.legs[i];
        const LegNewtonResult r = leg_inverse_newton(m.l1, m.l2, m.l3, s.ik.legs[i].p_B_globular, m.branch[i],
                                                     Vector3d(h.t1, h.t2, h.t3));
        if (r.status != Status::Ok || !s.legs[i].converged) ++newton.failures;
        else errors.push_back(leg_joint_error(r.t, s.legs[i]));
      }
    fill_statistics(newton, errors);
    newton.seconds_per_evaluation = median_pass_seconds(o.repeats, [&] {
                                      double acc = 0;
                                      for (const auto& s : samples)
                                        for (int i = 0; i < 6; ++i) {
                                          const auto& h = home_ik.legs[i];
                                          acc += leg_inverse_newton(m.l1, m.l2, m.l3, s.ik.legs[i].p_B_globular,
                                                                    m.branch[i], Vector3d(h.t1, h.t2, h.t3))
                                                     .t(0);
                                        }
                                      g_sink = acc;
                                    }) / (6 * n);
    rows.push_back(newton);
  }

  // Forward kinematics.
  if (!stage(0.45, "forward kinematics")) return rows;
  {
    methods::MethodRow nine = new_row("fk", "nine-sensor", "pose");
    std::vector<double> errors;
    for (const auto& s : samples) {
      const pathos2::FkResult r = pathos2::forward_nine_sensors(g, s.sensors);
      if (r.status != Status::Ok || !s.fk_nine.converged) ++nine.failures;
      else errors.push_back(pose_error(r.pose, s.fk_nine, L));
    }
    fill_statistics(nine, errors);
    nine.seconds_per_evaluation = median_pass_seconds(o.repeats, [&] {
                                    double acc = 0;
                                    for (const auto& s : samples) acc += pathos2::forward_nine_sensors(g, s.sensors).pose.h0;
                                    g_sink = acc;
                                  }) / n;
    rows.push_back(nine);
    // Numeric FK from the home pose and from a seed 0.5 cm / 2 deg off (tracking).
    for (int near = 0; near < 2; ++near) {
      methods::MethodRow row = new_row("fk", near ? "numeric-near" : "numeric", "pose");
      row.parameter = near ? "0.5cm/2deg" : "home seed";
      auto seed_of = [&](const PoseSample& s) {
        if (!near) return home;
        Vector6d off;
        off << 0.5 / std::sqrt(3.0), -0.5 / std::sqrt(3.0), 0.5 / std::sqrt(3.0), 0.02, -0.02, 0.02;
        return step_pose(s.pose, off);
      };
      errors.clear();
      for (const auto& s : samples) {
        const pathos2::FkResult r = pathos2::forward_numeric(g, s.ik.q_active, s.pose.h0, seed_of(s));
        if (r.status != Status::Ok || !s.fk_numeric.converged) {
          ++row.failures;
          continue;
        }
        double e = pose_error(r.pose, s.fk_numeric, L);
        if (e > 1e-6) {
          // Another assembly with the same actuator angles: compare with the nearest exact solution.
          const PoseReference other = reference_forward(g, s.ik.q_active, s.pose.h0, r.pose);
          if (other.converged) e = std::min(e, pose_error(r.pose, other, L));
        }
        errors.push_back(e);
      }
      fill_statistics(row, errors);
      row.seconds_per_evaluation = median_pass_seconds(o.repeats, [&] {
                                     double acc = 0;
                                     for (const auto& s : samples)
                                       acc += pathos2::forward_numeric(g, s.ik.q_active, s.pose.h0, seed_of(s)).residual;
                                     g_sink = acc;
                                   }) / n;
      rows.push_back(row);
    }
  }

  // Jacobian.
  if (!stage(0.75, "Jacobians")) return rows;
  {
    struct Method {
      const char* name;
      double step;
      std::function<bool(const PoseSample&, Matrix6d&)> eval;
    };
    const std::vector<Method> jac = {
        {"analytic", 0,
         [&](const PoseSample& s, Matrix6d& J) {
           const pathos2::JacobianResult r = pathos2::jacobian(g, s.pose, s.ik);
           J = r.J_twist_from_qdot;
           return r.status == Status::Ok;
         }},
        {"central-difference", methods::kCentralDifferenceStep,
         [&](const PoseSample& s, Matrix6d& J) {
           return jacobian_finite_difference(g, s.pose, methods::kCentralDifferenceStep, true, J);
         }},
        {"forward-difference", methods::kForwardDifferenceStep,
         [&](const PoseSample& s, Matrix6d& J) {
           return jacobian_finite_difference(g, s.pose, methods::kForwardDifferenceStep, false, J);
         }},
    };
    for (const Method& method : jac) {
      methods::MethodRow row = new_row("jacobian", method.name, "relative");
      if (method.step > 0) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "h=%.2g", method.step);
        row.parameter = buf;
      }
      std::vector<double> errors;
      for (const auto& s : samples) {
        Matrix6d J = Matrix6d::Zero();
        if (!s.jacobian_ok || !method.eval(s, J)) ++row.failures;
        else errors.push_back((J - s.J_ref).norm() / s.J_ref.norm());
      }
      fill_statistics(row, errors);
      row.seconds_per_evaluation = median_pass_seconds(o.repeats, [&] {
                                     double acc = 0;
                                     Matrix6d J = Matrix6d::Zero();
                                     for (const auto& s : samples) acc += method.eval(s, J) ? J(0, 0) : 0;
                                     g_sink = acc;
                                   }) / n;
      rows.push_back(row);
    }
  }

  // Conditioning of the analytic J's blocks.
  if (!stage(0.9, "condition numbers")) return rows;
  {
    std::vector<Matrix6d> Js;
    for (const auto& s : samples) Js.push_back(pathos2::jacobian(g, s.pose, s.ik).J_twist_from_qdot);
    const std::vector<std::pair<const char*, std::function<std::array<double, 2>(const Matrix6d&)>>> conds = {
        {"closed-form",
         [](const Matrix6d& J) {
           return std::array<double, 2>{pathos2::block_condition_number(J.topRows<3>()),
                                        pathos2::block_condition_number(J.bottomRows<3>())};
         }},
        {"svd", &condition_numbers_svd},
    };
    for (const auto& [name, condition_numbers] : conds) {
      const auto& fn = condition_numbers;  // lambdas below cannot capture a structured binding under clang 14
      methods::MethodRow row = new_row("conditioning", name, "relative");
      std::vector<double> errors;
      for (std::size_t k = 0; k < samples.size(); ++k) {
        if (!samples[k].jacobian_ok) {
          ++row.failures;
          continue;
        }
        const auto c = fn(Js[k]);
        const auto& r = samples[k].cond_ref;
        if (!std::isfinite(c[0]) || !std::isfinite(c[1])) ++row.failures;
        else errors.push_back(std::max(std::abs(c[0] - r[0]) / r[0], std::abs(c[1] - r[1]) / r[1]));
      }
      fill_statistics(row, errors);
      row.seconds_per_evaluation = median_pass_seconds(o.repeats, [&] {
                                     double acc = 0;
                                     for (const auto& J : Js) acc += fn(J)[0];
                                     g_sink = acc;
                                   }) / n;
      rows.push_back(row);
    }
  }
  return rows;
}

}  // namespace linkscape::pathos2_methods
