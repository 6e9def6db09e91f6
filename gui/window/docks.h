// The window's docks and status bar: a scrollable dock per panel, the
// methods dock, and the status bar of a window with fields.
#pragma once

#include <QString>
#include <functional>
#include <initializer_list>

#include "core/preset.h"

class QDockWidget;
class QLabel;
class QMainWindow;
class QProgressBar;
class QWidget;

namespace linkscape::gui {

class FieldJobRunner;
class MethodsPanel;
class VtkWidget;

// A dock on the right holding `content` (scrollable); `name` is its object name.
QDockWidget* add_dock(QMainWindow* window, const QString& title, const QString& name, QWidget* content);

// A "Methods" dock tabbed behind `tab_with`, measuring `preset`'s methods
// when the user presses Run (keep it current with MethodsPanel::setMechanism).
MethodsPanel* add_methods_dock(QMainWindow* window, const Preset& preset, QDockWidget* tab_with);

// The status bar of a window with fields: compute time (set by the window; it
// and the frame time hidden until View > Show timings),
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

}  // namespace linkscape::gui
