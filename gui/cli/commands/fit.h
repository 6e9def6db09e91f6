// linkscape fit: the smallest design of a device whose task volume meets the
// criteria, or the largest ratio at a given size (core/fit.h), as a report, a CSV of every design evaluated and a
// Pareto chart of size against the worst measure.
#pragma once

#include <CLI/CLI.hpp>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "core/fit.h"
#include "gui/cli/sampling.h"

namespace linkscape::gui {

struct FitOptions {
  SamplingOptions device;              // the device, pose (default: each design's home), method, branch, torque
  std::string task;                    // "sphere:diameter=15[,centre=x,y,z]" or "box:size=..."
  std::vector<std::string> criteria;   // "cond<3", "force_iso>1", ...; reach is always implied
  std::vector<std::string> free;       // free parameters (empty: the design panel's)
  std::vector<std::string> equal;      // groups held equal, e.g. "L1,L2"
  std::vector<std::string> bounds;     // "NAME=lo:hi"
  int resolution = 64, refinements = 2, places = 3;  // the largest inscribed shape (docs/task-volumes.md)
  int task_resolution = task::kTaskResolution;  // the task evaluated at its centre
  std::string centre_region;           // where a free centre may go (core/task.h CentreRegion); empty: anywhere
  double tolerance = 1e-3;             // relative, on the size (or the ratio search's step)
  std::optional<double> size;          // set: the largest ratio at this size
  std::string output;                  // CSV: the smallest design first, then every design by size
  std::string chart;                   // size against the worst measure (.png, .svg, .pdf)
  bool quiet = false;                  // no progress on stderr
  // Certified sizing instead of the sampled search: the answer bracketed
  // between a design proved to meet the task and one disproved, `bracket`
  // apart (the variable's unit); one free variable (core/verify/verify.h).
  bool certify = false;
  double bracket = 0.05;
};

// Runs the search, writes the CSV and chart when asked and prints the
// chosen design, every criterion's margin and the time to `out`. A task no
// design meets is a result ("no design in the bounds meets it; closest:
// ..."), not an error. Throws std::invalid_argument for bad options (exit 2,
// nothing written). The chart needs a QGuiApplication. Returns the exit
// status: 0, or with --certify the certified sizing's (0 bracketed, 3 even
// the upper bound disproved, 4 undecided).
int run_fit(const FitOptions& options, std::ostream& out);

// The parts `fit` shares with `sweep`: the device, task, criteria, free
// parameters and sampling options (every FitOptions field but size,
// tolerance, output, chart and quiet), and the problem they describe,
// checked (messages start with `command`; throws std::invalid_argument).
void add_problem_options(CLI::App& command, FitOptions& options, const DeviceHelp& devices);
fit::Problem make_problem(const FitOptions& options, const std::string& command);

}  // namespace linkscape::gui
