// Screenshot mode of the window: the event loop runs until the fields are
// computed in full and a frame shows them; then the picture is saved.
#pragma once

#include <QObject>
#include <QWidget>
#include <functional>
#include <string>

namespace linkscape::gui {

namespace detail {
// Runs the event loop until ready() after an update, then saves `path`:
// write() where given (it returns the size written, "WxH"), else the whole
// window. Returns the exit code.
int save_screenshot_when(QWidget& window, const std::string& path, const std::function<bool()>& ready,
                         const std::function<void(std::function<void()>)>& on_update,
                         const std::function<std::string()>& write = {});
}  // namespace detail

// Runs the event loop until the fields are computed in full
// (window.fieldsSettled() after fieldsUpdated) and a frame shows them, then
// writes a PNG of the window atomically. Returns the exit code: 0, or 1 if
// the file cannot be written or after 60 s.
template <class Window>
int save_screenshot_when_settled(Window& window, const std::string& path, std::function<std::string()> write = {}) {
  return detail::save_screenshot_when(
      window, path, [&window] { return window.fieldsSettled(); },
      [&window](std::function<void()> check) {
        QObject::connect(&window, &Window::fieldsUpdated, &window, [check](bool) { check(); });
      },
      write);
}

}  // namespace linkscape::gui
