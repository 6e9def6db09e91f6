// Fuzz target for the CSV reader (core/csv.h): any text either reads as a
// table whose rows all have the header's width, or throws
// std::invalid_argument that names the origin and a line of the input. A
// table written back with format_number reads back to the same table.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/csv.h"
#include "fuzz_check.h"

namespace {

constexpr std::string_view kOrigin = "fuzz.csv";

bool same_number(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::memcmp(&a, &b, sizeof a) == 0;  // also tells -0 from 0
}

std::string write_back(const linkscape::Table& table) {
  std::string text;
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    if (i) text += ',';
    text += table.columns[i];
  }
  text += '\n';
  for (const auto& row : table.rows) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (i) text += ',';
      text += linkscape::format_number(row[i]);
    }
    text += '\n';
  }
  return text;
}

// The message is "origin:line: ..." (line 1-based, within the input) or
// "origin: ..." for an input without a header.
void check_message(const std::string& message, const std::string& text) {
  FUZZ_CHECK(message.starts_with(std::string(kOrigin) + ":"), "message: " << message);
  std::size_t pos = kOrigin.size() + 1, line = 0;
  if (pos < message.size() && message[pos] == ' ') return;
  const std::size_t lines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  for (; pos < message.size() && message[pos] >= '0' && message[pos] <= '9' && line <= lines; ++pos)
    line = 10 * line + static_cast<std::size_t>(message[pos] - '0');
  FUZZ_CHECK(line >= 1 && line <= lines && pos < message.size() && message[pos] == ':',
             "message names no line of the input (" << lines << " lines): " << message);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  linkscape::Table table;
  try {
    std::istringstream in(text);
    table = linkscape::read_csv(in, std::string(kOrigin));
  } catch (const std::invalid_argument& e) {
    check_message(e.what(), text);
    return 0;
  }

  FUZZ_CHECK(!table.columns.empty(), "a table without columns");
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    FUZZ_CHECK(table.rows[r].size() == table.columns.size(),
               "row " << r << " has " << table.rows[r].size() << " values, header " << table.columns.size());

  // column() finds the first column of a name and throws for a missing one.
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    const std::size_t found = table.column(table.columns[i]);
    FUZZ_CHECK(found <= i && table.columns[found] == table.columns[i], "column('" << table.columns[i] << "') = " << found);
  }
  bool threw = false;
  try {
    table.column("\n");  // a header field never holds a newline
  } catch (const std::invalid_argument&) {
    threw = true;
  }
  FUZZ_CHECK(threw, "column() of a missing name did not throw");

  // Round trip: the shortest text of each number reads back to the same bits.
  const std::string again_text = write_back(table);
  std::istringstream again_in(again_text);
  linkscape::Table again;
  try {
    again = linkscape::read_csv(again_in, "written back");
  } catch (const std::invalid_argument& e) {
    FUZZ_CHECK(false, "the table written back does not read: " << e.what() << "\n" << again_text);
  }
  FUZZ_CHECK(again.columns == table.columns, "header changed in the round trip:\n" << again_text);
  FUZZ_CHECK(again.rows.size() == table.rows.size(), "row count changed in the round trip:\n" << again_text);
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    for (std::size_t c = 0; c < table.columns.size(); ++c)
      FUZZ_CHECK(same_number(again.rows[r][c], table.rows[r][c]),
                 "value " << table.rows[r][c] << " read back as " << again.rows[r][c] << " (written '"
                          << linkscape::format_number(table.rows[r][c]) << "')");
  return 0;
}
