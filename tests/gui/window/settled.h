// Showing a device window and waiting for its fields, for the window tests.
#pragma once

#include <QtTest>

namespace window_tests {

// Shows the window at 1200x800 and waits until its fields are computed in
// full; false when it is not exposed or the fields do not settle in 30 s.
template <class Window>
bool show_settled(Window& w) {
  w.resize(1200, 800);
  w.show();
  if (!QTest::qWaitForWindowExposed(&w)) return false;
  return QTest::qWaitFor([&] { return w.fieldsSettled(); }, 30000);
}

}  // namespace window_tests
