// Work off the GUI thread while the window keeps drawing.
#pragma once

#include <functional>
#include <string>

#include "core/preset.h"

namespace linkscape::gui {

// Runs `work` on a worker thread and rethrows what it throws; the GUI thread
// meanwhile keeps drawing and running its timers (user input waits).
void run_off_gui_thread(const std::function<void()>& work);

// Reads a preset file and checks its model (load_preset, make_mechanism)
// through run_off_gui_thread: a large or hostile description never freezes
// the window. Throws what they throw.
Preset load_checked_preset(const std::string& name_or_path);

}  // namespace linkscape::gui
