#include "core/csv.h"

#include <charconv>
#include <sstream>
#include <stdexcept>

namespace linkscape {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream ss(line);
  std::string field;
  while (std::getline(ss, field, ',')) fields.push_back(trim(field));
  if (!line.empty() && line.back() == ',') fields.push_back("");
  return fields;
}

}  // namespace

std::size_t Table::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i;
  std::string have;
  for (const auto& c : columns) have += (have.empty() ? "" : ",") + c;
  throw std::invalid_argument("missing column '" + name + "' (header is: " + have + ")");
}

Table read_csv(std::istream& in, const std::string& origin) {
  Table t;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string content = trim(line);
    if (content.empty() || content[0] == '#') continue;
    const auto fields = split(content);
    if (t.columns.empty()) {
      t.columns = fields;
      continue;
    }
    if (fields.size() != t.columns.size())
      throw std::invalid_argument(origin + ":" + std::to_string(number) + ": expected " +
                                  std::to_string(t.columns.size()) + " fields, got " +
                                  std::to_string(fields.size()));
    std::vector<double> row;
    for (const auto& f : fields) {
      double v = 0.0;
      const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
      if (ec != std::errc() || ptr != f.data() + f.size() || f.empty())
        throw std::invalid_argument(origin + ":" + std::to_string(number) + ": '" + f +
                                    "' is not a number");
      row.push_back(v);
    }
    t.rows.push_back(std::move(row));
  }
  if (t.columns.empty()) throw std::invalid_argument(origin + ": empty input, expected a header row");
  return t;
}

std::string format_number(double value) {
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, value);
  return ec == std::errc() ? std::string(buf, ptr) : std::string("nan");
}

}  // namespace linkscape
