// A window panel (QDockWidget content) with the interactive speed-against-
// accuracy chart of the numerical methods and their table (gui/window/methods_view.h),
// for the mechanism parameters the main window passes in; Enlarge shows them
// in a window of its own. "Run" measures them again
// on a worker thread (the GUI stays responsive), with progress text and
// Cancel; results come back to the GUI thread through a queued call.
#pragma once

#include <QWidget>
#include <cstddef>
#include <memory>
#include <vector>

#include "core/method_harness.h"
#include "core/preset.h"
#include "gui/window/background.h"

class QComboBox;
class QLabel;
class QPushButton;

namespace linkscape::gui {

class MethodsView;
class MethodsWindow;

class MethodsPanel : public QWidget {
  Q_OBJECT

 public:
  explicit MethodsPanel(QWidget* parent = nullptr);
  ~MethodsPanel() override;  // cancels and joins a running measurement

  // The device (a preset with the window's current parameters) that the
  // next Run measures through its Mechanism::measure_methods. Throws
  // std::invalid_argument for an invalid preset. Does not start a run.
  void setMechanism(const linkscape::Preset& preset);
  // Samples (workspace targets or poses) per run, and timed repeats; fields
  // are measured, by the devices whose harness times them, only when
  // include_fields is set (they take seconds). Defaults: 2000 samples,
  // 3 repeats, no fields.
  void setHarnessSize(std::size_t samples, int repeats, bool include_fields = false);

  const std::vector<methods::MethodRow>& rows() const;
  MethodsView* view() const { return view_; }
  MethodsWindow* enlargedWindow() const { return enlarged_; }  // null until Enlarge
  const linkscape::Preset& mechanism() const { return preset_; }
  bool isRunning() const { return task_.running(); }
  QString statusText() const;

 public slots:
  void run();     // no-op while running
  void enlarge();  // shows (and raises) the chart and table in a window of their own
  void cancel();  // the running measurement stops at its next stage

 signals:
  void runFinished(bool completed);  // false when cancelled or failed

 private:
  void finish(std::vector<methods::MethodRow> rows, bool completed, const QString& message);

  linkscape::Preset preset_;
  QString measured_title_;  // the device the shown rows measured
  std::size_t samples_ = 2000;
  int repeats_ = 3;
  bool include_fields_ = false;
  MethodsView* view_ = nullptr;
  MethodsWindow* enlarged_ = nullptr;  // a child: lives as long as the panel
  QLabel* status_ = nullptr;
  QComboBox* compare_ = nullptr;  // a second preset measured beside this device
  QPushButton* run_button_ = nullptr;
  QPushButton* cancel_button_ = nullptr;
  // Last, so a run in flight is cancelled and joined before the rest goes.
  BackgroundTask task_;  // its end disables Cancel
};

}  // namespace linkscape::gui
