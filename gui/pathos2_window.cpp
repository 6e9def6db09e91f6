#include "gui/pathos2_window.h"

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QImage>
#include <QLabel>
#include <QMenuBar>
#include <QProgressBar>
#include <QSettings>
#include <QSignalBlocker>
#include <QSlider>
#include <QStatusBar>
#include <QVBoxLayout>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <numbers>
#include <stdexcept>

#include "core/pathos2_field.h"
#include "gui/methods_panel.h"
#include "gui/window_parts.h"
#include "gui/vtk_widget.h"
#include "render/field_scene.h"
#include "render/pathos2_scene.h"
#include "render/slice_image.h"

namespace linkscape::gui {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr int kStepsPerUnit = 100;  // slider steps per cm or per degree
constexpr int kPositionSteps = 400;
const char* const kDriveKey = "pathos2/drive";

QString number(double v, int precision = 4) { return QString::number(v, 'g', precision); }
// Fixed-point text; values that round to zero print as 0, never -0.
QString fixed(double v, int decimals = 2) {
  if (std::abs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0.0;
  return QString::number(v, 'f', decimals);
}

QString cond_text(double c) { return std::isfinite(c) ? number(c) : QString::fromUtf8("∞ (singular)"); }

QString pose_text(const pathos2::Pose& p) {
  const Eigen::Vector3d r = p.rpy() / kDeg;
  return QString::fromUtf8("x, y, z = (%1, %2, %3) cm\nRx, Ry, Rz = (%4, %5, %6)°")
      .arg(fixed(p.p_world_E.x(), 3), fixed(p.p_world_E.y(), 3), fixed(p.p_world_E.z(), 3))
      .arg(fixed(r.x()), fixed(r.y()), fixed(r.z()));
}

// What a failing leg's status means to the user.
QString leg_problem(Status s) {
  switch (s) {
    case Status::Unreachable: return QObject::tr("unreachable");
    case Status::Singular: return QObject::tr("singular");
    case Status::OutOfLimits: return QObject::tr("out of limits");
    case Status::NotConverged: return QObject::tr("not converged");
    case Status::Ok: break;
  }
  return QObject::tr("ok");
}


// A slider and a spin box showing the same value (the spin box carries the
// unit); `changed` runs when either is moved by the user.
struct SliderRow {
  QSlider* slider;
  QDoubleSpinBox* box;
};
SliderRow slider_row(QWidget* parent, QFormLayout* form, const QString& label, const QString& name, double lo,
                     double hi, double value, int decimals, const QString& suffix, std::function<void()> changed) {
  auto* slider = new QSlider(Qt::Horizontal, parent);
  slider->setObjectName(name + "Slider");
  slider->setRange(int(std::lround(lo * kStepsPerUnit)), int(std::lround(hi * kStepsPerUnit)));
  slider->setValue(int(std::lround(value * kStepsPerUnit)));
  auto* box = new QDoubleSpinBox(parent);
  box->setObjectName(name + "Box");
  box->setRange(lo, hi);
  box->setDecimals(decimals);
  box->setSingleStep(decimals >= 2 ? 0.1 : 1.0);
  box->setValue(value);
  box->setSuffix(suffix);
  box->setKeyboardTracking(false);
  box->setMinimumWidth(92);
  auto* row = new QHBoxLayout;
  row->addWidget(slider, 1);
  row->addWidget(box);
  form->addRow(label, row);
  QObject::connect(slider, &QSlider::valueChanged, box, [box](int v) { box->setValue(double(v) / kStepsPerUnit); });
  QObject::connect(box, &QDoubleSpinBox::valueChanged, slider, [slider, changed](double v) {
    {
      const QSignalBlocker block(slider);
      slider->setValue(int(std::lround(v * kStepsPerUnit)));
    }
    changed();
  });
  return {slider, box};
}

void set_quietly(QSlider* slider, QDoubleSpinBox* box, double value) {
  const QSignalBlocker b1(slider), b2(box);
  box->setValue(value);
  slider->setValue(int(std::lround(box->value() * kStepsPerUnit)));
}

void set_range_quietly(QSlider* slider, QDoubleSpinBox* box, double lo, double hi) {
  const QSignalBlocker b1(slider), b2(box);
  box->setRange(lo, hi);
  slider->setRange(int(std::lround(lo * kStepsPerUnit)), int(std::lround(hi * kStepsPerUnit)));
}

}  // namespace

Pathos2Window::Pathos2Window(const Preset& preset, QWidget* parent)
    : QMainWindow(parent),
      preset_(preset),
      scene_(std::make_unique<render::Pathos2Scene>()),
      field_scene_(std::make_unique<render::FieldScene>()) {
  setWindowTitle(QString("Linkscape — %1").arg(QString::fromStdString(preset.title)));
  const pathos2::Model m = make_pathos2(preset_);
  geometry_ = pathos2::make_geometry(m);
  const pathos2::Pose home = pathos2::home_pose(m);
  ik_ = pathos2::inverse(geometry_, home);
  if (ik_.status != Status::Ok)
    throw std::invalid_argument("pathos2: the design cannot reach its home pose (leg " +
                                std::to_string(ik_.failing_leg + 1) + " " + std::string(to_string(ik_.status)) + ")");

  view_ = new VtkWidget(this);
  setCentralWidget(view_);
  vtkNew<vtkRenderer> renderer;
  renderer->GradientBackgroundOn();
  renderer->SetBackground(0.97, 0.97, 0.98);
  renderer->SetBackground2(0.80, 0.84, 0.90);
  renderer->SetUseDepthPeeling(false);  // plain alpha blending: interactive under software GL
  view_->renderWindow()->AddRenderer(renderer);
  renderer_ = renderer;
  scene_->set_model(m, home);
  scene_->add_to(renderer_);
  field_scene_->add_to(renderer_);
  renderer_->SetUseDepthPeeling(false);
  scene_->reset_camera(renderer_);

  QDockWidget* design = add_dock(this, tr("Design"), "designDock", buildDesignPanel());
  QDockWidget* drive = add_dock(this, tr("Drive"), "driveDock", buildDrivePanel());
  QDockWidget* field = add_dock(this, tr("Field"), "fieldDock", buildFieldPanel());
  // One column of tabs: the drive in front, fields and design behind it.
  tabifyDockWidget(drive, field);
  tabifyDockWidget(drive, design);
  methods_ = add_methods_dock(this, preset_, drive);
  drive->raise();

  QMenu* file = menuBar()->addMenu(tr("&File"));
  file->addAction(tr("&Open session…"), QKeySequence::Open, this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, tr("Open session"), {}, tr("Sessions (*.json)"));
    if (!path.isEmpty()) openSession(path);
  });
  file->addAction(tr("&Save session…"), QKeySequence::Save, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, tr("Save session"), "pathos2-session.json",
                                                      tr("Sessions (*.json)"));
    if (!path.isEmpty()) saveSession(path);
  });
  file->addSeparator();
  file->addAction(tr("Export slice &image…"), this, [this] { export_slice_image(this, slice_field_.get(), sliceStyle()); });
  file->addAction(tr("Export workspace &mesh…"), this, [this] {
    export_surface_mesh(this, surfaces_.volume.get(), surfaces_.reach, surfaces_.well_conditioned,
                        threshold_box_->value());
  });
  file->addAction(tr("Export &field (VTI)…"), this, [this] { export_volume(this, surfaces_.volume.get()); });
  file->addAction(tr("Save screens&hot…"), this, [this] { export_screenshot(this); });
  file->addSeparator();
  file->addAction(tr("&Quit"), QKeySequence::Quit, this, &QWidget::close);
  QMenu* view = menuBar()->addMenu(tr("&View"));
  view->addAction(tr("&Reset camera"), this, [this] {
    scene_->reset_camera(renderer_);
    view_->update();
  });

  compute_label_ = add_field_status(this, view_, {&slice_runner_, &volume_runner_}, [this] {
                     slice_settled_ = surfaces_settled_ = true;  // nothing more is coming
                   }).compute;
  connect(&slice_runner_, &FieldJobRunner::sliceReady, this, &Pathos2Window::onSlice);
  connect(&volume_runner_, &FieldJobRunner::surfacesReady, this, &Pathos2Window::onSurfaces);

  // The drive mode is remembered; the layout is not, so screenshots are reproducible.
  setDrive(QSettings().value(kDriveKey).toString() == "actuators" ? Drive::Actuators : Drive::Pose);
  accept(home, ik_);
  requestFields(true, true);
}

Pathos2Window::~Pathos2Window() {
  slice_runner_.cancel();
  volume_runner_.cancel();
}

const pathos2::Model& Pathos2Window::model() const { return geometry_.model; }
const pathos2::Pose& Pathos2Window::pose() const { return scene_->pose(); }

// ---- Panels -----------------------------------------------------------------

QWidget* Pathos2Window::buildDesignPanel() {
  auto* w = new QWidget;
  auto* form = new QFormLayout(w);
  form->addRow(tr("Preset"), make_preset_chooser(this, preset_));
  const pathos2::Model& m = model();
  struct Spec {
    const char* label;
    const char* name;
    double lo, hi, value;
    const char* suffix;
    const char* tip;
  };
  const Spec specs[kDesignCount] = {
      {"l0", "l0", 30.0, 60.0, m.l0, " cm", "Distance between the base plates"},
      {"l2", "l2", 6.0, 24.0, m.l2, " cm", "Link R2 -> R3"},
      {"l3", "l3", 2.0, 12.0, m.l3, " cm", "Link R3 -> globular joint"},
      {"lp", "lp", 0.5, 6.0, m.lp, " cm", "Radius of the globular joints on the top plates"},
      {"θt", "theta_t", 0.0, 60.0, m.theta_t / kDeg, " °",
       "Tilt of the R1 axis from the plate normal (also sets db = lb tan θt and lx = lb / cos θt)"},
      {"db", "db", 0.0, 15.0, m.db, " cm", "Offset of the R1 joint along the plate normal"},
  };
  for (int i = 0; i < kDesignCount; ++i) {
    const Spec& s = specs[i];
    const SliderRow row = slider_row(w, form, QString::fromUtf8(s.label), s.name, s.lo, s.hi, s.value, 2,
                                     QString::fromUtf8(s.suffix), [this, i] {
                                       if (i == 4) {  // keep R1 on the plate: db = lb tan(theta_t)
                                         const double t = design_boxes_[4]->value() * kDeg;
                                         set_quietly(design_sliders_[5], design_boxes_[5], model().lb * std::tan(t));
                                       }
                                       setModel(modelFromDesignPanel());
                                     });
    row.slider->setToolTip(tr(s.tip));
    row.box->setToolTip(tr(s.tip));
    design_sliders_[i] = row.slider;
    design_boxes_[i] = row.box;
  }
  form->addRow(new QLabel(tr("lb %1 cm, l1 %2 cm (fixed by the preset)").arg(number(m.lb), number(m.l1)), w));
  return w;
}

QWidget* Pathos2Window::buildDrivePanel() {
  auto* w = new QWidget;
  auto* column = new QVBoxLayout(w);
  auto* top = new QFormLayout;
  drive_box_ = new QComboBox(w);
  drive_box_->setObjectName("driveBox");
  drive_box_->addItems({tr("pose (IK)"), tr("actuators (FK)")});
  drive_box_->setToolTip(tr("Pose: the sliders place the top plates and IK drives the legs.\n"
                            "Actuators: the sliders turn the six motors and numerical FK moves the plates."));
  top->addRow(tr("Drive"), drive_box_);
  column->addLayout(top);
  connect(drive_box_, &QComboBox::activated, this, [this](int i) { setDrive(i == 0 ? Drive::Pose : Drive::Actuators); });

  const pathos2::Model& m = model();
  const pathos2::Pose home = pathos2::home_pose(m);
  const Eigen::Vector3d rpy = home.rpy() / kDeg;
  pose_group_ = new QGroupBox(tr("Top-plate pose"), w);
  auto* pose_form = new QFormLayout(pose_group_);
  struct Spec {
    const char* label;
    const char* name;
    double lo, hi, value;
    const char* suffix;
  };
  const Spec pose_specs[7] = {
      {"x", "x", -12.0, 12.0, home.p_world_E.x(), " cm"}, {"y", "y", -12.0, 12.0, home.p_world_E.y(), " cm"},
      {"z", "z", 0.0, m.l0, home.p_world_E.z(), " cm"},   {"Rx", "rx", -90.0, 90.0, rpy.x(), " °"},
      {"Ry", "ry", -89.0, 89.0, rpy.y(), " °"},           {"Rz", "rz", -180.0, 180.0, rpy.z(), " °"},
      {"h0 (grip)", "h0", 1.0, 15.0, home.h0, " cm"},
  };
  for (int i = 0; i < 7; ++i) {
    const Spec& s = pose_specs[i];
    const SliderRow row = slider_row(pose_group_, pose_form, QString::fromUtf8(s.label), s.name, s.lo, s.hi, s.value,
                                     2, QString::fromUtf8(s.suffix), [this] { setPose(poseFromPanel()); });
    pose_sliders_[i] = row.slider;
    pose_boxes_[i] = row.box;
  }
  column->addWidget(pose_group_);

  actuator_group_ = new QGroupBox(tr("Actuators (R1 of each leg)"), w);
  auto* act_form = new QFormLayout(actuator_group_);
  for (int i = 0; i < 7; ++i) {
    const bool grip = i == 6;
    const QString name = grip ? "fkH0" : QString("q%1").arg(i + 1);
    const SliderRow row = slider_row(
        actuator_group_, act_form, grip ? tr("h0 (grip)") : QString("q%1").arg(i + 1), name, grip ? 1.0 : -180.0,
        grip ? 15.0 : 180.0, grip ? home.h0 : 0.0, 2, QString::fromUtf8(grip ? " cm" : " °"), [this] {
          pathos2::Vector6d q;
          for (int k = 0; k < 6; ++k) q(k) = actuator_boxes_[k]->value() * kDeg;
          setActuators(q, actuator_boxes_[6]->value());
        });
    actuator_sliders_[i] = row.slider;
    actuator_boxes_[i] = row.box;
  }
  column->addWidget(actuator_group_);

  auto* readouts = new QGroupBox(tr("State"), w);
  auto* grid = new QGridLayout(readouts);
  for (int i = 0; i < 6; ++i) {
    q_labels_[i] = new QLabel(readouts);
    q_labels_[i]->setObjectName(QString("q%1Label").arg(i + 1));
    q_labels_[i]->setTextInteractionFlags(Qt::TextSelectableByMouse);
    grid->addWidget(q_labels_[i], i % 3, i / 3);
  }
  auto* form = new QFormLayout;
  cond_p_label_ = new QLabel(readouts);
  cond_p_label_->setObjectName("condPLabel");
  cond_o_label_ = new QLabel(readouts);
  cond_o_label_->setObjectName("condOLabel");
  status_label_ = new QLabel(readouts);
  status_label_->setObjectName("poseStatus");
  status_label_->setWordWrap(true);
  form->addRow(tr("cond(Jp)"), cond_p_label_);
  form->addRow(tr("cond(Jo)"), cond_o_label_);
  form->addRow(tr("Status"), status_label_);
  grid->addLayout(form, 3, 0, 1, 2);
  column->addWidget(readouts);

  fk_group_ = new QGroupBox(tr("Forward kinematics"), w);
  auto* fk_form = new QFormLayout(fk_group_);
  fk_numeric_label_ = new QLabel(fk_group_);
  fk_numeric_label_->setObjectName("fkNumericLabel");
  fk_nine_label_ = new QLabel(fk_group_);
  fk_nine_label_->setObjectName("fkNineLabel");
  fk_difference_label_ = new QLabel(fk_group_);
  fk_difference_label_->setObjectName("fkDifferenceLabel");
  for (QLabel* l : {fk_numeric_label_, fk_nine_label_, fk_difference_label_}) {
    l->setWordWrap(true);
    l->setTextInteractionFlags(Qt::TextSelectableByMouse);
  }
  fk_numeric_label_->setToolTip(tr("Damped Newton on the six active angles, seeded from the last pose"));
  fk_nine_label_->setToolTip(tr("Closed form from (t1, t2, t3) of legs 1, 5 and 6 (Eqs. 19-20)"));
  fk_form->addRow(tr("Numerical"), fk_numeric_label_);
  fk_form->addRow(tr("Nine sensors"), fk_nine_label_);
  fk_form->addRow(tr("Difference"), fk_difference_label_);
  column->addWidget(fk_group_);
  column->addStretch(1);
  return w;
}

QWidget* Pathos2Window::buildFieldPanel() {
  auto* w = new QWidget;
  auto* form = new QFormLayout(w);
  field_box_ = new QComboBox(w);
  field_box_->setObjectName("fieldBox");
  field_box_->addItem(tr("cond(Jp)"), "cond");
  field_box_->addItem(tr("cond(Jo)"), "cond_jo");
  field_box_->addItem(tr("reach margin (cm)"), "reach");
  field_box_->addItem(tr("IK status"), "status");
  form->addRow(tr("Slice field"), field_box_);
  normal_box_ = new QComboBox(w);
  normal_box_->setObjectName("normalBox");
  normal_box_->addItems({"x", "y", "z"});
  normal_box_->setCurrentText("y");
  form->addRow(tr("Slice normal"), normal_box_);
  position_slider_ = new QSlider(Qt::Horizontal, w);
  position_slider_->setObjectName("positionSlider");
  position_slider_->setRange(-kPositionSteps, kPositionSteps);
  position_slider_->setValue(0);
  position_label_ = new QLabel(w);
  position_label_->setMinimumWidth(70);
  auto* row = new QHBoxLayout;
  row->addWidget(position_slider_, 1);
  row->addWidget(position_label_);
  form->addRow(tr("Position"), row);
  follow_box_ = new QCheckBox(tr("Through the platform centre"), w);
  follow_box_->setObjectName("followBox");
  follow_box_->setChecked(true);
  form->addRow(follow_box_);
  threshold_box_ = new QDoubleSpinBox(w);
  threshold_box_->setObjectName("thresholdBox");
  threshold_box_->setRange(1.05, 100.0);
  threshold_box_->setDecimals(2);
  threshold_box_->setValue(5.0);
  threshold_box_->setKeyboardTracking(false);
  threshold_box_->setToolTip(tr("cond(Jp) contour on the slice and the well-conditioned surface (paper: < 5)"));
  form->addRow(tr("cond(Jp) threshold"), threshold_box_);
  slice_resolution_box_ = new QComboBox(w);
  slice_resolution_box_->setObjectName("sliceResolutionBox");
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
  show_slice_box_->setObjectName("showSliceBox");
  show_reach_box_ = new QCheckBox(tr("Reachable workspace"), w);
  show_reach_box_->setObjectName("showReachBox");
  show_well_box_ = new QCheckBox(tr("Well-conditioned workspace"), w);
  show_well_box_->setObjectName("showWellBox");
  reach_opacity_slider_ = new QSlider(Qt::Horizontal, w);
  reach_opacity_slider_->setObjectName("reachOpacitySlider");
  well_opacity_slider_ = new QSlider(Qt::Horizontal, w);
  for (QSlider* s : {reach_opacity_slider_, well_opacity_slider_}) s->setRange(0, 100);
  reach_opacity_slider_->setValue(15);
  well_opacity_slider_->setValue(25);
  show_slice_box_->setChecked(true);
  show_reach_box_->setChecked(true);
  show_well_box_->setChecked(false);
  form->addRow(show_slice_box_);
  form->addRow(show_reach_box_, reach_opacity_slider_);
  form->addRow(show_well_box_, well_opacity_slider_);
  form->addRow(new QLabel(tr("Fields are sampled at the platform's current orientation and grip."), w));

  auto slice_changed = [this] { requestFields(true, false); };
  connect(normal_box_, &QComboBox::currentIndexChanged, this, slice_changed);
  connect(position_slider_, &QSlider::valueChanged, this, [this] {
    if (!follow_box_->isChecked()) requestFields(true, false);
  });
  connect(slice_resolution_box_, &QComboBox::currentIndexChanged, this, slice_changed);
  connect(follow_box_, &QCheckBox::toggled, this, slice_changed);
  connect(volume_resolution_box_, &QComboBox::currentIndexChanged, this, [this] { requestFields(false, true); });
  connect(threshold_box_, &QDoubleSpinBox::valueChanged, this, [this] {
    restyleSlice();
    requestFields(false, true);
  });
  connect(field_box_, &QComboBox::currentIndexChanged, this, [this] { restyleSlice(); });
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

// ---- Drive ----------------------------------------------------------------------

pathos2::Pose Pathos2Window::poseFromPanel() const {
  auto v = [this](int i) { return pose_boxes_[i]->value(); };
  return pathos2::Pose::from_xyz_rpy(v(0), v(1), v(2), v(3) * kDeg, v(4) * kDeg, v(5) * kDeg, v(6));
}

pathos2::Model Pathos2Window::modelFromDesignPanel() const {
  pathos2::Model m = model();
  m.l0 = design_boxes_[0]->value();
  m.l2 = design_boxes_[1]->value();
  m.l3 = design_boxes_[2]->value();
  m.lp = design_boxes_[3]->value();
  m.theta_t = design_boxes_[4]->value() * kDeg;
  m.db = design_boxes_[5]->value();
  m.lx = m.lb / std::cos(m.theta_t);
  return m;
}

bool Pathos2Window::setPose(const pathos2::Pose& pose) {
  pathos2::PoseIkResult ik;
  try {
    ik = pathos2::inverse(geometry_, pose);
  } catch (const std::invalid_argument& e) {
    refuse(QString::fromStdString(e.what()), -1);
    return false;
  }
  if (ik.status != Status::Ok) {
    refuse(tr("leg %1: %2 (the device stays at the last valid pose)")
               .arg(ik.failing_leg + 1)
               .arg(leg_problem(ik.legs[ik.failing_leg].status)),
           ik.failing_leg);
    return false;
  }
  accept(pose, ik);
  return true;
}

bool Pathos2Window::setActuators(const pathos2::Vector6d& q_active, double h0) {
  pathos2::FkResult fk;
  try {
    fk = pathos2::forward_numeric(geometry_, q_active, h0, pose());
  } catch (const std::invalid_argument& e) {
    refuse(QString::fromStdString(e.what()), -1);
    return false;
  }
  if (fk.status != Status::Ok) {
    refuse(tr("FK %1 after %2 iterations (residual %3 rad): the device stays at the last valid pose")
               .arg(leg_problem(fk.status))
               .arg(fk.iterations)
               .arg(number(fk.residual, 2)),
           -1);
    return false;
  }
  const pathos2::PoseIkResult ik = pathos2::inverse(geometry_, fk.pose);
  if (ik.status != Status::Ok) {
    refuse(tr("leg %1: %2 at the FK pose").arg(ik.failing_leg + 1).arg(leg_problem(ik.status)), ik.failing_leg);
    return false;
  }
  fk_numeric_ = fk;
  fk_nine_ = pathos2::forward_nine_sensors(geometry_, pathos2::sensors_of(ik));
  accept(fk.pose, ik);
  return true;
}

void Pathos2Window::refuse(const QString& why, int failing_leg) {
  refusal_ = why;
  status_label_->setText(why);
  status_label_->setStyleSheet("color: #b00020");
  scene_->set_highlighted_leg(failing_leg);
  view_->update();
}

void Pathos2Window::accept(const pathos2::Pose& pose, const pathos2::PoseIkResult& ik) {
  const pathos2::Pose before = scene_->pose();
  try {
    scene_->set_pose(pose);
  } catch (const std::invalid_argument& e) {
    refuse(QString::fromStdString(e.what()), ik.failing_leg);
    return;
  }
  ik_ = ik;
  refusal_.clear();
  status_label_->setText(tr("ok: every leg solves"));
  status_label_->setStyleSheet("color: #1b5e20");
  scene_->set_highlighted_leg(-1);
  syncPanels();
  updateReadouts();
  // Fields depend on the orientation and the grip; the slice also on the
  // position while it follows the platform.
  const bool orientation_changed =
      !(before.R_world_E - pose.R_world_E).isZero(1e-12) || std::abs(before.h0 - pose.h0) > 1e-12;
  if (orientation_changed) requestFields(true, true);
  else if (follow_box_ && follow_box_->isChecked() && (before.p_world_E - pose.p_world_E).norm() > 1e-12)
    requestFields(true, false);
  view_->update();
  emit poseChanged();
}

void Pathos2Window::setDrive(Drive drive) {
  drive_ = drive;
  const bool fk = drive == Drive::Actuators;
  {
    const QSignalBlocker block(drive_box_);
    drive_box_->setCurrentIndex(fk ? 1 : 0);
  }
  pose_group_->setVisible(!fk);
  actuator_group_->setVisible(fk);
  fk_group_->setVisible(fk);
  syncPanels(true);
  QSettings().setValue(kDriveKey, fk ? "actuators" : "pose");
  // Both FK solutions at once for the pose shown (Newton converges at once).
  if (fk) setActuators(ik_.q_active, pose().h0);
}

void Pathos2Window::syncPanels(bool both) {
  const pathos2::Pose& p = pose();
  const Eigen::Vector3d rpy = p.rpy() / kDeg;
  const double pose_values[7] = {p.p_world_E.x(), p.p_world_E.y(), p.p_world_E.z(), rpy.x(), rpy.y(), rpy.z(), p.h0};
  // The panel that drives keeps what the user set; the other one follows.
  if (both || drive_ == Drive::Actuators)
    for (int i = 0; i < 7; ++i) set_quietly(pose_sliders_[i], pose_boxes_[i], pose_values[i]);
  if (both || drive_ == Drive::Pose) {
    for (int i = 0; i < 6; ++i)
      set_quietly(actuator_sliders_[i], actuator_boxes_[i], std::remainder(ik_.q_active(i), 2 * std::numbers::pi) / kDeg);
    set_quietly(actuator_sliders_[6], actuator_boxes_[6], p.h0);
  }
}

void Pathos2Window::updateReadouts() {
  for (int i = 0; i < 6; ++i)
    q_labels_[i]->setText(QString::fromUtf8("q%1 = %2°").arg(i + 1).arg(
        fixed(std::remainder(ik_.q_active(i), 2 * std::numbers::pi) / kDeg)));
  const pathos2::JacobianResult j = pathos2::jacobian(geometry_, pose(), ik_);
  cond_p_label_->setText(cond_text(j.cond_p));
  cond_o_label_->setText(cond_text(j.cond_o));
  if (fk_numeric_ && fk_nine_) {
    fk_numeric_label_->setText(tr("%1\n%2 iterations, max |Δq| %3 rad")
                                   .arg(pose_text(fk_numeric_->pose))
                                   .arg(fk_numeric_->iterations)
                                   .arg(number(fk_numeric_->residual, 2)));
    if (fk_nine_->status == Status::Ok) {
      fk_nine_label_->setText(pose_text(fk_nine_->pose));
      const double dp = (fk_nine_->pose.p_world_E - fk_numeric_->pose.p_world_E).norm();
      const double dr = Eigen::AngleAxisd(fk_nine_->pose.R_world_E.transpose() * fk_numeric_->pose.R_world_E).angle();
      fk_difference_label_->setText(QString::fromUtf8("|Δp| = %1 cm, |ΔR| = %2°").arg(number(dp, 2), number(dr / kDeg, 2)));
    } else {
      fk_nine_label_->setText(tr("no solution (%1)").arg(QString::fromUtf8(to_string(fk_nine_->status).data())));
      fk_difference_label_->setText("—");
    }
  } else {
    fk_numeric_label_->setText(tr("move an actuator"));
    fk_nine_label_->setText("—");
    fk_difference_label_->setText("—");
  }
}

bool Pathos2Window::setModel(const pathos2::Model& m) {
  auto revert = [this](const QString& why) {
    const pathos2::Model& cur = model();
    const double values[kDesignCount] = {cur.l0, cur.l2, cur.l3, cur.lp, cur.theta_t / kDeg, cur.db};
    for (int i = 0; i < kDesignCount; ++i) set_quietly(design_sliders_[i], design_boxes_[i], values[i]);
    statusBar()->showMessage(why, 8000);
    return false;
  };
  pathos2::Geometry g;
  try {
    g = pathos2::make_geometry(m);
  } catch (const std::invalid_argument& e) {
    return revert(QString::fromStdString(e.what()));
  }
  // Keep the pose relative to the mid-plane; else the new design's home.
  pathos2::Pose p = pose();
  p.p_world_E.z() += 0.5 * (m.l0 - model().l0);
  pathos2::PoseIkResult ik = pathos2::inverse(g, p);
  if (ik.status != Status::Ok) {
    p = pathos2::home_pose(m);
    p.h0 = pose().h0;
    ik = pathos2::inverse(g, p);
  }
  if (ik.status != Status::Ok)
    return revert(tr("This design cannot reach its home pose (leg %1: %2); design unchanged.")
                      .arg(ik.failing_leg + 1)
                      .arg(leg_problem(ik.status)));
  scene_->set_model(m, p);
  geometry_ = std::move(g);
  Preset current = preset_;
  current.parameters = m.to_parameters();
  methods_->setMechanism(current);  // the next Run measures the new design
  ik_ = ik;
  refusal_.clear();
  scene_->set_highlighted_leg(-1);
  status_label_->setText(tr("ok: every leg solves"));
  status_label_->setStyleSheet("color: #1b5e20");
  set_range_quietly(pose_sliders_[2], pose_boxes_[2], 0.0, m.l0);
  const double design[kDesignCount] = {m.l0, m.l2, m.l3, m.lp, m.theta_t / kDeg, m.db};
  for (int i = 0; i < kDesignCount; ++i) set_quietly(design_sliders_[i], design_boxes_[i], design[i]);
  syncPanels(true);  // the actuator angles change with the design
  updateReadouts();
  requestFields(true, true);
  view_->update();
  emit poseChanged();
  return true;
}

// ---- Fields -------------------------------------------------------------------

std::pair<Eigen::Vector3d, Eigen::Vector3d> Pathos2Window::fieldBox() const {
  // The workspace at Table 1 dimensions is about 14 cm across (docs); a box
  // of half the leg length on each side of the mid-plane centre holds it.
  const pathos2::Model& m = model();
  const double h = std::max(8.0, 0.45 * (m.l1 + m.l2 + m.l3));
  const Eigen::Vector3d centre(0, 0, 0.5 * m.l0);
  return {centre - Eigen::Vector3d::Constant(h), centre + Eigen::Vector3d::Constant(h)};
}

double Pathos2Window::slicePosition() const {
  const int n = normal_box_->currentIndex();
  const auto [lo, hi] = fieldBox();
  if (follow_box_->isChecked()) return pose().p_world_E(n);
  return 0.5 * (lo(n) + hi(n)) + 0.5 * (hi(n) - lo(n)) * position_slider_->value() / kPositionSteps;
}

void Pathos2Window::requestFields(bool slice, bool volume) {
  if (!field_box_) return;  // panels not built yet
  const pathos2::Model m = model();
  pathos2::FieldRequest request;
  request.rpy = pose().rpy();
  request.h0 = pose().h0;
  FieldJob job;
  job.sampler = [m, request](const Grid& grid, const FieldProgress& progress) {
    pathos2::FieldRequest r = request;
    r.grid = grid;
    return pathos2::compute_field(m, r, progress);
  };
  job.cond_threshold = threshold_box_->value();
  const auto [lo, hi] = fieldBox();
  if (slice && show_slice_box_->isChecked()) {
    const Axis normal = parse_axis(normal_box_->currentText().toStdString());
    const int n = int(normal);
    const double position = std::clamp(slicePosition(), lo(n), hi(n));
    if (follow_box_->isChecked()) {
      const QSignalBlocker block(position_slider_);
      position_slider_->setValue(int(std::lround((position - 0.5 * (lo(n) + hi(n))) / (0.5 * (hi(n) - lo(n))) * kPositionSteps)));
    }
    position_label_->setText(QString("%1 = %2 cm").arg(normal_box_->currentText(), fixed(position, 2)));
    const auto [u, v] = Grid::slice_axes(normal);
    const int res = slice_resolution_box_->currentText().toInt();
    FieldJob slice_job = job;
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

void Pathos2Window::onSlice(const SliceResult& result) {
  slice_field_ = result.field;
  restyleSlice();
  compute_label_->setText(tr("slice %1 ms, %2 M points/s")
                              .arg(result.seconds * 1e3, 0, 'f', 1)
                              .arg(result.points_per_second / 1e6, 0, 'f', 2));
  if (result.fine) slice_settled_ = true;
  emit sliceUpdated(result.fine);
  emit fieldsUpdated(result.fine);
}

void Pathos2Window::onSurfaces(const SurfaceResult& result) {
  surfaces_ = result;  // kept for export
  field_scene_->set_surface(render::Surface::Reach, result.reach);
  field_scene_->set_surface(render::Surface::WellConditioned, result.well_conditioned);
  applyFieldVisibility();
  statusBar()->showMessage(tr("workspace surfaces (%1) in %2 ms")
                               .arg(result.fine ? tr("full") : tr("coarse"))
                               .arg(result.seconds * 1e3, 0, 'f', 0),
                           4000);
  if (result.fine) surfaces_settled_ = true;
  emit surfacesUpdated(result.fine);
  emit fieldsUpdated(result.fine);
}

render::SliceStyle Pathos2Window::sliceStyle() const {
  render::SliceStyle style;
  style.field = field_box_->currentData().toString().toStdString();
  style.contour_levels = {threshold_box_->value()};
  return style;
}

void Pathos2Window::restyleSlice() {
  if (!slice_field_) return;
  render::SliceStyle style = sliceStyle();
  style.scale = std::max(1, 512 / slice_resolution_box_->currentText().toInt());
  style.unreachable_alpha = 40;
  try {
    field_scene_->set_slice(*slice_field_, style);
  } catch (const std::invalid_argument& e) {
    statusBar()->showMessage(QString::fromStdString(e.what()), 8000);
  }
  applyFieldVisibility();
}

void Pathos2Window::applyFieldVisibility() {
  const bool slice = show_slice_box_->isChecked() && slice_field_ != nullptr;
  field_scene_->set_slice_visible(slice);
  field_scene_->set_colour_bar_visible(slice);
  field_scene_->set_surface_visible(render::Surface::Reach, show_reach_box_->isChecked());
  field_scene_->set_surface_visible(render::Surface::WellConditioned, show_well_box_->isChecked());
  field_scene_->set_surface_opacity(render::Surface::Reach, reach_opacity_slider_->value() / 100.0);
  field_scene_->set_surface_opacity(render::Surface::WellConditioned, well_opacity_slider_->value() / 100.0);
  view_->update();
}

// ---- Sessions -----------------------------------------------------------------------

Session Pathos2Window::session() const {
  Session s;
  s.mechanism = preset_reference(preset_);
  s.parameters = model().to_parameters();
  const pathos2::Pose& p = pose();
  const Eigen::Vector3d rpy = p.rpy();
  s.platform_pose = std::array<double, 7>{p.p_world_E.x(), p.p_world_E.y(), p.p_world_E.z(), rpy.x(), rpy.y(), rpy.z(), p.h0};
  s.camera = camera_state(renderer_);
  FieldSettings& f = s.field;
  f.field = field_box_->currentData().toString().toStdString();
  f.normal = normal_box_->currentText().toStdString();
  f.position = slicePosition();
  f.follow_endpoint = follow_box_->isChecked();
  f.threshold = threshold_box_->value();
  f.slice_resolution = slice_resolution_box_->currentText().toInt();
  f.volume_resolution = volume_resolution_box_->currentText().toInt();
  f.show_slice = show_slice_box_->isChecked();
  f.show_reach = show_reach_box_->isChecked();
  f.show_well_conditioned = show_well_box_->isChecked();
  f.reach_opacity = reach_opacity_slider_->value() / 100.0;
  f.well_conditioned_opacity = well_opacity_slider_->value() / 100.0;
  return s;
}

void Pathos2Window::applySession(const Session& s) {
  if (!s.platform_pose) throw std::invalid_argument("the session has no platform_pose (a parallel-12r session?)");
  if (!setModel(pathos2::Model::from_parameters(s.parameters)))
    throw std::invalid_argument("the session's design cannot reach its home pose");
  const auto& v = *s.platform_pose;
  const FieldSettings& f = s.field;
  {
    const QSignalBlocker b1(field_box_), b2(normal_box_), b3(follow_box_), b4(threshold_box_), b5(slice_resolution_box_),
        b6(volume_resolution_box_), b7(show_slice_box_), b8(show_reach_box_), b9(show_well_box_),
        b10(reach_opacity_slider_), b11(well_opacity_slider_);
    field_box_->setCurrentIndex(field_box_->findData(QString::fromStdString(f.field)));  // checked by load_session
    normal_box_->setCurrentText(QString::fromStdString(f.normal));
    follow_box_->setChecked(f.follow_endpoint);
    threshold_box_->setValue(f.threshold);
    slice_resolution_box_->setCurrentText(QString::number(f.slice_resolution));
    volume_resolution_box_->setCurrentText(QString::number(f.volume_resolution));
    show_slice_box_->setChecked(f.show_slice);
    show_reach_box_->setChecked(f.show_reach);
    show_well_box_->setChecked(f.show_well_conditioned);
    reach_opacity_slider_->setValue(int(std::lround(f.reach_opacity * 100)));
    well_opacity_slider_->setValue(int(std::lround(f.well_conditioned_opacity * 100)));
  }
  if (!setPose(pathos2::Pose::from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5], v[6])))
    statusBar()->showMessage(tr("The session's pose is not reachable (%1); the device stays where it was.").arg(refusal_),
                             8000);
  syncPanels(true);  // the pose sliders show the session's pose too
  if (s.camera) apply_camera(renderer_, *s.camera);
  applyFieldVisibility();
  requestFields(true, true);
  view_->update();
}

bool Pathos2Window::openSession(const QString& path) { return open_session_file(this, preset_, path); }

bool Pathos2Window::saveSession(const QString& path) { return save_session_file(this, session(), path); }

// ---- Entry ------------------------------------------------------------------------

int run_pathos2_window(const Preset& preset, const std::optional<Session>& session, const std::string& screenshot,
                       int width, int height) {
  Pathos2Window window(preset);
  if (session) window.applySession(*session);
  window.resize(width, height);
  window.show();
  if (screenshot.empty()) return QApplication::exec();
  return save_screenshot_when_settled(window, screenshot);
}

}  // namespace linkscape::gui
