#include "gui/main_window.h"

#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QCloseEvent>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QImage>
#include <QLabel>
#include <QMenuBar>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QSignalBlocker>
#include <QSlider>
#include <QStatusBar>
#include <QSurfaceFormat>
#include <QScrollArea>
#include <QTimer>
#include <QVBoxLayout>
#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkHandleWidget.h>
#include <vtkNew.h>
#include <vtkPointHandleRepresentation3D.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "gui/latency_probe.h"
#include "gui/methods_panel.h"
#include "gui/window_parts.h"
#include "gui/pathos2_window.h"
#include "gui/slice_figure.h"
#include "gui/vtk_widget.h"
#include "render/field_scene.h"
#include "render/field_vtk.h"
#include "render/linkage_scene.h"
#include "render/slice_image.h"
#include "render/workspace_mesh.h"

namespace linkscape::gui {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int kMaxWindowSide = 8192;
constexpr int kSliderStepsPerDegree = 10;
constexpr int kLengthSliderSteps = 1000;
constexpr int kPositionSteps = 400;
// While dragging or animating, one step may move an actuator at most this
// much; a larger jump means the same branch continues on the other side of
// a singular set, which would make the linkage jump.
constexpr double kMaxTrackingStep = 0.6;  // rad

// A pose that shows every link clearly: well conditioned, branch 0.
const Eigen::Vector3d kInitialPose(20 * kDeg, 65 * kDeg, 5 * kDeg);

QString number(double v, int precision = 4) { return QString::number(v, 'g', precision); }

double angle_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Eigen::Vector3d d = a - b;
  for (int k = 0; k < 3; ++k) d(k) = std::remainder(d(k), 2 * std::numbers::pi);
  return d.cwiseAbs().maxCoeff();
}

QDoubleSpinBox* spin(QWidget* parent, double lo, double hi, double value, int decimals, const QString& suffix) {
  auto* s = new QDoubleSpinBox(parent);
  s->setRange(lo, hi);
  s->setDecimals(decimals);
  s->setValue(value);
  s->setSuffix(suffix);
  s->setKeyboardTracking(false);
  return s;
}


}  // namespace

MainWindow::MainWindow(const Preset& preset, QWidget* parent)
    : QMainWindow(parent),
      preset_(preset),
      scene_(std::make_unique<render::LinkageScene>()),
      field_scene_(std::make_unique<render::FieldScene>()),
      q_(kInitialPose) {
  setWindowTitle(QString("Linkscape — %1").arg(QString::fromStdString(preset.title)));
  view_ = new VtkWidget(this);
  setCentralWidget(view_);

  vtkNew<vtkRenderer> renderer;
  renderer->GradientBackgroundOn();
  renderer->SetBackground(0.97, 0.97, 0.98);
  renderer->SetBackground2(0.80, 0.84, 0.90);
  view_->renderWindow()->AddRenderer(renderer);
  renderer_ = renderer;

  scene_->set_model(make_parallel12r(preset_));
  scene_->set_pose(q_);
  scene_->add_to(renderer_);
  field_scene_->add_to(renderer_);
  scene_->reset_camera(renderer_);

  // Drag the endpoint: a handle on D, solved by IK as it moves.
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
    auto* self = static_cast<MainWindow*>(client);
    double p[3];
    self->handle_rep_->GetWorldPosition(p);
    self->moveEndpointTo(Eigen::Vector3d(p[0], p[1], p[2]));
    if (event == vtkCommand::EndInteractionEvent) self->placeHandle();
  });
  handle_->AddObserver(vtkCommand::InteractionEvent, handle_callback_);
  handle_->AddObserver(vtkCommand::EndInteractionEvent, handle_callback_);
  handle_->EnabledOn();

  auto* mechanism_and_actuators = new QWidget;
  auto* column = new QVBoxLayout(mechanism_and_actuators);
  column->addWidget(buildMechanismPanel());
  column->addWidget(buildActuatorPanel());
  column->addStretch(1);
  QDockWidget* first = add_dock(this, tr("Mechanism and actuators"), "mechanismDock", mechanism_and_actuators);
  QDockWidget* endpoint = add_dock(this, tr("Endpoint"), "endpointDock", buildEndpointPanel());
  QDockWidget* field = add_dock(this, tr("Field"), "fieldDock", buildFieldPanel());
  QDockWidget* animation = add_dock(this, tr("Animation"), "animationDock", buildAnimationPanel());
  // Mechanism and actuators on top; field, endpoint and animation as tabs below.
  splitDockWidget(first, field, Qt::Vertical);
  // Once laid out: the top dock shows every read-out, the tabs below scroll
  // if they must, and the column is wide enough for the field panel.
  QTimer::singleShot(0, this, [this, first, field] {
    const int top = static_cast<QScrollArea*>(first->widget())->widget()->sizeHint().height() + 36;  // + title bar
    resizeDocks({first, field}, {top, std::max(200, height() - top)}, Qt::Vertical);
    resizeDocks({first}, {std::max(first->width(), 470)}, Qt::Horizontal);
  });
  tabifyDockWidget(field, endpoint);
  tabifyDockWidget(field, animation);
  methods_ = add_methods_dock(this, preset_, field);
  field->raise();
  buildMenus();

  compute_label_ = add_field_status(this, view_, {&slice_runner_, &volume_runner_}, [this] {
                     slice_settled_ = surfaces_settled_ = true;  // nothing more is coming
                   }).compute;
  connect(&slice_runner_, &FieldJobRunner::sliceReady, this, &MainWindow::onSlice);
  connect(&volume_runner_, &FieldJobRunner::surfacesReady, this, &MainWindow::onSurfaces);

  animation_timer_ = new QTimer(this);
  animation_timer_->setInterval(33);
  connect(animation_timer_, &QTimer::timeout, this, &MainWindow::animationStep);

  QSettings settings;
  restoreGeometry(settings.value("window/geometry").toByteArray());
  restoreState(settings.value("window/state").toByteArray());
  rebuildRecentMenu();

  setPose(q_);
  requestFields(true, true);
}

MainWindow::~MainWindow() {
  slice_runner_.cancel();
  volume_runner_.cancel();
  handle_->EnabledOff();
}

const parallel12r::Model& MainWindow::model() const { return scene_->model(); }

QString MainWindow::endpointMessage() const { return endpoint_message_; }

// ---- Panels -----------------------------------------------------------------

QWidget* MainWindow::buildMechanismPanel() {
  const auto& m = scene_->model();
  const QString unit = " " + QString::fromStdString(m.length_unit);
  auto* box = new QGroupBox(tr("Mechanism"));
  auto* form = new QFormLayout(box);
  form->addRow(tr("Preset"), make_preset_chooser(this, preset_));
  const char* names[] = {"L1", "L2"};
  const double values[] = {m.L1, m.L2};
  for (int i = 0; i < 2; ++i) {
    const double lo = 0.1 * values[i], hi = 3.0 * values[i];
    auto* slider = new QSlider(Qt::Horizontal, box);
    slider->setObjectName(QString("%1Slider").arg(names[i]));
    slider->setRange(0, kLengthSliderSteps);
    auto* box_i = spin(box, lo, hi, values[i], 2, unit);
    box_i->setObjectName(QString("%1Box").arg(names[i]));
    box_i->setToolTip(i == 0 ? tr("Link along u(alpha, beta) (Eqs. 11-13)") : tr("Link along u(alpha, gamma)"));
    slider->setValue(int(std::lround((values[i] - lo) / (hi - lo) * kLengthSliderSteps)));
    auto* row = new QHBoxLayout;
    row->addWidget(slider, 1);
    row->addWidget(box_i);
    form->addRow(names[i], row);
    length_boxes_[i] = box_i;
    length_sliders_[i] = slider;
    connect(slider, &QSlider::valueChanged, this, [this, i, lo, hi](int v) {
      length_boxes_[i]->setValue(lo + (hi - lo) * v / kLengthSliderSteps);
    });
    connect(box_i, &QDoubleSpinBox::valueChanged, this, [this, i, lo, hi](double v) {
      const QSignalBlocker block(length_sliders_[i]);
      length_sliders_[i]->setValue(int(std::lround((v - lo) / (hi - lo) * kLengthSliderSteps)));
      setLinkLengths(length_boxes_[0]->value(), length_boxes_[1]->value());
    });
  }
  // Actuator ranges: min and max per actuator; the sliders, the IK and the
  // fields (reachable set) follow them.
  auto* ranges = new QGridLayout;
  const parallel12r::Interval limits[] = {m.alpha_limits, m.beta_limits, m.gamma_limits};
  const char* actuators[] = {"alpha", "beta", "gamma"};
  const QString symbols[] = {QString::fromUtf8("α"), QString::fromUtf8("β"), QString::fromUtf8("γ")};
  for (int i = 0; i < 3; ++i) {
    const double bound = i == 0 ? 90.0 : 180.0;
    ranges->addWidget(new QLabel(symbols[i], box), i, 0);
    for (int k = 0; k < 2; ++k) {
      auto* limit = spin(box, -bound, bound, (k == 0 ? limits[i].lo : limits[i].hi) / kDeg, 1, QString::fromUtf8(" °"));
      limit->setObjectName(QString("%1%2Box").arg(actuators[i], k == 0 ? "Min" : "Max"));
      limit->setToolTip(k == 0 ? tr("Lower end of the actuator's range") : tr("Upper end of the actuator's range"));
      limit_boxes_[i][k] = limit;
      ranges->addWidget(limit, i, 1 + k);
      connect(limit, &QDoubleSpinBox::editingFinished, this, [this] {
        std::array<parallel12r::Interval, 3> deg;
        for (int a = 0; a < 3; ++a) deg[a] = {limit_boxes_[a][0]->value(), limit_boxes_[a][1]->value()};
        setActuatorRanges(deg);
      });
    }
  }
  form->addRow(tr("Actuator ranges"), ranges);
  return box;
}

QWidget* MainWindow::buildActuatorPanel() {
  auto* box = new QGroupBox(tr("Actuators"));
  auto* form = new QFormLayout(box);
  const auto& m = scene_->model();
  const parallel12r::Interval limits[] = {m.alpha_limits, m.beta_limits, m.gamma_limits};
  const char* names[] = {"alpha", "beta", "gamma"};
  const QString symbols[] = {QString::fromUtf8("α (A)"), QString::fromUtf8("β (B)"), QString::fromUtf8("γ (C)")};
  for (int i = 0; i < 3; ++i) {
    // alpha stays inside the open interval (-90, 90) deg of Eq. 14.
    const double lo = std::max(limits[i].lo / kDeg, i == 0 ? -89.9 : -180.0);
    const double hi = std::min(limits[i].hi / kDeg, i == 0 ? 89.9 : 180.0);
    auto* slider = new QSlider(Qt::Horizontal, box);
    slider->setObjectName(QString("%1Slider").arg(names[i]));
    slider->setRange(int(std::lround(lo * kSliderStepsPerDegree)), int(std::lround(hi * kSliderStepsPerDegree)));
    auto* s = spin(box, lo, hi, 0.0, 1, QString::fromUtf8(" °"));
    s->setObjectName(QString("%1Box").arg(names[i]));
    auto* row = new QHBoxLayout;
    row->addWidget(slider, 1);
    row->addWidget(s);
    form->addRow(symbols[i], row);
    sliders_[i] = slider;
    angle_boxes_[i] = s;
    connect(slider, &QSlider::valueChanged, this, [this, i](int v) {
      Eigen::Vector3d q = q_;
      q(i) = v * kDeg / kSliderStepsPerDegree;
      setPose(q);
    });
    connect(s, &QDoubleSpinBox::valueChanged, this, [this, i](double deg) {
      Eigen::Vector3d q = q_;
      q(i) = deg * kDeg;
      setPose(q);
    });
  }
  endpoint_label_ = new QLabel(box);
  endpoint_label_->setObjectName("endpointLabel");
  cond_label_ = new QLabel(box);
  cond_label_->setObjectName("condLabel");
  det_label_ = new QLabel(box);
  singular_label_ = new QLabel(box);
  singular_label_->setObjectName("singularLabel");
  branch_label_ = new QLabel(box);
  for (QLabel* l : {endpoint_label_, cond_label_, det_label_, singular_label_, branch_label_})
    l->setTextInteractionFlags(Qt::TextSelectableByMouse);
  form->addRow(tr("Endpoint D"), endpoint_label_);
  form->addRow(tr("c(J)"), cond_label_);
  form->addRow(tr("det J"), det_label_);
  form->addRow(tr("Nearest singular"), singular_label_);
  form->addRow(tr("Branch"), branch_label_);
  return box;
}

QWidget* MainWindow::buildEndpointPanel() {
  auto* w = new QWidget;
  auto* form = new QFormLayout(w);
  const QString unit = " " + QString::fromStdString(scene_->model().length_unit);
  const double r = scene_->model().reach();
  const char* names[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    target_boxes_[k] = spin(w, -1.5 * r, 1.5 * r, 0.0, 3, unit);
    target_boxes_[k]->setObjectName(QString("target%1Box").arg(names[k]));
    form->addRow(names[k], target_boxes_[k]);
  }
  auto* go = new QPushButton(tr("Move endpoint here"), w);
  go->setObjectName("moveEndpointButton");
  form->addRow(go);
  branch_box_ = new QComboBox(w);
  branch_box_->setObjectName("branchBox");
  branch_box_->addItems({tr("0: sin(β − γ) > 0"), tr("1: sin(β − γ) < 0")});
  branch_box_->setToolTip(tr("Assembly mode used by IK. Dragging keeps the current one."));
  form->addRow(tr("Branch"), branch_box_);
  endpoint_status_ = new QLabel(w);
  endpoint_status_->setObjectName("endpointStatus");
  endpoint_status_->setWordWrap(true);
  form->addRow(endpoint_status_);
  form->addRow(new QLabel(tr("Or drag the red handle on D in the view."), w));
  connect(go, &QPushButton::clicked, this, [this] {
    moveEndpointTo({target_boxes_[0]->value(), target_boxes_[1]->value(), target_boxes_[2]->value()},
                   branch_box_->currentIndex());
  });
  connect(branch_box_, &QComboBox::activated, this, [this](int b) {
    const Eigen::Vector3d d = parallel12r::forward(model(), q_);
    moveEndpointTo(d, b);
  });
  return w;
}

QWidget* MainWindow::buildFieldPanel() {
  auto* w = new QWidget;
  auto* form = new QFormLayout(w);
  field_box_ = new QComboBox(w);
  field_box_->setObjectName("fieldBox");
  for (const auto& name : field_choices(preset_.mechanism).fields) field_box_->addItem(QString::fromStdString(name));
  field_box_->setToolTip(tr("method: which IK method served each sample (blue planar, orange Newton, purple paper, "
                            "green DLS, grey none); with the fallback method it shows where planar gave up"));
  form->addRow(tr("Field"), field_box_);
  method_box_ = new QComboBox(w);
  for (const auto& name : field_choices(preset_.mechanism).methods) method_box_->addItem(QString::fromStdString(name));
  method_box_->setToolTip(tr("fallback: planar, then Newton from its candidate where planar misses the tolerance"));
  form->addRow(tr("IK method"), method_box_);
  normal_box_ = new QComboBox(w);
  normal_box_->setObjectName("normalBox");
  normal_box_->addItems({"x", "y", "z"});
  form->addRow(tr("Slice normal"), normal_box_);
  position_slider_ = new QSlider(Qt::Horizontal, w);
  position_slider_->setObjectName("positionSlider");
  position_slider_->setRange(-kPositionSteps, kPositionSteps);
  position_slider_->setValue(kPositionSteps / 8);
  position_label_ = new QLabel(w);
  auto* row = new QHBoxLayout;
  row->addWidget(position_slider_, 1);
  row->addWidget(position_label_);
  form->addRow(tr("Position"), row);
  follow_box_ = new QCheckBox(tr("Follow the endpoint"), w);
  form->addRow(follow_box_);
  threshold_box_ = spin(w, 1.05, 100.0, 3.0, 2, "");
  threshold_box_->setObjectName("thresholdBox");
  threshold_box_->setToolTip(tr("c(J) contour on the slice and the well-conditioned surface"));
  form->addRow(tr("c(J) threshold"), threshold_box_);
  auto_range_box_ = new QCheckBox(tr("Automatic colour range"), w);
  auto_range_box_->setChecked(true);
  range_min_box_ = spin(w, -1e6, 1e6, 1.0, 3, "");
  range_max_box_ = spin(w, -1e6, 1e6, 10.0, 3, "");
  auto* range_row = new QHBoxLayout;
  range_row->addWidget(range_min_box_);
  range_row->addWidget(range_max_box_);
  form->addRow(auto_range_box_);
  form->addRow(tr("Colour range"), range_row);
  slice_resolution_box_ = new QComboBox(w);
  const FieldChoices choices = field_choices(preset_.mechanism);
  for (int n : choices.slice_resolutions) slice_resolution_box_->addItem(QString::number(n));
  slice_resolution_box_->setCurrentText(QString::number(choices.default_slice_resolution));
  volume_resolution_box_ = new QComboBox(w);
  volume_resolution_box_->setObjectName("volumeResolutionBox");
  for (int n : choices.volume_resolutions) volume_resolution_box_->addItem(QString::number(n));
  volume_resolution_box_->setCurrentText(QString::number(choices.default_volume_resolution));
  form->addRow(tr("Slice samples"), slice_resolution_box_);
  form->addRow(tr("Volume samples"), volume_resolution_box_);
  show_slice_box_ = new QCheckBox(tr("Slice"), w);
  show_reach_box_ = new QCheckBox(tr("Reachable workspace"), w);
  show_well_box_ = new QCheckBox(tr("Well-conditioned workspace"), w);
  show_reach_box_->setObjectName("showReachBox");
  show_well_box_->setObjectName("showWellBox");
  reach_opacity_slider_ = new QSlider(Qt::Horizontal, w);
  well_opacity_slider_ = new QSlider(Qt::Horizontal, w);
  for (QSlider* s : {reach_opacity_slider_, well_opacity_slider_}) s->setRange(0, 100);
  reach_opacity_slider_->setValue(10);
  well_opacity_slider_->setValue(22);
  for (QCheckBox* c : {show_slice_box_, show_reach_box_, show_well_box_}) c->setChecked(true);
  form->addRow(show_slice_box_);
  form->addRow(show_reach_box_, reach_opacity_slider_);
  form->addRow(show_well_box_, well_opacity_slider_);

  auto slice_changed = [this] { requestFields(true, false); };
  connect(normal_box_, &QComboBox::currentIndexChanged, this, slice_changed);
  connect(position_slider_, &QSlider::valueChanged, this, slice_changed);
  connect(slice_resolution_box_, &QComboBox::currentIndexChanged, this, slice_changed);
  connect(follow_box_, &QCheckBox::toggled, this, slice_changed);
  connect(method_box_, &QComboBox::currentIndexChanged, this, [this] { requestFields(true, true); });
  connect(volume_resolution_box_, &QComboBox::currentIndexChanged, this, [this] { requestFields(false, true); });
  connect(threshold_box_, &QDoubleSpinBox::valueChanged, this, [this] {
    restyleSlice();
    requestFields(false, true);
  });
  connect(field_box_, &QComboBox::currentIndexChanged, this, [this] { restyleSlice(); });
  connect(auto_range_box_, &QCheckBox::toggled, this, [this] { restyleSlice(); });
  connect(range_min_box_, &QDoubleSpinBox::valueChanged, this, [this] { restyleSlice(); });
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

QWidget* MainWindow::buildAnimationPanel() {
  auto* w = new QWidget;
  auto* form = new QFormLayout(w);
  path_box_ = new QComboBox(w);
  path_box_->setObjectName("pathBox");
  path_box_->addItems({tr("Circle around D (slice plane)"), tr("Line through D (along the slice's first axis)"),
                       tr("Sweep α"), tr("Sweep β"), tr("Sweep γ")});
  form->addRow(tr("Path"), path_box_);
  const QString unit = QString::fromStdString(scene_->model().length_unit);
  amplitude_box_ = spin(w, 0.0, 1e3, 0.15 * scene_->model().reach(), 2, "");
  amplitude_box_->setToolTip(tr("Radius or half-length (%1), or sweep half-angle (deg)").arg(unit));
  form->addRow(tr("Size"), amplitude_box_);
  speed_box_ = spin(w, 0.01, 100.0, 0.5, 2, tr(" cycles/s"));
  form->addRow(tr("Speed"), speed_box_);
  loop_box_ = new QCheckBox(tr("Loop"), w);
  loop_box_->setChecked(true);
  form->addRow(loop_box_);
  play_button_ = new QPushButton(tr("Play"), w);
  play_button_->setObjectName("playButton");
  play_button_->setCheckable(true);
  form->addRow(play_button_);
  connect(play_button_, &QPushButton::toggled, this, [this](bool on) {
    play_button_->setText(on ? tr("Pause") : tr("Play"));
    if (on) {
      if (animation_phase_ == 0.0) {
        animation_centre_ = parallel12r::forward(model(), q_);
        animation_pose_ = q_;
      }
      animation_timer_->start();
    } else {
      animation_timer_->stop();
    }
  });
  connect(path_box_, &QComboBox::currentIndexChanged, this, [this] { animation_phase_ = 0.0; });
  return w;
}

void MainWindow::buildMenus() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  file->addAction(tr("&Open session…"), QKeySequence::Open, this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, tr("Open session"), QString(), tr("Linkscape session (*.json)"));
    if (!path.isEmpty()) openSession(path);
  });
  file->addAction(tr("&Save session…"), QKeySequence::Save, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, tr("Save session"), "session.json", tr("Linkscape session (*.json)"));
    if (!path.isEmpty()) saveSession(path);
  });
  recent_menu_ = file->addMenu(tr("Recent sessions"));
  file->addSeparator();
  file->addAction(tr("Export slice &image…"), this, &MainWindow::exportSliceImage);
  file->addAction(tr("Export workspace &mesh…"), this, [this] {
    export_surface_mesh(this, volume_field_.get(), reach_mesh_, well_mesh_, threshold_box_->value());
  });
  file->addAction(tr("Export &field (VTI)…"), this, [this] { export_volume(this, volume_field_.get()); });
  file->addAction(tr("Save screens&hot…"), this, [this] { export_screenshot(this); });
  file->addSeparator();
  file->addAction(tr("&Quit"), QKeySequence::Quit, this, &QWidget::close);
  QMenu* view = menuBar()->addMenu(tr("&View"));
  view->addAction(tr("&Reset camera"), this, [this] {
    scene_->reset_camera(renderer_);
    view_->update();
  });
  // Depth peeling composites the translucent surfaces exactly but costs
  // several full-screen passes per frame (about 8x the frame time on a
  // software renderer, docs/performance.md), so interaction uses plain
  // alpha blending unless the user asks.
  QAction* exact = view->addAction(tr("&Exact transparency (slower)"));
  exact->setObjectName("exactTransparencyAction");
  exact->setCheckable(true);
  connect(exact, &QAction::toggled, this, [this](bool on) {
    renderer_->SetUseDepthPeeling(on);
    view_->update();
  });
  renderer_->SetUseDepthPeeling(false);
}

// ---- Pose and IK ---------------------------------------------------------------

void MainWindow::setPose(const Eigen::Vector3d& q) {
  if (!q.allFinite()) return;
  q_ = q;
  for (int i = 0; i < 3; ++i) {
    const QSignalBlocker block_slider(sliders_[i]), block_box(angle_boxes_[i]);
    sliders_[i]->setValue(int(std::lround(q(i) / kDeg * kSliderStepsPerDegree)));
    angle_boxes_[i]->setValue(q(i) / kDeg);
  }
  scene_->set_pose(q_);
  placeHandle();
  updateReadouts();
  if (follow_box_ && follow_box_->isChecked()) requestFields(true, false);
  view_->update();
  emit poseChanged();
}

bool MainWindow::moveEndpointTo(const Eigen::Vector3d& target, int branch) {
  // An explicit branch means a typed target: the linkage may move anywhere.
  // Without one (drags, animation) it tracks the current branch continuously.
  const bool tracking = branch < 0;
  const int wanted = branch >= 0 ? branch : this->branch();
  const QString unit = QString::fromStdString(model().length_unit);
  auto refuse = [&](const QString& why) {
    endpoint_message_ = why;
    endpoint_status_->setText(why);
    endpoint_status_->setStyleSheet("color: #b00020");
    return false;
  };
  if (!target.allFinite()) return refuse(tr("The target is not a finite point."));
  const parallel12r::IkResult r = parallel12r::inverse(model(), target, parallel12r::IkMethod::Planar);
  const parallel12r::IkSolution* s = nullptr;
  for (const auto& c : r.solutions)
    if (c.branch == wanted) s = &c;
  if (r.status == Status::Unreachable)
    return refuse(tr("Unreachable: |D| = %1 %2 is outside the reach %3–%4 %2.")
                      .arg(number(target.norm()), unit, number(model().inner_reach()), number(model().reach())));
  if (!s || s->status == Status::Singular)
    return refuse(tr("Singular: the target is on the %1 (stays at the last valid pose).")
                      .arg(QString::fromUtf8(parallel12r::to_string(
                          parallel12r::nearest_singularity(model(), s ? s->q_actuated : q_).nearest).data())));
  if (s->status == Status::OutOfLimits) return refuse(tr("Out of the actuator ranges in branch %1.").arg(wanted));
  if (s->status != Status::Ok) return refuse(tr("No solution in branch %1 (%2).").arg(wanted).arg(QString::fromUtf8(to_string(s->status).data())));
  if (tracking && angle_distance(s->q_actuated, q_) > kMaxTrackingStep)
    return refuse(tr("Reaching this target would make the linkage jump (it lies across a singular set); "
                     "move through the workspace instead."));
  endpoint_message_.clear();
  endpoint_status_->setText(tr("Branch %1, residual %2 %3").arg(wanted).arg(number(s->residual, 2), unit));
  endpoint_status_->setStyleSheet("");
  setPose(s->q_actuated);
  return true;
}

void MainWindow::placeHandle() {
  if (!handle_rep_) return;
  const Eigen::Vector3d d = parallel12r::forward(model(), q_);
  handle_rep_->SetWorldPosition(const_cast<double*>(d.data()));
}

void MainWindow::setLinkLengths(double L1, double L2) {
  parallel12r::Model m = scene_->model();
  m.L1 = L1;
  m.L2 = L2;
  try {
    scene_->set_model(m);
  } catch (const std::invalid_argument& e) {
    statusBar()->showMessage(QString::fromStdString(e.what()), 8000);
    return;
  }
  preset_.parameters["L1"] = L1;
  preset_.parameters["L2"] = L2;
  // Changes from sessions or scripts show in the panel too.
  const double lengths[] = {L1, L2};
  for (int i = 0; i < 2; ++i) {
    QDoubleSpinBox* box = length_boxes_[i];
    if (!box) continue;
    const QSignalBlocker block_box(box), block_slider(length_sliders_[i]);
    box->setValue(lengths[i]);
    length_sliders_[i]->setValue(
        int(std::lround((box->value() - box->minimum()) / (box->maximum() - box->minimum()) * kLengthSliderSteps)));
  }
  methods_->setMechanism(preset_);  // the next Run measures the new lengths
  placeHandle();
  updateReadouts();
  requestFields(true, true);
  view_->update();
}

void MainWindow::setActuatorRanges(const std::array<parallel12r::Interval, 3>& ranges_deg) {
  parallel12r::Model m = scene_->model();
  m.alpha_limits = {ranges_deg[0].lo * kDeg, ranges_deg[0].hi * kDeg};
  m.beta_limits = {ranges_deg[1].lo * kDeg, ranges_deg[1].hi * kDeg};
  m.gamma_limits = {ranges_deg[2].lo * kDeg, ranges_deg[2].hi * kDeg};
  try {
    m.validate();  // empty or inverted ranges
    scene_->set_model(m);
  } catch (const std::invalid_argument& e) {
    statusBar()->showMessage(QString::fromStdString(e.what()), 8000);
    syncRangeBoxes();  // back to the ranges in force
    return;
  }
  const char* names[] = {"alpha", "beta", "gamma"};
  for (int i = 0; i < 3; ++i) preset_.limits_deg[names[i]] = ranges_deg[i];
  syncRangeBoxes();
  // Sliders span the new ranges (alpha inside the open interval of Eq. 14);
  // the pose is clamped into them.
  const parallel12r::Interval limits[] = {m.alpha_limits, m.beta_limits, m.gamma_limits};
  Eigen::Vector3d q = q_;
  for (int i = 0; i < 3; ++i) {
    const double lo = std::max(limits[i].lo / kDeg, i == 0 ? -89.9 : -180.0);
    const double hi = std::min(limits[i].hi / kDeg, i == 0 ? 89.9 : 180.0);
    const QSignalBlocker b1(sliders_[i]), b2(angle_boxes_[i]);
    sliders_[i]->setRange(int(std::lround(lo * kSliderStepsPerDegree)), int(std::lround(hi * kSliderStepsPerDegree)));
    angle_boxes_[i]->setRange(lo, hi);
    q(i) = std::clamp(q(i), lo * kDeg, hi * kDeg);
  }
  methods_->setMechanism(preset_);
  setPose(q);
  requestFields(true, true);
}

void MainWindow::syncRangeBoxes() {
  const auto& m = scene_->model();
  const parallel12r::Interval limits[] = {m.alpha_limits, m.beta_limits, m.gamma_limits};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 2; ++k) {
      const QSignalBlocker block(limit_boxes_[i][k]);
      limit_boxes_[i][k]->setValue((k == 0 ? limits[i].lo : limits[i].hi) / kDeg);
    }
}

void MainWindow::updateReadouts() {
  const auto& m = scene_->model();
  const QString unit = QString::fromStdString(m.length_unit);
  const Eigen::Vector3d p = parallel12r::forward(m, q_);
  const auto c = parallel12r::conditioning(m, q_);
  const auto s = parallel12r::nearest_singularity(m, q_);
  endpoint_label_->setText(QString("(%1, %2, %3) %4").arg(number(p.x()), number(p.y()), number(p.z()), unit));
  cond_label_->setText(std::isfinite(c.cond) ? number(c.cond) : tr("∞ (singular)"));
  det_label_->setText(number(c.det));
  singular_label_->setText(
      QString("%1, %2 %3").arg(QString::fromUtf8(to_string(s.nearest).data())).arg(number(s.distance, 3)).arg(unit));
  branch_label_->setText(QString::number(parallel12r::branch_of(q_)));
  if (branch_box_) branch_box_->setCurrentIndex(parallel12r::branch_of(q_));
  for (int k = 0; k < 3; ++k)
    if (target_boxes_[k] && !target_boxes_[k]->hasFocus()) {
      const QSignalBlocker block(target_boxes_[k]);
      target_boxes_[k]->setValue(p(k));
    }
}

// ---- Fields -------------------------------------------------------------------

FieldSettings MainWindow::fieldSettingsFromPanel() const {
  FieldSettings f;
  f.field = field_box_->currentText().toStdString();
  f.method = method_box_->currentText().toStdString();
  f.normal = normal_box_->currentText().toStdString();
  f.position = double(position_slider_->value()) / kPositionSteps * model().reach();
  f.follow_endpoint = follow_box_->isChecked();
  f.threshold = threshold_box_->value();
  if (!auto_range_box_->isChecked()) {
    f.range_min = range_min_box_->value();
    f.range_max = range_max_box_->value();
  }
  f.slice_resolution = slice_resolution_box_->currentText().toInt();
  f.volume_resolution = volume_resolution_box_->currentText().toInt();
  f.show_slice = show_slice_box_->isChecked();
  f.show_reach = show_reach_box_->isChecked();
  f.show_well_conditioned = show_well_box_->isChecked();
  f.reach_opacity = reach_opacity_slider_->value() / 100.0;
  f.well_conditioned_opacity = well_opacity_slider_->value() / 100.0;
  return f;
}

// Fields are computed only when shown, coarse first, on worker threads; a
// new request cancels the one in flight.
void MainWindow::requestFields(bool slice, bool volume) {
  if (!field_box_) return;  // panels not built yet
  const FieldSettings f = fieldSettingsFromPanel();
  const auto& m = model();
  const double r = m.reach();
  FieldRequest request;
  request.method = parallel12r::parse_ik_method(f.method);
  request.branch = branch();
  FieldJob job;
  job.sampler = [m, request](const Grid& grid, const FieldProgress& progress) {
    FieldRequest r = request;
    r.grid = grid;
    return compute_field(m, r, progress);
  };
  job.cond_threshold = f.threshold;
  if (slice && f.show_slice) {
    const Axis normal = parse_axis(f.normal);
    double position = f.position;
    if (f.follow_endpoint) {
      position = parallel12r::forward(m, q_)(int(normal));
      const QSignalBlocker block(position_slider_);
      position_slider_->setValue(int(std::lround(position / r * kPositionSteps)));
    }
    position_label_->setText(QString("%1 %2").arg(number(position, 3), QString::fromStdString(m.length_unit)));
    FieldJob slice_job = job;
    slice_job.slice = Grid::slice(normal, position, -r, r, -r, r, f.slice_resolution, f.slice_resolution);
    slice_settled_ = false;
    slice_runner_.submit(slice_job);
  } else if (slice) {
    slice_runner_.cancel();
    slice_settled_ = true;
  }
  if (volume && (f.show_reach || f.show_well_conditioned)) {
    const int n = f.volume_resolution;
    FieldJob volume_job = job;
    volume_job.volume = Grid::box({-r, -r, -r}, {r, r, r}, {n, n, n});
    volume_job.coarse_divisor = 2;
    surfaces_settled_ = false;
    volume_runner_.submit(volume_job);
  } else if (volume) {
    volume_runner_.cancel();
    surfaces_settled_ = true;
  }
}

void MainWindow::onSlice(const SliceResult& result) {
  slice_field_ = result.field;
  restyleSlice();
  compute_label_->setText(tr("slice %1 ms, %2 M points/s").arg(result.seconds * 1e3, 0, 'f', 1).arg(result.points_per_second / 1e6, 0, 'f', 1));
  if (result.fine) slice_settled_ = true;
  emit sliceUpdated(result.fine);
  emit fieldsUpdated(result.fine);
}

void MainWindow::onSurfaces(const SurfaceResult& result) {
  volume_field_ = result.volume;
  reach_mesh_ = result.reach;
  well_mesh_ = result.well_conditioned;
  field_scene_->set_surface(render::Surface::Reach, reach_mesh_);
  field_scene_->set_surface(render::Surface::WellConditioned, well_mesh_);
  applyFieldVisibility();
  statusBar()->showMessage(tr("isosurfaces (%1) in %2 ms").arg(result.fine ? tr("full") : tr("coarse")).arg(result.seconds * 1e3, 0, 'f', 0), 4000);
  if (result.fine) surfaces_settled_ = true;
  emit surfacesUpdated(result.fine);
  emit fieldsUpdated(result.fine);
}

void MainWindow::restyleSlice() {
  if (!slice_field_) return;
  const FieldSettings f = fieldSettingsFromPanel();
  render::SliceStyle style;
  style.field = f.field;
  style.contour_levels = {f.threshold};
  style.min = f.range_min;
  style.max = f.range_max;
  style.scale = std::max(1, 768 / f.slice_resolution);
  style.unreachable_alpha = 50;
  try {
    field_scene_->set_slice(*slice_field_, style);
  } catch (const std::invalid_argument& e) {
    statusBar()->showMessage(QString::fromStdString(e.what()), 8000);
  }
  applyFieldVisibility();
}

void MainWindow::applyFieldVisibility() {
  const FieldSettings f = fieldSettingsFromPanel();
  field_scene_->set_slice_visible(f.show_slice && slice_field_ != nullptr);
  // The method field is categorical: its colours are named in the field box's tooltip, not on a scale.
  field_scene_->set_colour_bar_visible(f.show_slice && slice_field_ != nullptr && f.field != "method");
  field_scene_->set_surface_visible(render::Surface::Reach, f.show_reach);
  field_scene_->set_surface_visible(render::Surface::WellConditioned, f.show_well_conditioned);
  field_scene_->set_surface_opacity(render::Surface::Reach, f.reach_opacity);
  field_scene_->set_surface_opacity(render::Surface::WellConditioned, f.well_conditioned_opacity);
  view_->update();
}

// ---- Animation ------------------------------------------------------------------

void MainWindow::animationStep() {
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
  const double angle = 2 * std::numbers::pi * animation_phase_;
  const int path = path_box_->currentIndex();
  if (path >= 2) {  // sweep one actuator around where the animation started
    Eigen::Vector3d q = animation_pose_;
    q(path - 2) += amplitude_box_->value() * kDeg * std::sin(angle);
    setPose(q);
    return;
  }
  const auto [u, v] = Grid::slice_axes(parse_axis(normal_box_->currentText().toStdString()));
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  const double a = amplitude_box_->value();
  if (path == 0) {
    offset(int(u)) = a * std::cos(angle) - a;  // starts at D
    offset(int(v)) = a * std::sin(angle);
  } else {
    offset(int(u)) = a * std::sin(angle);
  }
  moveEndpointTo(animation_centre_ + offset);  // an unreachable point is skipped, the panel says why
}

// ---- Sessions, files, exports ---------------------------------------------------------

Session MainWindow::session() const {
  Session s;
  s.mechanism = preset_reference(preset_);
  s.parameters = {{"L1", model().L1}, {"L2", model().L2}};
  const auto& m = model();
  s.actuator_limits_deg = {{"alpha", {m.alpha_limits.lo / kDeg, m.alpha_limits.hi / kDeg}},
                           {"beta", {m.beta_limits.lo / kDeg, m.beta_limits.hi / kDeg}},
                           {"gamma", {m.gamma_limits.lo / kDeg, m.gamma_limits.hi / kDeg}}};
  s.pose = q_;
  s.camera = camera_state(renderer_);
  s.field = fieldSettingsFromPanel();
  return s;
}

void MainWindow::applySession(const Session& s) {
  // Refuse before changing anything: the length boxes span 0.1 to 3 times
  // the preset's lengths, and a value outside would be clamped.
  for (int i = 0; i < 2; ++i) {
    const char* name = i == 0 ? "L1" : "L2";
    const auto it = s.parameters.find(name);
    if (it != s.parameters.end() &&
        (it->second < length_boxes_[i]->minimum() || it->second > length_boxes_[i]->maximum()))
      throw std::invalid_argument("session: " + std::string(name) + " = " + format_number(it->second) +
                                  " is outside the window's range [" + format_number(length_boxes_[i]->minimum()) +
                                  ", " + format_number(length_boxes_[i]->maximum()) + "] for this preset");
  }
  const FieldSettings& f = s.field;
  {
    const QSignalBlocker b1(field_box_), b2(normal_box_), b3(position_slider_), b4(follow_box_), b5(threshold_box_),
        b6(auto_range_box_), b7(slice_resolution_box_), b8(volume_resolution_box_), b9(show_slice_box_),
        b10(show_reach_box_), b11(show_well_box_), b12(reach_opacity_slider_), b13(well_opacity_slider_),
        b14(method_box_), b15(length_boxes_[0]), b16(length_boxes_[1]);
    field_box_->setCurrentText(QString::fromStdString(f.field));
    method_box_->setCurrentText(QString::fromStdString(f.method));
    normal_box_->setCurrentText(QString::fromStdString(f.normal));
    follow_box_->setChecked(f.follow_endpoint);
    threshold_box_->setValue(f.threshold);
    auto_range_box_->setChecked(!(f.range_min && f.range_max));
    if (f.range_min) range_min_box_->setValue(*f.range_min);
    if (f.range_max) range_max_box_->setValue(*f.range_max);
    slice_resolution_box_->setCurrentText(QString::number(f.slice_resolution));
    volume_resolution_box_->setCurrentText(QString::number(f.volume_resolution));
    show_slice_box_->setChecked(f.show_slice);
    show_reach_box_->setChecked(f.show_reach);
    show_well_box_->setChecked(f.show_well_conditioned);
    reach_opacity_slider_->setValue(int(std::lround(f.reach_opacity * 100)));
    well_opacity_slider_->setValue(int(std::lround(f.well_conditioned_opacity * 100)));
    const double L1 = s.parameters.count("L1") ? s.parameters.at("L1") : model().L1;
    const double L2 = s.parameters.count("L2") ? s.parameters.at("L2") : model().L2;
    length_boxes_[0]->setValue(L1);
    length_boxes_[1]->setValue(L2);
    const double r = L1 + L2;
    position_slider_->setValue(int(std::lround(f.position / r * kPositionSteps)));
  }
  setLinkLengths(length_boxes_[0]->value(), length_boxes_[1]->value());
  if (!s.actuator_limits_deg.empty()) {
    std::array<parallel12r::Interval, 3> ranges;
    const auto& m = model();
    const parallel12r::Interval current[] = {m.alpha_limits, m.beta_limits, m.gamma_limits};
    const char* names[] = {"alpha", "beta", "gamma"};
    for (int i = 0; i < 3; ++i) {
      const auto it = s.actuator_limits_deg.find(names[i]);
      ranges[i] = it != s.actuator_limits_deg.end() ? parallel12r::Interval{it->second[0], it->second[1]}
                                                     : parallel12r::Interval{current[i].lo / kDeg, current[i].hi / kDeg};
    }
    setActuatorRanges(ranges);
  }
  if (s.camera) apply_camera(renderer_, *s.camera);
  setPose(s.pose);
  restyleSlice();
  requestFields(true, true);
}

bool MainWindow::openSession(const QString& path) {
  if (!open_session_file(this, preset_, path)) return false;
  addRecent(path);
  return true;
}

bool MainWindow::saveSession(const QString& path) {
  if (!save_session_file(this, session(), path)) return false;
  addRecent(path);
  return true;
}

void MainWindow::addRecent(const QString& path) {
  QSettings settings;
  QStringList recent = settings.value("recentSessions").toStringList();
  const QString absolute = QFileInfo(path).absoluteFilePath();
  recent.removeAll(absolute);
  recent.prepend(absolute);
  while (recent.size() > 8) recent.removeLast();
  settings.setValue("recentSessions", recent);
  rebuildRecentMenu();
}

void MainWindow::rebuildRecentMenu() {
  if (!recent_menu_) return;
  recent_menu_->clear();
  const QStringList recent = QSettings().value("recentSessions").toStringList();
  for (const QString& path : recent) recent_menu_->addAction(path, this, [this, path] { openSession(path); });
  recent_menu_->setEnabled(!recent.isEmpty());
}

void MainWindow::exportSliceImage() {
  const FieldSettings f = fieldSettingsFromPanel();
  render::SliceStyle style;
  style.field = f.field;
  style.contour_levels = {f.threshold};
  style.min = f.range_min;
  style.max = f.range_max;
  export_slice_image(this, slice_field_.get(), style);
}

void MainWindow::closeEvent(QCloseEvent* event) {
  QSettings settings;
  settings.setValue("window/geometry", saveGeometry());
  settings.setValue("window/state", saveState());
  QMainWindow::closeEvent(event);
}

// ---- Entry ------------------------------------------------------------------------

int run_window(const WindowOptions& options, int argc, char** argv) {
  std::optional<Session> session;
  if (!options.session.empty()) session = load_session(options.session);  // bad file: exit code 2
  // A session brings its own mechanism.
  Preset preset = load_preset(session ? session->mechanism : options.mechanism.mechanism);
  apply_overrides(preset, options.mechanism.params);
  // Off-screen framebuffers beyond 8192 pixels a side fail inside the
  // OpenGL driver (a crash, not an error), so the size is bounded here.
  int width = 0, height = 0;
  char x = 0, rest = 0;
  if (std::sscanf(options.size.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || x != 'x' || width < 200 ||
      height < 150 || width > kMaxWindowSide || height > kMaxWindowSide)
    throw std::invalid_argument("--size expects WIDTHxHEIGHT from 200x150 to " + std::to_string(kMaxWindowSide) + "x" +
                                std::to_string(kMaxWindowSide) + ", got '" + options.size + "'");
  const bool is_pathos2 = preset.mechanism == pathos2::kMechanismName;
  if (is_pathos2 && options.latency)
    throw std::invalid_argument("--latency measures the parallel-12r window");

  QSurfaceFormat::setDefaultFormat(VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setApplicationName("Linkscape");
  QApplication::setOrganizationName("Linkscape");
  if (is_pathos2) return run_pathos2_window(preset, session, options.screenshot, width, height);
  MainWindow window(preset);
  if (session) window.applySession(*session);
  window.resize(width, height);
  window.show();
  if (options.latency) return run_latency_probe(window, std::cout);
  if (options.screenshot.empty()) return QApplication::exec();
  return save_screenshot_when_settled(window, options.screenshot);
}

}  // namespace linkscape::gui
