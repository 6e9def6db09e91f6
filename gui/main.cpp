// linkscape: kinematic design of parallel haptic-device mechanisms.
#include <exception>
#include <iostream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "gui/cli/cli.h"
#ifdef LINKSCAPE_WITH_WINDOW
#include "gui/window/window_menus.h"
#include "gui/window/launch.h"
#endif

int main(int argc, char** argv) {
  try {
#ifdef LINKSCAPE_WITH_WINDOW
    const linkscape::gui::WindowLauncher window{linkscape::gui::prepare_window, linkscape::gui::run_window,
                                                linkscape::gui::print_shortcuts};
    const linkscape::gui::WindowLauncher* launcher = &window;
#else
    const linkscape::gui::WindowLauncher* launcher = nullptr;  // a build for cluster nodes: the commands alone
#endif
    const int code = linkscape::gui::run(argc, argv, launcher);
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
