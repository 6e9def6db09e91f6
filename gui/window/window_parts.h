// Pieces of the device window (gui/window/mechanism_window.h): docks, the preset
// chooser (picking another preset opens a window of that device in place,
// keeping the field settings) and the methods dock (speed against accuracy
// for the window's parameters).
#pragma once

#include <QObject>
#include <QString>
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>

#include "core/field.h"
#include "core/preset.h"
#include "gui/window/session.h"
#include "render/slice_image.h"

class QComboBox;
class QImage;
class QDockWidget;
class QLabel;
class QProgressBar;
class QMainWindow;
class QWidget;
class vtkPolyData;

namespace linkscape::gui {

class FieldJobRunner;
class MechanismWindow;
class MethodsPanel;
class VtkWidget;

// The status bar of a window with fields: compute time (set by the window),
// a progress bar fed by the runners and the frame time of the view.
struct FieldStatus {
  QLabel* compute = nullptr;
  QLabel* frame = nullptr;
  QProgressBar* progress = nullptr;
};
// A runner's failure is shown in the status bar, then `on_failure` runs (the
// window marks its fields settled: nothing more is coming).
FieldStatus add_field_status(QMainWindow* window, VtkWidget* view, std::initializer_list<FieldJobRunner*> runners,
                             const std::function<void()>& on_failure);

// A dock on the right holding `content` (scrollable); `name` is its object name.
QDockWidget* add_dock(QMainWindow* window, const QString& title, const QString& name, QWidget* content);

// A combo box of every preset on the search path, showing `current`. Picking
// another one opens a window of it (same size and place, same field settings
// where the device offers them) and closes `window`; a preset that fails to
// load leaves everything as it was and says why.
QComboBox* make_preset_chooser(QWidget* window, const Preset& current);

// Runs `work` on a worker thread and rethrows what it throws; the GUI thread
// meanwhile keeps drawing and running its timers (user input waits).
void run_off_gui_thread(const std::function<void()>& work);

// Reads a preset file and checks its model (load_preset, make_mechanism)
// through run_off_gui_thread: a large or hostile description never freezes
// the window. Throws what they throw.
Preset load_checked_preset(const std::string& name_or_path);

// A window of `preset`'s device in the place of `window` (same geometry and
// panel layout), with `session` applied, else with the old window's field
// settings; its document is `session_path` (empty: a new one). The old
// window says so (MechanismWindow::replacedBy) and closes. Throws
// std::invalid_argument with nothing changed.
MechanismWindow* replace_window(QWidget* window, const Preset& preset, const std::optional<Session>& session,
                                const QString& session_path = {});

// A "Methods" dock tabbed behind `tab_with`, measuring `preset`'s methods
// when the user presses Run (keep it current with MethodsPanel::setMechanism).
MethodsPanel* add_methods_dock(QMainWindow* window, const Preset& preset, QDockWidget* tab_with);

// Sessions from the window's File menu. A session of the window's own
// device is applied there; one of another device opens a window of it in
// its place. Failures are shown in a message box.
bool open_session_file(QMainWindow* window, const Preset& current, const QString& path);
bool save_session_file(QMainWindow* window, const Session& session, const QString& path);

// File menu exports of the window, through the headless commands' writers
// (atomic); a failure is shown in a message box. Without data, nothing happens.
void export_slice_image(QWidget* parent, const Field* slice, const render::SliceStyle& style);
void export_surface_mesh(QWidget* parent, const Field* volume, vtkPolyData* reach, vtkPolyData* well,
                         double cond_threshold);
void export_volume(QWidget* parent, const Field* volume);
void export_screenshot(QWidget* window);
// An image as PNG, atomically. Throws std::runtime_error if it cannot be written.
void save_png(const QImage& image, const std::string& path);

// Help menu: the versions of the program and its libraries; where the
// documentation is (the docs folder of the source tree when there is one,
// else the manual page).
void show_about(QWidget* parent);
void show_documentation(QWidget* parent);

namespace detail {
// Runs the event loop until ready() after an update, then saves `path`:
// write() where given (it returns the size written, "WxH"), else the whole
// window. Returns the exit code.
int save_screenshot_when(QWidget& window, const std::string& path, const std::function<bool()>& ready,
                         const std::function<void(std::function<void()>)>& on_update,
                         const std::function<std::string()>& write = {});
}  // namespace detail

// Screenshot mode of the window: runs the event loop until the fields
// are computed in full (window.fieldsSettled() after fieldsUpdated) and a
// frame shows them, then writes a PNG of the window atomically. Returns the
// exit code: 0, or 1 if the file cannot be written or after 60 s.
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
