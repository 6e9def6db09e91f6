// The window's entry points, handed to the command line by main().
#pragma once

#include "gui/cli/window_request.h"

namespace linkscape::gui {

// Resolves `options.file` (a session or a preset) and loads what the window
// will open; throws std::invalid_argument for bad files and parameters.
void prepare_window(WindowOptions& options);

// Opens the window (QApplication lives here). Returns the exit code.
int run_window(const WindowOptions& options, int argc, char** argv);

}  // namespace linkscape::gui
