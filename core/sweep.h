// Design sweeps (`linkscape sweep`): a grid or a seeded random sample of a
// device's free design parameters, each design scored as `fit` scores it
// (core/fit.h) plus, on request, conditioning measures over a sampled field,
// written as one CSV table in design order with its Pareto front marked.
// Rows are text from the start, so a table assembled from a checkpoint, from
// one process or from many is the same bytes. No MPI here: gui/sweep_mpi.*
// hands designs to ranks. docs/sweeps.md describes the measures and the runs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/fit.h"

namespace linkscape::sweep {

enum class Sampling { Grid, Random };

struct Plan {
  fit::Problem problem;              // the device, the free variables with their bounds, the task and criteria
  Sampling sampling = Sampling::Grid;
  int levels = 5;                    // grid: values per variable, bounds included
  std::size_t count = 100;           // random: designs
  std::uint64_t seed = 1;            // random: the designs are a function of the seed alone
  // Field measures: samples along the longest side of the device's default
  // box (0: none). Over the reachable samples: the reachable volume and the
  // GCI; over the samples inside the task at the design's centre: the
  // reachable share and the worst and mean first measure.
  int field_resolution = 0;
  std::vector<std::string> columns;  // design parameters named in the table (every free one among them)
};

// The number of designs of the plan. Throws std::invalid_argument for
// bounds fit::check_bounds refuses, fewer than 1 design, a grid of one
// level, or more than 10^9 designs.
std::size_t design_count(const Plan& plan);

// About the memory the sweep keeps until its table is written, in bytes.
double table_bytes(const Plan& plan);

// Every design of the plan, as one value per variable, in table order: the
// grid with the first variable slowest, or `count` uniform draws from a
// 64-bit Mersenne twister seeded with `seed`. Throws as design_count, and
// std::invalid_argument where table_bytes exceeds the memory available now.
std::vector<std::vector<double>> designs(const Plan& plan);

// The table's header line (no newline), pareto and error columns included.
std::string header(const Plan& plan);

// The table row of one design (no newline, the pareto cell left as "0"):
// never throws for the design itself; a design that cannot be built or whose
// evaluation throws has its reason in the error column (commas and line
// breaks replaced by spaces, the cell quoted as RFC 4180 quotes it) and empty scores.
std::string evaluate_row(const Plan& plan, std::size_t index, const std::vector<double>& values);

// The whole table, header first, rows in index order, with the pareto column
// set: 1 for each valid design that no other valid design beats on both size
// (smaller) and the first measure criterion's worst value (better; the margin
// where no criterion has a measure), as fit's chart draws its front.
// `rows` must hold every index 0..n-1.
std::string table(const Plan& plan, const std::map<std::size_t, std::string>& rows);

// The rows of a finished table as fit::Result rows (size, meets, fit, margin
// and each criterion's worst value), for fit's Pareto chart; rows with an error are
// left out. Also returns the index of the smallest meeting design, if any.
fit::Result as_fit_result(const Plan& plan, const std::map<std::size_t, std::string>& rows);

// A text that changes whenever anything that decides the table's bytes does
// (device, variables, task, criteria, sampling, resolutions); a checkpoint
// is resumed only under the same text.
std::string fingerprint(const Plan& plan);

// The checkpoint: a journal beside the table, its first line the plan's
// fingerprint, then each finished design's table row (its first cell the
// design index), appended and
// flushed as designs finish. A process killed mid-line leaves a partial last
// line, which resuming drops.
class Checkpoint {
 public:
  // Starts a new journal, or with `resume` reads the rows of an existing one
  // and appends to it. Throws std::invalid_argument where a new journal
  // would replace one (a stopped run's work), or `resume` finds no journal,
  // a journal of another plan, or a malformed line (naming file and line).
  Checkpoint(const std::filesystem::path& path, const Plan& plan, std::size_t designs, bool resume);
  const std::map<std::size_t, std::string>& rows() const { return rows_; }
  void add(std::size_t index, const std::string& row);  // appended; flush() writes it through
  void flush();
  // Once the table is written: the journal goes; a symbolic link to it
  // stays, as every output's link does.
  void remove();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::filesystem::path file_;  // path_ with its links followed
  std::ofstream out_;
  std::map<std::size_t, std::string> rows_;
};

}  // namespace linkscape::sweep
