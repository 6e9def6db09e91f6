#include "core/mechanisms/parallel12r/stability.h"

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

#include "core/conditioning.h"
#include "core/mechanisms/parallel12r/methods.h"

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
  const std::vector<double> eps_values = sweep_eps(o);
  const parallel12r::IkOptions ik = methods::ik_options(o.ik);

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
  for (SweepPath path : kParallel12rPaths)
    for (int b = 0; b < o.base_points; ++b)
      for (double eps : eps_values) {
        const SweepPoint point = sweep_point(m, path, eps, b, o.seed);
        const methods::IkReference ref = methods::reference_ik(m, point.target, point.q_path);
        const auto& r0 = ref.branch[0] ? ref.branch[0] : ref.branch[1];
        SweepRow base;
        base.mechanism = std::string(parallel12r::kMechanismName);
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
        for (const auto& [name, method] : ik_methods) add_ik(name, method, ik);
        {
          parallel12r::IkOptions near = ik;
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

}  // namespace linkscape::stability
