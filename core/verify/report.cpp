// The text and JSON forms of certified verdicts and sizings.
#include <cmath>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/csv.h"
#include "core/verify/verify.h"

namespace linkscape::verify {
namespace {

using nlohmann::json;

std::string short_number(double v, int digits = 6) {
  if (!std::isfinite(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream out;
  out << std::setprecision(digits) << v;
  return out.str();
}

std::string point_text(const Eigen::Vector3d& p) {
  return "(" + short_number(p.x()) + ", " + short_number(p.y()) + ", " + short_number(p.z()) + ")";
}

// JSON has no infinity: unbounded values are null.
json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json point_json(const Eigen::Vector3d& p) { return json::array({p.x(), p.y(), p.z()}); }

std::string design_text(const std::map<std::string, double>& parameters) {
  std::string text;
  for (const auto& [name, value] : parameters) text += (text.empty() ? "" : ", ") + name + " = " + short_number(value);
  return text;
}

void write_counterexample(std::ostream& out, const Counterexample& ce) {
  out << "  counterexample: " << point_text(ce.point) << " fails " << ce.criterion << ": " << ce.reason << "\n";
  if (std::isfinite(ce.bound))
    out << "    there: certified bound " << short_number(ce.bound, 8) << ", long double "
        << short_number(ce.long_double_value, 8) << ", the device " << short_number(ce.device_value, 8) << "\n";
}

json counterexample_json(const Counterexample& ce) {
  return {{"point", point_json(ce.point)},
          {"criterion", ce.criterion},
          {"reason", ce.reason},
          {"bound", number(ce.bound)},
          {"long_double_value", number(ce.long_double_value)},
          {"device_value", number(ce.device_value)}};
}

json result_json(const Result& r) {
  json j = {{"verdict", std::string(to_string(r.verdict))},
            {"mechanism", r.mechanism},
            {"parameters", r.parameters},
            {"task", r.task},
            {"criteria", r.criteria},
            {"counterexample", r.counterexample ? counterexample_json(*r.counterexample) : json(nullptr)},
            {"largest_box_bound", r.largest_box_bound ? json(*r.largest_box_bound) : json(nullptr)},
            {"task_volume", r.task_volume},
            {"proved_volume", r.proved_volume},
            {"undecided_volume", r.undecided_volume},
            {"undecided_fraction", r.undecided_fraction()},
            {"boxes", r.boxes},
            {"deepest", r.deepest},
            {"timed_out", r.timed_out},
            {"box_limit", r.box_limit},
            {"seconds", r.seconds}};
  if (!r.not_covered.empty())
    j["not_covered"] = {{"what", r.not_covered},
                        {"samples", r.stop_samples},
                        {"stopped", r.stop_failures},
                        {"example", r.stop_example}};
  return j;
}

std::string criteria_text(const std::vector<std::string>& criteria) {
  std::string text;
  for (const std::string& c : criteria) text += (text.empty() ? "" : ", ") + c;
  return text;
}

}  // namespace

void write_report(std::ostream& out, const Result& r) {
  out << "verify " << r.mechanism << " (" << design_text(r.parameters) << "): " << r.task << " meeting "
      << criteria_text(r.criteria) << "\n";
  switch (r.verdict) {
    case Verdict::Proved:
      out << "proved: every point of the task meets every criterion\n";
      break;
    case Verdict::Disproved:
      out << "disproved: a point of the task fails\n";
      write_counterexample(out, *r.counterexample);
      break;
    case Verdict::Undecided:
      out << "undecided: no point found failing, but " << short_number(100 * r.undecided_fraction())
          << " % of the task's volume is not proved ("
          << (r.timed_out ? "time limit reached" : r.box_limit ? "too many open boxes" : "depth limit reached") << ")\n";
      break;
  }
  if (!r.not_covered.empty()) {
    out << "  not covered: " << r.not_covered << " (the verdict is about the device without them)\n";
    const std::string sampled = "    the device's own evaluation with them, not certified: ";
    if (r.stop_samples > 0 && r.stop_failures == 0)
      out << sampled << "they stop none of " << r.stop_samples << " samples of the task\n";
    else if (r.stop_failures > 0)
      out << sampled << "they stop " << r.stop_failures << " of " << r.stop_samples << " samples of the task, e.g. at "
          << r.stop_example << "\n";
  }
  out << "  " << r.boxes << " boxes, " << r.deepest << " bisections deep, " << short_number(r.seconds) << " s\n";
}

void write_json(std::ostream& out, const Result& r) { out << result_json(r).dump(2) << "\n"; }

void write_report(std::ostream& out, const SizingResult& s) {
  out << "certified sizing of " << s.variable << " (tolerance " << short_number(s.tolerance) << ")\n";
  if (s.proved_at_lower_bound) {
    out << s.variable << " <= " << short_number(*s.proved_at) << ": proved at the lower bound (lower it to go smaller)\n";
  } else if (s.proved_at && s.disproved_at) {
    out << s.variable << " in (" << short_number(*s.disproved_at) << ", " << short_number(*s.proved_at)
        << "]: proved at " << short_number(*s.proved_at) << "; disproved at " << short_number(*s.disproved_at);
    const Counterexample& ce = *s.disproved->counterexample;
    out << " by " << point_text(ce.point) << ", " << ce.reason << "\n";
    out << "  the task there: " << s.proved->task << " (proved), " << s.disproved->task << " (disproved)\n";
    if (!s.bracketed()) out << "  the bracket is wider than the tolerance: a design between was undecided\n";
  } else if (s.proved_at) {
    out << "proved at " << short_number(*s.proved_at) << ", but the lower bound was not disproved\n";
  } else if (s.disproved_at) {
    out << "no design in the bounds is proved: disproved at the upper bound " << short_number(*s.disproved_at) << " by "
        << point_text(s.disproved->counterexample->point) << ", " << s.disproved->counterexample->reason << "\n";
  } else {
    out << "undecided at the upper bound: no design proved\n";
  }
  for (const SizingStep& step : s.steps)
    out << "  " << s.variable << " = " << short_number(step.value) << ": " << to_string(step.result.verdict) << " ("
        << step.result.boxes << " boxes, " << short_number(step.result.seconds) << " s)\n";
  out << "  " << s.steps.size() << " designs in " << short_number(s.seconds) << " s\n";
}

void write_json(std::ostream& out, const SizingResult& s) {
  json steps = json::array();
  for (const SizingStep& step : s.steps) steps.push_back({{"value", step.value}, {"result", result_json(step.result)}});
  json j = {{"variable", s.variable},
            {"tolerance", s.tolerance},
            {"bracketed", s.bracketed()},
            {"proved_at", s.proved_at ? json(*s.proved_at) : json(nullptr)},
            {"disproved_at", s.disproved_at ? json(*s.disproved_at) : json(nullptr)},
            {"proved_at_lower_bound", s.proved_at_lower_bound},
            {"counterexample", s.disproved ? counterexample_json(*s.disproved->counterexample) : json(nullptr)},
            {"steps", steps},
            {"seconds", s.seconds}};
  out << j.dump(2) << "\n";
}

}  // namespace linkscape::verify
