#include "render/colour_scale.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "core/field_names.h"
#include "core/status.h"

namespace linkscape::render {

namespace {
constexpr int kStatuses = 5;  // linkscape::Status, Ok .. OutOfLimits

double sample_value(const Field& f, const std::string& name, std::size_t s) {
  if (const auto a = field_array(name)) return field_value(f, field_array_info(*a), s);
  if (const Field::NamedArray* a = f.extra(name)) return a->values[s];
  return f.cond[s];
}
}  // namespace

double percentile(std::vector<double> values, double q) {
  if (values.empty()) throw std::invalid_argument("percentile: expected at least one value, got none");
  if (!(q >= 0 && q <= 1)) throw std::invalid_argument("percentile: expected a fraction in [0, 1], got " + std::to_string(q));
  std::sort(values.begin(), values.end());
  const double rank = q * double(values.size() - 1);
  const std::size_t below = std::size_t(std::floor(rank));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (rank - double(below)) * (values[above] - values[below]);
}

bool is_categorical(const std::string& field) {
  const auto a = field_array(field);
  return a == FieldArray::Status || a == FieldArray::Method;
}

bool is_integer(const std::string& field) { return field_array(field) == FieldArray::Iterations; }

AutoRange robust_range(const Field& field, const SliceStyle& style_in, double low, double high) {
  SliceStyle style = style_in;
  style.min.reset();
  style.max.reset();
  const auto [full_lo, full_hi] = colour_range(field, style);  // validates; the full range of the values
  AutoRange out{full_lo, full_hi, false, false};
  const auto a = field_array(style.field);
  if (a == FieldArray::Cond || a == FieldArray::CondOrientation || is_categorical(style.field)) return out;
  const bool log = uses_log_scale(style);
  std::vector<double> values;
  for (std::size_t s = 0; s < field.grid.size(); ++s) {
    if (!field.reachable[s]) continue;
    const double v = sample_value(field, style.field, s);
    if (std::isfinite(v) && (!log || v > 0)) values.push_back(v);
  }
  if (values.empty()) return out;
  const auto [min_it, max_it] = std::minmax_element(values.begin(), values.end());
  const double min = *min_it, max = *max_it;
  double lo = percentile(values, low), hi = percentile(values, high);
  if (is_integer(style.field)) {
    lo = std::floor(lo);
    hi = std::ceil(hi);
  }
  if (style.colour_map == "diverging" && !log) centre_diverging_range(style.field, lo, hi);
  if (!(lo < hi)) return out;  // all equal: colour_range's widened range
  out = {lo, hi, min < lo, max > hi};
  return out;
}

SliceStyle categorical_style(const SliceStyle& style) {
  SliceStyle out = style;
  if (field_array(style.field) == FieldArray::Status) {
    out.min = -0.5;
    out.max = kStatuses - 0.5;
    out.log_scale = false;
  }
  return out;
}

std::vector<LegendEntry> categorical_legend(const Field& field, const SliceStyle& style) {
  std::vector<LegendEntry> out;
  const auto a = field_array(style.field);
  if (a == FieldArray::Status) {
    const SliceStyle s = categorical_style(style);
    for (int k = 0; k < kStatuses; ++k)
      out.push_back({double(k), std::string(to_string(Status(k))), colour_of(normalised_value(k, s), s.colour_map)});
  } else if (a == FieldArray::Method) {
    std::set<int> codes;
    for (std::size_t s = 0; s < field.method_used.size(); ++s)
      if (field.reachable[s]) codes.insert(field.method_used[s]);
    for (int code : codes) out.push_back({double(code), method_code_name(field, code), method_colour(std::uint8_t(code))});
  }
  return out;
}

std::vector<double> integer_ticks(double lo, double hi, int count) {
  std::vector<double> ticks;
  for (double t : nice_ticks(lo, hi, count))
    if (t == std::round(t)) ticks.push_back(t);
  if (ticks.size() < 2) {  // a step below 1: every whole number in range
    ticks.clear();
    for (double t = std::ceil(lo); t <= hi; t += 1) ticks.push_back(t);
  }
  return ticks;
}

}  // namespace linkscape::render
