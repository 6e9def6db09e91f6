#include "core/csv.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace linkscape {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// Fields as RFC 4180 writes them: a field in double quotes may hold commas,
// and "" within it is one quote (spreadsheets quote cells: "0").
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false, was_quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c != '"') field += c;
      else if (i + 1 < line.size() && line[i + 1] == '"') field += line[++i];
      else quoted = false;
    } else if (c == '"' && trim(field).empty()) {
      field.clear();
      quoted = was_quoted = true;
    } else if (c == ',') {
      fields.push_back(was_quoted ? field : trim(field));
      field.clear();
      was_quoted = false;
    } else if (!(was_quoted && std::isspace(static_cast<unsigned char>(c)))) {
      field += c;
    }
  }
  fields.push_back(was_quoted ? field : trim(field));
  return fields;
}

}  // namespace

std::size_t Table::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i;
  std::string have;
  for (const auto& c : columns) have += (have.empty() ? "" : ",") + c;
  throw std::invalid_argument(origin + ": missing column '" + name + "' (header is: " + have + ")");
}

std::string Table::where(std::size_t row) const {
  return origin + ":" + std::to_string(row < lines.size() ? lines[row] : 0);
}

std::optional<double> parse_number(std::string_view text, bool* out_of_range) {
  if (out_of_range) *out_of_range = false;
  // from_chars takes no '+'; a sign followed by another sign is not a number.
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (!text.empty() && (text.front() == '+' || text.front() == '-')) return std::nullopt;
  }
  if (text.empty()) return std::nullopt;
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ptr != text.data() + text.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) {
    if (out_of_range) *out_of_range = true;
    return std::nullopt;
  }
  if (ec != std::errc()) return std::nullopt;
  return v;
}

double parse_number_or_throw(std::string_view text, const std::string& what, bool allow_non_finite) {
  bool out_of_range = false;
  const std::optional<double> v = parse_number(text, &out_of_range);
  std::string quoted = "'";  // appended: GCC 12 warns (-Wrestrict) on "'" + string here, wrongly
  quoted += text;
  quoted += '\'';
  if (out_of_range)
    throw std::invalid_argument(what + ": " + quoted +
                                " is out of the range of double precision (magnitudes 2.2e-308 to 1.8e308, or 0)");
  if (!v) throw std::invalid_argument(what + ": " + quoted + " is not a number");
  if (!allow_non_finite && !std::isfinite(*v))
    throw std::invalid_argument(what + ": " + quoted + " is not a finite number");
  return *v;
}

Table read_csv(std::istream& in, const std::string& origin) {
  Table t;
  t.origin = origin;
  std::string line;
  int number = 0;
  const auto at = [&](int n) { return origin + ":" + std::to_string(n) + ": "; };
  while (std::getline(in, line)) {
    ++number;
    // Spreadsheets save UTF-8 with a byte-order mark before the header.
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    // Anywhere else one is an invisible character inside a name or number.
    if (line.find("\xEF\xBB\xBF") != std::string::npos)
      throw std::invalid_argument(at(number) + "byte-order mark (U+FEFF) inside the text; only the file's first bytes may hold one");
    const std::string content = trim(line);
    if (content.find('\r') != std::string::npos)
      throw std::invalid_argument(at(number) + "lines end in a lone carriage return (CR); save the file with LF or CR LF "
                                  "line ends");
    if (content.empty() || content[0] == '#') continue;
    const auto fields = split(content);
    if (t.columns.empty()) {
      // numpy's savetxt writes its header as a comment ("# x,y,z"), which is skipped.
      if (std::all_of(fields.begin(), fields.end(), [](const std::string& f) { return parse_number(f).has_value(); }))
        throw std::invalid_argument(at(number) + "the header holds numbers ('" + content +
                                    "'); the first line that is not a comment (#) must name the columns");
      for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].empty()) throw std::invalid_argument(at(number) + "column " + std::to_string(i + 1) + " of the header has no name");
        for (std::size_t j = 0; j < i; ++j)
          if (fields[j] == fields[i]) throw std::invalid_argument(at(number) + "column '" + fields[i] + "' appears twice in the header");
      }
      t.columns = fields;
      continue;
    }
    if (fields.size() != t.columns.size())
      throw std::invalid_argument(at(number) + "expected " + std::to_string(t.columns.size()) + " fields, got " +
                                  std::to_string(fields.size()));
    std::vector<double> row;
    row.reserve(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (fields[i].empty()) {  // no value, as csv_number writes NaN
        row.push_back(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      bool out_of_range = false;
      const std::optional<double> v = parse_number(fields[i], &out_of_range);
      if (!v)
        throw std::invalid_argument(at(number) + "column '" + t.columns[i] + "': '" + fields[i] + "' " +
                                    (out_of_range ? "is out of the range of double precision" : "is not a number"));
      row.push_back(*v);
    }
    t.rows.push_back(std::move(row));
    t.lines.push_back(number);
  }
  if (t.columns.empty()) throw std::invalid_argument(origin + ": empty input, expected a header row");
  return t;
}

std::string format_number(double value) {
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, value);
  return ec == std::errc() ? std::string(buf, ptr) : std::string("nan");
}

// + 0.0: a cell of -0 is 0 (the sign of a zero is an artefact of its arithmetic).
std::string csv_number(double value) { return std::isnan(value) ? std::string() : format_number(value + 0.0); }

std::string csv_column(std::string_view name, std::string_view unit) {
  std::string column(name);
  if (!unit.empty()) (column += '_') += unit;
  return column;
}

std::string csv_text(std::string_view text) {
  const bool plain = text.find_first_of(",\"\r\n") == std::string_view::npos &&
                     (text.empty() || (text.front() != ' ' && text.back() != ' '));
  if (plain) return std::string(text);
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + '"';
}

std::vector<std::string> csv_cells(std::string_view line) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (true) {
    std::string cell;
    if (at < line.size() && line[at] == '"') {
      for (++at;; ++at) {
        if (at >= line.size()) throw std::invalid_argument("CSV line: a quoted cell is not closed");
        if (line[at] == '"') {
          if (at + 1 < line.size() && line[at + 1] == '"') ++at;
          else break;
        }
        cell += line[at];
      }
      ++at;  // past the closing quote
      if (at < line.size() && line[at] != ',')
        throw std::invalid_argument("CSV line: a quoted cell is followed by '" + std::string(1, line[at]) +
                                    "', not a comma");
    } else {
      const std::size_t comma = std::min(line.find(',', at), line.size());
      cell = line.substr(at, comma - at);
      at = comma;
    }
    out.push_back(std::move(cell));
    if (at >= line.size()) return out;
    ++at;  // past the comma
  }
}

}  // namespace linkscape
