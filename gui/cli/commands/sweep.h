// linkscape sweep: a grid or random sample of a device's design parameters,
// each design scored as fit scores it plus field measures, written as one
// CSV table with the Pareto front marked (core/sweep.h); the same command on
// one process or under mpirun (gui/cli/sweep_ranks.h). docs/sweeps.md.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>

#include "gui/cli/commands/fit.h"

namespace linkscape::gui {

struct SweepOptions {
  FitOptions problem;            // device, task, criteria, free parameters and bounds, sampling
  std::optional<int> grid;       // values per free parameter, bounds included (at least 2)
  std::size_t random = 0;        // or this many uniform random designs
  std::uint64_t seed = 1;
  int field_resolution = 0;      // field measures over the default box (0: none)
  int threads = 0;               // per process (0: OpenMP's default)
  std::size_t chunk = 16;        // most designs handed to a rank at once
  std::string output;            // the table (.csv)
  std::string checkpoint;        // default: <output>.checkpoint
  bool resume = false;
  std::string chart;             // Pareto chart (.png, .svg, .pdf)
  std::string vti;               // a grid sweep of 1 to 3 variables as image data
  bool quiet = false;
};

// Runs the sweep on this process, or as one rank of an MPI job. Rank 0
// writes the checkpoint as designs finish, then the table and chart, and
// prints a summary to `out`; the other ranks write nothing. Throws
// std::invalid_argument for bad options (exit 2, nothing written). The
// chart needs a QGuiApplication.
void run_sweep(const SweepOptions& options, std::ostream& out);

}  // namespace linkscape::gui
