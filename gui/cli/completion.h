// The values an option takes, for the shell's completion (packaging/
// linkscape.bash-completion asks `linkscape --complete-values OPTION`), read
// from the same lists the commands check against, so the two never differ.
#pragma once

#include <string>
#include <vector>

#include "gui/cli/device_help.h"

namespace linkscape::gui {

// The values of `option` (with or without its dashes): methods and fields of
// every device, colour maps, torque ratings, plane and criterion stems.
// Empty for an option with free values (numbers, files).
std::vector<std::string> completion_values(const std::string& option, const DeviceHelp& help);

}  // namespace linkscape::gui
