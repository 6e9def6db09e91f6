// The default speed-against-accuracy harness and stability sweeps of a device
// (Mechanism::measure_methods, Mechanism::stability_sweeps): measured through
// the interface alone, so every device has them.
//
// Ground truth without a higher-precision model: targets are made by the
// device's forward kinematics from seeded actuator values q* on branch 0
// (the branch every IK method solves), so the IK error of a method is the
// joint distance of its branch-0 solution to q*, and the FK error is the
// joint distance to q* of the actuator values its pose gives back (the
// first IK method, nearest branch): FK is not measured against itself.
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <numbers>
#include <random>

#include "core/mechanism.h"

namespace linkscape {
namespace {

using Eigen::VectorXd;

// Largest actuator difference: an angle's wrapped (rad), a slide's plain
// (the length unit).
double joint_distance(const MechanismInfo& info, const VectorXd& a, const VectorXd& b) {
  double worst = 0;
  for (Eigen::Index k = 0; k < a.size(); ++k) {
    const bool angle = info.actuators[std::size_t(k)].unit == "rad";
    worst = std::max(worst, std::abs(angle ? std::remainder(a(k) - b(k), 2 * std::numbers::pi) : a(k) - b(k)));
  }
  return worst;
}

// The unit of joint_distance: rad, the length unit, or both where a device mixes them.
std::string joint_unit(const MechanismInfo& info) {
  const auto angle = [](const Quantity& q) { return q.unit == "rad"; };
  if (std::all_of(info.actuators.begin(), info.actuators.end(), angle)) return "rad";
  if (std::none_of(info.actuators.begin(), info.actuators.end(), angle)) return info.length_unit;
  return "rad or " + info.length_unit;
}

struct Sample {
  VectorXd q, x;
};

// Of the first IK method's solutions at x on every branch, the one nearest
// q: its branch and joint distance (-1 and +inf where none is ok).
struct Nearest {
  int branch = -1;
  double distance = INFINITY;
};
Nearest nearest_solution(const Mechanism& m, const VectorXd& x, const VectorXd& q) {
  Nearest out;
  for (const IkSolution& s : m.inverse(x, IkOptions{}).solutions)
    if (s.status == Status::Ok)
      if (const double d = joint_distance(m.info(), s.q, q); d < out.distance) out = {s.branch, d};
  return out;
}

// Whether q at the pose x is on branch 0, the branch every method is
// measured on: branch 0's solution is q (to 1e-7 rad or length unit). A
// drawn q on another branch would be compared with branch 0's, radians away.
bool on_branch_0(const Mechanism& m, const VectorXd& q, const VectorXd& x) {
  const Nearest n = nearest_solution(m, x, q);
  return n.branch == 0 && n.distance < 1e-7;
}

// Seeded actuator values in their ranges whose FK succeeds and whose main
// measure is finite and below 1e3 (away from singular sets), on branch 0; where too few
// assemble, seeded task poses (below).
std::vector<Sample> reachable_samples(const Mechanism& m, std::size_t count, unsigned seed) {
  const MechanismInfo& info = m.info();
  std::mt19937_64 rng(seed);
  std::vector<Sample> out;
  const VectorXd home_x = m.home_task();
  // Keeps (q, FK(q) from the seed) where FK succeeds away from singular sets.
  auto keep = [&](const VectorXd& q, const VectorXd& seed_x) {
    FkOptions fo;
    fo.seed = seed_x;
    const FkResult fk = m.forward(q, fo);
    if (fk.status != Status::Ok) return;
    const Measures meas = m.measures(q, fk.x);
    if (meas.status != Status::Ok || meas.values.empty() || !(meas.values[0] < 1e3)) return;
    if (info.branches.size() > 1 && !on_branch_0(m, q, fk.x)) return;
    out.push_back({q, fk.x});
  };
  for (std::size_t tries = 0; out.size() < count && tries < 20 * count; ++tries) {
    VectorXd q(info.actuators.size());
    for (std::size_t k = 0; k < info.actuators.size(); ++k) {
      const Range r = info.actuators[k].range;
      q(Eigen::Index(k)) = std::uniform_real_distribution<double>(r.lo, r.hi)(rng);
    }
    keep(q, home_x);
  }
  // Devices whose random actuator values seldom assemble (six legs): poses
  // drawn in the middle half of each task coordinate's span instead, their
  // IK giving q* and FK from the drawn pose the target made from q*.
  for (std::size_t tries = 0; out.size() < count && tries < 50 * count; ++tries) {
    VectorXd x = home_x;
    for (std::size_t k = 0; k < info.task.size(); ++k) {
      const Range r = info.task[k].range;
      const double mid = 0.5 * (r.lo + r.hi), half = 0.25 * (r.hi - r.lo);
      x(Eigen::Index(k)) = std::uniform_real_distribution<double>(mid - half, mid + half)(rng);
    }
    IkOptions io;
    io.branch = 0;
    const IkResult ik = m.inverse(x, io);
    if (ik.status == Status::Ok && !ik.solutions.empty()) keep(ik.solutions.front().q, x);
  }
  return out;
}

}  // namespace

std::vector<methods::MethodRow> Mechanism::measure_methods(const methods::HarnessOptions& options) const {
  const MechanismInfo& info = this->info();
  const std::vector<Sample> samples = reachable_samples(*this, options.samples, options.seed);
  std::vector<methods::MethodRow> rows;
  const double stages = double(info.ik_methods.size() + info.fk_methods.size());
  // One row: `solve` gives a sample's answer, or nothing where the method is
  // not ok (timed); `error` that answer's error (after the timing).
  using Answer = std::optional<VectorXd>;
  auto measure = [&](const std::string& family, const std::string& method, const std::string& unit,
                     const std::function<Answer(const Sample&)>& solve,
                     const std::function<double(const Sample&, const VectorXd&)>& error) {
    if (options.cancel && options.cancel->load()) return false;
    if (options.progress) options.progress(double(rows.size()) / stages, family + " " + method);
    methods::MethodRow row;
    row.mechanism = info.name;
    row.family = family;
    row.method = method;
    row.error_unit = unit;
    std::vector<Answer> answers(samples.size());
    row.seconds_per_evaluation = methods::median_pass_seconds(options.repeats, [&] {
      for (std::size_t i = 0; i < samples.size(); ++i) answers[i] = solve(samples[i]);
    }) / double(std::max<std::size_t>(samples.size(), 1));
    std::vector<double> errors;
    row.failures = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      if (answers[i]) errors.push_back(error(samples[i], *answers[i]));
      else ++row.failures;
    }
    methods::fill_statistics(row, errors);
    rows.push_back(row);
    return true;
  };
  for (const NamedItem& method : info.ik_methods) {
    IkOptions io;
    io.method = method.name;
    io.branch = 0;  // the samples' branch: every method solves that one (not every branch, nor some)
    io.tolerance = options.ik.tolerance;
    io.max_iterations = options.ik.max_iterations;
    const bool going = measure(
        "ik", method.name, joint_unit(info),
        [&](const Sample& s) -> Answer {
          const IkResult r = inverse(s.x, io);
          if (r.status != Status::Ok) return std::nullopt;
          return r.solutions.front().q;
        },
        [&](const Sample& s, const VectorXd& q) { return joint_distance(info, q, s.q); });
    if (!going) return rows;
  }
  for (const NamedItem& method : info.fk_methods) {
    FkOptions fo;
    fo.method = method.name;
    fo.seed = home_task();
    // Against the drawn actuator values: FK's pose must give them back by
    // the first IK method on some branch (FK may find another assembly than
    // the sample's; the sample's own pose would be FK's where drawn from q).
    const bool going = measure(
        "fk", method.name, joint_unit(info),
        [&](const Sample& s) -> Answer {
          const FkResult r = forward(s.q, fo);
          if (r.status != Status::Ok) return std::nullopt;
          return r.x;
        },
        [&](const Sample& s, const VectorXd& x) { return nearest_solution(*this, x, s.q).distance; });  // +inf: wrong
    if (!going) return rows;
  }
  if (options.progress) options.progress(1.0, "done");
  return rows;
}

std::vector<stability::SweepRow> Mechanism::stability_sweeps(const stability::SweepOptions& options) const {
  const MechanismInfo& info = this->info();
  std::vector<stability::SweepRow> rows;
  const double decades = std::log10(options.eps_max / options.eps_min);
  const int steps = std::max(1, int(std::lround(decades * options.steps_per_decade)));
  for (const SingularApproach& approach : singular_approaches()) {
    for (int k = 0; k < options.base_points; ++k) {
      for (int step = 0; step <= steps; ++step) {
        const double eps = options.eps_max * std::pow(options.eps_min / options.eps_max, double(step) / steps);
        const VectorXd x = approach.target(eps, k);
        for (const NamedItem& method : info.ik_methods) {
          IkOptions io;
          io.method = method.name;
          io.branch = 0;  // the approaches are branch 0's
          const IkResult r = inverse(x, io);
          stability::SweepRow row;
          row.mechanism = info.name;
          row.path_name = info.singular_sets[std::size_t(approach.set)].name;
          row.base_point = k;
          row.eps = eps;
          row.distance = eps * size();
          row.family = "ik";
          row.method = method.name;
          row.status = r.status;
          row.error = NAN;  // no independent reference: the residual is the measure
          row.residual = INFINITY;  // the least of the ok solutions'; none: no value (NaN, below)
          row.cond = NAN;
          row.sigma_min = NAN;  // not measured here
          for (const IkSolution& sol : r.solutions) {
            if (sol.status != Status::Ok || !(sol.residual < row.residual)) continue;
            row.residual = sol.residual;
            row.iterations = sol.iterations;
            const Measures meas = measures(sol.q, x);
            row.cond = meas.values.empty() ? INFINITY : meas.values[0];
          }
          row.error = std::isfinite(row.residual) ? row.residual / size() : NAN;
          if (!std::isfinite(row.residual)) row.residual = NAN;
          row.ik_error_unit = "relative";
          row.predicted = NAN;
          rows.push_back(row);
        }
      }
    }
  }
  return rows;
}

}  // namespace linkscape
