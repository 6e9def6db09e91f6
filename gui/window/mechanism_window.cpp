#include "gui/window/mechanism_window.h"

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QCloseEvent>
#include <QComboBox>
#include <QDockWidget>
#include <QEvent>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFileSystemWatcher>
#include <QPointer>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QInputDialog>
#include <QLineEdit>
#include <QMenuBar>
#include <QMessageBox>
#include <QPushButton>
#include <QScrollArea>
#include <QSettings>
#include <QSignalBlocker>
#include <QSlider>
#include <QStandardPaths>
#include <QStatusBar>
#include <QSurfaceFormat>
#include <QTimer>
#include <QVBoxLayout>
#include <vtkCallbackCommand.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkHandleWidget.h>
#include <vtkNew.h>
#include <vtkPointHandleRepresentation3D.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkInteractorObserver.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <numbers>
#include <stdexcept>

#include "core/csv.h"
#include "core/haptics.h"
#include "gui/window/error_panel.h"
#include "gui/window/fit_panel.h"
#include "gui/window/methods_panel.h"
#include "gui/window/session_history.h"
#include "gui/window/task_panel.h"
#include "gui/window/vtk_widget.h"
#include "gui/window/background.h"
#include "gui/window/docks.h"
#include "gui/window/export_actions.h"
#include "gui/window/file_actions.h"
#include "gui/window/help_actions.h"
#include "gui/window/mechanism_actions.h"
#include "render/field_scene.h"
#include "render/scene_renderer.h"
#include "render/skeleton_scene.h"
#include "render/task_scene.h"
#include "render/slice_image.h"

namespace linkscape::gui {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr int kSliderSteps = 1000;
constexpr int kPositionSteps = 400;

QString qs(const std::string& s) { return QString::fromStdString(s); }
QString number(double v, int precision = 4) { return QString::number(v, 'g', precision); }
// Fixed-point text; values that round to zero print as 0, never -0.
QString fixed(double v, int decimals = 2) {
  if (std::abs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0.0;
  return QString::number(v, 'f', decimals);
}

// Angles are shown in degrees; everything else in its own unit.
double display_scale(const Quantity& q) { return q.unit == "rad" ? 1.0 / kDeg : 1.0; }
QString display_suffix(const Quantity& q) {
  if (q.unit == "rad" || q.unit == "deg") return QString::fromUtf8(" °");
  return q.unit.empty() ? QString() : " " + qs(q.unit);
}
QString value_text(const Quantity& q, double v) {
  return QString("%1 = %2%3").arg(qs(q.name), fixed(v * display_scale(q), q.unit == "rad" || q.unit == "deg" ? 1 : 3),
                                  display_suffix(q));
}

}  // namespace

// A slider and a spin box showing one quantity (the spin box carries the
// unit; angles in degrees); `changed` runs when the user moves either.
struct QuantityControl {
  Quantity quantity;
  double scale = 1.0;  // display units per model unit
  QSlider* slider = nullptr;
  QDoubleSpinBox* box = nullptr;
  QLabel* label = nullptr;
  QFormLayout* form = nullptr;  // its row

  double value() const { return box->value() / scale; }
  int step_of(double display) const {
    const double lo = box->minimum(), hi = box->maximum();
    return hi > lo ? int(std::lround((display - lo) / (hi - lo) * kSliderSteps)) : 0;
  }
  void set(double v) {
    const QSignalBlocker b1(slider), b2(box);
    // Angles with a full turn of travel are shown in (-180, 180].
    if (quantity.unit == "rad" && quantity.range.hi - quantity.range.lo >= 2 * kPi - 1e-9)
      v = std::remainder(v, 2 * kPi);
    box->setValue(v * scale);
    slider->setValue(step_of(box->value()));
  }
  void set_range(const Range& r) {
    const double v = value();
    quantity.range = r;
    {
      const QSignalBlocker b(box);
      box->setRange(r.lo * scale, r.hi * scale);
    }
    set(v);
  }
  void set_enabled(bool on) {
    slider->setEnabled(on);
    box->setEnabled(on);
    form->setRowVisible(label, on);
  }
};

namespace {

std::unique_ptr<QuantityControl> make_control(QWidget* parent, QFormLayout* form, const Quantity& q,
                                              std::function<void()> changed) {
  auto c = std::make_unique<QuantityControl>();
  c->quantity = q;
  c->scale = display_scale(q);
  c->slider = new QSlider(Qt::Horizontal, parent);
  c->slider->setObjectName(qs(q.name) + "Slider");
  c->slider->setRange(0, kSliderSteps);
  c->box = new QDoubleSpinBox(parent);
  c->box->setObjectName(qs(q.name) + "Box");
  c->box->setDecimals(q.unit == "rad" || q.unit == "deg" ? 1 : 3);
  c->box->setRange(q.range.lo * c->scale, q.range.hi * c->scale);
  c->box->setSingleStep(q.unit == "rad" || q.unit == "deg" ? 1.0 : 0.1);
  c->box->setSuffix(display_suffix(q));
  c->box->setKeyboardTracking(false);
  c->box->setMinimumWidth(96);
  // What it is, and in which unit (the spin box shows the unit too).
  const std::string unit = q.unit == "rad" ? "degrees" : q.unit;
  const QString tip = qs((q.description.empty() ? q.name : q.description) + (unit.empty() ? "" : " (" + unit + ")"));
  c->slider->setToolTip(tip);
  c->box->setToolTip(tip);
  auto* row = new QHBoxLayout;
  row->addWidget(c->slider, 1);
  row->addWidget(c->box);
  c->form = form;
  c->label = new QLabel(qs(q.name), parent);
  c->label->setToolTip(tip);
  form->addRow(c->label, row);
  c->set(q.value);
  QuantityControl* raw = c.get();
  QObject::connect(c->slider, &QSlider::valueChanged, c->box, [raw](int v) {
    const double lo = raw->box->minimum(), hi = raw->box->maximum();
    raw->box->setValue(lo + (hi - lo) * v / kSliderSteps);
  });
  QObject::connect(c->box, &QDoubleSpinBox::valueChanged, c->slider, [raw, changed](double v) {
    {
      const QSignalBlocker block(raw->slider);
      raw->slider->setValue(raw->step_of(v));
    }
    changed();
  });
  return c;
}

QDoubleSpinBox* spin(QWidget* parent, double lo, double hi, double value, int decimals, const QString& suffix = {}) {
  auto* s = new QDoubleSpinBox(parent);
  s->setRange(lo, hi);
  s->setDecimals(decimals);
  s->setValue(value);
  s->setSuffix(suffix);
  s->setKeyboardTracking(false);
  return s;
}

// The camera frames the middle of the sampling box: the box's corners hold
// no workspace, and framing them would make the device small.
Eigen::AlignedBox3d view_box(const Mechanism& m) {
  const Eigen::AlignedBox3d box = m.default_box();
  const Eigen::Vector3d half = 0.5 * 0.7 * box.sizes();
  return {box.center() - half, box.center() + half};
}

bool same_camera(const CameraState& a, const CameraState& b) {
  const double scale = std::max(1.0, (a.position - a.focal_point).norm());
  return (a.position - b.position).norm() <= 1e-9 * scale && (a.focal_point - b.focal_point).norm() <= 1e-9 * scale &&
         (a.view_up - b.view_up).norm() <= 1e-9 && std::abs(a.view_angle - b.view_angle) <= 1e-9;
}

}  // namespace

// ---- Construction ------------------------------------------------------------

MechanismWindow::MechanismWindow(const Preset& preset, QWidget* parent)
    : QMainWindow(parent),
      state_(preset),
      scene_(std::make_unique<render::SkeletonScene>()),
      field_scene_(std::make_unique<render::FieldScene>()),
      task_scene_(std::make_unique<render::TaskScene>()) {
  view_ = new VtkWidget(this);
  // A preset that fails to load is reported above the view, where it is seen.
  auto* centre = new QWidget(this);
  auto* column = new QVBoxLayout(centre);
  column->setContentsMargins(0, 0, 0, 0);
  column->setSpacing(0);
  error_panel_ = new ErrorPanel(centre);
  column->addWidget(error_panel_);
  column->addWidget(view_, 1);
  setCentralWidget(centre);
  connect(error_panel_, &ErrorPanel::reloadRequested, this, [this](const QString& path) {
    // The file that failed: this device's own preset is reloaded, another one opened.
    if (path == preset_file(state_.preset())) reloadMechanism();
    else openMechanismFile(path);
  });
  vtkNew<render::SceneRenderer> renderer;
  renderer->GradientBackgroundOn();
  renderer->SetBackground(0.97, 0.97, 0.98);
  renderer->SetBackground2(0.80, 0.84, 0.90);
  view_->renderWindow()->AddRenderer(renderer);
  renderer_ = renderer;
  // The colour bar has a strip of its own at the right, so it never covers the data.
  vtkNew<vtkRenderer> legend;
  legend->GradientBackgroundOn();
  legend->SetBackground(renderer->GetBackground());
  legend->SetBackground2(renderer->GetBackground2());
  legend->InteractiveOff();
  view_->renderWindow()->AddRenderer(legend);
  legend_ = legend;
  placeLegend();
  view_->installEventFilter(this);
  scene_->set_model(state_.mechanism().skeleton_model());
  // Translucent props blend in the order they were added (render/scene_renderer.h):
  // the fields first, the task volume, then the device (its joint labels last).
  field_scene_->add_to(renderer_, legend_);
  task_scene_->add_to(renderer_);
  scene_->add_to(renderer_);
  renderer_->SetUseDepthPeeling(false);  // plain alpha blending: interactive under software GL
  fitCamera();

  // Drag the driven point: a handle on it, solved by IK as it moves.
  handle_rep_ = vtkSmartPointer<vtkPointHandleRepresentation3D>::New();
  handle_rep_->SetHandleSize(18);
  handle_rep_->AllOff();
  handle_rep_->GetProperty()->SetColor(0.95, 0.1, 0.1);
  handle_rep_->GetSelectedProperty()->SetColor(1.0, 0.6, 0.0);
  handle_ = vtkSmartPointer<vtkHandleWidget>::New();
  handle_->SetInteractor(view_->interactor());
  handle_->SetRepresentation(handle_rep_);
  handle_callback_ = vtkSmartPointer<vtkCallbackCommand>::New();
  handle_callback_->SetClientData(this);
  handle_callback_->SetCallback([](vtkObject*, unsigned long event, void* client, void*) {
    auto* self = static_cast<MechanismWindow*>(client);
    if (event == vtkCommand::StartInteractionEvent || event == vtkCommand::EndInteractionEvent)
      self->setMoving(kHandleDrag, event == vtkCommand::StartInteractionEvent);
    if (event == vtkCommand::StartInteractionEvent) return;
    double p[3];
    self->handle_rep_->GetWorldPosition(p);
    self->moveEndpointTo(Eigen::Vector3d(p[0], p[1], p[2]));
    if (event == vtkCommand::EndInteractionEvent) self->placeHandle();
  });
  handle_->AddObserver(vtkCommand::StartInteractionEvent, handle_callback_);
  handle_->AddObserver(vtkCommand::InteractionEvent, handle_callback_);
  handle_->AddObserver(vtkCommand::EndInteractionEvent, handle_callback_);
  // Turning or zooming the camera with the mouse moves the picture too.
  camera_callback_ = vtkSmartPointer<vtkCallbackCommand>::New();
  camera_callback_->SetClientData(this);
  camera_callback_->SetCallback([](vtkObject*, unsigned long event, void* client, void*) {
    static_cast<MechanismWindow*>(client)->setMoving(kCameraDrag, event == vtkCommand::StartInteractionEvent);
  });
  if (vtkInteractorObserver* style = view_->interactor()->GetInteractorStyle()) {
    style->AddObserver(vtkCommand::StartInteractionEvent, camera_callback_);
    style->AddObserver(vtkCommand::EndInteractionEvent, camera_callback_);
  }
  handle_->EnabledOn();

  QDockWidget* drive = add_dock(this, tr("Drive"), "driveDock", buildDrivePanel());
  QDockWidget* design = add_dock(this, tr("Design"), "designDock", buildDesignPanel());
  QDockWidget* field = add_dock(this, tr("Field"), "fieldDock", buildFieldPanel());
  QDockWidget* animation = add_dock(this, tr("Animation"), "animationDock", buildAnimationPanel());
  task_panel_ = new TaskPanel(task_scene_.get());
  QDockWidget* task = add_dock(this, tr("Task"), "taskDock", task_panel_);
  connect(task_panel_, &TaskPanel::changed, view_, [this] {
    view_->requestRender();
    noteChange();  // the task volume is part of the document
  });
  fit_panel_ = new FitPanel(task_panel_);
  QDockWidget* fit = add_dock(this, tr("Fit"), "fitDock", fit_panel_);
  connect(fit_panel_, &FitPanel::applyRequested, this, [this](const std::map<std::string, double>& design) {
    if (!setParameters(design)) return;
    if (const auto centre = fit_panel_->chosenCentre()) task_panel_->setCentre(*centre);  // where it fits
  });
  // One column of tabs: the drive (with every read-out) in front.
  tabifyDockWidget(drive, design);
  tabifyDockWidget(drive, field);
  tabifyDockWidget(drive, animation);
  tabifyDockWidget(drive, task);
  tabifyDockWidget(drive, fit);
  methods_ = add_methods_dock(this, state_.preset(), drive);
  drive->raise();
  QTimer::singleShot(0, this, [this, drive] { resizeDocks({drive}, {std::max(drive->width(), 440)}, Qt::Horizontal); });
  history_ = new SessionHistory([this] { return session(); }, [this](const Session& s) { applySession(s); }, this);
  buildMenus();

  compute_label_ = add_field_status(this, view_, {&slice_runner_, &volume_runner_}, [this] {
                     slice_settled_ = surfaces_settled_ = true;  // nothing more is coming
                   }).compute;
  connect(&slice_runner_, &FieldJobRunner::sliceReady, this, &MechanismWindow::onSlice);
  connect(&volume_runner_, &FieldJobRunner::surfacesReady, this, &MechanismWindow::onSurfaces);
  connect(&volume_runner_, &FieldJobRunner::lightSurfacesReady, this, [this](const SurfaceResult& light) {
    if (light.volume != surfaces_.volume) return;  // for surfaces no longer shown
    field_scene_->set_light_surface(render::Surface::Reach, light.reach_light);
    field_scene_->set_light_surface(render::Surface::WellConditioned, light.well_conditioned_light);
    if (moving_) view_->requestRender();
  });

  animation_timer_ = new QTimer(this);
  animation_timer_->setInterval(33);
  connect(animation_timer_, &QTimer::timeout, this, &MechanismWindow::animationStep);

  // Neither the drive nor the layout is remembered, so screenshots are reproducible.
  rebuildRecentMenu();
  setDrive(Drive::Task);
  showPose(state_.task(), state_.branch());
  requestFields(true, true);
  history_->reset({});
  connect(history_, &SessionHistory::modifiedChanged, this, &MechanismWindow::updateTitle);
  connect(history_, &SessionHistory::pathChanged, this, &MechanismWindow::updateTitle);
  updateTitle();
  initial_layout_ = saveState();

  // The preset file is watched: a change on disk reloads the device (a
  // window that replaces this one watches the file itself).
  preset_watcher_ = new PresetWatcher(this, [this] {
    if (!reloadMechanism()) preset_watcher_->watch(preset_file(state_.preset()));
  });
  preset_watcher_->watch(preset_file(state_.preset()));
}

void MechanismWindow::noteChange() {
  if (history_ && !animation_timer_->isActive()) history_->noteChange();
}

void MechanismWindow::updateTitle() {
  const QString device = qs(state_.preset().title.empty() ? state_.mechanism().info().title : state_.preset().title);
  const QString document = history_ && !history_->path().isEmpty() ? QFileInfo(history_->path()).fileName() : tr("Untitled");
  // [*] is where Qt shows the modified mark.
  setWindowTitle(QString("%1[*] — %2 — Linkscape").arg(document, device));
  setWindowModified(history_ && history_->modified());
}

void MechanismWindow::setMoving(Moving source, bool on) {
  const unsigned before = moving_;
  moving_ = on ? moving_ | source : moving_ & ~unsigned(source);
  if (bool(before) == bool(moving_)) return;
  field_scene_->set_light(moving_ != 0);
  if (moving_ && !light_asked_) {
    light_asked_ = true;  // for the surfaces shown; made once, on a worker thread
    volume_runner_.submitLight(surfaces_);
  }
  if (!moving_) view_->requestRender();  // the surfaces in full as soon as nothing moves
}

void MechanismWindow::placeLegend() {
  // About 120 pixels wide, at most a quarter of the view; the whole view is
  // the scene's while no colour bar is shown.
  const bool shown = field_scene_->colour_bar_visible();
  const double width = shown ? std::min(0.25, 120.0 / std::max(1, view_->width())) : 0.0;
  renderer_->SetViewport(0, 0, 1 - width, 1);
  legend_->SetDraw(shown);
  if (shown) legend_->SetViewport(1 - width, 0, 1, 1);
}

bool MechanismWindow::eventFilter(QObject* watched, QEvent* event) {
  if (watched == view_ && event->type() == QEvent::Resize) placeLegend();  // docks resize the view too
  return QMainWindow::eventFilter(watched, event);
}

QImage MechanismWindow::viewImage(int width, int height) {
  if (width < 16 || height < 16 || width > kMaxWindowSide || height > kMaxWindowSide)
    throw std::invalid_argument("the view image must be 16..8192 pixels a side, got " + std::to_string(width) + "x" +
                                std::to_string(height));
  const QSize min = view_->minimumSize(), max = view_->maximumSize();
  view_->setFixedSize(width, height);  // the window grows or shrinks around it for this frame
  QCoreApplication::processEvents();
  const QImage image = view_->grabFramebuffer();
  view_->setMinimumSize(min);
  view_->setMaximumSize(max);
  if (image.isNull()) throw std::runtime_error("the view has no picture yet: the window is not on screen");
  return image.size() == QSize(width, height) ? image : image.scaled(width, height);
}

void MechanismWindow::fitCamera() {
  scene_->reset_camera(renderer_, view_box(state_.mechanism()));
  fitted_camera_ = camera_state(renderer_);
}

MechanismWindow::~MechanismWindow() {
  slice_runner_.cancel();
  volume_runner_.cancel();
  handle_->EnabledOff();
  // The view (a child widget) outlives this part of the window.
  if (vtkInteractorObserver* style = view_->interactor()->GetInteractorStyle()) style->RemoveObserver(camera_callback_);
}

// ---- Panels -----------------------------------------------------------------

QWidget* MechanismWindow::buildDesignPanel() {
  auto* w = new QWidget;
  auto* form = new QFormLayout(w);
  form->addRow(tr("Preset"), make_preset_chooser(
                                this, state_.preset(), [this] { return maybeSave(); },
                                [this](const Preset& preset) { replaceWith(preset, std::nullopt); }));
  auto* title = new QLabel(qs(state_.mechanism().info().title), w);
  title->setWordWrap(true);
  form->addRow(title);
  // Ranges come from the preset's device and stay while the design changes.
  for (const Quantity& q : state_.mechanism().info().parameters) {
    if (!q.in_panel) continue;
    const std::string name = q.name;
    parameter_controls_.push_back(make_control(w, form, q, [this, name] {
      for (const auto& c : parameter_controls_)
        if (c->quantity.name == name) setParameters({{name, c->value()}});
    }));
  }
  if (state_.takes_limits()) {
    auto* grid = new QGridLayout;
    int row = 0;
    for (const Quantity& a : state_.mechanism().info().actuators) {
      grid->addWidget(new QLabel(qs(a.name), w), row, 0);
      for (int k = 0; k < 2; ++k) {
        auto* box = spin(w, -360, 360, (k == 0 ? a.range.lo : a.range.hi) / kDeg, 1, QString::fromUtf8(" °"));
        box->setObjectName(qs(a.name) + (k == 0 ? "MinBox" : "MaxBox"));
        box->setToolTip(k == 0 ? tr("Lower end of the actuator's travel") : tr("Upper end of the actuator's travel"));
        limit_boxes_[a.name][k] = box;
        grid->addWidget(box, row, 1 + k);
        connect(box, &QDoubleSpinBox::editingFinished, this, [this] {
          std::map<std::string, std::array<double, 2>> limits;
          for (const auto& [name, boxes] : limit_boxes_) limits[name] = {boxes[0]->value(), boxes[1]->value()};
          setActuatorLimits(limits);
        });
      }
      ++row;
    }
    form->addRow(tr("Actuator travel"), grid);
  }
  return w;
}

QWidget* MechanismWindow::buildDrivePanel() {
  const MechanismInfo& info = state_.mechanism().info();
  auto* w = new QWidget;
  auto* column = new QVBoxLayout(w);
  auto* top = new QFormLayout;
  drive_box_ = new QComboBox(w);
  drive_box_->setObjectName("driveBox");
  drive_box_->addItems({tr("Task coordinates (inverse kinematics)"), tr("Actuators (forward kinematics)")});
  drive_box_->setToolTip(tr("Which sliders move the device; the others follow."));
  top->addRow(tr("Drive"), drive_box_);
  // Both modes where the device has both kinds of kinematics.
  if (info.ik_methods.empty() || info.fk_methods.empty()) drive_box_->setEnabled(false);
  connect(drive_box_, &QComboBox::activated, this, [this](int i) { setDrive(i == 1 ? Drive::Actuators : Drive::Task); });
  branch_box_ = new QComboBox(w);
  branch_box_->setObjectName("branchBox");
  for (const auto& b : info.branches) branch_box_->addItem(qs(b));
  branch_box_->setToolTip(tr("Assembly branch of inverse kinematics. Dragging and the sliders keep the current one."));
  connect(branch_box_, &QComboBox::activated, this, [this](int b) { moveEndpointTo(endpoint(), b); });
  if (info.branches.size() > 1) top->addRow(tr("Branch"), branch_box_);
  else branch_box_->hide();
  column->addLayout(top);

  task_group_ = new QGroupBox(tr("Task"), w);
  auto* task_form = new QFormLayout(task_group_);
  for (std::size_t k = 0; k < info.task.size(); ++k)
    task_controls_.push_back(make_control(task_group_, task_form, info.task[k], [this, k] {
      Eigen::VectorXd x = state_.task();
      x(Eigen::Index(k)) = task_controls_[k]->value();
      if (drive_ == Drive::Task) setTask(x);
      else setActuators(state_.actuators(), x);  // an FK input (e.g. a grip) changed
    }));
  column->addWidget(task_group_);
  const auto drags_pose = [this](const QuantityControl& c) {
    connect(c.slider, &QSlider::sliderPressed, this, [this] { setMoving(kSliderDrag, true); });
    connect(c.slider, &QSlider::sliderReleased, this, [this] { setMoving(kSliderDrag, false); });
  };
  for (const auto& c : task_controls_) drags_pose(*c);
  actuator_group_ = new QGroupBox(tr("Actuators"), w);
  auto* actuator_form = new QFormLayout(actuator_group_);
  for (std::size_t k = 0; k < info.actuators.size(); ++k)
    actuator_controls_.push_back(make_control(actuator_group_, actuator_form, info.actuators[k], [this, k] {
      Eigen::VectorXd q = state_.actuators();
      q(Eigen::Index(k)) = actuator_controls_[k]->value();
      setActuators(q);
    }));
  for (const auto& c : actuator_controls_) drags_pose(*c);
  column->addWidget(actuator_group_);

  auto* state = new QGroupBox(tr("State"), w);
  auto* form = new QFormLayout(state);
  status_label_ = new QLabel(state);
  status_label_->setObjectName("statusLabel");
  status_label_->setWordWrap(true);
  status_label_->setToolTip(tr("Whether the last requested pose was taken; if not, why and which part fails "
                               "(drawn red). The device stays at the last valid pose."));
  form->addRow(tr("Status"), status_label_);
  task_label_ = new QLabel(state);
  task_label_->setObjectName("taskLabel");
  actuator_label_ = new QLabel(state);
  actuator_label_->setObjectName("actuatorLabel");
  form->addRow(tr("Task"), task_label_);
  form->addRow(tr("Actuators"), actuator_label_);
  for (const NamedItem& m : info.measures) {
    auto* label = new QLabel(state);
    label->setObjectName(qs(m.name) + "Label");
    label->setToolTip(qs(m.description));
    auto* name = new QLabel(qs(m.title), state);
    name->setToolTip(qs(m.description));
    form->addRow(name, label);
    measure_labels_.push_back(label);
  }
  det_label_ = new QLabel(state);
  det_label_->setObjectName("detLabel");
  det_label_->setToolTip(tr("Determinant of the Jacobian dx/dq where it is square (0 otherwise)"));
  form->addRow(tr("det J"), det_label_);
  singular_label_ = new QLabel(state);
  singular_label_->setObjectName("singularLabel");
  QString sets;
  for (const NamedItem& s : info.singular_sets) sets += "\n" + qs(s.title) + ": " + qs(s.description);
  singular_label_->setToolTip(tr("The nearest singular set and the distance to it (task, %1):").arg(qs(info.length_unit)) + sets);
  form->addRow(tr("Nearest singular"), singular_label_);
  branch_label_ = new QLabel(state);
  branch_label_->setObjectName("branchLabel");
  form->addRow(tr("Branch"), branch_label_);
  for (QLabel* l : {task_label_, actuator_label_, det_label_, singular_label_, branch_label_})
    l->setTextInteractionFlags(Qt::TextSelectableByMouse);
  column->addWidget(state);
  auto* extra = new QWidget(w);
  extra_form_ = new QFormLayout(extra);
  extra_form_->setContentsMargins(0, 0, 0, 0);
  column->addWidget(extra);
  column->addWidget(new QLabel(tr("Or drag the red handle on the driven point in the view."), w));
  column->addStretch(1);
  return w;
}

QWidget* MechanismWindow::buildFieldPanel() {
  const MechanismInfo& info = state_.mechanism().info();
  const FieldChoices choices = field_choices(info);
  auto* w = new QWidget;
  auto* form = new QFormLayout(w);
  field_box_ = new QComboBox(w);
  field_box_->setObjectName("fieldBox");
  for (const auto& name : choices.fields) {
    QString text = qs(name);
    if (name == "cond") text = qs(info.measures.front().title);
    else if (info.measures.size() > 1 && name == info.measures[1].name) text = qs(info.measures[1].title);
    for (const haptics::FieldInfo& f : haptics::all_field_infos())
      if (f.name == name) text = qs(f.title + " (" + f.unit + ")");
    field_box_->addItem(text, qs(name));
  }
  field_box_->setToolTip(tr("method: which IK method served each sample (categorical colours)"));
  form->addRow(tr("Field"), field_box_);
  method_box_ = new QComboBox(w);
  method_box_->setObjectName("methodBox");
  for (const auto& m : info.ik_methods) {
    method_box_->addItem(qs(m.name));
    method_box_->setItemData(method_box_->count() - 1, qs(m.description), Qt::ToolTipRole);
  }
  if (choices.methods.empty()) method_box_->hide();
  else form->addRow(tr("IK method"), method_box_);
  method_box_->setToolTip(tr("The inverse kinematics method that solves each sample of the fields"));
  field_branch_box_ = new QComboBox(w);
  field_branch_box_->setObjectName("fieldBranchBox");
  for (const auto& b : info.branches) field_branch_box_->addItem(qs(b));
  field_branch_box_->setToolTip(tr("The branch the fields are sampled in; follows the device's branch."));
  if (info.branches.size() > 1) form->addRow(tr("Branch"), field_branch_box_);
  else field_branch_box_->hide();
  normal_box_ = new QComboBox(w);
  normal_box_->setObjectName("normalBox");
  normal_box_->addItems({"x", "y", "z"});
  // The device's own first plane (a planar device's is its plane of motion).
  normal_box_->setCurrentIndex(int(state_.mechanism().default_slice_plane(state_.mechanism().home_task()).first));
  normal_box_->setToolTip(tr("The axis the slice plane is normal to"));
  form->addRow(tr("Slice normal"), normal_box_);
  position_slider_ = new QSlider(Qt::Horizontal, w);
  position_slider_->setObjectName("positionSlider");
  position_slider_->setRange(-kPositionSteps, kPositionSteps);
  position_slider_->setValue(kPositionSteps / 8);
  position_label_ = new QLabel(w);
  position_label_->setObjectName("positionLabel");
  position_label_->setMinimumWidth(80);
  const QString position_tip = tr("Where the slice cuts the sampling box, and how far across it (0 %: its low side). "
                                  "The fraction stays when the design changes size.");
  position_slider_->setToolTip(position_tip);
  position_label_->setToolTip(position_tip);
  auto* row = new QHBoxLayout;
  row->addWidget(position_slider_, 1);
  row->addWidget(position_label_);
  form->addRow(tr("Position"), row);
  follow_box_ = new QCheckBox(tr("Through the driven point"), w);
  follow_box_->setObjectName("followBox");
  follow_box_->setToolTip(tr("The slice moves with the driven point (the position slider follows it)"));
  form->addRow(follow_box_);
  const QString main_measure = qs(info.measures.front().title);
  threshold_box_ = spin(w, 1.05, 100.0, 3.0, 2);
  threshold_box_->setObjectName("thresholdBox");
  threshold_box_->setToolTip(tr("%1 contour on the slice and the well-conditioned surface").arg(main_measure));
  form->addRow(tr("%1 threshold").arg(main_measure), threshold_box_);
  auto_range_box_ = new QCheckBox(tr("Automatic colour range"), w);
  auto_range_box_->setChecked(true);
  range_min_box_ = spin(w, -1e6, 1e6, 1.0, 3);
  range_max_box_ = spin(w, -1e6, 1e6, 10.0, 3);
  auto* range_row = new QHBoxLayout;
  range_row->addWidget(range_min_box_);
  range_row->addWidget(range_max_box_);
  form->addRow(auto_range_box_);
  form->addRow(tr("Colour range"), range_row);
  colour_map_box_ = new QComboBox(w);
  colour_map_box_->setObjectName("colourMapBox");
  for (const std::string& map : render::colour_maps()) colour_map_box_->addItem(qs(map));
  colour_map_box_->setToolTip(tr("viridis: perceptually uniform; cividis: also for colour vision deficiency; "
                                 "diverging: blue below, red above the middle (the range is symmetric about 0 "
                                 "for signed fields such as the reach margin)"));
  log_scale_box_ = new QCheckBox(tr("Logarithmic"), w);
  log_scale_box_->setObjectName("logScaleBox");
  log_scale_box_->setChecked(true);
  log_scale_box_->setToolTip(tr("A log10 colour scale for c(J), the residual and the haptic measures "
                                "(the other fields are always linear)"));
  auto* map_row = new QHBoxLayout;
  map_row->addWidget(colour_map_box_, 1);
  map_row->addWidget(log_scale_box_);
  form->addRow(tr("Colour map"), map_row);
  slice_resolution_box_ = new QComboBox(w);
  slice_resolution_box_->setObjectName("sliceResolutionBox");
  for (int n : choices.slice_resolutions) slice_resolution_box_->addItem(QString::number(n));
  slice_resolution_box_->setCurrentText(QString::number(choices.default_slice_resolution));
  volume_resolution_box_ = new QComboBox(w);
  volume_resolution_box_->setObjectName("volumeResolutionBox");
  for (int n : choices.volume_resolutions) volume_resolution_box_->addItem(QString::number(n));
  volume_resolution_box_->setCurrentText(QString::number(choices.default_volume_resolution));
  slice_resolution_box_->setToolTip(tr("Samples along each side of the slice"));
  volume_resolution_box_->setToolTip(tr("Samples along each side of the volume the workspace surfaces come from"));
  form->addRow(tr("Slice samples"), slice_resolution_box_);
  form->addRow(tr("Volume samples"), volume_resolution_box_);
  show_slice_box_ = new QCheckBox(tr("Slice"), w);
  show_slice_box_->setObjectName("showSliceBox");
  show_reach_box_ = new QCheckBox(tr("Reachable workspace"), w);
  show_reach_box_->setObjectName("showReachBox");
  show_well_box_ = new QCheckBox(tr("Well-conditioned workspace"), w);
  show_well_box_->setObjectName("showWellBox");
  reach_opacity_slider_ = new QSlider(Qt::Horizontal, w);
  well_opacity_slider_ = new QSlider(Qt::Horizontal, w);
  for (QSlider* s : {reach_opacity_slider_, well_opacity_slider_}) s->setRange(0, 100);
  reach_opacity_slider_->setValue(10);
  well_opacity_slider_->setValue(22);
  for (QCheckBox* c : {show_slice_box_, show_reach_box_, show_well_box_}) c->setChecked(true);
  show_slice_box_->setToolTip(tr("Show the slice (it is computed only while shown)"));
  show_reach_box_->setToolTip(tr("The boundary of the reachable set, translucent; the slider sets its opacity"));
  show_well_box_->setToolTip(tr("The region where the main measure is below the threshold; the slider sets its opacity"));
  reach_opacity_slider_->setToolTip(tr("Opacity of the reachable workspace"));
  well_opacity_slider_->setToolTip(tr("Opacity of the well-conditioned workspace"));
  form->addRow(show_slice_box_);
  form->addRow(show_reach_box_, reach_opacity_slider_);
  form->addRow(show_well_box_, well_opacity_slider_);
  if (info.task.size() > 3)
    form->addRow(new QLabel(tr("Fields are sampled with the other task coordinates as they are now."), w));

  auto slice_changed = [this] { requestFields(true, false); };
  connect(normal_box_, &QComboBox::currentIndexChanged, this, slice_changed);
  connect(position_slider_, &QSlider::valueChanged, this, [this] {
    if (!follow_box_->isChecked()) requestFields(true, false);
  });
  connect(slice_resolution_box_, &QComboBox::currentIndexChanged, this, slice_changed);
  connect(follow_box_, &QCheckBox::toggled, this, slice_changed);
  connect(method_box_, &QComboBox::currentIndexChanged, this, [this] { requestFields(true, true); });
  connect(field_branch_box_, &QComboBox::currentIndexChanged, this, [this] { requestFields(true, true); });
  connect(volume_resolution_box_, &QComboBox::currentIndexChanged, this, [this] { requestFields(false, true); });
  connect(threshold_box_, &QDoubleSpinBox::valueChanged, this, [this] {
    restyleSlice();
    requestFields(false, true);
  });
  // A haptic field needs its own pass over the slice (core/haptics.h): the
  // slice is sampled again when the choice moves to or from one.
  connect(field_box_, &QComboBox::currentIndexChanged, this, [this] {
    const bool haptic = haptics::is_haptic_field(field_box_->currentData().toString().toStdString());
    if (haptic || (slice_field_ && !slice_field_->extras.empty())) requestFields(true, false);
    else restyleSlice();
  });
  connect(auto_range_box_, &QCheckBox::toggled, this, [this] { restyleSlice(); });
  range_min_box_->setObjectName("rangeMinBox");
  range_min_box_->setToolTip(tr("Lower end of the colour range (the value's unit); shows the automatic one when that is on"));
  range_max_box_->setToolTip(tr("Upper end of the colour range (the value's unit); shows the automatic one when that is on"));
  range_max_box_->setObjectName("rangeMaxBox");
  auto_range_box_->setObjectName("autoRangeBox");
  auto_range_box_->setToolTip(tr("Colour range from the slice's data (the boxes show it); off: type the range"));
  connect(range_min_box_, &QDoubleSpinBox::valueChanged, this, [this] { restyleSlice(); });
  connect(colour_map_box_, &QComboBox::currentIndexChanged, this, [this] { restyleSlice(); });
  connect(log_scale_box_, &QCheckBox::toggled, this, [this] { restyleSlice(); });
  connect(range_max_box_, &QDoubleSpinBox::valueChanged, this, [this] { restyleSlice(); });
  // Fields are computed only while shown.
  connect(show_slice_box_, &QCheckBox::toggled, this, [this] {
    applyFieldVisibility();
    requestFields(true, false);
  });
  for (QCheckBox* c : {show_reach_box_, show_well_box_})
    connect(c, &QCheckBox::toggled, this, [this] {
      applyFieldVisibility();
      requestFields(false, true);
    });
  for (QSlider* s : {reach_opacity_slider_, well_opacity_slider_})
    connect(s, &QSlider::valueChanged, this, [this] { applyFieldVisibility(); });
  return w;
}

QWidget* MechanismWindow::buildAnimationPanel() {
  auto* w = new QWidget;
  auto* form = new QFormLayout(w);
  path_box_ = new QComboBox(w);
  path_box_->setObjectName("pathBox");
  path_box_->addItems({tr("Circle around the driven point (slice plane)"),
                       tr("Line through the driven point (slice's first axis)")});
  path_box_->setToolTip(tr("The path the driven point follows while playing"));
  form->addRow(tr("Path"), path_box_);
  amplitude_box_ = spin(w, 0.0, 1e4, 0.15 * state_.mechanism().size(), 2, " " + qs(state_.mechanism().info().length_unit));
  amplitude_box_->setObjectName("amplitudeBox");
  amplitude_box_->setToolTip(tr("Radius of the circle or half-length of the line"));
  form->addRow(tr("Size"), amplitude_box_);
  speed_box_ = spin(w, 0.01, 100.0, 0.5, 2, tr(" cycles/s"));
  speed_box_->setToolTip(tr("Turns of the circle, or back-and-forth sweeps of the line, per second"));
  form->addRow(tr("Speed"), speed_box_);
  loop_box_ = new QCheckBox(tr("Loop"), w);
  loop_box_->setToolTip(tr("Play again from the start at the end of the path"));
  loop_box_->setChecked(true);
  form->addRow(loop_box_);
  play_button_ = new QPushButton(tr("Play"), w);
  play_button_->setObjectName("playButton");
  play_button_->setToolTip(tr("Move the driven point along the path (again to stop)"));
  play_button_->setCheckable(true);
  form->addRow(play_button_);
  form->addRow(new QLabel(tr("The path is followed by inverse kinematics in the current branch;\n"
                             "points the device cannot reach are skipped."), w));
  connect(play_button_, &QPushButton::toggled, this, [this](bool on) {
    play_button_->setText(on ? tr("Pause") : tr("Play"));
    if (on) {
      if (animation_phase_ == 0.0) animation_centre_ = endpoint();
      animation_timer_->start();
    } else {
      animation_timer_->stop();
    }
    setMoving(kAnimation, on);
  });
  connect(path_box_, &QComboBox::currentIndexChanged, this, [this] { animation_phase_ = 0.0; });
  return w;
}

void MechanismWindow::buildMenus() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  file->addAction(tr("&Open session…"), QKeySequence::Open, this, [this] {
    if (!maybeSave()) return;
    const QString path = ask_session_to_open(this);
    if (!path.isEmpty()) openSession(path);
  });
  file->addAction(tr("&Save session"), QKeySequence::Save, this, &MechanismWindow::save);
  file->addAction(tr("Save session &as…"), QKeySequence::SaveAs, this, &MechanismWindow::saveAs);
  recent_menu_ = file->addMenu(tr("Recent sessions"));
  file->addSeparator();
  const QKeySequence open_mechanism_key(Qt::CTRL | Qt::SHIFT | Qt::Key_O);
  QAction* open_mechanism = file->addAction(tr("Open &mechanism…"), open_mechanism_key, this, [this] {
    const QString path = ask_mechanism_file(this, state_.preset());
    if (!path.isEmpty()) openMechanismFile(path);
  });
  open_mechanism->setObjectName("openMechanismAction");
  open_mechanism->setStatusTip(
      tr("Open a device from its preset file (.json), a shipped one or a described mechanism"));
  QAction* reload =
      file->addAction(tr("&Reload mechanism"), QKeySequence(Qt::Key_F5), this, [this] { reloadMechanism(); });
  reload->setObjectName("reloadMechanismAction");
  reload->setStatusTip(tr("Read the preset file again (done by itself when the file changes): the design is the "
                          "file's; the camera, the pose, the field and task settings stay"));
  file->addSeparator();
  file->addAction(tr("Export slice &image…"), this, [this] { export_slice_image(this, slice_field_.get(), sliceStyle()); });
  file->addAction(tr("Export workspace &mesh…"), this, [this] {
    export_surface_mesh(this, surfaces_.volume.get(), surfaces_.reach, surfaces_.well_conditioned,
                        threshold_box_->value());
  });
  file->addAction(tr("Export &field (VTI)…"), this, [this] { export_volume(this, surfaces_.volume.get()); });
  file->addAction(tr("Save screens&hot…"), this, [this] { export_screenshot(this); });
  file->addAction(tr("Save &view image…"), this, [this] {
    const QString suggested = QString("%1x%2").arg(2 * view_->width()).arg(2 * view_->height());
    const QString saved = export_view_image(this, suggested, [this](int w, int h) { return viewImage(w, h); });
    if (!saved.isEmpty()) statusBar()->showMessage(saved, 4000);
  });
  file->addSeparator();
  file->addAction(tr("&Quit"), QKeySequence::Quit, this, &QWidget::close);
  QMenu* edit = menuBar()->addMenu(tr("&Edit"));
  QAction* undo = history_->stack()->createUndoAction(this, tr("&Undo"));
  undo->setShortcut(QKeySequence::Undo);
  QAction* redo = history_->stack()->createRedoAction(this, tr("&Redo"));
  redo->setShortcut(QKeySequence::Redo);
  edit->addAction(undo);
  edit->addAction(redo);
  QMenu* view = menuBar()->addMenu(tr("&View"));
  view->addAction(tr("&Reset camera"), this, [this] {
    fitCamera();
    view_->requestRender();
  });
  view->addAction(tr("Reset &layout"), this, [this] {
    restoreState(initial_layout_);
    for (QDockWidget* dock : findChildren<QDockWidget*>()) dock->show();
  });
  view->addSeparator();
  for (QDockWidget* dock : findChildren<QDockWidget*>()) view->addAction(dock->toggleViewAction());
  view->addSeparator();
  // Depth peeling composites the translucent surfaces exactly but costs
  // several full-screen passes per frame (docs/performance.md), so
  // interaction uses plain alpha blending unless the user asks.
  QAction* exact = view->addAction(tr("&Exact transparency (slower)"));
  exact->setObjectName("exactTransparencyAction");
  exact->setCheckable(true);
  connect(exact, &QAction::toggled, this, [this](bool on) {
    renderer_->SetUseDepthPeeling(on);
    view_->requestRender();
  });
  QMenu* help = menuBar()->addMenu(tr("&Help"));
  help->addAction(tr("&Documentation"), this, [this] { show_documentation(this); });
  help->addAction(tr("&About Linkscape"), this, [this] { show_about(this); });
}

bool MechanismWindow::save() {
  if (history_->path().isEmpty()) return saveAs();
  return saveSession(history_->path());
}

bool MechanismWindow::saveAs() {
  const QString path =
      ask_session_to_save(this, history_->path().isEmpty() ? QStringLiteral("session.json") : history_->path());
  return !path.isEmpty() && saveSession(path);
}

bool MechanismWindow::maybeSave() {
  history_->flush();
  if (!interactive_ || !history_->modified()) return true;
  const auto answer = QMessageBox::warning(
      this, tr("Unsaved changes"), tr("The session has changes that are not saved. Save them first?"),
      QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
  if (answer == QMessageBox::Save) return save();
  return answer == QMessageBox::Discard;
}

// ---- Pose ---------------------------------------------------------------------

bool MechanismWindow::setTask(const Eigen::VectorXd& x, bool tracking) {
  return settle([&] { return state_.set_task(x, tracking); });
}

bool MechanismWindow::moveEndpointTo(const Eigen::Vector3d& target, int branch) {
  if (settle([&] { return state_.move_endpoint_to(target, branch); })) return true;
  syncPanels();  // the branch box shows the branch in force
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
  status_label_->setText(refusal());
  status_label_->setStyleSheet("color: #b00020");
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
  status_label_->setText(tr("ok"));
  status_label_->setStyleSheet("color: #1b5e20");
  drawPose();
  syncPanels();
  updateReadouts();
  placeHandle();
  task_panel_->setDevice(state_.shared_mechanism(), state_.preset(), state_.task());  // its read-outs follow the design and the held pose
  fit_panel_->setDevice(state_.preset(), state_.task());                 // the next Run holds this design's other parameters
  // Fields depend on the fixed task coordinates and the branch; the slice
  // also on the driven point while it follows it.
  if (branch_changed) {
    const QSignalBlocker block(field_branch_box_);
    field_branch_box_->setCurrentIndex(state_.branch());
  }
  if (fixed_changed || branch_changed) requestFields(true, true);
  else if (moved && follow_box_ && follow_box_->isChecked()) requestFields(true, false);
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

void MechanismWindow::placeHandle() {
  if (!handle_rep_) return;
  Eigen::Vector3d p = endpoint();
  handle_rep_->SetWorldPosition(p.data());
}

void MechanismWindow::setDrive(Drive drive) {
  drive_ = drive;
  const bool fk = drive == Drive::Actuators && drive_box_->isEnabled();
  if (!fk) drive_ = Drive::Task;
  {
    const QSignalBlocker block(drive_box_);
    drive_box_->setCurrentIndex(fk ? 1 : 0);
  }
  const auto& inputs = state_.mechanism().info().fk_inputs;
  // The panel that drives is shown; the other one's values are in the read-outs.
  bool any_task = false;
  for (const auto& c : task_controls_) {
    const bool input = !fk || std::find(inputs.begin(), inputs.end(), c->quantity.name) != inputs.end();
    c->set_enabled(input);
    any_task = any_task || input;
  }
  for (const auto& c : actuator_controls_) c->set_enabled(fk);
  task_group_->setVisible(any_task);
  actuator_group_->setVisible(fk);
}

void MechanismWindow::syncPanels() {
  for (std::size_t k = 0; k < task_controls_.size(); ++k) task_controls_[k]->set(state_.task()(Eigen::Index(k)));
  for (std::size_t k = 0; k < actuator_controls_.size(); ++k) actuator_controls_[k]->set(state_.actuators()(Eigen::Index(k)));
  const QSignalBlocker block(branch_box_);
  branch_box_->setCurrentIndex(state_.branch());
}

void MechanismWindow::syncRanges() {
  const MechanismInfo& info = state_.mechanism().info();
  for (std::size_t k = 0; k < task_controls_.size(); ++k) task_controls_[k]->set_range(info.task[k].range);
  for (std::size_t k = 0; k < actuator_controls_.size(); ++k) actuator_controls_[k]->set_range(info.actuators[k].range);
  for (const auto& c : parameter_controls_) {
    const auto p = state_.mechanism().parameters();
    if (p.count(c->quantity.name)) c->set(p.at(c->quantity.name));
  }
  for (const Quantity& a : info.actuators) {
    const auto it = limit_boxes_.find(a.name);
    if (it == limit_boxes_.end()) continue;
    for (int k = 0; k < 2; ++k) {
      const QSignalBlocker block(it->second[k]);
      it->second[k]->setValue((k == 0 ? a.range.lo : a.range.hi) / kDeg);
    }
  }
}

void MechanismWindow::updateReadouts() {
  const MechanismInfo& info = state_.mechanism().info();
  QStringList task, actuators;
  for (std::size_t k = 0; k < info.task.size(); ++k) task << value_text(info.task[k], state_.task()(Eigen::Index(k)));
  for (std::size_t k = 0; k < info.actuators.size(); ++k) {
    double v = state_.actuators()(Eigen::Index(k));
    if (info.actuators[k].unit == "rad") v = std::remainder(v, 2 * kPi);
    actuators << value_text(info.actuators[k], v);
  }
  auto lines = [](const QStringList& items) {
    QString text;
    for (int i = 0; i < items.size(); ++i) text += (i == 0 ? "" : i % 3 == 0 ? "\n" : ", ") + items[i];
    return text;
  };
  task_label_->setText(lines(task));
  actuator_label_->setText(lines(actuators));
  try {
    const Measures m = state_.mechanism().measures(state_.actuators(), state_.task());
    for (std::size_t k = 0; k < measure_labels_.size(); ++k) {
      const double v = k < m.values.size() ? m.values[k] : NAN;
      measure_labels_[k]->setText(std::isfinite(v) ? number(v) : QString::fromUtf8("∞ (singular)"));
    }
    det_label_->setText(number(m.det));
    const SingularityReport s = state_.mechanism().nearest_singularity(state_.actuators(), state_.task());
    singular_label_->setText(QString("%1, %2 %3")
                                 .arg(qs(info.singular_sets.at(s.nearest).title), number(s.distance, 3),
                                      qs(info.length_unit)));
  } catch (const std::exception& e) {
    statusBar()->showMessage(qs(e.what()), 8000);
  }
  branch_label_->setText(qs(info.branches.at(state_.branch())));
  while (extra_form_->rowCount() > 0) extra_form_->removeRow(0);
  for (const auto& [label, text] : state_.mechanism().readouts(state_.actuators(), state_.task())) {
    auto* value = new QLabel(qs(text));
    value->setTextInteractionFlags(Qt::TextSelectableByMouse);
    extra_form_->addRow(qs(label), value);
  }
}

// ---- Design ---------------------------------------------------------------------

bool MechanismWindow::setParameters(const std::map<std::string, double>& parameters) {
  const DesignPlan plan = state_.with_parameters(parameters);
  if (!plan.ok()) {
    syncRanges();  // the panel shows the design in force
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
  const bool refit = fitted_camera_ && same_camera(*fitted_camera_, camera_state(renderer_));
  adoptDesign(plan);
  if (refit) fitCamera();
  requestFields(true, true);
  return true;
}

void MechanismWindow::adoptDesign(const DesignPlan& plan) {
  const Eigen::VectorXd x_before = state_.task();
  const int branch_before = state_.branch();
  state_.adopt(plan);
  syncRanges();
  methods_->setMechanism(state_.preset());  // the next Run measures the new design
  showPose(x_before, branch_before);
}

bool MechanismWindow::setActuatorLimits(const std::map<std::string, std::array<double, 2>>& limits_deg) {
  const Eigen::VectorXd x_before = state_.task();
  const int branch_before = state_.branch();
  std::string why;
  if (!state_.set_actuator_limits(limits_deg, why)) {
    syncRanges();  // back to the limits in force
    statusBar()->showMessage(qs(why), 8000);
    return false;
  }
  syncRanges();
  methods_->setMechanism(state_.preset());
  showPose(x_before, branch_before);
  requestFields(true, true);
  return true;
}

// ---- Fields -------------------------------------------------------------------

FieldSettings MechanismWindow::fieldSettings() const {
  FieldSettings f;
  f.field = field_box_->currentData().toString().toStdString();
  if (!field_choices(state_.mechanism().info()).methods.empty()) f.method = method_box_->currentText().toStdString();
  f.normal = normal_box_->currentText().toStdString();
  f.position = slicePosition();
  f.follow_endpoint = follow_box_->isChecked();
  f.threshold = threshold_box_->value();
  if (!auto_range_box_->isChecked()) {
    f.range_min = range_min_box_->value();
    f.range_max = range_max_box_->value();
  }
  f.colour_map = colour_map_box_->currentText().toStdString();
  f.log_scale = log_scale_box_->isChecked();
  f.slice_resolution = slice_resolution_box_->currentText().toInt();
  f.volume_resolution = volume_resolution_box_->currentText().toInt();
  f.show_slice = show_slice_box_->isChecked();
  f.show_reach = show_reach_box_->isChecked();
  f.show_well_conditioned = show_well_box_->isChecked();
  f.reach_opacity = reach_opacity_slider_->value() / 100.0;
  f.well_conditioned_opacity = well_opacity_slider_->value() / 100.0;
  return f;
}

void MechanismWindow::applyFieldSettings(const FieldSettings& f) {
  {
    const QSignalBlocker b1(field_box_), b2(normal_box_), b3(position_slider_), b4(follow_box_), b5(threshold_box_),
        b6(auto_range_box_), b7(slice_resolution_box_), b8(volume_resolution_box_), b9(show_slice_box_),
        b10(show_reach_box_), b11(show_well_box_), b12(reach_opacity_slider_), b13(well_opacity_slider_),
        b14(method_box_), b15(range_min_box_), b16(range_max_box_), b17(colour_map_box_), b18(log_scale_box_);
    auto choose = [](QComboBox* box, int index) {
      if (index >= 0) box->setCurrentIndex(index);
    };
    choose(field_box_, field_box_->findData(qs(f.field)));
    choose(method_box_, method_box_->findText(qs(f.method)));
    choose(normal_box_, normal_box_->findText(qs(f.normal)));
    choose(slice_resolution_box_, slice_resolution_box_->findText(QString::number(f.slice_resolution)));
    choose(volume_resolution_box_, volume_resolution_box_->findText(QString::number(f.volume_resolution)));
    follow_box_->setChecked(f.follow_endpoint);
    threshold_box_->setValue(f.threshold);
    choose(colour_map_box_, colour_map_box_->findText(qs(f.colour_map)));
    log_scale_box_->setChecked(f.log_scale);
    auto_range_box_->setChecked(!(f.range_min && f.range_max));
    if (f.range_min) range_min_box_->setValue(*f.range_min);
    if (f.range_max) range_max_box_->setValue(*f.range_max);
    show_slice_box_->setChecked(f.show_slice);
    show_reach_box_->setChecked(f.show_reach);
    show_well_box_->setChecked(f.show_well_conditioned);
    reach_opacity_slider_->setValue(int(std::lround(f.reach_opacity * 100)));
    well_opacity_slider_->setValue(int(std::lround(f.well_conditioned_opacity * 100)));
    const Eigen::AlignedBox3d box = state_.mechanism().default_box();
    const int n = normal_box_->currentIndex();
    const double half = 0.5 * (box.max()(n) - box.min()(n));
    position_slider_->setValue(int(std::lround((f.position - box.center()(n)) / half * kPositionSteps)));
  }
  applyFieldVisibility();
  restyleSlice();
  requestFields(true, true);
}

double MechanismWindow::slicePosition() const {
  const int n = normal_box_->currentIndex();
  const Eigen::AlignedBox3d box = state_.mechanism().default_box();
  if (follow_box_->isChecked()) return state_.task()(n);
  return box.center()(n) + 0.5 * (box.max()(n) - box.min()(n)) * position_slider_->value() / kPositionSteps;
}

// Fields are computed only when shown, coarse first, on worker threads; a
// new request cancels the one in flight.
void MechanismWindow::requestFields(bool slice, bool volume) {
  if (!field_box_) return;  // panels not built yet
  noteChange();
  const MechanismInfo& info = state_.mechanism().info();
  IkOptions options;
  if (!field_choices(info).methods.empty()) options.method = method_box_->currentText().toStdString();
  if (info.branches.size() > 1) options.branch = field_branch_box_->currentIndex();
  FieldJob job;
  job.sampler = [m = state_.shared_mechanism(), fixed = state_.task(), options](const Grid& grid, const FieldProgress& progress) {
    return m->compute_field(grid, fixed, options, 0, progress);
  };
  std::optional<haptics::DeviceData> haptic_data;
  if (haptics::is_haptic_field(field_box_->currentData().toString().toStdString())) {
    try {
      haptic_data = haptics::device_data(state_.preset(), info);
    } catch (const std::invalid_argument& e) {
      statusBar()->showMessage(qs(e.what()), 8000);
    }
  }
  job.cond_threshold = threshold_box_->value();
  const Eigen::AlignedBox3d box = state_.mechanism().default_box();
  const Eigen::Vector3d lo = box.min(), hi = box.max();
  if (slice && show_slice_box_->isChecked()) {
    const Axis normal = parse_axis(normal_box_->currentText().toStdString());
    const int n = int(normal);
    const double position = std::clamp(slicePosition(), lo(n), hi(n));
    if (follow_box_->isChecked()) {
      const QSignalBlocker block(position_slider_);
      position_slider_->setValue(
          int(std::lround((position - 0.5 * (lo(n) + hi(n))) / (0.5 * (hi(n) - lo(n))) * kPositionSteps)));
    }
    position_label_->setText(QString("%1 = %2 %3 (%4 %)")
                                 .arg(normal_box_->currentText(), fixed(position, 2), qs(info.length_unit))
                                 .arg(std::lround(100.0 * (position - lo(n)) / (hi(n) - lo(n)))));
    const auto [u, v] = Grid::slice_axes(normal);
    const int res = slice_resolution_box_->currentText().toInt();
    FieldJob slice_job = job;
    if (haptic_data)
      slice_job.sampler = [m = state_.shared_mechanism(), fixed = state_.task(), options, data = *haptic_data](const Grid& grid,
                                                                                    const FieldProgress& progress) {
        return haptics::sample_field(*m, grid, fixed, options, 0, progress, &data);
      };
    slice_job.slice = Grid::slice(normal, position, lo(int(u)), hi(int(u)), lo(int(v)), hi(int(v)), res, res);
    slice_settled_ = false;
    slice_runner_.submit(slice_job);
  } else if (slice) {
    slice_runner_.cancel();
    slice_settled_ = true;
  }
  if (volume && (show_reach_box_->isChecked() || show_well_box_->isChecked())) {
    const int n = volume_resolution_box_->currentText().toInt();
    FieldJob volume_job = job;
    volume_job.volume = Grid::box(lo, hi, {n, n, n});
    volume_job.coarse_divisor = 2;
    surfaces_settled_ = false;
    volume_runner_.submit(volume_job);
  } else if (volume) {
    volume_runner_.cancel();
    surfaces_settled_ = true;
  }
}

void MechanismWindow::onSlice(const SliceResult& result) {
  slice_field_ = result.field;
  restyleSlice();
  compute_label_->setText(tr("slice %1 ms, %2 M points/s")
                              .arg(result.seconds * 1e3, 0, 'f', 1)
                              .arg(result.points_per_second / 1e6, 0, 'f', 2));
  if (result.fine) slice_settled_ = true;
  emit sliceUpdated(result.fine);
  emit fieldsUpdated(result.fine);
}

void MechanismWindow::onSurfaces(const SurfaceResult& result) {
  surfaces_ = result;  // kept for export
  field_scene_->set_surface(render::Surface::Reach, result.reach);
  field_scene_->set_surface(render::Surface::WellConditioned, result.well_conditioned);
  light_asked_ = false;
  if (moving_ && result.fine) {  // fields that follow the pose: light meshes for the next frames
    light_asked_ = true;
    volume_runner_.submitLight(result);
  }
  applyFieldVisibility();
  statusBar()->showMessage(tr("isosurfaces (%1) in %2 ms")
                               .arg(result.fine ? tr("full") : tr("coarse"))
                               .arg(result.seconds * 1e3, 0, 'f', 0),
                           4000);
  if (result.fine) surfaces_settled_ = true;
  emit surfacesUpdated(result.fine);
  emit fieldsUpdated(result.fine);
}

render::SliceStyle MechanismWindow::sliceStyle() const {
  const FieldSettings f = fieldSettings();
  render::SliceStyle style;
  style.field = f.field;
  style.contour_levels = {f.threshold};
  style.min = f.range_min;
  style.max = f.range_max;
  style.colour_map = f.colour_map;
  style.log_scale = f.log_scale;
  return style;
}

void MechanismWindow::restyleSlice() {
  noteChange();
  // The range boxes show the range in use: typed, or the automatic one.
  range_min_box_->setEnabled(!auto_range_box_->isChecked());
  range_max_box_->setEnabled(!auto_range_box_->isChecked());
  if (!slice_field_) return;
  render::SliceStyle style = sliceStyle();
  if (auto_range_box_->isChecked()) {
    try {
      const auto [lo, hi] = render::colour_range(*slice_field_, style);
      const QSignalBlocker b1(range_min_box_), b2(range_max_box_);
      range_min_box_->setValue(lo);
      range_max_box_->setValue(hi);
    } catch (const std::invalid_argument&) {
      // categorical fields have no range; the error is shown below
    }
  }
  style.scale = std::max(1, 768 / slice_resolution_box_->currentText().toInt());
  style.unreachable_alpha = 50;
  try {
    field_scene_->set_slice(*slice_field_, style);
  } catch (const std::invalid_argument& e) {
    statusBar()->showMessage(qs(e.what()), 8000);
  }
  applyFieldVisibility();
}

void MechanismWindow::applyFieldVisibility() {
  noteChange();
  const bool slice = show_slice_box_->isChecked() && slice_field_ != nullptr;
  field_scene_->set_slice_visible(slice);
  // The method field is categorical: its colours are not on a scale.
  field_scene_->set_colour_bar_visible(slice && field_box_->currentData().toString() != "method");
  placeLegend();
  field_scene_->set_surface_visible(render::Surface::Reach, show_reach_box_->isChecked());
  field_scene_->set_surface_visible(render::Surface::WellConditioned, show_well_box_->isChecked());
  field_scene_->set_surface_opacity(render::Surface::Reach, reach_opacity_slider_->value() / 100.0);
  field_scene_->set_surface_opacity(render::Surface::WellConditioned, well_opacity_slider_->value() / 100.0);
  view_->requestRender();
}

// ---- Animation ------------------------------------------------------------------

void MechanismWindow::animationStep() {
  const double dt = animation_timer_->interval() / 1000.0;
  animation_phase_ += speed_box_->value() * dt;
  if (animation_phase_ >= 1.0) {
    if (!loop_box_->isChecked()) {
      play_button_->setChecked(false);
      animation_phase_ = 0.0;
      return;
    }
    animation_phase_ -= 1.0;
  }
  const double angle = 2 * kPi * animation_phase_;
  const auto [u, v] = Grid::slice_axes(parse_axis(normal_box_->currentText().toStdString()));
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  const double a = amplitude_box_->value();
  if (path_box_->currentIndex() == 0) {
    offset(int(u)) = a * std::cos(angle) - a;  // starts at the driven point
    offset(int(v)) = a * std::sin(angle);
  } else {
    offset(int(u)) = a * std::sin(angle);
  }
  moveEndpointTo(animation_centre_ + offset);  // an unreachable point is skipped, the panel says why
}

// ---- Sessions, files ---------------------------------------------------------------

Session MechanismWindow::session() const {
  Session s;
  s.mechanism = preset_reference(state_.preset());
  s.parameters = state_.mechanism().parameters();
  if (!limit_boxes_.empty())
    for (const Quantity& a : state_.mechanism().info().actuators)
      s.actuator_limits_deg[a.name] = {a.range.lo / kDeg, a.range.hi / kDeg};
  s.pose = state_.actuators();
  s.task = state_.task();
  s.camera = camera_state(renderer_);
  s.field = fieldSettings();
  s.task_volume = task_panel_->setting();
  return s;
}

void MechanismWindow::applySession(const Session& s) {
  // Refuse before changing anything: a value outside a slider's range would be clamped.
  for (const auto& c : parameter_controls_) {
    const auto it = s.parameters.find(c->quantity.name);
    if (it != s.parameters.end() && (it->second * c->scale < c->box->minimum() || it->second * c->scale > c->box->maximum()))
      throw std::invalid_argument("session: " + c->quantity.name + " = " + format_number(it->second) +
                                  " is outside the window's range [" + format_number(c->box->minimum() / c->scale) +
                                  ", " + format_number(c->box->maximum() / c->scale) + "] for this preset");
  }
  Preset next = state_.preset();
  for (const auto& [name, value] : s.parameters) next.parameters[name] = value;
  for (const auto& [name, range] : s.actuator_limits_deg) next.limits_deg[name] = {range[0], range[1]};
  const DesignPlan plan = state_.with_saved_pose(next, s.pose, s.task);  // throws: nothing changed
  scene_->set_model(plan.mechanism->skeleton_model());
  adoptDesign(plan);
  applyFieldSettings(s.field);
  if (s.camera) apply_camera(renderer_, *s.camera);
  if (plan.kept == DesignPlan::Kept::Home)
    statusBar()->showMessage(tr("The session's pose is not reachable; the device is at its home pose."), 8000);
  if (s.task_volume) {
    try {
      task_panel_->applySetting(*s.task_volume);
    } catch (const std::invalid_argument& e) {  // e.g. a criterion this device has no measure for
      statusBar()->showMessage(tr("The session's task volume was not applied: %1").arg(qs(e.what())), 8000);
    }
  }
  restyleSlice();
  requestFields(true, true);
}

bool MechanismWindow::openSession(const QString& path) {
  const bool opened = open_session_file(this, path, [this, path](const Session& s, const Preset& preset) {
    if (preset.mechanism == state_.preset().mechanism) {
      applySession(s);
      history_->reset(path);
    } else {
      replaceWith(preset, s, path);
    }
  });
  if (!opened) return false;
  addRecent(path);
  return true;
}

bool MechanismWindow::saveSession(const QString& path) {
  history_->flush();
  if (!save_session_file(this, session(), path)) return false;
  history_->markSaved(path);
  addRecent(path);
  return true;
}

std::optional<Preset> MechanismWindow::readPresetFile(const QString& file, const QString& failure_title) {
  if (reading_preset_) return std::nullopt;  // one file at a time; the watcher tries again
  reading_preset_ = true;
  const QPointer<MechanismWindow> alive(this);
  std::optional<Preset> next;
  QString error;
  try {
    next = load_checked_preset(file.toStdString());
  } catch (const std::exception& e) {
    error = qs(e.what());
  }
  if (!alive) return std::nullopt;  // closed while the file was read
  reading_preset_ = false;
  if (!next) showLoadError(failure_title, file, error);
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
  const std::optional<Preset> read = readPresetFile(file, tr("Cannot reload the mechanism"));
  if (!read) return nullptr;
  try {
    const Preset& next = *read;
    const std::shared_ptr<const Mechanism> m = make_mechanism(next);
    history_->flush();
    const Session before = session();
    const Session kept = reload_session(before, next, *m, state_.mechanism(), state_.actuators(), state_.task());
    const bool same_task = same_task_coordinates(*m, state_.mechanism());
    MechanismWindow* shown = replaceWith(next, kept, history_->path());
    shown->setDrive(drive_);
    // A camera nobody moved still follows the device's size.
    if (fitted_camera_ && same_camera(*fitted_camera_, *kept.camera)) shown->fitted_camera_ = kept.camera;
    if (history_->modified() || !same_document(before, shown->session())) shown->history()->markModified();
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

void MechanismWindow::addRecent(const QString& path) {
  add_recent_session(path);
  rebuildRecentMenu();
}

void MechanismWindow::rebuildRecentMenu() {
  if (recent_menu_) fill_recent_menu(recent_menu_, this, [this](const QString& path) { openSession(path); });
}

MechanismWindow* MechanismWindow::replaceWith(const Preset& preset, const std::optional<Session>& session,
                                              const QString& session_path) {
  auto next = std::make_unique<MechanismWindow>(preset);
  if (session) next->applySession(*session);
  else next->applyFieldSettings(fieldSettings());
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
  animation_timer_->stop();
  // A closed window no longer follows its file (the window in its place does).
  preset_watcher_->stop();
  if (interactive_) {
    QSettings settings;
    settings.setValue("windowGeometry", saveGeometry());
    settings.setValue("windowState", saveState());
  }
  QMainWindow::closeEvent(event);
}

}  // namespace linkscape::gui
