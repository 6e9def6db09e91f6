// The window of any device: the 3-D view of its skeleton and fields, with
// docked panels built from the device's description (core/mechanism.h), as
// a physics viewer builds its sliders from the model: one slider per design
// parameter, per actuator and per task coordinate, read-outs of every
// measure and singular set, field choices from the measures and methods.
// The window works through the Mechanism interface only; it never asks
// which device it has. Field work runs on FieldJobRunner threads.
#pragma once

#include <QImage>
#include <QMainWindow>
#include <QString>
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <vtkSmartPointer.h>

#include "core/mechanism.h"
#include "core/preset.h"
#include "gui/window/device_state.h"
#include "gui/window/field_job.h"
#include "gui/window/session.h"
#include "render/slice_image.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QFormLayout;
class QGridLayout;
class QGroupBox;
class QLabel;
class QMenu;
class QPushButton;
class QSlider;
class QTimer;
class vtkCallbackCommand;
class vtkHandleWidget;
class vtkPointHandleRepresentation3D;
class vtkRenderer;

namespace linkscape::render {
class FieldScene;
class SkeletonScene;
class TaskScene;
}  // namespace linkscape::render

namespace linkscape::gui {

class ErrorPanel;
class FitPanel;
class MethodsPanel;
class PresetWatcher;
class SessionHistory;
class TaskPanel;
class VtkWidget;

// The largest side of the window and of the view image, in pixels:
// off-screen framebuffers beyond that fail inside the OpenGL driver.
inline constexpr int kMaxWindowSide = 8192;

// A slider with a spin box for one named quantity (see mechanism_window.cpp).
struct QuantityControl;

class MechanismWindow : public QMainWindow {
  Q_OBJECT

 public:
  // Task: the task sliders drive by inverse kinematics. Actuators: the
  // actuator sliders drive by forward kinematics (task coordinates listed in
  // info().fk_inputs stay editable: FK reads them).
  enum class Drive { Task, Actuators };

  explicit MechanismWindow(const Preset& preset, QWidget* parent = nullptr);
  ~MechanismWindow() override;

  const Mechanism& mechanism() const { return state_.mechanism(); }
  const Preset& preset() const { return state_.preset(); }  // with the window's parameters and limits
  const Eigen::VectorXd& actuators() const { return state_.actuators(); }
  const Eigen::VectorXd& task() const { return state_.task(); }
  Eigen::Vector3d endpoint() const { return state_.endpoint(); }
  int branch() const { return state_.branch(); }
  // The device and its pose, without the window.
  const DeviceState& state() const { return state_; }
  Drive drive() const { return drive_; }
  VtkWidget* view() const { return view_; }
  const render::FieldScene& fieldScene() const { return *field_scene_; }
  const render::SkeletonScene& scene() const { return *scene_; }
  const render::TaskScene& taskScene() const { return *task_scene_; }
  TaskPanel* taskPanel() const { return task_panel_; }
  FitPanel* fitPanel() const { return fit_panel_; }
  // True once the latest field request has been answered at full resolution.
  bool fieldsSettled() const { return slice_settled_ && surfaces_settled_; }
  // Why the last requested pose was refused, empty when it was taken.
  QString refusal() const { return QString::fromStdString(state_.refusal()); }
  // The failing part named by the last refused IK ("3": leg 3), else empty.
  QString failingPart() const { return QString::fromStdString(state_.failing_part()); }
  FieldSettings fieldSettings() const;
  Session session() const;

 public slots:
  // Inverse kinematics to the task coordinates x in the current branch,
  // seeded with the current actuators. `tracking` (drags, animation) also
  // refuses a step that would make the device jump (across a singular set).
  // A refused target leaves the pose, says why and draws the failing part red.
  bool setTask(const Eigen::VectorXd& x, bool tracking = false);
  // The driven point to `target` with the other task coordinates kept. Without
  // `branch` the current branch is tracked (as a drag); with it, any pose of
  // that branch is taken.
  bool moveEndpointTo(const Eigen::Vector3d& target, int branch = -1);
  // Forward kinematics from the current task (the seed; fk_inputs are read
  // from `task_inputs` where given). Refuses when it does not converge.
  bool setActuators(const Eigen::VectorXd& q, const std::optional<Eigen::VectorXd>& task_inputs = std::nullopt);
  void setDrive(Drive drive);
  // A new design: the device is made again from the preset with these
  // parameters; the pose is kept where the new design reaches it, else the
  // actuators, else its home. An invalid design is refused (false, message).
  bool setParameters(const std::map<std::string, double>& parameters);
  // Actuator limits in degrees by actuator name (devices that take them);
  // the pose is clamped into them. Refused (false) when the device rejects them.
  bool setActuatorLimits(const std::map<std::string, std::array<double, 2>>& limits_deg);
  // Field settings the window offers are taken; the others stay.
  void applyFieldSettings(const FieldSettings& settings);
  // Throws std::invalid_argument (nothing changed) for a session the window
  // cannot honour, e.g. a parameter outside its slider's range.
  void applySession(const Session& session);
  bool openSession(const QString& path);
  bool saveSession(const QString& path);
  // File > Open mechanism: the preset file at `path` in a window of its
  // device that takes this one's place, as picking a preset does (a new
  // document; the field settings and panel layout stay). Returns that
  // window, or nullptr when the file does not load: then this window and its
  // device stay as they were and the error panel says why.
  MechanismWindow* openMechanismFile(const QString& path);
  // File > Reload mechanism (F5), and by itself when the preset file changes
  // on disk: the file is read again and the device made anew in a window
  // that takes this one's place. The file is the truth for the design (its
  // parameters and actuator travel); the camera, the field settings, the
  // task volume, the document (its file; modified if it was or if the design
  // changed) and the pose stay: the same task coordinates, clamped into the
  // new ranges, where the device has the same ones and reaches them, else
  // its home pose. The undo history starts again, as with a change of device.
  // Returns the new window, or nullptr when the file does not load (this
  // window stays, the error panel says why).
  MechanismWindow* reloadMechanism();
  // The panel above the view that says why a preset did not load (hidden when none failed).
  ErrorPanel* errorPanel() const { return error_panel_; }
  // The document: its file (empty: not saved yet), undo/redo, the modified mark.
  SessionHistory* history() const { return history_; }
  // Asks to save unsaved changes (only when interactive); false: the user cancelled.
  bool maybeSave();
  // Interactive: asks before unsaved work is discarded, and remembers the
  // window's size and panel layout when it closes. Off in tests,
  // screenshots and latency runs, which never wait for a dialog and must be
  // reproducible.
  void setInteractive(bool on) { interactive_ = on; }
  bool interactive() const { return interactive_; }
  // The camera frames the device; it does so again after a change of size
  // unless the user has moved it since.
  void fitCamera();
  // The 3-D view alone drawn at width x height pixels (the view is resized
  // for one frame, so the picture is rendered at that size, not scaled).
  // Throws std::invalid_argument outside 16..8192 pixels a side.
  QImage viewImage(int width, int height);

 signals:
  void poseChanged();
  void fieldsUpdated(bool fine);
  void sliceUpdated(bool fine);
  void surfacesUpdated(bool fine);
  // Another window took this one's place (a new device, or its preset
  // reloaded); this one closes.
  void replacedBy(MechanismWindow* next);

 protected:
  void closeEvent(QCloseEvent* event) override;
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  QWidget* buildDesignPanel();
  QWidget* buildDrivePanel();
  QWidget* buildFieldPanel();
  QWidget* buildAnimationPanel();
  void buildMenus();
  // Runs a change of pose of the device state and shows its outcome: the
  // pose taken, or why it was refused (the failing part drawn red).
  bool settle(const std::function<bool()>& change);
  // Shows the state's pose: panels, picture, read-outs, the fields that
  // depend on what changed since the pose at x_before in branch_before.
  void showPose(const Eigen::VectorXd& x_before, int branch_before);
  // Takes a new design with its pose (scene model already set).
  void adoptDesign(const DesignPlan& plan);
  void syncPanels();
  void syncRanges();
  void updateReadouts();
  void drawPose(const IkResult* failed = nullptr);
  void placeHandle();
  void requestFields(bool slice, bool volume);
  void restyleSlice();
  render::SliceStyle sliceStyle() const;
  void applyFieldVisibility();
  void onSlice(const SliceResult& result);
  void onSurfaces(const SurfaceResult& result);
  double slicePosition() const;
  void animationStep();
  void addRecent(const QString& path);
  void rebuildRecentMenu();
  bool save();
  bool saveAs();
  void updateTitle();
  void showLoadError(const QString& title, const QString& path, const QString& message);
  // The preset in `file`, read and checked off the GUI thread, or nothing
  // (the error shown under `failure_title`; or another read under way).
  std::optional<Preset> readPresetFile(const QString& file, const QString& failure_title);
  // A window of `preset`'s device in this one's place (same geometry and
  // panel layout), with `session` applied, else with this one's field
  // settings; its document is `session_path` (empty: a new one). This
  // window says so (replacedBy) and closes. Throws std::invalid_argument
  // with nothing changed.
  MechanismWindow* replaceWith(const Preset& preset, const std::optional<Session>& session,
                               const QString& session_path = {});
  void noteChange();
  void placeLegend();
  // What is moving the picture every frame: while any is, the workspace
  // surfaces draw their light meshes (render::FieldScene::set_light); once
  // none is, the next frame draws them in full.
  enum Moving : unsigned { kSliderDrag = 1, kHandleDrag = 2, kAnimation = 4, kCameraDrag = 8 };
  void setMoving(Moving source, bool on);

  DeviceState state_;
  bool reading_preset_ = false;
  std::unique_ptr<render::SkeletonScene> scene_;
  std::unique_ptr<render::FieldScene> field_scene_;
  std::unique_ptr<render::TaskScene> task_scene_;
  TaskPanel* task_panel_ = nullptr;
  FitPanel* fit_panel_ = nullptr;
  vtkRenderer* renderer_ = nullptr;  // owned by the view's render window
  vtkRenderer* legend_ = nullptr;    // the colour bar's strip, likewise
  VtkWidget* view_ = nullptr;
  Drive drive_ = Drive::Task;
  FieldJobRunner slice_runner_, volume_runner_;
  std::shared_ptr<const Field> slice_field_;
  SurfaceResult surfaces_;  // the last isosurfaces and their volume, for export
  bool slice_settled_ = false, surfaces_settled_ = false;

  // Endpoint dragging in the view.
  vtkSmartPointer<vtkHandleWidget> handle_;
  vtkSmartPointer<vtkPointHandleRepresentation3D> handle_rep_;
  vtkSmartPointer<vtkCallbackCommand> handle_callback_;
  vtkSmartPointer<vtkCallbackCommand> camera_callback_;
  unsigned moving_ = 0;       // Moving flags
  bool light_asked_ = false;  // the light meshes of the surfaces shown are made or being made

  // Panels: one control per parameter shown, per actuator, per task coordinate.
  std::vector<std::unique_ptr<QuantityControl>> parameter_controls_, actuator_controls_, task_controls_;
  std::map<std::string, std::array<QDoubleSpinBox*, 2>> limit_boxes_;  // per actuator: min, max (degrees)
  QComboBox *drive_box_ = nullptr, *branch_box_ = nullptr;
  QGroupBox *task_group_ = nullptr, *actuator_group_ = nullptr;
  QLabel *status_label_ = nullptr, *task_label_ = nullptr, *actuator_label_ = nullptr, *det_label_ = nullptr,
         *singular_label_ = nullptr, *branch_label_ = nullptr;
  std::vector<QLabel*> measure_labels_;
  QFormLayout* extra_form_ = nullptr;  // the device's own read-outs
  // Field panel.
  QComboBox *field_box_ = nullptr, *method_box_ = nullptr, *normal_box_ = nullptr, *slice_resolution_box_ = nullptr,
            *volume_resolution_box_ = nullptr, *field_branch_box_ = nullptr;
  QSlider* position_slider_ = nullptr;
  QLabel* position_label_ = nullptr;
  QComboBox* colour_map_box_ = nullptr;
  QCheckBox* log_scale_box_ = nullptr;
  QCheckBox *follow_box_ = nullptr, *auto_range_box_ = nullptr, *show_slice_box_ = nullptr, *show_reach_box_ = nullptr,
            *show_well_box_ = nullptr;
  QDoubleSpinBox *threshold_box_ = nullptr, *range_min_box_ = nullptr, *range_max_box_ = nullptr;
  QSlider *reach_opacity_slider_ = nullptr, *well_opacity_slider_ = nullptr;
  // Animation.
  QComboBox* path_box_ = nullptr;
  QDoubleSpinBox *speed_box_ = nullptr, *amplitude_box_ = nullptr;
  QCheckBox* loop_box_ = nullptr;
  QPushButton* play_button_ = nullptr;
  QTimer* animation_timer_ = nullptr;
  double animation_phase_ = 0.0;
  Eigen::Vector3d animation_centre_ = Eigen::Vector3d::Zero();
  QMenu* recent_menu_ = nullptr;
  QLabel* compute_label_ = nullptr;  // in the status bar (docks.h)
  MethodsPanel* methods_ = nullptr;
  SessionHistory* history_ = nullptr;
  bool interactive_ = false;
  std::optional<CameraState> fitted_camera_;  // where fitCamera() put it
  QByteArray initial_layout_;                 // for View > Reset layout
  ErrorPanel* error_panel_ = nullptr;
  PresetWatcher* preset_watcher_ = nullptr;  // reloads the device when its file changes
};

}  // namespace linkscape::gui
