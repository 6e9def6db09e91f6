// Commands a device adds to `linkscape` beside the generic ones (e.g.
// PATHOS-II's design study). gui/cli/mechanisms/commands.cpp is the one list.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <iosfwd>
#include <vector>

#include "gui/cli/headless.h"

namespace linkscape::gui {

struct DeviceCommand {
  CLI::App* command = nullptr;             // the subcommand (parsed() after parsing)
  std::function<void(std::ostream&)> run;  // runs it with the parsed options; charts need a QGuiApplication
};

// Adds every device's commands to `app`.
std::vector<DeviceCommand> add_device_commands(CLI::App& app);

// The --mechanism and --param options every command shares (gui/cli/cli.cpp).
void add_mechanism_options(CLI::App& app, PresetChoice& choice);

}  // namespace linkscape::gui
