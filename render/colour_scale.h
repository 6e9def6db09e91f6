// How the window colours a slice when the user has not typed a range:
// robust automatic ranges (percentiles, so one spike does not wash out the
// rest), ranges centred on 0 for the diverging map, integer ranges and
// ticks for counts, and discrete legends for the categorical fields.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/field.h"
#include "render/slice_image.h"

namespace linkscape::render {

// The value at fraction q (0..1) of `values` sorted (linear between ranks,
// as numpy's default). Throws std::invalid_argument for no values or q
// outside [0, 1].
double percentile(std::vector<double> values, double q);

struct AutoRange {
  double lo = 0, hi = 1;
  // Values beyond the range exist (drawn in the end colours): the colour
  // bar marks these ends.
  bool clipped_low = false, clipped_high = false;
};

// The automatic range of style.field over the reachable samples with a
// value (finite; > 0 on a log scale): from the `low` to the `high`
// percentile (defaults 1st and 99th); symmetric about 0 for the diverging
// map; widened to whole numbers for iterations. cond and the categorical
// fields keep colour_range()'s. Throws std::invalid_argument as colour_range.
AutoRange robust_range(const Field& field, const SliceStyle& style, double low = 0.01, double high = 0.99);

// Whether `field` (a style's field name) is a code with names (status,
// method) rather than a quantity, or a count (iterations).
bool is_categorical(const std::string& field);
bool is_integer(const std::string& field);

struct LegendEntry {
  double value;  // the code
  std::string label;
  std::array<double, 3> rgb;  // as the slice draws it
};
// The discrete legend of a categorical field: every status by name, or
// every method that some reachable sample of `field` used, by its name
// (core/field_names.h: method_code_name). Empty for
// other fields. The slice must be drawn with categorical_style() so the
// colours match.
std::vector<LegendEntry> categorical_legend(const Field& field, const SliceStyle& style);
// `style` with the range that gives each status its own colour (status:
// -0.5 .. 4.5, linear); other fields unchanged.
SliceStyle categorical_style(const SliceStyle& style);

// Ticks at whole numbers over [lo, hi] (steps of 1, 2, 5, 10, ...), about `count`.
std::vector<double> integer_ticks(double lo, double hi, int count = 5);

}  // namespace linkscape::render
