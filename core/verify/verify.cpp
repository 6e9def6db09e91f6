#include "core/verify/verify.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <numbers>
#include <sstream>

#include "core/mechanisms/described/mechanism.h"
#include "core/preset.h"
#include "core/verify/certifier.h"
#include "core/verify/legs.h"

namespace linkscape::verify {
namespace {

using Eigen::Vector3d;

// With reach the only criterion, c(J) must stay below this: the devices
// call a point singular (not reached) within bands of about 1e-12 of their
// size around the singular sets (the 12R also beyond c(J) = 5e7), where
// c(J) exceeds 1e6; a bound of 1e5 keeps proved boxes clear of them.
constexpr double kReachConditionBound = 1e5;
// Counterexamples are sought this far inside the task's surface, so that
// they are inside it for certain after rounding.
constexpr double kInsideFactor = 1 - 1e-9;

// ---- The task's geometry -------------------------------------------------------------

struct TaskGeometry {
  task::TaskVolume task;
  Vector3d centre;
  double radius() const { return task.diameter() / 2; }
  bool sphere() const { return task.shape == task::Shape::Sphere; }

  // The task's exact bounds, enclosed: outward-rounded (every box split
  // from it covers the task) and inward-rounded (every point in it is in the task).
  Interval extent(int k) const { return Interval(centre(k)) + Interval(0.5) * Interval(task.size(k)) * Interval(-1.0, 1.0); }
  Box bounds() const {
    Box b;
    for (int k = 0; k < 3; ++k) b.lo(k) = extent(k).lo, b.hi(k) = extent(k).hi;
    return b;
  }

  // The box's part inside the task, as a box around it (outward-rounded);
  // nullopt where the box certainly misses the task.
  std::optional<Box> clip(const Box& b) const {
    if (!sphere()) return b;  // boxes are split from the task's own box
    Interval gap2[3];
    for (int k = 0; k < 3; ++k) {
      const double below = b.lo(k) - centre(k), above = centre(k) - b.hi(k);
      gap2[k] = below > 0 ? sqr(Interval(b.lo(k)) - Interval(centre(k)))
                          : above > 0 ? sqr(Interval(centre(k)) - Interval(b.hi(k))) : Interval(0.0);
    }
    const Interval r2 = sqr(Interval(radius()));
    if ((gap2[0] + gap2[1] + gap2[2]).lo > r2.hi) return std::nullopt;
    Box out = b;
    for (int k = 0; k < 3; ++k) {
      // Along axis k the ball's chord at the box's nearest offset in the other two.
      const Interval other = gap2[(k + 1) % 3] + gap2[(k + 2) % 3];
      const double half_chord = sqrt(Interval(std::max(0.0, up(r2.hi - other.lo)))).hi;
      out.lo(k) = std::max(b.lo(k), down(centre(k) - half_chord));
      out.hi(k) = std::min(b.hi(k), up(centre(k) + half_chord));
      if (out.lo(k) > out.hi(k)) return std::nullopt;
    }
    return out;
  }

  // Whether p is certainly in the task.
  bool certainly_contains(const Vector3d& p) const {
    if (sphere()) {
      Interval d2(0.0);
      for (int k = 0; k < 3; ++k) d2 += sqr(Interval(p(k)) - Interval(centre(k)));
      return d2.hi <= sqr(Interval(radius())).lo;
    }
    for (int k = 0; k < 3; ++k) {
      const Interval lo = Interval(centre(k)) - Interval(0.5) * Interval(task.size(k));
      const Interval hi = Interval(centre(k)) + Interval(0.5) * Interval(task.size(k));
      if (!(p(k) >= lo.hi && p(k) <= hi.lo)) return false;
    }
    return true;
  }

  // The nearest point of the task, a hair inside.
  Vector3d project(const Vector3d& p) const {
    if (sphere()) {
      const Vector3d d = p - centre;
      const double limit = radius() * kInsideFactor;
      return d.norm() > limit ? Vector3d(centre + d * (limit / d.norm())) : p;
    }
    const Vector3d half = task.size / 2 * kInsideFactor;
    return p.cwiseMax(centre - half).cwiseMin(centre + half);
  }
};

// ---- The counterexample search -------------------------------------------------------

// Points of the task (its surface, where the worst values usually are, and
// a grid of its inside), about `count` of them.
std::vector<Vector3d> search_points(const TaskGeometry& g, int count) {
  std::vector<Vector3d> points;
  if (count <= 0) return points;
  const int surface = std::max(64, count / 2);
  const int n = std::max(2, int(std::cbrt(double(count - surface))));
  const Box b = g.bounds();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vector3d f((i + 0.5) / n, (j + 0.5) / n, (k + 0.5) / n);
        const Vector3d p = b.lo + f.cwiseProduct(b.hi - b.lo);
        if (!g.sphere() || (p - g.centre).norm() <= g.radius()) points.push_back(p);
      }
  for (int k = 0; k < surface; ++k) {
    // Fibonacci points on the sphere; on a box, the same directions pushed out to its faces.
    const double z = 1 - (2 * k + 1.0) / surface, rho = std::sqrt(1 - z * z), phi = k * 2.399963229728653;
    const Vector3d dir(rho * std::cos(phi), rho * std::sin(phi), z);
    points.push_back(g.sphere() ? Vector3d(g.centre + g.radius() * dir)
                                : Vector3d(g.centre + (g.task.size / 2).cwiseProduct(dir / dir.cwiseAbs().maxCoeff())));
  }
  for (Vector3d& p : points) p = g.project(p);
  return points;
}

// From p, the largest c(J) nearby in the task by a compass search (at most
// a few dozen moves per step length: it only sharpens a sample).
Vector3d climb(const Certifier& c, const TaskGeometry& g, Vector3d p) {
  double best = c.badness(p);
  for (double step = g.task.size.maxCoeff() / 16; step > 1e-9 * g.task.size.maxCoeff() && std::isfinite(best);
       step /= 2) {
    for (int moves = 0; moves < 32; ++moves) {
      bool moved = false;
      for (int axis = 0; axis < 3 && !moved; ++axis)
        for (double sign : {-1.0, 1.0}) {
          const Vector3d trial = g.project(p + sign * step * Vector3d::Unit(axis));
          const double value = c.badness(trial);
          if (value > best) {
            p = trial, best = value, moved = true;
            break;
          }
        }
      if (!moved) break;
    }
  }
  return p;
}

// ---- Subdivision ---------------------------------------------------------------------

struct Open {
  Box box;
  int depth = 0;
};

struct Search {
  const Certifier& certifier;
  const TaskGeometry& geometry;
  const Options& options;
  const std::function<std::optional<Counterexample>(const Vector3d&)>& confirm;
  std::chrono::steady_clock::time_point deadline;
  bool limited = false;
  Result& result;

  std::atomic<bool> stop{false}, timed_out{false};
  std::mutex mutex{};
  std::exception_ptr failure{};

  bool out_of_time() const {
    return (options.cancel && options.cancel->load()) || (limited && std::chrono::steady_clock::now() > deadline);
  }

  void record_counterexample(Counterexample ce) {
    std::lock_guard lock(mutex);
    if (!result.counterexample) result.counterexample = std::move(ce);
    stop = true;
  }

  // One box: proved, split, or left open at the depth limit.
  void visit(const Open& open, std::vector<Open>& children, double& proved, double& undecided, double& bound,
             std::vector<Box>& proved_boxes, std::vector<Box>& open_boxes) {
    const std::optional<Box> clipped = geometry.clip(open.box);
    if (!clipped) return;
    const Box& b = *clipped;
    if (const std::optional<double> c = certifier.condition_bound(b.lo, b.hi)) {
      proved += b.volume();
      bound = std::max(bound, *c);
      if (options.keep_boxes) proved_boxes.push_back(b);
      return;
    }
    const Vector3d mid = 0.5 * (b.lo + b.hi);
    if (geometry.certainly_contains(mid) && !(certifier.badness(mid) < 0.999))
      if (std::optional<Counterexample> ce = confirm(mid)) {
        record_counterexample(std::move(*ce));
        return;
      }
    if (open.depth >= options.max_depth) {
      undecided += b.volume();
      if (options.keep_boxes) open_boxes.push_back(b);
      return;
    }
    int axis;
    (b.hi - b.lo).maxCoeff(&axis);
    const double cut = 0.5 * (b.lo(axis) + b.hi(axis));
    Open lower{b, open.depth + 1}, upper{b, open.depth + 1};
    lower.box.hi(axis) = cut;
    upper.box.lo(axis) = cut;
    children.push_back(lower);
    children.push_back(upper);
  }

  void run() {
    std::vector<Open> level{{geometry.bounds(), 0}};
    double bound = 0;
    const int team = options.threads > 0 ? options.threads : omp_get_max_threads();
    while (!level.empty() && !stop) {
      std::vector<Open> next;
      result.boxes += std::int64_t(level.size());
      result.deepest = std::max(result.deepest, level.front().depth);
#pragma omp parallel num_threads(team)
      {
        std::vector<Open> children;
        std::vector<Box> proved_boxes, open_boxes;
        double proved = 0, undecided = 0, local_bound = 0;
#pragma omp for schedule(dynamic, 64)
        for (std::int64_t i = 0; i < std::int64_t(level.size()); ++i) {
          if (stop) continue;
          const Open& open = level[std::size_t(i)];
          try {
            if (!out_of_time()) {
              visit(open, children, proved, undecided, local_bound, proved_boxes, open_boxes);
            } else if (const std::optional<Box> b = geometry.clip(open.box)) {
              timed_out = true;
              undecided += b->volume();
              if (options.keep_boxes) open_boxes.push_back(*b);
            }
          } catch (...) {  // an exception must not leave the parallel region
            std::lock_guard lock(mutex);
            if (!failure) failure = std::current_exception();
            stop = true;
          }
        }
        std::lock_guard lock(mutex);
        next.insert(next.end(), children.begin(), children.end());
        result.proved_volume += proved;
        result.undecided_volume += undecided;
        bound = std::max(bound, local_bound);
        result.proved_boxes.insert(result.proved_boxes.end(), proved_boxes.begin(), proved_boxes.end());
        result.undecided_boxes.insert(result.undecided_boxes.end(), open_boxes.begin(), open_boxes.end());
      }
      if (failure) std::rethrow_exception(failure);
      if (next.size() > std::size_t(options.max_open_boxes)) {
        // Memory, not time, would run out first: what is open stays undecided.
        result.box_limit = true;
        for (const Open& o : next)
          if (const std::optional<Box> b = geometry.clip(o.box)) {
            result.undecided_volume += b->volume();
            if (options.keep_boxes) result.undecided_boxes.push_back(*b);
          }
        break;
      }
      level = std::move(next);
    }
    if (bound > 0) result.largest_box_bound = bound;
    result.timed_out = timed_out;
  }
};

void check_options(const Options& o) {
  if (o.max_depth < 1 || o.max_depth > 200)
    throw std::invalid_argument("verify: the depth must be 1..200 bisections, got " + std::to_string(o.max_depth));
  if (o.threads < 0) throw std::invalid_argument("verify: threads must be >= 0 (0: all), got " + std::to_string(o.threads));
  if (o.search_samples < 0)
    throw std::invalid_argument("verify: search samples must be >= 0, got " + std::to_string(o.search_samples));
  if (std::isnan(o.time_limit_seconds)) throw std::invalid_argument("verify: the time limit is not a number");
  if (o.max_open_boxes < 1)
    throw std::invalid_argument("verify: the open-box limit must be positive, got " + std::to_string(o.max_open_boxes));
}

// 2 pi, enclosed (the double nearest it is below it).
const Interval kTwoPi(6.283185307179586, 6.283185307179587);

// The certifier for these criteria: c(J) below the smallest cond threshold
// (or the reach bound), and force_iso and resolution as bounds on J's
// columns. Throws Uncertifiable for a criterion without an enclosure.
Certifier certifier_for(const Preset& preset, const task::Device& device, const std::vector<task::Criterion>& criteria,
                        int branch) {
  const MechanismInfo& info = device.mechanism->info();
  double bound = kReachConditionBound;
  std::vector<Certifier::ColumnCriterion> columns;
  for (const task::Criterion& given : criteria) {
    const task::Criterion c = task::resolve(given, info, device.data ? &*device.data : nullptr);
    if (c.reach()) continue;
    if ((c.measure == "force_iso" || c.measure == "resolution") && preset.mechanism == described::kMechanismName)
      throw Uncertifiable("verify: criterion '" + c.text + "' cannot be certified on a described device (reach and " +
                          info.measures.front().name + "<T can)");
    if (c.measure == "force_iso" || c.measure == "resolution") {
      Certifier::ColumnCriterion column{c.text, c.measure == "force_iso", c.threshold, {}};
      for (std::size_t i = 0; i < 3; ++i) {
        const haptics::Rating& r = device.data->actuators.at(i);
        const Interval metres(device.data->metres_per_motor_radian(i));
        const double torque = device.torque == haptics::TorqueRating::Peak ? r.peak_torque_Nm : r.continuous_torque_Nm;
        column.scale[i] = column.force ? Interval(torque) / metres
                                       : Interval(1000.0) * kTwoPi / Interval(r.encoder_counts_per_rev) * metres;
      }
      columns.push_back(column);
      continue;
    }
    if (c.haptic() || c.measure_index != 0)
      throw Uncertifiable("verify: criterion '" + c.text + "' cannot be certified (reach, " + info.measures.front().name +
                          "<T, force_iso>F and resolution<R can)");
    bound = std::min(bound, c.threshold);
  }
  Certifier certifier = Certifier::from_preset(preset, branch, bound);
  certifier.columns = columns;
  return certifier;
}

// The index of the criterion a certain failure fails: its column criterion,
// the cond criterion where c(J) is too large, else reach (which every
// criterion implies; -1 where none is given as such).
int failing_criterion(const std::vector<task::Criterion>& criteria, const Certifier& certifier,
                      const Certifier::PointFailure& failure) {
  for (std::size_t k = 0; k < criteria.size(); ++k) {
    const task::Criterion& c = criteria[k];
    if (failure.column >= 0 ? c.text == certifier.columns[std::size_t(failure.column)].text
                            : std::isfinite(failure.bound) ? !c.reach() && !c.haptic() : c.reach())
      return int(k);
  }
  return -1;
}

// Whether the independent long-double evaluation fails the same way.
bool reference_fails(const Certifier& certifier, const Certifier::PointFailure& failure, const Vector3d& p,
                     long double& value) {
  if (failure.column < 0) {
    value = reference_condition(certifier, p);
    return value >= certifier.cond_bound;
  }
  const Certifier::ColumnCriterion& c = certifier.columns[std::size_t(failure.column)];
  value = reference_value(certifier, c, p);
  return c.force ? value <= c.threshold : value >= c.threshold;
}

// What the verdict does not cover: the stops a described device's legs
// certifier names, or those a compiled device states and checks.
std::string stops_not_covered(const Certifier& certifier, const Preset& preset) {
  if (certifier.legs) return certifier.legs->not_covered();
  const StopChecks stated = stated_stops(preset);
  std::string out;
  if (stated.joint_limits && preset.checks.joint_limits) out = "its passive-joint limits";
  if (stated.interference && preset.checks.interference) out += (out.empty() ? "" : " and ") + std::string("link interference");
  return out;
}

// The device's own evaluation, stops included, at the search's samples:
// how many assemble on the branch but are stopped by a passive joint or
// two links (not certified; the verdict does not cover them).
void sample_stops(const Mechanism& mechanism, const task::Device& device, const std::vector<Vector3d>& points,
                  Result& result) {
  result.stop_samples = int(points.size());
  for (const Vector3d& p : points) {
    Eigen::VectorXd x = device.fixed_task;
    x.head<3>() = p;
    const IkResult ik = mechanism.inverse(x, device.ik);
    if (ik.status != Status::OutOfLimits || ik.status_text.empty()) continue;
    if (result.stop_failures++ == 0) {
      std::ostringstream example;
      example << "(" << p.x() << ", " << p.y() << ", " << p.z() << "): " << ik.status_text;
      result.stop_example = example.str();
    }
  }
}

}  // namespace

std::string_view to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::Proved: return "proved";
    case Verdict::Disproved: return "disproved";
    case Verdict::Undecided: return "undecided";
  }
  return "undecided";
}

int exit_status(Verdict verdict) {
  switch (verdict) {
    case Verdict::Proved: return kExitProved;
    case Verdict::Disproved: return kExitDisproved;
    case Verdict::Undecided: return kExitUndecided;
  }
  return kExitUndecided;
}

Result verify(const Preset& preset, const task::TaskVolume& task, const std::vector<task::Criterion>& criteria,
              const Options& options, int branch) {
  const auto start = std::chrono::steady_clock::now();
  check_options(options);
  if (!task.centre)
    throw std::invalid_argument("verify: the task '" + task.text +
                                "' needs its centre (add ,centre=x,y,z): a proof is about a task at a place");
  if (!(task.size.array() > 0).all() || !task.size.allFinite() || !task.centre->allFinite())
    throw std::invalid_argument("verify: the task must have a positive size and a finite centre");
  if (criteria.empty()) throw std::invalid_argument("verify: give at least one criterion (reach, cond<T)");
  const std::shared_ptr<const Mechanism> mechanism = make_mechanism(preset);
  task::Device device;
  device.mechanism = mechanism;
  device.ik.branch = branch;
  device.fixed_task = mechanism->home_task();
  device.torque = options.torque;
  if (std::any_of(criteria.begin(), criteria.end(), [](const task::Criterion& c) { return c.haptic(); }))
    device.data = haptics::device_data(preset, mechanism->info());
  const Certifier certifier = certifier_for(preset, device, criteria, branch);
  const std::vector<task::Criterion> resolved = task::resolve(device, criteria);

  Result result;
  result.mechanism = mechanism->info().name;  // a described device by its file's name
  result.parameters = mechanism->parameters();
  result.task = task::to_text(task);
  for (const task::Criterion& c : criteria) result.criteria.push_back(c.text);
  const TaskGeometry geometry{task, *task.centre};
  result.task_volume = task.volume();

  // The device the verdict is about: its stops removed.
  const std::string not_covered = stops_not_covered(certifier, preset);
  task::Device evaluated = device;
  if (!not_covered.empty()) {
    Preset plain = certifier.legs ? without_stops(preset) : preset;
    plain.checks = {false, false};
    evaluated.mechanism = make_mechanism(plain);
  }

  // A certain failure there, confirmed in long double and by the device itself.
  const std::function<std::optional<Counterexample>(const Vector3d&)> confirm =
      [&](const Vector3d& p) -> std::optional<Counterexample> {
    if (!geometry.certainly_contains(p)) return std::nullopt;
    const std::optional<Certifier::PointFailure> failure = certifier.certain_failure(p);
    if (!failure) return std::nullopt;
    long double reference = 0;
    if (!reference_fails(certifier, *failure, p, reference)) return std::nullopt;  // the evaluations disagree: no claim
    const task::PointValues device_values = task::evaluate_point(evaluated, resolved, p);
    if (device_values.meets) return std::nullopt;
    const int k = failing_criterion(criteria, certifier, *failure);
    Counterexample ce;
    ce.point = p;
    ce.criterion = k >= 0 ? criteria[std::size_t(k)].text : "reach (implied by every criterion)";
    ce.reason = failure->reason;
    ce.bound = failure->bound;
    ce.long_double_value = double(reference);
    ce.device_value = k >= 0 && device_values.reachable ? device_values.values[std::size_t(k)] : kInf;
    return ce;
  };

  // The search first: a failing task usually fails clearly somewhere on its surface.
  std::vector<Vector3d> points = search_points(geometry, options.search_samples);
  std::vector<double> scores(points.size());
  const int team = options.threads > 0 ? options.threads : omp_get_max_threads();
#pragma omp parallel for schedule(static) num_threads(team)
  for (std::int64_t i = 0; i < std::int64_t(points.size()); ++i)
    scores[std::size_t(i)] = certifier.badness(points[std::size_t(i)]);
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const std::size_t worst = std::min<std::size_t>(4, order.size());
  std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(worst), order.end(),
                    [&](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
  for (std::size_t k = 0; k < worst && !result.counterexample; ++k) {
    const Vector3d& p = points[order[k]];
    if (scores[order[k]] < 0.95) break;
    result.counterexample = confirm(std::isfinite(scores[order[k]]) ? climb(certifier, geometry, p) : p);
    if (!result.counterexample) result.counterexample = confirm(p);
  }

  if (!result.counterexample) {
    const auto limit = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(std::clamp(options.time_limit_seconds, 0.0, 1e9)));
    Search search{certifier, geometry, options, confirm, start + limit, options.time_limit_seconds > 0, result};
    search.run();
  }
  if (!not_covered.empty()) {
    result.not_covered = not_covered;
    sample_stops(*mechanism, device, points, result);
  }
  if (result.counterexample) {
    result.verdict = Verdict::Disproved;
    result.largest_box_bound.reset();
    result.proved_boxes.clear();
  } else {
    result.verdict = result.undecided_volume > 0 ? Verdict::Undecided : Verdict::Proved;
    const bool conditioning =
        std::any_of(criteria.begin(), criteria.end(), [](const auto& c) { return !c.reach() && !c.haptic(); });
    if (result.verdict != Verdict::Proved || !conditioning) result.largest_box_bound.reset();
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace linkscape::verify
