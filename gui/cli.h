// Command-line entry: the window (default) or a headless command.
#pragma once

namespace linkscape::gui {

// Parses the command line and runs the window or a headless command.
// Returns the process exit code: 0 success, 2 bad arguments or input,
// 1 other failures. std::invalid_argument escaping means bad input (2).
int run(int argc, char** argv);

}  // namespace linkscape::gui
