#include "gui/cli/mechanisms/commands.h"

#include "gui/cli/mechanisms/pathos2/design.h"

namespace linkscape::gui {

std::vector<DeviceCommand> add_device_commands(CLI::App& app) { return {add_design_command(app)}; }

}  // namespace linkscape::gui
