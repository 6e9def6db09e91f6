// The PATHOS-II window: the 3-D view of the device and its fields, with
// docked panels for the design (link lengths, tilt), the drive (pose by IK,
// or the six actuators by numerical FK with the nine-sensor closed form
// beside it) and the fields (slices of cond(Jp) / cond(Jo) / reach / status
// and the reachable and well-conditioned surfaces at the current orientation
// and grip). Field work runs on FieldJobRunner threads, never on the GUI
// thread. Units: cm and degrees in the panels, cm and rad in the API.
#pragma once

#include <QMainWindow>
#include <QString>
#include <array>
#include <memory>
#include <optional>
#include <string>

#include "core/pathos2.h"
#include "core/preset.h"
#include "gui/field_job.h"
#include "gui/session.h"
#include "render/slice_image.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QGroupBox;
class QLabel;
class QProgressBar;
class QSlider;
class vtkRenderer;

namespace linkscape::render {
class FieldScene;
class Pathos2Scene;
}  // namespace linkscape::render

namespace linkscape::gui {

class MethodsPanel;
class VtkWidget;

class Pathos2Window : public QMainWindow {
  Q_OBJECT

 public:
  enum class Drive { Pose, Actuators };

  explicit Pathos2Window(const Preset& preset, QWidget* parent = nullptr);
  ~Pathos2Window() override;

  const pathos2::Model& model() const;
  // The pose shown: the last one whose IK (or FK) succeeded.
  const pathos2::Pose& pose() const;
  const pathos2::PoseIkResult& ik() const { return ik_; }
  pathos2::Vector6d activeAngles() const { return ik_.q_active; }
  Drive drive() const { return drive_; }
  VtkWidget* view() const { return view_; }
  const render::FieldScene& fieldScene() const { return *field_scene_; }
  const render::Pathos2Scene& scene() const { return *scene_; }
  // True once the latest field request has been answered at full resolution.
  bool fieldsSettled() const { return slice_settled_ && surfaces_settled_; }
  // Why the last requested pose or actuator set was refused ("leg 2:
  // unreachable"), empty when it was taken.
  QString refusal() const { return refusal_; }
  // FK mode: the numerical solution shown and the nine-sensor closed form
  // at the same actuator angles (empty before the first FK step).
  const std::optional<pathos2::FkResult>& numericFk() const { return fk_numeric_; }
  const std::optional<pathos2::FkResult>& nineSensorFk() const { return fk_nine_; }

 public slots:
  // Inverse kinematics: moves the device to `pose` if every leg solves;
  // otherwise keeps the last valid pose, highlights the failing leg and says
  // which leg fails and why. Returns whether the pose was taken.
  bool setPose(const pathos2::Pose& pose);
  // Forward kinematics: damped Newton from the current pose to the six
  // active angles (rad) and grip h0 (cm); the nine-sensor closed form is
  // evaluated beside it. Refuses (keeping the pose) when it does not converge.
  bool setActuators(const pathos2::Vector6d& q_active, double h0);
  void setDrive(Drive drive);
  // New design; keeps the pose (shifted with l0/2) when the new design
  // reaches it, else goes to its home pose; refuses an invalid design.
  bool setModel(const pathos2::Model& model);
  // Sessions: design, pose, drive, camera and field settings as JSON (the
  // 12R window's format, with platform_pose). Report failures in a message box.
  Session session() const;
  void applySession(const Session& session);
  bool openSession(const QString& path);
  bool saveSession(const QString& path);

 signals:
  void poseChanged();
  void fieldsUpdated(bool fine);
  void sliceUpdated(bool fine);
  void surfacesUpdated(bool fine);

 private:
  QWidget* buildDesignPanel();
  QWidget* buildDrivePanel();
  QWidget* buildFieldPanel();
  void refuse(const QString& why, int failing_leg);
  void accept(const pathos2::Pose& pose, const pathos2::PoseIkResult& ik);
  // The panel that is not driving follows the pose; `both`: both panels.
  void syncPanels(bool both = false);
  void updateReadouts();
  pathos2::Model modelFromDesignPanel() const;
  pathos2::Pose poseFromPanel() const;
  void requestFields(bool slice, bool volume);
  void restyleSlice();
  render::SliceStyle sliceStyle() const;  // of the field panel, for the view and exports
  void applyFieldVisibility();
  void onSlice(const SliceResult& result);
  void onSurfaces(const SurfaceResult& result);
  // Sampled box: x, y in [-H, H], z in [l0/2 - H, l0/2 + H].
  std::pair<Eigen::Vector3d, Eigen::Vector3d> fieldBox() const;
  double slicePosition() const;

  Preset preset_;
  MethodsPanel* methods_ = nullptr;  // measures the current design on Run
  std::unique_ptr<render::Pathos2Scene> scene_;
  std::unique_ptr<render::FieldScene> field_scene_;
  vtkRenderer* renderer_ = nullptr;  // owned by the view's render window
  VtkWidget* view_ = nullptr;
  pathos2::Geometry geometry_;
  pathos2::PoseIkResult ik_;
  Drive drive_ = Drive::Pose;
  QString refusal_;
  std::optional<pathos2::FkResult> fk_numeric_, fk_nine_;
  FieldJobRunner slice_runner_, volume_runner_;
  std::shared_ptr<const Field> slice_field_;
  SurfaceResult surfaces_;  // the last isosurfaces and their volume, for export
  bool slice_settled_ = false, surfaces_settled_ = false;

  // Design panel: l0, l2, l3, lp, theta_t, db.
  static constexpr int kDesignCount = 6;
  std::array<QSlider*, kDesignCount> design_sliders_{};
  std::array<QDoubleSpinBox*, kDesignCount> design_boxes_{};
  // Drive panel: pose x, y, z, rx, ry, rz, h0 and actuators q1..q6, h0.
  QComboBox* drive_box_ = nullptr;
  QGroupBox *pose_group_ = nullptr, *actuator_group_ = nullptr, *fk_group_ = nullptr;
  std::array<QSlider*, 7> pose_sliders_{};
  std::array<QDoubleSpinBox*, 7> pose_boxes_{};
  std::array<QSlider*, 7> actuator_sliders_{};
  std::array<QDoubleSpinBox*, 7> actuator_boxes_{};
  std::array<QLabel*, 6> q_labels_{};
  QLabel *cond_p_label_ = nullptr, *cond_o_label_ = nullptr, *status_label_ = nullptr;
  QLabel *fk_numeric_label_ = nullptr, *fk_nine_label_ = nullptr, *fk_difference_label_ = nullptr;
  // Field panel.
  QComboBox *field_box_ = nullptr, *normal_box_ = nullptr, *slice_resolution_box_ = nullptr,
            *volume_resolution_box_ = nullptr;
  QSlider* position_slider_ = nullptr;
  QLabel* position_label_ = nullptr;
  QCheckBox *follow_box_ = nullptr, *show_slice_box_ = nullptr, *show_reach_box_ = nullptr, *show_well_box_ = nullptr;
  QDoubleSpinBox* threshold_box_ = nullptr;
  QSlider *reach_opacity_slider_ = nullptr, *well_opacity_slider_ = nullptr;
  QLabel* compute_label_ = nullptr;  // in the status bar (window_parts.h)
};

// Opens a Pathos2Window of `preset` (then `session`, if given) at width x
// height inside the running QApplication. With a screenshot path, waits until the fields are computed
// in full, saves a PNG of the window and returns 0 (1 on failure); otherwise
// runs the event loop. The drive mode is restored from the last session.
int run_pathos2_window(const Preset& preset, const std::optional<Session>& session, const std::string& screenshot,
                       int width, int height);

}  // namespace linkscape::gui
