// Numeric CSV tables with a header row, for the headless commands.
#pragma once

#include <charconv>
#include <istream>
#include <type_traits>
#include <optional>
#include <string_view>
#include <string>
#include <vector>

namespace linkscape {

struct Table {
  std::string origin;  // file name, or "<stdin>"
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;  // 1-based line number of each row in the input
  // Index of a column; throws std::invalid_argument listing the columns.
  std::size_t column(const std::string& name) const;
  // "origin:line" of a row, for messages.
  std::string where(std::size_t row) const;
};

// Reads a header row then rows of numbers. Blank lines and lines starting
// with '#' are skipped, as is a UTF-8 byte-order mark. Numbers may carry a
// sign ('+' or '-'); "inf" and "nan" are read as such, and an empty cell
// as NaN (no value, as csv_number writes it); callers that need finite
// values check them. Throws std::invalid_argument with
// "origin:line: ..." for an empty or repeated column name, a wrong field
// count or a field that is not a number.
Table read_csv(std::istream& in, const std::string& origin);

// Parses one whole decimal number ("+1.5", "-2e-3", "inf"), or returns
// nothing for anything else. `out_of_range` is set when the text is a
// number that a double cannot hold (e.g. 1e400, or 1e-320 below the
// smallest normal double).
std::optional<double> parse_number(std::string_view text, bool* out_of_range = nullptr);

// parse_number for a user-facing value: throws std::invalid_argument
// "<what>: '<text>' is not a number" (or "... is out of the range of double
// precision") and, unless `allow_non_finite`, rejects inf and nan.
double parse_number_or_throw(std::string_view text, const std::string& what, bool allow_non_finite = false);

// Shortest text that reads back to the same double ("%.17g"-exact).
std::string format_number(double value);

// A number cell as every table writes it: format_number's exact round trip
// ("inf" and "-inf" for infinities), an empty cell for NaN (no value).
// A missing value is written as NaN through it, never as a stand-in (0, inf).
std::string csv_number(double value);

// Appends a number cell as csv_number writes it: a float as its own
// shortest text (0.1f as "0.1"), an integer as it is, NaN as nothing.
template <class T>
void append_csv_number(std::string& out, T value) {
  if constexpr (std::is_floating_point_v<T>)
    if (value != value) return;  // NaN: no value
  char buffer[64];               // enough for any number
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, ec == std::errc() ? end : buffer);
}

// A column's name in a header: `name` followed by "_" and its unit where it
// has one (x_cm, reach_margin_cm, force_iso_N); a column without a unit
// suffix holds a ratio, a count, a code or a label.
std::string csv_column(std::string_view name, std::string_view unit);

// A text cell as RFC 4180 writes it: quoted (inner quotes doubled) when it
// holds a comma, a quote, a line break or leading or trailing spaces; as it
// is otherwise. Names and statuses from a description file can hold any of them.
std::string csv_text(std::string_view text);

// The cells of one CSV line as csv_text writes them, unquoted. Throws
// std::invalid_argument for a quoted cell that is not closed or is
// followed by anything but a comma.
std::vector<std::string> csv_cells(std::string_view line);

}  // namespace linkscape

