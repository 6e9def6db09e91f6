// The window's Task tab: a task volume (sphere or box, size, centre) and
// criteria, drawn in the scene coloured where the criteria fail, with live
// read-outs (share of the volume meeting them, each criterion's worst value
// and margin, where it fails) as the design, the pose or the task change,
// and the largest sphere or box of the good region on request
// (core/task.h; docs/task-volumes.md).
#pragma once

#include <QWidget>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/preset.h"
#include "core/task.h"
#include "core/verify/verify.h"
#include "gui/window/session.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QTimer;

namespace linkscape::render {
class TaskScene;
class VerifyRegions;
}

namespace linkscape::gui {

class BackgroundTask;

// "centre = home + (dx, dy, dz) unit": where a task's centre sits from the
// device's home point; differences below 1e-12 of `size` print as 0.
QString centre_from_home_text(const Eigen::Vector3d& centre, const Eigen::Vector3d& home, double size,
                              const QString& unit);

class TaskPanel : public QWidget {
  Q_OBJECT

 public:
  explicit TaskPanel(render::TaskScene* scene, QWidget* parent = nullptr);
  ~TaskPanel() override;

  // The device, its preset (actuator data) and the pose, whose coordinates
  // beyond x, y, z the task holds. The read-outs follow shortly (debounced);
  // a new device forgets the largest shape found for the old one.
  void setDevice(std::shared_ptr<const Mechanism> mechanism, const Preset& preset, const Eigen::VectorXd& task);
  // A task and criteria as the command line gives them (core/task.h), shown
  // at once; without a centre the task is placed at the largest shape of
  // the good region. Throws std::invalid_argument for bad text.
  void setTask(const std::string& task, const std::vector<std::string>& criteria);
  // The task's centre (the read-outs follow shortly, debounced).
  void setCentre(const Eigen::Vector3d& centre);
  // The read-outs now, without waiting for the debounce.
  void evaluateNow();
  // What a session keeps of the tab, and back (throws std::invalid_argument
  // for bad text, nothing changed then).
  TaskSetting setting() const;
  void applySetting(const TaskSetting& setting);

  // The task as the panel holds it (with its centre), and its criteria with
  // reach first, resolved on the device (throws std::invalid_argument for
  // bad text).
  task::TaskVolume volume() const;
  std::vector<task::Criterion> criteria() const;

  // Verify: a proof that every point of the task meets every criterion
  // (core/verify, on branch 0), or a counterexample, off the GUI thread;
  // the button cancels a run under way. The verdict's words, and in the
  // view the boxes proved and undecided and the counterexample
  // (render/verify_regions.h), stay until the design, the pose or the task
  // change.
  void verifyTask();
  const render::VerifyRegions& verifyRegions() const { return *regions_; }

  const std::optional<task::TaskReport>& report() const { return report_; }
  const std::optional<task::Inscribed>& largest() const { return largest_; }
  QString readout() const;

 signals:
  void changed();  // the scene changed: render the view

 private:
  task::Device device() const;                    // throws std::invalid_argument
  void schedule();
  void placeAtLargest();
  void showRegions(const verify::Result& result, double task_size);  // in the window's view
  void syncShape();

  render::TaskScene* scene_;
  std::shared_ptr<const Mechanism> mechanism_;
  Preset preset_;
  Eigen::VectorXd pose_;
  QCheckBox* show_box_ = nullptr;
  QComboBox* shape_box_ = nullptr;
  QDoubleSpinBox* size_[3] = {};
  QDoubleSpinBox* centre_[3] = {};
  QLabel* centre_label_ = nullptr;
  QLabel* size_label_ = nullptr;
  QLineEdit* criteria_edit_ = nullptr;
  QPushButton* place_button_ = nullptr;
  QLabel* readout_label_ = nullptr;
  QPushButton* verify_button_ = nullptr;
  QLabel* verdict_label_ = nullptr;
  std::unique_ptr<BackgroundTask> verifier_;
  std::unique_ptr<render::VerifyRegions> regions_;  // added to the window's view at the first verdict
  QTimer* debounce_ = nullptr;
  std::optional<task::TaskReport> report_;
  std::optional<task::Inscribed> largest_;
  bool centred_ = false;  // the centre was set for this device (else its home)
};

}  // namespace linkscape::gui
