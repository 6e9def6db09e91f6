#include "gui/window/screenshot.h"

#include <QApplication>
#include <QImage>
#include <QTimer>
#include <iostream>

#include "gui/window/export_actions.h"
#include "gui/window/vtk_widget.h"

namespace linkscape::gui {

namespace detail {

int save_screenshot_when(QWidget& window, const std::string& path, const std::function<bool()>& ready,
                         const std::function<void(std::function<void()>)>& on_update,
                         const std::function<std::string()>& write) {
  int status = 1;
  bool grabbing = false;
  const std::function<void()> grab_when_ready = [&] {
    if (grabbing || !ready()) return;
    grabbing = true;
    // One more frame so the picture shows the last fields.
    QTimer::singleShot(100, &window, [&] {
      try {  // exceptions must not cross Qt's event loop
        const std::string size = write ? write() : [&] {
          const QImage image = VtkWidget::grabWindow(&window);
          save_png(image, path);
          return std::to_string(image.width()) + "x" + std::to_string(image.height());
        }();
        std::cout << "wrote " << path << " (" << size << ")\n";
        status = 0;
      } catch (const std::exception& e) {
        std::cerr << "linkscape: error: " << e.what() << "\n";
      }
      QApplication::quit();
    });
  };
  on_update(grab_when_ready);
  QTimer::singleShot(0, &window, grab_when_ready);
  QTimer::singleShot(60000, &window, [] {
    std::cerr << "linkscape: the window did not finish rendering within 60 s\n";
    QApplication::exit(1);
  });
  QApplication::exec();
  return status;
}

}  // namespace detail

}  // namespace linkscape::gui
