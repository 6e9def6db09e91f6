// The Drive panel: which sliders move the device (task coordinates by
// inverse kinematics, or actuators by forward kinematics), the assembly
// branch, one slider per task coordinate and per actuator, and the
// read-outs of the pose (status, measures, the haptic forces force_iso and
// force_max at the continuous torque, nearest singular set, branch, the
// device's own). Built from the device's description.
#pragma once

#include <QString>
#include <QWidget>
#include <memory>
#include <string>
#include <vector>

#include "core/mechanism.h"

class QComboBox;
class QFormLayout;
class QGroupBox;
class QLabel;

namespace linkscape::gui {

class DeviceState;
struct QuantityControl;

// Task: the task sliders drive by inverse kinematics. Actuators: the
// actuator sliders drive by forward kinematics (task coordinates listed in
// info().fk_inputs stay editable: FK reads them).
enum class Drive { Task, Actuators };

class DrivePanel : public QWidget {
  Q_OBJECT

 public:
  explicit DrivePanel(const MechanismInfo& info, QWidget* parent = nullptr);
  ~DrivePanel() override;

  // Shows the sliders that drive (the others' values are in the read-outs).
  // Returns the drive in force: Task where the device lacks either kind of kinematics.
  Drive setDrive(Drive drive, const std::vector<std::string>& fk_inputs);
  // The sliders and the branch box show the state's pose (quietly).
  void showValues(const DeviceState& state);
  // The sliders' travel from the description.
  void showRanges(const MechanismInfo& info);
  // The read-outs of the state's pose; returns why a measure could not be
  // computed (empty when all are shown).
  QString showReadouts(const DeviceState& state);
  // The status line: "ok" in green, or a refusal in red.
  void showStatus(const QString& text, bool ok);

 signals:
  void taskEdited(int coordinate, double value);
  void actuatorEdited(int actuator, double value);
  void driveChosen(Drive drive);
  void branchChosen(int branch);
  // A slider is held down (a drag) or let go.
  void sliderHeld(bool held);

 private:
  bool planar_ = false;  // the task's z is the device's plane: no slider for it
  std::vector<std::unique_ptr<QuantityControl>> task_controls_, actuator_controls_;
  QComboBox *drive_box_ = nullptr, *branch_box_ = nullptr;
  QGroupBox *task_group_ = nullptr, *actuator_group_ = nullptr;
  QLabel *status_label_ = nullptr, *task_label_ = nullptr, *actuator_label_ = nullptr, *det_label_ = nullptr,
         *singular_label_ = nullptr, *branch_label_ = nullptr;
  std::vector<QLabel*> measure_labels_;
  QLabel *force_iso_label_ = nullptr, *force_max_label_ = nullptr;  // at the pose, continuous torque
  void showForces(const DeviceState& state);
  QFormLayout* state_form_ = nullptr;  // the State box's rows, the device's own read-outs last
  int fixed_rows_ = 0;                 // the rows before them
};

}  // namespace linkscape::gui
