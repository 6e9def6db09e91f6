// What the command line asks of the window: the device or session to open
// and what to do with it. A plain struct, so the command line needs no window
// code; main() hands the request to the window (gui/window/launch.h).
#pragma once

#include <string>
#include <vector>

#include "core/mechanism.h"

namespace linkscape::gui {

struct WindowOptions {
  PresetChoice mechanism;
  std::string session;         // open this session file at start
  std::string file;            // a session or a preset given as the argument (resolved into the two above)
  std::string screenshot;      // save a PNG of the window and exit
  bool latency = false;        // measure interaction latencies, print them and exit
  std::string size = "1280x800";
  std::string view_image;      // save the 3-D view alone as PNG at view_size and exit
  std::string view_size = "1920x1080";
  bool size_given = false;     // --size was on the command line (else the remembered size is used)
  // A task volume shown at start (Task tab): "sphere:diameter=15[,centre=x,y,z]"
  // and its criteria; without a centre it is placed in the largest sphere.
  std::string task;
  std::vector<std::string> criteria;
};

// The window as the command line sees it; null in a build without a window.
struct WindowLauncher {
  // Resolves `file` into a session or a preset and loads it: throws
  // std::invalid_argument for bad files and parameters (exit 2).
  void (*prepare)(WindowOptions& options);
  // Opens the window (QApplication lives there). Returns the exit code.
  int (*run)(const WindowOptions& options, int argc, char** argv);
  // Prints the window's keyboard shortcuts (--shortcuts). Returns the exit code.
  int (*print_shortcuts)(int argc, char** argv);
};

}  // namespace linkscape::gui
