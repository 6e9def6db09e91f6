#include "gui/window/launch.h"

#include "core/size_text.h"

#include <QApplication>
#include <QDockWidget>
#include <QFileInfo>
#include <QSettings>
#include <QSurfaceFormat>
#include <array>
#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "core/task.h"
#include "gui/window/export_actions.h"
#include "gui/window/latency_probe.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/screenshot.h"
#include "gui/window/session_history.h"
#include "gui/window/task_panel.h"
#include "gui/window/vtk_widget.h"

namespace linkscape::gui {

namespace {

// WIDTHxHEIGHT from min_w x min_h to kMaxWindowSide a side: off-screen
// framebuffers beyond that fail inside the OpenGL driver (a crash, not an
// error). Throws std::invalid_argument naming `option`.
std::array<int, 2> pixel_size(const std::string& text, const char* option, int min_w, int min_h) {
  return parse_width_height(text, option, {min_w, min_h, kMaxWindowSide});
}

}  // namespace

void prepare_window(WindowOptions& options) {
  if (!options.file.empty()) {
    if (is_session_file(options.file)) options.session = options.file;
    else options.mechanism.name_or_path = options.file;
  }
  if (!options.session.empty() && !options.mechanism.params.empty())
    throw std::invalid_argument("--param: a session brings its own design; open it and change the design in the window");
  if (!options.session.empty()) load_session(options.session);
  else make_mechanism(chosen_preset(options.mechanism));
  // The rest of the window's input, checked here too: bad input is exit 2,
  // with a display or without.
  if (!options.task.empty()) task::parse_task(options.task);
  for (const std::string& c : options.criteria) task::parse_criterion(c);
  pixel_size(options.size, "--size", 200, 150);
  if (!options.view_image.empty()) pixel_size(options.view_size, "--view-size", 16, 16);
}

int run_window(const WindowOptions& options, int argc, char** argv) {
  std::optional<Session> session;
  if (!options.session.empty()) session = load_session(options.session);  // bad file: exit code 2
  // A session brings its own mechanism.
  Preset preset = load_preset(session ? session->mechanism : options.mechanism.name_or_path);
  apply_overrides(preset, options.mechanism.params);
  const auto [width, height] = pixel_size(options.size, "--size", 200, 150);
  const auto [view_width, view_height] =
      options.view_image.empty() ? std::array<int, 2>{} : pixel_size(options.view_size, "--view-size", 16, 16);
  QSurfaceFormat::setDefaultFormat(VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setApplicationName("Linkscape");
  QApplication::setOrganizationName("Linkscape");
  MechanismWindow window(preset);
  if (session) {  // as File > Open session: the session's file is the document
    window.applySession(*session);
    window.applyViewSession(*session);
    window.history()->reset(QFileInfo(QString::fromStdString(options.session)).absoluteFilePath());
  }
  if (!options.task.empty()) {
    window.taskPanel()->setTask(options.task, options.criteria);
    if (auto* dock = window.findChild<QDockWidget*>("taskDock")) dock->raise();
  }
  // Interactive use remembers the window's size and layout; an explicit
  // --size, screenshots and latency runs start from the defaults.
  const bool interactive = options.screenshot.empty() && options.view_image.empty() && !options.latency;
  window.setInteractive(interactive);
  const QSettings settings;
  if (interactive && !options.size_given && settings.contains("windowGeometry")) {
    window.restoreGeometry(settings.value("windowGeometry").toByteArray());
    window.restoreState(settings.value("windowState").toByteArray());
  } else {
    window.resize(width, height);
  }
  window.show();
  if (options.latency) return run_latency_probe(window, std::cout);
  if (!options.view_image.empty())
    return save_screenshot_when_settled(window, options.view_image, [&] {
      save_png(window.viewImage(view_width, view_height), options.view_image);
      return std::to_string(view_width) + "x" + std::to_string(view_height);
    });
  if (options.screenshot.empty()) return QApplication::exec();
  return save_screenshot_when_settled(window, options.screenshot);
}

}  // namespace linkscape::gui
