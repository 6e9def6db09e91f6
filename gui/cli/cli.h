// Command-line entry: the window (default) or a headless command.
#pragma once

#include "gui/cli/window_request.h"

namespace linkscape::gui {

// Parses the command line and runs the window or a headless command.
// Returns the process exit code: 0 success, 2 bad arguments or input,
// 1 other failures. std::invalid_argument escaping means bad input (2).
// `window` opens the window; null in a build without one.
int run(int argc, char** argv, const WindowLauncher* window);

}  // namespace linkscape::gui
