// linkscape: kinematic design of parallel haptic-device mechanisms.
#include <exception>
#include <iostream>
#include <stdexcept>

#include "gui/cli.h"

int main(int argc, char** argv) {
  try {
    return linkscape::gui::run(argc, argv);
  } catch (const std::invalid_argument& e) {
    std::cerr << "linkscape: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "linkscape: error: " << e.what() << "\n";
    return 1;
  }
}
