// Numeric CSV tables with a header row, for the headless commands.
#pragma once

#include <istream>
#include <string>
#include <vector>

namespace linkscape {

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  // Index of a column; throws std::invalid_argument listing the columns.
  std::size_t column(const std::string& name) const;
};

// Reads a header row then rows of numbers. Blank lines and lines starting
// with '#' are skipped. Throws std::invalid_argument with "origin:line: ..."
// for a wrong field count or a field that is not a number.
Table read_csv(std::istream& in, const std::string& origin);

// Shortest text that reads back to the same double ("%.17g"-exact).
std::string format_number(double value);

}  // namespace linkscape
