// linkscape: kinematic design of parallel haptic-device mechanisms.
#include <exception>
#include <iostream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "gui/cli/cli.h"
#include "gui/window/launch.h"

int main(int argc, char** argv) {
  try {
    const linkscape::gui::WindowLauncher window{linkscape::gui::prepare_window, linkscape::gui::run_window};
    const int code = linkscape::gui::run(argc, argv, &window);
    linkscape::check_stdout();  // output lost to a full disk or a closed pipe is an error
    return code;
  } catch (const std::invalid_argument& e) {
    std::cerr << "linkscape: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "linkscape: error: " << e.what() << "\n";
    return 1;
  }
}
