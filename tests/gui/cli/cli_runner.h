// Runs the linkscape binary as a user does, for the command-line tests.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <map>
#include <string>
#include <vector>

#include "core/csv.h"

namespace fs = std::filesystem;

namespace cli_runner {

// Whether the binary has the window: a build with -DLINKSCAPE_WINDOW=OFF has
// the commands alone, and the tests that open the window skip there.
inline constexpr bool kWindowBuilt = LINKSCAPE_TEST_WINDOW;
#define SKIP_WITHOUT_WINDOW() \
  if (!cli_runner::kWindowBuilt) GTEST_SKIP() << "this build has no window (-DLINKSCAPE_WINDOW=OFF)"

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout and stderr
};

// Runs a shell command line, capturing what it prints (add 2>&1 for stderr).
inline CommandResult run_shell(const std::string& command) {
  CommandResult r;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  while (std::size_t n = fread(buffer, 1, sizeof buffer, pipe)) r.out.append(buffer, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Runs the binary with `args`; `environment` is prefixed as in a shell;
// `stdout_redirect` (e.g. ">/dev/full") sends stdout elsewhere, so that `out`
// holds stderr alone.
inline CommandResult run_linkscape(const std::string& args, const std::string& environment = "",
                                   const std::string& stdout_redirect = "") {
  return run_shell(environment + " " + std::string(LINKSCAPE_BINARY) + " " + args + " 2>&1 " + stdout_redirect);
}

inline fs::path temp_file(const std::string& name, const std::string& content) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << content;
  return p;
}

inline linkscape::Table parse(const std::string& csv) {
  std::istringstream in(csv);
  return linkscape::read_csv(in, "output");
}

// Rows of a CSV with text cells (such as a status column), keyed by header.
inline std::vector<std::map<std::string, std::string>> parse_cells(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::vector<std::string> header;
  auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::stringstream ss(text);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (!text.empty() && text.back() == ',') cells.push_back("");
    return cells;
  };
  std::getline(in, line);
  header = split(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const auto cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < header.size(); ++k) row[header[k]] = k < cells.size() ? cells[k] : "";
    rows.push_back(row);
  }
  return rows;
}

}  // namespace cli_runner

using namespace cli_runner;
