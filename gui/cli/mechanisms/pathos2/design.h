// linkscape design: the PATHOS-II design studies of the paper — the Table 2
// grid search over l2, l3, lp and the initial Rz (cost G of Eq. 21) and the
// l0 sweep of Fig. 6 — written as CSV tables and one chart.
#pragma once

#include <iosfwd>
#include <string>

#include "gui/cli/headless.h"
#include "gui/cli/mechanisms/commands.h"

namespace linkscape::gui {

struct DesignOptions {
  PresetChoice mechanism{"pathos2", {}};  // Table 1 values: l0 = 50 unless --param l0 says otherwise
  std::string table;   // Table 2 search as CSV (one row per design)
  std::string sweep;   // l0 sweep as CSV
  std::string chart;   // both as a chart (.png, .svg, .pdf)
  bool quick = false;  // a coarse grid (a smoke test, not the paper's Table 2)
  bool quiet = false;  // no progress on stderr
};

// Runs the search and the sweep, writes what was asked for and prints a
// summary (best design, the paper's design and its rank) to `out`. Throws
// std::invalid_argument for bad options (nothing written).
void run_design(const DesignOptions& options, std::ostream& out);

// `linkscape design`, added to the command line.
DeviceCommand add_design_command(CLI::App& app);

}  // namespace linkscape::gui
