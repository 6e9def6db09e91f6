#include "core/fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "core/simd.h"

namespace linkscape::fit {
namespace {

using Eigen::VectorXd;
constexpr double kInf = std::numeric_limits<double>::infinity();

// The i-th point of the Halton sequence in `base` (low discrepancy in [0, 1)).
double halton(int i, int base) {
  double f = 1, r = 0;
  for (int n = i + 1; n > 0; n /= base) {
    f /= base;
    r += f * (n % base);
  }
  return r;
}

// Below this ratio (largest shape found over the task) a place is not
// evaluated unless it is the largest: its shape misses the task by several
// cells of the placement's grid, where the task fails.
constexpr double kPlausibleRatio = 0.95;

// Centre fixed: the smallest ratio of bound and worst value over the
// criteria on a measure (>= 1 where every one holds; an unreachable sample
// makes it 0), or the fraction covered where reach is the only criterion.
double fixed_centre_ratio(const task::TaskReport& report) {
  double ratio_min = kInf;
  for (const task::CriterionReport& c : report.criteria) {
    if (c.criterion.reach()) continue;
    const double ratio = c.criterion.above ? c.worst / c.criterion.threshold : c.criterion.threshold / c.worst;
    ratio_min = std::min(ratio_min, std::isfinite(ratio) ? std::max(ratio, 0.0) : 0.0);
  }
  return std::isinf(ratio_min) ? report.fraction : ratio_min;
}

class Search {
 public:
  Search(const Problem& problem, const Progress& progress) : problem_(problem), progress_(progress) {
    const std::size_t k = problem.variables.size();
    lo_.resize(Eigen::Index(k));
    hi_.resize(Eigen::Index(k));
    for (std::size_t i = 0; i < k; ++i) {
      lo_(Eigen::Index(i)) = problem.variables[i].lo;
      hi_(Eigen::Index(i)) = problem.variables[i].hi;
    }
  }

  bool cancelled() const { return progress_.cancel && progress_.cancel->load(); }
  double tolerance() const { return problem_.tolerance; }
  const VectorXd& lo() const { return lo_; }
  const VectorXd& hi() const { return hi_; }
  Result& result() { return result_; }

  // Evaluates the design at `v` (per variable); returns its row's index (an
  // earlier row where the same design, to rounding, was evaluated).
  std::size_t evaluate(const VectorXd& v) {
    for (std::size_t i = 0; i < result_.rows.size(); ++i)
      if (((Eigen::Map<const VectorXd>(result_.rows[i].values.data(), v.size()) - v).array().abs() <=
           1e-12 * (1 + v.array().abs()))
              .all())
        return i;
    std::optional<Row> row = fit::evaluate(problem_, std::vector<double>(v.data(), v.data() + v.size()), progress_.cancel);
    if (!row) return result_.rows.size();  // cancelled: nothing added
    return add(std::move(*row));
  }

  const Row& row(std::size_t i) const { return result_.rows[i]; }

  // The design on the ray lo + t w.
  VectorXd on_ray(const VectorXd& w, double t) const { return lo_ + t * w; }

  // The smallest t in (t_fail, t_meet] where the ray's design meets the
  // task, by bisection until the sizes at both ends agree to the tolerance.
  // Returns the meeting row, or nullopt if cancelled.
  std::optional<std::size_t> bisect(const VectorXd& w, double t_fail, double t_meet, std::size_t meet_row) {
    std::optional<double> size_fail;
    for (int it = 0; it < 60 && !cancelled(); ++it) {
      const double size_meet = row(meet_row).cost;
      if (size_fail && size_meet - *size_fail <= problem_.tolerance * size_meet) break;
      if (t_meet - t_fail <= 1e-12) break;
      const double mid = 0.5 * (t_fail + t_meet);
      const std::size_t r = evaluate(on_ray(w, mid));
      if (r >= result_.rows.size()) return std::nullopt;
      if (row(r).meets) {
        t_meet = mid;
        meet_row = r;
      } else {
        t_fail = mid;
        if (row(r).invalid.empty()) size_fail = row(r).cost;
      }
    }
    return meet_row;
  }

 private:
  std::size_t add(Row row) {
    result_.rows.push_back(std::move(row));
    if (progress_.design) progress_.design(result_.rows.back(), result_.rows.size());
    return result_.rows.size() - 1;
  }

  const Problem& problem_;
  const Progress& progress_;
  VectorXd lo_, hi_;
  Result result_;
};

// The first designs: a line (one variable), a 5 x 5 grid (two) or Halton
// points and the upper corner (more).
std::vector<VectorXd> scan_points(const VectorXd& lo, const VectorXd& hi) {
  const Eigen::Index k = lo.size();
  std::vector<VectorXd> out;
  if (k == 1) {
    for (int i = 0; i < 7; ++i) out.push_back(lo + (hi - lo) * (i / 6.0));
  } else if (k == 2) {
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) out.push_back(lo + (hi - lo).cwiseProduct(Eigen::Vector2d(i / 4.0, j / 4.0)));
  } else {
    static constexpr int kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37};
    if (k > 12) throw std::invalid_argument("fit: at most 12 free variables");
    for (int i = 0; i < 12 * int(k); ++i) {
      VectorXd u(k);
      for (Eigen::Index d = 0; d < k; ++d) u(d) = halton(i, kPrimes[d]);
      out.push_back(lo + (hi - lo).cwiseProduct(u));
    }
    out.push_back(hi);
  }
  return out;
}

}  // namespace

namespace {

void require_a_valid_design(const Result& r) {
  const bool any_valid = std::any_of(r.rows.begin(), r.rows.end(), [](const Row& row) { return row.invalid.empty(); });
  if (!any_valid && !r.rows.empty())
    throw std::invalid_argument("fit: the bounds exclude every design (" + r.rows.front().invalid + ")");
}

// `v` rounded by `round` (std::ceil, std::round) to a multiple of `step`, a
// power of ten, through the step's reciprocal where it is whole: 1228 / 100
// is the double nearest 12.28, 1228 * 0.01 is not.
template <typename Round>
double to_step(double v, double step, Round round) {
  const double inverse = std::round(1 / step);
  return step < 1 ? round(v * inverse) / inverse : round(v / step) * step;
}

// `v` rounded up (towards hi) to a multiple of `step`.
double round_up_to(double v, double step, double hi) {
  return std::min(to_step(v, step, [](double x) { return std::ceil(x - 1e-9); }), hi);
}

}  // namespace

double step_up(double v, double step) {
  return to_step(v + step, step, [](double x) { return std::round(x); });
}

namespace {

// The smallest meeting design `best` in round numbers: each variable
// rounded up to a power of ten near the tolerance, then one such step up at
// a time (at most five) until the rounded design meets the task; the first
// that does becomes the best. None: `best` stays as the search found it.
void round_up(Search& search, std::size_t& best) {
  const Row found = search.row(best);
  const Eigen::Index k = search.lo().size();
  VectorXd steps(k), v(k);
  for (Eigen::Index d = 0; d < k; ++d) {
    const double x = found.values[std::size_t(d)];
    const double scale = x != 0 ? std::abs(x) : search.hi()(d) - search.lo()(d);
    steps(d) = std::pow(10.0, std::floor(std::log10(std::max(search.tolerance() * scale, 1e-300))));
    v(d) = round_up_to(x, steps(d), search.hi()(d));
  }
  for (int attempt = 0; attempt < 5 && !search.cancelled(); ++attempt) {
    const std::size_t i = search.evaluate(v);
    if (i >= search.result().rows.size()) return;
    if (search.row(i).meets) {
      best = i;
      return;
    }
    for (Eigen::Index d = 0; d < k; ++d) v(d) = std::min(step_up(v(d), steps(d)), search.hi()(d));
  }
}

// The smallest design meeting the task: a scan, then rays from the lower
// corner (docs/task-volumes.md).
void smallest_size(Search& search) {
  const VectorXd lo = search.lo(), hi = search.hi();
  Result& r = search.result();
  std::vector<std::size_t> scanned;
  for (const VectorXd& v : scan_points(lo, hi)) {
    if (search.cancelled()) break;
    scanned.push_back(search.evaluate(v));
  }
  require_a_valid_design(r);

  // The smallest meeting scanned designs.
  std::vector<std::size_t> meeting;
  for (std::size_t i : scanned)
    if (i < r.rows.size() && r.rows[i].meets) meeting.push_back(i);
  std::sort(meeting.begin(), meeting.end(), [&](std::size_t a, std::size_t b) { return r.rows[a].cost < r.rows[b].cost; });

  const Eigen::Index k = lo.size();
  if (!meeting.empty() && !search.cancelled()) {
    // The lower corner, once: the ray searches end there.
    const std::size_t corner = search.evaluate(lo);
    if (corner < r.rows.size() && !r.rows[corner].meets) {
      if (k == 1) {
        // Between the smallest meeting scan point and the one before it.
        const VectorXd w = hi - lo;
        const double span = w(0) > 0 ? w(0) : 1;
        const double t_meet = (r.rows[meeting.front()].values[0] - lo(0)) / span;
        search.bisect(w, std::max(0.0, t_meet - 1.0 / 6), t_meet, meeting.front());
      } else if (k == 2) {
        // The boundary along rays from the lower corner at angle theta (in
        // the bounds' normalised square); its size is minimised over theta
        // by golden section around the best scanned design's angle.
        const VectorXd span = (hi - lo).cwiseMax(1e-300);
        auto ray = [&](double theta) {
          const Eigen::Vector2d d(std::cos(theta), std::sin(theta));
          return VectorXd(span.cwiseProduct(d / d.maxCoeff()));
        };
        std::vector<std::pair<double, double>> known;  // theta, boundary t
        auto boundary_size = [&](double theta) -> double {
          const VectorXd w = ray(theta);
          double guess = 1;
          double nearest = kInf;
          for (const auto& [th, t] : known)
            if (std::abs(th - theta) < nearest) nearest = std::abs(th - theta), guess = t;
          // Bracket the boundary around the guess, then bisect.
          double t_meet = std::min(1.0, guess * 1.05), t_fail = 0;
          std::size_t at = search.evaluate(search.on_ray(w, t_meet));
          if (at >= r.rows.size()) return kInf;
          while (!r.rows[at].meets && t_meet < 1) {
            t_fail = t_meet;
            t_meet = std::min(1.0, t_meet * 1.25);
            at = search.evaluate(search.on_ray(w, t_meet));
            if (at >= r.rows.size()) return kInf;
          }
          if (!r.rows[at].meets) return kInf;  // the whole ray fails
          if (t_fail == 0) {
            double t = guess * 0.95;
            for (int it = 0; it < 20 && t > 1e-3; ++it, t *= 0.8) {
              const std::size_t below = search.evaluate(search.on_ray(w, t));
              if (below >= r.rows.size()) return kInf;
              if (!r.rows[below].meets) {
                t_fail = t;
                break;
              }
              t_meet = t;
              at = below;
            }
          }
          const auto found = search.bisect(w, t_fail, t_meet, at);
          if (!found) return kInf;
          // The ray's parameter of the design found, along w's longer component.
          Eigen::Index along = 0;
          w.cwiseAbs().maxCoeff(&along);
          known.push_back({theta, (r.rows[*found].values[std::size_t(along)] - lo(along)) / w(along)});
          return r.rows[*found].cost;
        };
        const Row& b = r.rows[meeting.front()];
        const double theta_best = std::atan2((b.values[1] - lo(1)) / span(1), (b.values[0] - lo(0)) / span(0));
        known.push_back({theta_best, std::max((b.values[0] - lo(0)) / span(0), (b.values[1] - lo(1)) / span(1))});
        double a = std::max(0.0, theta_best - std::numbers::pi / 8), c = std::min(std::numbers::pi / 2, theta_best + std::numbers::pi / 8);
        const double g = (std::sqrt(5.0) - 1) / 2;
        double x1 = c - g * (c - a), x2 = a + g * (c - a);
        double f1 = boundary_size(x1), f2 = boundary_size(x2);
        while (c - a > 5e-3 && !search.cancelled()) {
          if (f1 <= f2) {
            c = x2, x2 = x1, f2 = f1;
            x1 = c - g * (c - a);
            f1 = boundary_size(x1);
          } else {
            a = x1, x1 = x2, f1 = f2;
            x2 = a + g * (c - a);
            f2 = boundary_size(x2);
          }
        }
      } else {
        // Each of the three smallest meeting designs shortened along the ray
        // from the lower corner.
        for (std::size_t i = 0; i < std::min<std::size_t>(3, meeting.size()) && !search.cancelled(); ++i) {
          const VectorXd w = Eigen::Map<const VectorXd>(r.rows[meeting[i]].values.data(), k) - lo;
          search.bisect(w, 0.0, 1.0, meeting[i]);
        }
      }
    }
  }

  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const Row& row = r.rows[i];
    if (row.meets && (!r.best || row.cost < r.rows[*r.best].cost)) r.best = i;
    if (row.invalid.empty() && (!r.closest || row.fit > r.rows[*r.closest].fit)) r.closest = i;
  }
  if (r.best && !search.cancelled()) round_up(search, *r.best);
  if (r.best) {
    r.closest.reset();
    for (Eigen::Index d = 0; d < k; ++d)
      r.at_lower_bounds = r.at_lower_bounds || r.rows[*r.best].values[std::size_t(d)] <= lo(d) + 1e-12 * std::abs(lo(d));
  }
}

// The size as an affine function of the variables, size = held + c . v.
struct SizeLine {
  VectorXd c;
  double held = 0;
  double at(const VectorXd& v) const { return held + c.dot(v); }
};

// The size line measured on designs: from the middle of the bounds and a
// step of a quarter of each variable's span (the other way where that
// design cannot be built), checked at the bounds' corners. A compiled
// device's size is a sum of parameters (FitVariables.EverySizeIsTheSumItDescribes);
// a described one's is an expression of its description, which --size
// refuses where these designs show it is not affine.
SizeLine size_line(const Problem& problem, const VectorXd& lo, const VectorXd& hi) {
  const std::string described = make_mechanism(problem.preset)->info().size_description;
  auto size_at = [&](const VectorXd& v) -> std::optional<double> {
    try {
      return make_mechanism(design_preset(problem, std::vector<double>(v.data(), v.data() + v.size())))->size();
    } catch (const std::invalid_argument&) {
      return std::nullopt;  // a design that cannot be built
    }
  };
  const VectorXd mid = (lo + hi) / 2;
  const std::optional<double> at_mid = size_at(mid);
  if (!at_mid)
    throw std::invalid_argument("fit: --size measures the size (" + described +
                                ") on the design at the middle of the bounds, which cannot be built");
  SizeLine line;
  line.c = VectorXd::Zero(lo.size());
  for (Eigen::Index i = 0; i < lo.size(); ++i) {
    const double step = (hi(i) - lo(i)) / 4;
    if (step == 0) continue;  // a variable that cannot move
    std::optional<double> moved;
    for (const double sign : {1.0, -1.0}) {
      VectorXd v = mid;
      v(i) += sign * step;
      if ((moved = size_at(v))) {
        line.c(i) = (*moved - *at_mid) / (sign * step);
        break;
      }
    }
    if (!moved)
      throw std::invalid_argument("fit: --size measures the size (" + described + ") on designs around the middle "
                                  "of the bounds; moving " + problem.variables[std::size_t(i)].name() +
                                  " a quarter of its span either way gives designs that cannot be built");
  }
  line.held = *at_mid - line.c.dot(mid);
  for (const VectorXd& corner : {lo, hi}) {
    const std::optional<double> measured = size_at(corner);
    if (measured && std::abs(*measured - line.at(corner)) > 1e-9 * std::max(std::abs(*measured), std::abs(*at_mid)))
      throw std::invalid_argument("fit: --size needs a size that changes in proportion to the free parameters "
                                  "(as a sum of them does); this device's size (" + described + ") is " +
                                  format_number(*measured) + " at a corner of the bounds where that would give " +
                                  format_number(line.at(corner)));
  }
  return line;
}

// The design of size `size` nearest to u within the bounds (Euclidean, in
// the variables' units): clip(u + lambda c) with lambda found by bisection,
// the size being monotone in lambda.
VectorXd onto_size(const SizeLine& line, double size, const VectorXd& u, const VectorXd& lo, const VectorXd& hi) {
  auto at = [&](double lambda) { return VectorXd((u + lambda * line.c).cwiseMax(lo).cwiseMin(hi)); };
  double a = -1, b = 1;
  while (line.at(at(a)) > size && a > -1e12) a *= 2;
  while (line.at(at(b)) < size && b < 1e12) b *= 2;
  for (int it = 0; it < 200 && b - a > 1e-15 * std::max(1.0, std::abs(a) + std::abs(b)); ++it) {
    const double mid = 0.5 * (a + b);
    (line.at(at(mid)) < size ? a : b) = mid;
  }
  return at(0.5 * (a + b));
}

// The largest ratio among designs of the given size: the scan's designs
// moved onto the size, then a compass search from the best along each
// variable (each step moved onto the size), halving the step (from a
// quarter of the bounds) until it falls below the tolerance.
void largest_ratio_at_size(const Problem& problem, Search& search) {
  const double size = *problem.size;
  if (!std::isfinite(size) || size <= 0)
    throw std::invalid_argument("fit: the size must be positive and finite, got " + format_number(size));
  const VectorXd lo = search.lo(), hi = search.hi();
  const SizeLine line = size_line(problem, lo, hi);
  const std::string described = make_mechanism(problem.preset)->info().size_description;
  if (line.c.isZero())
    throw std::invalid_argument("fit: --size needs a free parameter the size counts (" + described + ")");
  // (A size may fall as a parameter grows.)
  const double smallest = line.held + line.c.cwiseProduct(lo).cwiseMin(line.c.cwiseProduct(hi)).sum(),
               largest = line.held + line.c.cwiseProduct(lo).cwiseMax(line.c.cwiseProduct(hi)).sum();
  if (size < smallest * (1 - 1e-12) || size > largest * (1 + 1e-12))
    throw std::invalid_argument("fit: no design within the bounds has size " + described + " = " + format_number(size) +
                                " (they span " + format_number(smallest) + " to " + format_number(largest) + ")");
  Result& r = search.result();
  auto ratio_of = [&](std::size_t i) { return i < r.rows.size() && r.rows[i].invalid.empty() ? r.rows[i].ratio : -kInf; };
  std::optional<std::size_t> best;
  for (const VectorXd& v : scan_points(lo, hi)) {
    if (search.cancelled()) break;
    const std::size_t i = search.evaluate(onto_size(line, size, v, lo, hi));
    if (i < r.rows.size() && (!best || ratio_of(i) > ratio_of(*best))) best = i;
  }
  require_a_valid_design(r);
  const VectorXd span = hi - lo;
  for (double step = 0.25; best && step >= problem.tolerance && !search.cancelled();) {
    bool moved = false;
    const VectorXd from = Eigen::Map<const VectorXd>(r.rows[*best].values.data(), lo.size());
    for (Eigen::Index d = 0; d < lo.size() && !moved && !search.cancelled(); ++d)
      for (const double sign : {1.0, -1.0}) {
        VectorXd next = from;
        next(d) += sign * step * span(d);
        const std::size_t i = search.evaluate(onto_size(line, size, next, lo, hi));
        if (ratio_of(i) > ratio_of(*best)) {
          best = i;
          moved = true;
          break;
        }
      }
    if (!moved) step /= 2;
  }
  if (best && r.rows[*best].invalid.empty()) (r.rows[*best].meets ? r.best : r.closest) = best;
}

}  // namespace

Result solve(const Problem& problem, const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  check_bounds(problem.variables, "fit");
  const auto motors = std::count_if(problem.variables.begin(), problem.variables.end(),
                                    [](const Variable& v) { return motor_parameter(v.parameters.front()) != nullptr; });
  if (motors > 0 && motors < std::ptrdiff_t(problem.variables.size()))
    throw std::invalid_argument("fit: free motor ratings and free lengths together have no smallest design (the ratings "
                                "do not change the size); fit the linkage with the ratings held (--param), or the "
                                "ratings with the linkage held");
  if (motors > 0 && problem.size)
    throw std::invalid_argument("fit: --size holds the linkage's size, which motor ratings do not change; fit the "
                                "smallest ratings without --size");
  if (!(problem.tolerance > 0 && problem.tolerance < 1))
    throw std::invalid_argument("fit: the tolerance must lie in (0, 1)");
  Search search(problem, progress);
  Result& r = search.result();
  if (problem.size) largest_ratio_at_size(problem, search);
  else smallest_size(search);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

std::string score_header(const Problem& p) {
  std::string s = "cx,cy,cz,size,meets,samples,failing";
  if (!p.task.centre) s += p.task.shape == task::Shape::Sphere ? ",inscribed_diameter" : ",inscribed_scale";
  s += ",fraction,ratio";
  for (const task::Criterion& c : p.criteria)
    s += "," + csv_text("worst_" + c.measure) + "," + csv_text("margin_" + c.measure) + "," + csv_text("failing_" + c.measure);
  return s;
}

std::string score_cells(const Problem& p, const Row& row) {
  std::ostringstream s;
  s << csv_number(row.centre.x()) << "," << csv_number(row.centre.y()) << "," << csv_number(row.centre.z()) << ","
    << csv_number(row.size) << "," << (row.meets ? 1 : 0) << "," << row.report.samples << "," << row.report.failing;
  if (!p.task.centre) s << "," << csv_number(p.task.shape == task::Shape::Sphere ? row.fit * p.task.diameter() : row.fit);
  s << "," << csv_number(row.report.fraction) << "," << csv_number(row.ratio);
  for (const task::CriterionReport& c : row.report.criteria)
    s << "," << csv_number(c.worst) << "," << csv_number(c.margin()) << "," << c.failing;
  return s.str();
}

double centre_step(double device_size) {
  return std::pow(10.0, std::floor(std::log10(std::max(std::abs(device_size), 1e-300))) - 4);
}

void check_bounds(const std::vector<Variable>& variables, const std::string& command) {
  if (variables.empty()) throw std::invalid_argument(command + ": no free design parameter");
  for (const Variable& v : variables)
    if (!(std::abs(v.lo) <= kLargestBound && std::abs(v.hi) <= kLargestBound && v.lo <= v.hi))
      throw std::invalid_argument(command + ": the bounds of " + v.name() + " must lie within -" +
                                  format_number(kLargestBound) + " to " + format_number(kLargestBound) +
                                  " (the parameter's unit) with lo <= hi, got " + format_number(v.lo) + ":" +
                                  format_number(v.hi));
}

Preset design_preset(const Problem& problem, const std::vector<double>& values) {
  Preset preset = problem.preset;
  for (std::size_t i = 0; i < problem.variables.size() && i < values.size(); ++i)
    for (const std::string& name : problem.variables[i].parameters) preset.parameters[name] = values[i];
  return preset;
}

std::optional<Row> evaluate(const Problem& problem, const std::vector<double>& values, const std::atomic<bool>* cancel) {
  if (values.size() != problem.variables.size())
    throw std::invalid_argument("fit: a design needs " + std::to_string(problem.variables.size()) + " values, got " +
                                std::to_string(values.size()));
  // Scalar code waits on upper register halves other libraries leave in use
  // (core/simd.h): 4x on the 12R's point-wise task evaluation.
  simd::clear_upper_registers();
  Row row;
  row.values = values;
  const Preset preset = design_preset(problem, values);
  std::shared_ptr<const Mechanism> mechanism;
  try {
    mechanism = make_mechanism(preset);
  } catch (const std::invalid_argument& e) {
    row.invalid = e.what();
    return row;
  }
  row.parameters = design_parameters(*mechanism, preset);
  row.size = mechanism->size();
  row.cost = row.size;
  if (!problem.variables.empty() && motor_parameter(problem.variables.front().parameters.front()))
    row.cost = std::accumulate(values.begin(), values.end(), 0.0);  // free ratings: the smallest ones
  task::Device device;
  device.mechanism = mechanism;
  device.fixed_task = problem.pose.size() ? problem.pose : mechanism->home_task();
  if (device.fixed_task.size() != Eigen::Index(mechanism->info().task.size()))
    throw std::invalid_argument("fit: the pose needs " + std::to_string(mechanism->info().task.size()) +
                                " task coordinates");
  device.ik = problem.ik;
  device.torque = problem.torque;
  device.threads = problem.threads;
  const bool haptic = std::any_of(problem.criteria.begin(), problem.criteria.end(),
                                  [](const task::Criterion& c) { return c.haptic(); });
  if (haptic) {
    try {
      device.data = haptics::device_data(preset, mechanism->info());
    } catch (const std::invalid_argument& e) {  // e.g. a continuous torque above the peak
      row.invalid = e.what();
      return row;
    }
  }
  const std::vector<task::Criterion> criteria = task::resolve(device, problem.criteria);
  const task::TaskVolume& t = problem.task;
  row.home = mechanism->home_task().head<3>();
  if (t.centre) {
    row.centre = *t.centre;
    row.report = task::evaluate(device, criteria, t, row.centre, problem.task_resolution);
    row.fit = row.report.fraction;
  } else {
    FieldProgress fp;
    fp.cancel = cancel;
    task::InscribedOptions options = problem.inscribed;
    options.prefer_near = row.home;
    Eigen::AlignedBox3d box = mechanism->default_box();
    if (options.centres)  // the shapes around every allowed centre are sampled
      box.extend(options.centres->bounds().min() - t.size).extend(options.centres->bounds().max() + t.size);
    const auto places = task::inscribed_places(device, criteria, t, box, options, fp);
    if (!places) return std::nullopt;  // cancelled
    // Each place, nearest the home point first, evaluated until one meets the
    // task (the 12R's good region is symmetric: equal places lie on both
    // sides); where none does, the largest. The centre is rounded to the
    // step the report prints.
    const double step = centre_step(row.size);
    auto rounded = [&](double x) { return to_step(x, step, [](double y) { return std::round(y); }); };
    auto centred = [&](const task::Inscribed& place) {
      return Eigen::Vector3d(rounded(place.centre.x()), rounded(place.centre.y()), rounded(place.centre.z()));
    };
    std::vector<const task::Inscribed*> order;
    for (const task::Inscribed& place : *places)
      if (place.found) order.push_back(&place);
    std::stable_sort(order.begin(), order.end(), [&](const task::Inscribed* a, const task::Inscribed* b) {
      return (a->centre - row.home).norm() < (b->centre - row.home).norm();
    });
    const task::Inscribed* chosen = nullptr;
    for (const task::Inscribed* place : order) {
      // A place whose shape is clearly smaller than the task cannot hold it
      // (it would fail); the largest is evaluated whatever its size.
      const double ratio = t.shape == task::Shape::Sphere ? place->size / t.diameter() : place->size;
      if (place != &places->front() && ratio < kPlausibleRatio) continue;
      if (auto report = task::evaluate_if_meets(device, criteria, t, centred(*place), problem.task_resolution)) {
        chosen = place;
        row.report = std::move(*report);
        break;
      }
    }
    if (!order.empty()) {
      if (!chosen) {  // none meets: the largest, fully evaluated
        chosen = &places->front();
        row.report = task::evaluate(device, criteria, t, centred(*chosen), problem.task_resolution);
      }
      row.centre = centred(*chosen);
      row.fit = t.shape == task::Shape::Sphere ? chosen->size / t.diameter() : chosen->size;
    }
    if (order.empty()) {  // no sample meets every criterion
      row.centre = options.centres ? options.centres->bounds().center() : mechanism->default_box().center();
      row.report = task::evaluate(device, criteria, t, row.centre, problem.task_resolution);
    }
  }
  row.meets = row.report.meets();
  row.ratio = t.centre ? fixed_centre_ratio(row.report) : row.fit;
  return row;
}

}  // namespace linkscape::fit
