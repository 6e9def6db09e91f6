// The window of any device: the 3-D view of its skeleton and fields, with
// docked panels built from the device's description (core/mechanism.h), as
// a physics viewer builds its sliders from the model: one slider per design
// parameter, per actuator and per task coordinate, read-outs of every
// measure and singular set, field choices from the measures and methods.
// The window works through the Mechanism interface only; it never asks
// which device it has. It is a shell: the device and its pose are a
// DeviceState, each dock a panel class, the fields a FieldDisplay, the
// menus' actions functions of their own (file, mechanism, export, help).
#pragma once

#include <QImage>
#include <QMainWindow>
#include <QString>
#include <QByteArray>
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mechanism.h"
#include "core/preset.h"
#include "gui/window/device_state.h"
#include "gui/window/drive_panel.h"
#include "gui/window/field_display.h"
#include "gui/window/mechanism_actions.h"
#include "gui/window/window_document.h"
#include "gui/window/session.h"

class QLabel;
class vtkRenderer;

namespace linkscape::render {
class FieldScene;
class SkeletonScene;
class TaskScene;
}  // namespace linkscape::render

namespace linkscape::gui {

class AnimationPanel;
class DesignPanel;
class ErrorPanel;
class FieldPanel;
class FitPanel;
class MethodsPanel;
class PresetWatcher;
class SessionHistory;
class TaskPanel;
class ViewHandles;
class ViewTools;
class VtkWidget;

class MechanismWindow : public QMainWindow {
  Q_OBJECT

 public:
  using Drive = gui::Drive;  // drive_panel.h

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
  const ViewHandles& handles() const { return *handles_; }
  const render::SkeletonScene& scene() const { return *scene_; }
  const render::TaskScene& taskScene() const { return *task_scene_; }
  TaskPanel* taskPanel() const { return task_panel_; }
  ViewTools* viewTools() const { return tools_; }
  FieldDisplay* fieldDisplay() const { return fields_; }
  FitPanel* fitPanel() const { return fit_panel_; }
  // True once the latest field request has been answered at full resolution.
  bool fieldsSettled() const { return fields_->settled(); }
  // Why the last requested pose was refused, empty when it was taken.
  QString refusal() const { return QString::fromStdString(state_.refusal()); }
  // The failing part named by the last refused IK ("3": leg 3), else empty.
  QString failingPart() const { return QString::fromStdString(state_.failing_part()); }
  FieldSettings fieldSettings() const { return fields_->settings(); }
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
  // Which stops the device states it checks (StopChecks); the pose is kept as a session's is.
  void setStopChecks(const StopChecks& checks);
  // Field settings the window offers are taken; the others stay.
  void applyFieldSettings(const FieldSettings& settings) { fields_->apply(settings); }
  // Throws std::invalid_argument (nothing changed) for a session the window
  // cannot honour, e.g. a parameter outside its slider's range.
  void applySession(const Session& session);
  // What an opened session sets beyond applySession (apply_window_session:
  // the Fit tab's settings and result, the View menu's toggles), then its
  // camera again (a toggle may have framed the view).
  void applyViewSession(const Session& session);
  bool openSession(const QString& path) { return document_->openSession(path); }
  bool saveSession(const QString& path) { return document_->saveSession(path); }
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
  SessionHistory* history() const { return document_->history(); }
  // Asks to save unsaved changes (only when interactive); false: the user cancelled.
  bool maybeSave() { return document_->maybeSave(); }
  // Interactive: asks before unsaved work is discarded, and remembers the
  // window's size and panel layout when it closes. Off in tests,
  // screenshots and latency runs, which never wait for a dialog and must be
  // reproducible.
  void setInteractive(bool on) { document_->setInteractive(on); }
  bool interactive() const { return document_->interactive(); }
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
  void buildDocks();
  void buildMenus();
  // Runs a change of pose of the device state and shows its outcome: the
  // pose taken, or why it was refused (the failing part drawn red).
  bool settle(const std::function<bool()>& change);
  // Shows the state's pose: panels, picture, read-outs, the fields that
  // depend on what changed since the pose at x_before in branch_before.
  void showPose(const Eigen::VectorXd& x_before, int branch_before);
  // Takes a new design with its pose (scene model already set).
  void adoptDesign(const DesignPlan& plan);
  void showDesign();  // the panels' ranges and the design in force
  void drawPose(const IkResult* failed = nullptr);
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

  DeviceState state_;
  PresetReader preset_reader_;  // reads the device's preset files
  std::unique_ptr<render::SkeletonScene> scene_;
  std::unique_ptr<render::FieldScene> field_scene_;
  std::unique_ptr<render::TaskScene> task_scene_;
  vtkRenderer* renderer_ = nullptr;  // owned by the view's render window
  vtkRenderer* legend_ = nullptr;    // the colour bar's strip, likewise
  VtkWidget* view_ = nullptr;
  std::unique_ptr<ViewHandles> handles_;
  ViewTools* tools_ = nullptr;  // picking, ruler, line probe, standard views
  Drive drive_ = Drive::Task;
  DrivePanel* drive_panel_ = nullptr;
  DesignPanel* design_panel_ = nullptr;
  FieldPanel* field_panel_ = nullptr;
  FieldDisplay* fields_ = nullptr;
  AnimationPanel* animation_panel_ = nullptr;
  TaskPanel* task_panel_ = nullptr;
  FitPanel* fit_panel_ = nullptr;
  MethodsPanel* methods_ = nullptr;
  QLabel* compute_label_ = nullptr;  // in the status bar (docks.h)
  WindowDocument* document_ = nullptr;  // the session file, undo/redo, the fitted camera
  QByteArray initial_layout_;                 // for View > Reset layout
  ErrorPanel* error_panel_ = nullptr;
  PresetWatcher* preset_watcher_ = nullptr;  // reloads the device when its file changes
  bool camera_given_ = false;  // a session or a reload placed the camera
};

}  // namespace linkscape::gui
