// Certified sizing: bisection of one design variable between a proved and a
// disproved design.
#include <chrono>
#include <cmath>

#include "core/verify/verify.h"

namespace linkscape::verify {

namespace {

Result verify_design(const SizingProblem& problem, double value) {
  Preset preset = problem.preset;
  for (const std::string& name : problem.variable.parameters) preset.parameters[name] = value;
  task::TaskVolume task = problem.task;
  if (problem.centre_at) task.centre = problem.centre_at(value);
  else if (problem.centre_scales_from) task.centre = *task.centre * (value / *problem.centre_scales_from);
  Result r = verify(preset, task, problem.criteria, problem.options, problem.branch);
  r.proved_boxes.clear();
  r.undecided_boxes.clear();
  return r;
}

}  // namespace

SizingResult size(const SizingProblem& problem, const std::function<void(const SizingStep&)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  const fit::Variable& v = problem.variable;
  if (v.parameters.empty()) throw std::invalid_argument("certified sizing: no parameter to size");
  if (!(std::isfinite(v.lo) && std::isfinite(v.hi) && v.lo < v.hi))
    throw std::invalid_argument("certified sizing: the bounds of " + v.name() + " must be finite with lo < hi, got " +
                                std::to_string(v.lo) + ":" + std::to_string(v.hi));
  if (!(problem.tolerance > 0) || !std::isfinite(problem.tolerance))
    throw std::invalid_argument("certified sizing: the tolerance must be positive, got " +
                                std::to_string(problem.tolerance));
  fit::check_bounds({v}, "certified sizing");
  if (!problem.task.centre && !problem.centre_at)
    throw std::invalid_argument("certified sizing: the task needs its centre (,centre=x,y,z) or a placement");
  if (problem.centre_scales_from && !(*problem.centre_scales_from > 0 && std::isfinite(*problem.centre_scales_from)))
    throw std::invalid_argument("certified sizing: the centre's reference value must be positive, got " +
                                std::to_string(*problem.centre_scales_from));

  SizingResult out;
  out.variable = v.name();
  out.tolerance = problem.tolerance;
  auto step = [&](double value) -> const Result& {
    out.steps.push_back({value, verify_design(problem, value)});
    if (progress) progress(out.steps.back());
    const Result& r = out.steps.back().result;
    if (r.verdict == Verdict::Proved && (!out.proved_at || value < *out.proved_at)) out.proved_at = value, out.proved = r;
    if (r.verdict == Verdict::Disproved && (!out.disproved_at || value > *out.disproved_at))
      out.disproved_at = value, out.disproved = r;
    return r;
  };
  auto finish = [&] {
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
  };

  if (step(v.hi).verdict != Verdict::Proved) return finish();
  const Verdict at_lo = step(v.lo).verdict;
  if (at_lo == Verdict::Proved) {
    out.proved_at_lower_bound = true;
    return finish();
  }
  if (at_lo != Verdict::Disproved) return finish();
  while (*out.proved_at - *out.disproved_at > problem.tolerance) {
    const double mid = 0.5 * (*out.proved_at + *out.disproved_at);
    if (step(mid).verdict == Verdict::Undecided) break;
  }
  return finish();
}

std::function<Eigen::Vector3d(double)> placement_by_fit(const fit::Problem& problem) {
  if (problem.variables.size() != 1)
    throw std::invalid_argument("certified sizing sizes one variable (parameters held equal count as one), got " +
                                std::to_string(problem.variables.size()));
  if (problem.task.centre) throw std::invalid_argument("certified sizing: placement by fit needs a task without a centre");
  return [problem](double value) {
    const std::optional<fit::Row> row = fit::evaluate(problem, {value});
    if (!row || !row->invalid.empty())
      throw std::invalid_argument("certified sizing: no placement for " + problem.variables[0].name() + " = " +
                                  std::to_string(value) + (row ? ": " + row->invalid : ""));
    return Eigen::Vector3d(row->centre);
  };
}

int exit_status(const SizingResult& r) {
  if (r.bracketed()) return kExitProved;
  if (!r.proved_at && r.disproved_at) return kExitDisproved;
  return kExitUndecided;
}

}  // namespace linkscape::verify
