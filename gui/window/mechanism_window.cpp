#include "gui/window/mechanism_window.h"

#include <QCloseEvent>
#include <QComboBox>
#include <QDockWidget>
#include <QEvent>
#include <QFileInfo>
#include <QLabel>
#include <QStatusBar>
#include <QTimer>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <stdexcept>

#include "gui/window/animation_panel.h"
#include "gui/window/design_panel.h"
#include "gui/window/docks.h"
#include "gui/window/error_panel.h"
#include "gui/window/export_actions.h"
#include "gui/window/help_actions.h"
#include "gui/window/field_panel.h"
#include "gui/window/file_actions.h"
#include "gui/window/fit_panel.h"
#include "gui/window/methods_panel.h"
#include "gui/window/quantity_control.h"
#include "gui/window/session_history.h"
#include "gui/window/task_panel.h"
#include "gui/window/view_handles.h"
#include "gui/window/view_overlays.h"
#include "gui/window/view_tools.h"
#include "gui/window/window_menus.h"
#include "gui/window/vtk_widget.h"
#include "render/field_scene.h"
#include "render/skeleton_scene.h"
#include "render/task_scene.h"

namespace linkscape::gui {

namespace {

// The camera frames the middle of the sampling box (its corners hold no
// workspace, and framing them would make the device small) and the device
// at home (a hexapod's cranks reach beyond the box): not where it stands,
// so that the framing does not depend on the pose.
Eigen::AlignedBox3d view_box(const Mechanism& m, const render::SkeletonScene& scene) {
  const Eigen::AlignedBox3d box = m.default_box();
  const Eigen::Vector3d half = 0.5 * 0.7 * box.sizes();
  Eigen::AlignedBox3d out(box.center() - half, box.center() + half);
  try {
    out.extend(scene.device_box(m.skeleton_pose(m.home_actuators(), m.home_task())));
  } catch (const std::invalid_argument&) {  // a home that does not assemble: the box alone
  }
  return out;
}

}  // namespace

MechanismWindow::MechanismWindow(const Preset& preset, QWidget* parent)
    : QMainWindow(parent),
      state_(preset),
      preset_reader_(this),
      scene_(std::make_unique<render::SkeletonScene>()),
      field_scene_(std::make_unique<render::FieldScene>()),
      task_scene_(std::make_unique<render::TaskScene>()) {
  view_ = new VtkWidget(this);
  error_panel_ = ErrorPanel::placeAbove(this, view_);  // says why a preset did not load
  connect(error_panel_, &ErrorPanel::reloadRequested, this, [this](const QString& path) {
    // The file that failed: this device's own preset is reloaded, another one opened.
    if (path == preset_file(state_.preset())) reloadMechanism();
    else openMechanismFile(path);
  });
  const VtkWidget::Renderers renderers = view_->addRenderers();
  renderer_ = renderers.scene;
  legend_ = renderers.legend;
  view_->installEventFilter(this);
  // A camera this window placed and no one has moved frames the device in
  // the view's new shape (not a session's or a reload's, nor for a picture).
  connect(view_, &VtkWidget::resized, this, [this] {
    if (!document_ || camera_given_ || view_->drawingPicture() || !document_->cameraUntouched(camera_state(renderer_))) return;
    fitCamera();
    view_->requestRender();
  });
  scene_->set_model(state_.mechanism().skeleton_model());
  // Translucent props blend in the order they were added (render/scene_renderer.h):
  // the fields first, the task volume, then the device (its joint labels last).
  field_scene_->add_to(renderer_, legend_);
  task_scene_->add_to(renderer_);
  scene_->add_to(renderer_);
  renderer_->SetUseDepthPeeling(false);  // plain alpha blending: interactive under software GL
  fitCamera();  // fitted again as the view takes its size

  buildDocks();
  fields_->placeLegend();
  // Drag the driven point: a handle on it, solved by IK as it moves.
  handles_ = std::make_unique<ViewHandles>(
      view_->interactor(), renderers.handles,
      ViewHandles::Hooks{[this](const Eigen::Vector3d& p) { moveEndpointTo(p); },
                         [this] { handles_->place(endpoint()); },
                         [this](bool on) { fields_->setMoving(FieldDisplay::kHandleDrag, on); },
                         [this](bool on) { fields_->setMoving(FieldDisplay::kCameraDrag, on); },
                         [this] { return state_.mechanism().info().plane_z; }});
  document_ = new WindowDocument(
      this, WindowDocument::Hooks{[this] { return session(); }, [this](const Session& s) { applySession(s); },
                                  [this](const Session& s, const Preset& preset, const QString& path) {
                                    if (preset.mechanism != state_.preset().mechanism) {
                                      replaceWith(preset, s, path);
                                      return;
                                    }
                                    applySession(s);
                                    applyViewSession(s);
                                    history()->reset(path);
                                  },
                                  [this] {
                                    const Preset& p = state_.preset();
                                    return qs(p.title.empty() ? state_.mechanism().info().title : p.title);
                                  },
                                  [this] { return preset_file(state_.preset()); }});
  document_->cameraFitted(camera_state(renderer_));  // as fitCamera() put it above
  buildMenus();
  compute_label_ = add_field_status(this, view_, {fields_->sliceRunner(), fields_->volumeRunner()}, [this] {
                     fields_->markSettled();  // nothing more is coming
                   }).compute;

  // Neither the drive nor the layout is remembered, so screenshots are reproducible.
  setDrive(Drive::Task);
  showPose(state_.task(), state_.branch());
  fields_->request(true, true);
  history()->reset({});
  document_->updateTitle();
  initial_layout_ = saveState();

  // The preset file is watched: a change on disk reloads the device (a
  // window that replaces this one watches the file itself).
  preset_watcher_ = new PresetWatcher(this, [this] {
    if (!reloadMechanism()) preset_watcher_->watch(preset_file(state_.preset()));
  });
  preset_watcher_->watch(preset_file(state_.preset()));
}

void MechanismWindow::buildDocks() {
  const MechanismInfo& info = state_.mechanism().info();
  drive_panel_ = new DrivePanel(info);
  connect(drive_panel_, &DrivePanel::driveChosen, this, &MechanismWindow::setDrive);
  connect(drive_panel_, &DrivePanel::branchChosen, this, [this](int b) { moveEndpointTo(endpoint(), b); });
  connect(drive_panel_, &DrivePanel::taskEdited, this, [this](int k, double v) {
    Eigen::VectorXd x = state_.task();
    x(k) = v;
    if (drive_ == Drive::Task) setTask(x);
    else setActuators(state_.actuators(), x);  // an FK input (e.g. a grip) changed
  });
  connect(drive_panel_, &DrivePanel::actuatorEdited, this, [this](int k, double v) {
    Eigen::VectorXd q = state_.actuators();
    q(k) = v;
    setActuators(q);
  });
  connect(drive_panel_, &DrivePanel::sliderHeld, this,
          [this](bool on) { fields_->setMoving(FieldDisplay::kSliderDrag, on); });
  QComboBox* chooser = make_preset_chooser(
      this, state_.preset(), [this] { return maybeSave(); },
      [this](const Preset& preset) { replaceWith(preset, std::nullopt); });
  design_panel_ = new DesignPanel(state_, chooser);
  connect(design_panel_, &DesignPanel::parametersEdited, this, &MechanismWindow::setParameters);
  connect(design_panel_, &DesignPanel::limitsEdited, this, &MechanismWindow::setActuatorLimits);
  connect(design_panel_, &DesignPanel::stopChecksEdited, this, &MechanismWindow::setStopChecks);
  field_panel_ = new FieldPanel(state_.mechanism());
  fields_ = new FieldDisplay(state_, field_panel_, field_scene_.get(), view_, renderer_, legend_, this);
  connect(fields_, &FieldDisplay::changed, this, &MechanismWindow::noteChange);
  connect(fields_, &FieldDisplay::message, this, [this](const QString& m, int ms) { statusBar()->showMessage(m, ms); });
  connect(fields_, &FieldDisplay::computed, this, [this](const QString& text) { compute_label_->setText(text); });
  connect(fields_, &FieldDisplay::sliceUpdated, this, &MechanismWindow::sliceUpdated);
  connect(fields_, &FieldDisplay::surfacesUpdated, this, &MechanismWindow::surfacesUpdated);
  connect(fields_, &FieldDisplay::fieldsUpdated, this, &MechanismWindow::fieldsUpdated);
  animation_panel_ = new AnimationPanel(
      state_.mechanism().size(), qs(info.length_unit),
      AnimationPanel::Hooks{[this] { return endpoint(); }, [this] { return field_panel_->normal(); },
                            [this](const Eigen::Vector3d& p) { moveEndpointTo(p); }});
  connect(animation_panel_, &AnimationPanel::playingChanged, this,
          [this](bool on) { fields_->setMoving(FieldDisplay::kAnimation, on); });
  QDockWidget* drive = add_dock(this, tr("Drive"), "driveDock", drive_panel_);
  QDockWidget* design = add_dock(this, tr("Design"), "designDock", design_panel_);
  QDockWidget* field = add_dock(this, tr("Field"), "fieldDock", field_panel_);
  QDockWidget* animation = add_dock(this, tr("Animation"), "animationDock", animation_panel_);
  task_panel_ = new TaskPanel(task_scene_.get());
  QDockWidget* task = add_dock(this, tr("Task"), "taskDock", task_panel_);
  connect(task_panel_, &TaskPanel::changed, view_, [this] {
    view_->requestRender();
    noteChange();  // the task volume is part of the document
  });
  fit_panel_ = new FitPanel(task_panel_);
  QDockWidget* fit = add_dock(this, tr("Fit"), "fitDock", fit_panel_);
  tools_ = new ViewTools({&state_, view_, renderer_, scene_.get(), field_scene_.get(), task_scene_.get(), fields_}, this);
  connect(this, &MechanismWindow::poseChanged, tools_->overlays(), &ViewOverlays::update);
  connect(fit_panel_, &FitPanel::applyRequested, this, [this](const std::map<std::string, double>& design) {
    if (!setParameters(design)) return;
    if (const auto centre = fit_panel_->chosenCentre()) task_panel_->setCentre(*centre);  // where it fits
  });
  // One column of tabs down its right edge (every label whole at any width
  // of the column): the drive (with every read-out) in front.
  setTabPosition(Qt::RightDockWidgetArea, QTabWidget::East);
  for (QDockWidget* d : {design, field, animation, task, fit}) tabifyDockWidget(drive, d);
  tools_->addDock(this, drive);
  methods_ = add_methods_dock(this, state_.preset(), drive);
  drive->raise();
  QTimer::singleShot(0, this, [this, drive] { resizeDocks({drive}, {std::max(drive->width(), 440)}, Qt::Horizontal); });
}

void MechanismWindow::noteChange() {
  if (document_ && !animation_panel_->playing()) history()->noteChange();
}


void MechanismWindow::setDrive(Drive drive) { drive_ = drive_panel_->setDrive(drive, state_.mechanism().info().fk_inputs); }

bool MechanismWindow::eventFilter(QObject* watched, QEvent* event) {
  if (watched == view_ && event->type() == QEvent::Resize && fields_) fields_->placeLegend();  // docks resize the view too
  return QMainWindow::eventFilter(watched, event);
}

QImage MechanismWindow::viewImage(int width, int height) { return view_->imageAt(width, height); }

void MechanismWindow::fitCamera() {
  const Eigen::AlignedBox3d box = view_box(state_.mechanism(), *scene_);
  if (tools_) tools_->reframe(box);  // the view and framing chosen last
  else scene_->reset_camera(renderer_, box);
  if (document_) document_->cameraFitted(camera_state(renderer_));
  camera_given_ = false;  // this window's own again
}

MechanismWindow::~MechanismWindow() {
  delete fields_;  // its jobs end before the state they sample goes
}

void MechanismWindow::buildMenus() {
  MenuActions a;
  a.open_session = [this] {
    if (!maybeSave()) return;
    if (const QString path = ask_session_to_open(this); !path.isEmpty()) openSession(path);
  };
  a.save = [this] { document_->save(); };
  a.save_as = [this] { document_->saveAs(); };
  a.recent_sessions = [this](QMenu* menu) { document_->setRecentMenu(menu); };
  a.open_mechanism = [this] {
    if (const QString path = ask_mechanism_file(this, state_.preset()); !path.isEmpty()) openMechanismFile(path);
  };
  a.reload_mechanism = [this] { reloadMechanism(); };
  a.export_slice = [this] { export_slice_image(this, fields_->slice(), fields_->sliceStyle()); };
  a.export_mesh = [this] {
    const SurfaceResult& s = fields_->surfaces();
    export_surface_mesh(this, s.volume.get(), s.reach, s.well_conditioned, fieldSettings().threshold);
  };
  a.export_field = [this] { export_volume(this, fields_->surfaces().volume.get()); };
  a.export_model = [this] { export_model(this, state_.preset()); };
  a.export_scene = [this] { export_scene(this, view_->renderWindow()); };
  a.about_mechanism = [this] { show_mechanism(this, state_.preset()); };
  a.save_screenshot = [this] { export_screenshot(this); };
  a.save_view_image = [this] {
    const QString suggested = QString("%1x%2").arg(2 * view_->width()).arg(2 * view_->height());
    const QString saved = export_view_image(this, suggested, [this](int w, int h) { return viewImage(w, h); });
    if (!saved.isEmpty()) statusBar()->showMessage(saved, 4000);
  };
  a.undo_stack = history()->stack();
  a.reset_camera = [this] { fitCamera(), view_->requestRender(); };
  a.reset_layout = [this] {
    restoreState(initial_layout_);
    for (QDockWidget* dock : findChildren<QDockWidget*>()) dock->show();
  };
  a.view_tools = [this](QMenu* menu) {
    tools_->addViewActions(menu, [this] { return view_box(state_.mechanism(), *scene_); },
                           [this] {
                             document_->cameraFitted(camera_state(renderer_));
                             camera_given_ = false;
                           });
  };
  a.exact_transparency = [this](bool on) { renderer_->SetUseDepthPeeling(on), view_->requestRender(); };
  add_menus(this, a);
}

// ---- Pose ---------------------------------------------------------------------

bool MechanismWindow::setTask(const Eigen::VectorXd& x, bool tracking) {
  return settle([&] { return state_.set_task(x, tracking); });
}

bool MechanismWindow::moveEndpointTo(const Eigen::Vector3d& target, int branch) {
  if (settle([&] { return state_.move_endpoint_to(target, branch); })) return true;
  drive_panel_->showValues(state_);  // the branch box shows the branch in force
  return false;
}

bool MechanismWindow::setActuators(const Eigen::VectorXd& q, const std::optional<Eigen::VectorXd>& task_inputs) {
  return settle([&] { return state_.set_actuators(q, task_inputs); });
}

bool MechanismWindow::settle(const std::function<bool()>& change) {
  const Eigen::VectorXd x_before = state_.task();
  const int branch_before = state_.branch();
  if (change()) {
    showPose(x_before, branch_before);
    return true;
  }
  drive_panel_->showStatus(refusal(), false);
  drive_panel_->showValues(state_);  // the sliders snap back to the pose the device holds
  statusBar()->showMessage(tr("Refused: %1. The sliders show the pose the device holds.").arg(refusal()), 8000);
  drawPose(state_.failed());
  view_->requestRender();
  return false;
}

void MechanismWindow::showPose(const Eigen::VectorXd& x_before, int branch_before) {
  const Eigen::VectorXd& x = state_.task();
  const bool fixed_changed =
      x_before.size() != x.size() || (x_before.tail(x.size() - 3) - x.tail(x.size() - 3)).norm() > 1e-12;
  const bool moved = x_before.size() != x.size() || (x_before.head<3>() - x.head<3>()).norm() > 1e-12;
  const bool branch_changed = state_.branch() != branch_before;
  drive_panel_->showStatus(tr("ok"), true);
  drawPose();
  drive_panel_->showValues(state_);
  if (const QString problem = drive_panel_->showReadouts(state_); !problem.isEmpty())
    statusBar()->showMessage(problem, 8000);
  if (handles_) handles_->place(endpoint());
  task_panel_->setDevice(state_.shared_mechanism(), state_.preset(), state_.task());  // its read-outs follow the design and the held pose
  fit_panel_->setDevice(state_.preset(), state_.task());                 // the next Run holds this design's other parameters
  // Fields depend on the fixed task coordinates and the branch; the slice
  // also on the driven point while it follows it.
  if (branch_changed) field_panel_->showFieldBranch(state_.branch());
  if (fixed_changed || branch_changed) fields_->request(true, true);
  else if (moved && fieldSettings().follow_endpoint) fields_->request(true, false);
  view_->requestRender();
  noteChange();
  emit poseChanged();
}

void MechanismWindow::drawPose(const IkResult* failed) {
  try {
    scene_->set_pose(state_.mechanism().skeleton_pose(state_.actuators(), state_.task(), failed));
  } catch (const std::invalid_argument& e) {
    statusBar()->showMessage(qs(e.what()), 8000);
  }
}

// ---- Design ---------------------------------------------------------------------

bool MechanismWindow::setParameters(const std::map<std::string, double>& parameters) {
  const DesignPlan plan = state_.with_parameters(parameters);
  if (!plan.ok()) {
    showDesign();  // the panel shows the design in force
    statusBar()->showMessage(qs(plan.refusal), 8000);
    return false;
  }
  try {
    scene_->set_model(plan.mechanism->skeleton_model());
  } catch (const std::invalid_argument& e) {
    statusBar()->showMessage(qs(e.what()), 8000);
    return false;
  }
  // The camera follows the device's size unless the user moved it since it was fitted.
  const bool refit = document_->cameraUntouched(camera_state(renderer_));
  adoptDesign(plan);
  if (refit) fitCamera();
  fields_->request(true, true);
  return true;
}

void MechanismWindow::showDesign() {
  drive_panel_->showRanges(state_.mechanism().info());
  design_panel_->showDesign(state_.mechanism());
}

void MechanismWindow::adoptDesign(const DesignPlan& plan) {
  const Eigen::VectorXd x_before = state_.task();
  const int branch_before = state_.branch();
  state_.adopt(plan);
  showDesign();
  methods_->setMechanism(state_.preset());  // the next Run measures the new design
  showPose(x_before, branch_before);
}

bool MechanismWindow::setActuatorLimits(const std::map<std::string, std::array<double, 2>>& limits_deg) {
  const Eigen::VectorXd x_before = state_.task();
  const int branch_before = state_.branch();
  std::string why;
  if (!state_.set_actuator_limits(limits_deg, why)) {
    showDesign();  // back to the limits in force
    statusBar()->showMessage(qs(why), 8000);
    return false;
  }
  showDesign();
  methods_->setMechanism(state_.preset());
  showPose(x_before, branch_before);
  fields_->request(true, true);
  return true;
}

void MechanismWindow::setStopChecks(const StopChecks& checks) {
  Preset next = state_.preset();
  next.checks = checks;
  adoptDesign(state_.with_saved_pose(next, state_.actuators(), state_.task()));
  fields_->request(true, true);
}

// ---- Sessions, files ---------------------------------------------------------------

Session MechanismWindow::session() const {
  Session s;
  s.mechanism = preset_reference(state_.preset());
  s.parameters = design_parameters(state_.mechanism(), state_.preset());  // motor ratings set as parameters too
  if (design_panel_->editsLimits()) s.actuator_limits_deg = state_.limits_deg();
  s.checks = state_.preset().checks;
  s.pose = state_.actuators();
  s.task = state_.task();
  s.camera = camera_state(renderer_);
  s.field = fieldSettings();
  s.task_volume = task_panel_->setting();
  return s;
}

void MechanismWindow::applySession(const Session& s) {
  // Refuse before changing anything: a value outside a slider's range would be clamped.
  design_panel_->checkParameters(s.parameters);
  Preset next = state_.design_with(s.parameters, s.actuator_limits_deg);
  next.checks = s.checks;
  const DesignPlan plan = state_.with_saved_pose(next, s.pose, s.task);  // throws: nothing changed
  scene_->set_model(plan.mechanism->skeleton_model());
  adoptDesign(plan);
  applyFieldSettings(s.field);
  if (s.camera) apply_camera(renderer_, *s.camera);
  camera_given_ = camera_given_ || s.camera.has_value();
  if (plan.kept == DesignPlan::Kept::Home)
    statusBar()->showMessage(tr("The session's pose is not reachable; the device is at its home pose."), 8000);
  if (s.task_volume) {
    try {
      task_panel_->applySetting(*s.task_volume);
    } catch (const std::invalid_argument& e) {  // e.g. a criterion this device has no measure for
      statusBar()->showMessage(tr("The session's task volume was not applied: %1").arg(qs(e.what())), 8000);
    }
  }
  fields_->restyle();
  fields_->request(true, true);
}

void MechanismWindow::applyViewSession(const Session& s) {
  apply_window_session(this, s);
  if (s.camera) apply_camera(renderer_, *s.camera);  // as saved, after toggles that frame the view
  camera_given_ = camera_given_ || s.camera.has_value();
  view_->requestRender();
}

std::optional<Preset> MechanismWindow::readPresetFile(const QString& file, const QString& failure_title) {
  QString error;
  std::optional<Preset> next = preset_reader_.read(file, error);
  if (!next && !error.isEmpty()) showLoadError(failure_title, file, error);  // (empty: this window may be gone)
  return next;
}

MechanismWindow* MechanismWindow::openMechanismFile(const QString& path) {
  const QString file = QFileInfo(path).absoluteFilePath();
  const std::optional<Preset> read = readPresetFile(file, tr("Cannot open the mechanism"));
  if (!read) return nullptr;
  const Preset& next = *read;
  if (!maybeSave()) return nullptr;  // the user keeps this document
  try {
    MechanismWindow* shown = replaceWith(next, std::nullopt);
    shown->statusBar()->showMessage(tr("Opened %1").arg(file), 4000);
    return shown;
  } catch (const std::exception& e) {
    showLoadError(tr("Cannot open the mechanism"), file, qs(e.what()));
    return nullptr;
  }
}

MechanismWindow* MechanismWindow::reloadMechanism() {
  const QString file = preset_file(state_.preset());
  if (file.isEmpty()) {
    showLoadError(tr("Cannot reload the mechanism"), QString(), tr("This device was not read from a file."));
    return nullptr;
  }
  if (!document_->mayReload()) return nullptr;  // asks before an applied design is replaced
  const std::optional<Preset> read = readPresetFile(file, tr("Cannot reload the mechanism"));
  if (!read) return nullptr;
  try {
    const Preset& next = *read;
    const std::shared_ptr<const Mechanism> m = make_mechanism(next);
    history()->flush();
    const Session before = session();
    const Session kept = reload_session(before, next, *m, state_.mechanism(), state_.actuators(), state_.task());
    const bool same_task = same_task_coordinates(*m, state_.mechanism());
    MechanismWindow* shown = replaceWith(next, kept, history()->path());
    shown->setDrive(drive_);
    // A camera nobody moved still follows the device's size.
    if (document_->cameraUntouched(*kept.camera)) shown->document_->cameraFitted(*kept.camera);
    shown->history()->adopt(*history(), tr("reload"));  // undo reaches back across the reload
    const bool pose_kept = same_task && (shown->task() - kept.task).norm() <= 1e-9;
    shown->statusBar()->showMessage(
        pose_kept || !same_task ? tr("Reloaded %1").arg(file)
                                : tr("Reloaded %1; the new design does not reach the pose: the device is at its home pose")
                                      .arg(file),
        8000);
    return shown;
  } catch (const std::exception& e) {
    showLoadError(tr("Cannot reload the mechanism"), file, qs(e.what()));
    return nullptr;
  }
}

void MechanismWindow::showLoadError(const QString& title, const QString& path, const QString& message) {
  error_panel_->showError(title, path, message);
  statusBar()->showMessage(title + ": " + message, 15000);
}

MechanismWindow* MechanismWindow::replaceWith(const Preset& preset, const std::optional<Session>& session,
                                              const QString& session_path) {
  auto next = std::make_unique<MechanismWindow>(preset);
  if (session) next->applySession(*session);
  else next->applyFieldSettings(fieldSettings());
  // The View menu and, for the same device (a reload), the Fit tab: the
  // session's, else as they are here.
  Session shown_as = session ? *session : Session{};
  if (shown_as.view.empty()) shown_as.view = view_toggles(this);
  if (!shown_as.fit && preset.mechanism == state_.preset().mechanism) {
    shown_as.fit = fit_panel_->setting();
    shown_as.fit_result = fit_panel_->outcome();
  }
  next->applyViewSession(shown_as);
  next->history()->reset(session ? session_path : QString());
  next->restoreState(saveState());  // the same panels where the user put them
  next->setInteractive(interactive());
  setInteractive(false);  // it asked already
  next->setAttribute(Qt::WA_DeleteOnClose);
  next->setGeometry(geometry());
  MechanismWindow* shown = next.release();
  shown->show();
  emit replacedBy(shown);
  close();
  return shown;
}

void MechanismWindow::closeEvent(QCloseEvent* event) {
  if (!maybeSave()) {
    event->ignore();
    return;
  }
  animation_panel_->stop();
  // A closed window no longer follows its file (the window in its place does).
  preset_watcher_->stop();
  document_->closing();
  QMainWindow::closeEvent(event);
}

}  // namespace linkscape::gui
