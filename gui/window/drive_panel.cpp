#include "gui/window/drive_panel.h"

#include <QComboBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QStringList>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/haptics.h"
#include "gui/window/device_state.h"
#include "gui/window/quantity_control.h"

namespace linkscape::gui {

DrivePanel::DrivePanel(const MechanismInfo& info, QWidget* parent) : QWidget(parent) {
  QWidget* w = this;
  auto* column = new QVBoxLayout(w);
  auto* top = new QFormLayout;
  drive_box_ = new QComboBox(w);
  drive_box_->setObjectName("driveBox");
  drive_box_->addItems({tr("Task coordinates (inverse kinematics)"), tr("Actuators (forward kinematics)")});
  drive_box_->setToolTip(tr("Which sliders move the device; the others follow."));
  top->addRow(tr("Drive"), drive_box_);
  // Both modes where the device has both kinds of kinematics.
  if (info.ik_methods.empty() || info.fk_methods.empty()) drive_box_->setEnabled(false);
  connect(drive_box_, &QComboBox::activated, this, [this](int i) { emit driveChosen(i == 1 ? Drive::Actuators : Drive::Task); });
  branch_box_ = new QComboBox(w);
  branch_box_->setObjectName("branchBox");
  for (const auto& b : info.branches) branch_box_->addItem(qs(b));
  branch_box_->setToolTip(tr("Assembly branch of inverse kinematics. Dragging and the sliders keep the current one."));
  connect(branch_box_, &QComboBox::activated, this, &DrivePanel::branchChosen);
  if (info.branches.size() > 1) top->addRow(tr("Branch"), branch_box_);
  else branch_box_->hide();
  column->addLayout(top);

  task_group_ = new QGroupBox(tr("Task"), w);
  auto* task_form = new QFormLayout(task_group_);
  for (std::size_t k = 0; k < info.task.size(); ++k)
    task_controls_.push_back(make_control(task_group_, task_form, info.task[k],
                                          [this, k] { emit taskEdited(int(k), task_controls_[k]->value()); }));
  // A planar device's z is its plane, not a freedom: no control for it.
  planar_ = info.plane_z.has_value();
  column->addWidget(task_group_);
  const auto drags_pose = [this](const QuantityControl& c) {
    connect(c.slider, &QSlider::sliderPressed, this, [this] { emit sliderHeld(true); });
    connect(c.slider, &QSlider::sliderReleased, this, [this] { emit sliderHeld(false); });
  };
  for (const auto& c : task_controls_) drags_pose(*c);
  actuator_group_ = new QGroupBox(tr("Actuators"), w);
  auto* actuator_form = new QFormLayout(actuator_group_);
  for (std::size_t k = 0; k < info.actuators.size(); ++k)
    actuator_controls_.push_back(make_control(actuator_group_, actuator_form, info.actuators[k],
                                              [this, k] { emit actuatorEdited(int(k), actuator_controls_[k]->value()); }));
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
  det_label_->setToolTip(tr("Determinant of the Jacobian J = dx/dq where it is square, in the units of its rows (task "
                            "coordinates) over those of its columns (actuators)"));
  form->addRow(tr("det J"), det_label_);
  // The haptic forces at the pose, from the Design tab's motor ratings.
  for (auto [label, name, title, tip] :
       {std::tuple{&force_iso_label_, "forceIsoLabel", tr("force_iso"),
                   tr("The largest force the driven point exerts in every direction, each motor at its continuous "
                      "torque (docs/haptic-measures.md)")},
        std::tuple{&force_max_label_, "forceMaxLabel", tr("force_max"),
                   tr("The largest force the driven point exerts in its best direction, each motor at its "
                      "continuous torque")}}) {
    *label = new QLabel(state);
    (*label)->setObjectName(name);
    (*label)->setToolTip(tip);
    (*label)->setTextInteractionFlags(Qt::TextSelectableByMouse);
    form->addRow(title, *label);
  }
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
  // Read-outs wrap rather than widen the dock past its width (cutting its controls).
  for (QLabel* l : state->findChildren<QLabel*>()) l->setWordWrap(true);
  column->addWidget(state);
  // The device's own read-outs (mobility, joint margin, clearance) follow
  // in the same form, aligned with these.
  state_form_ = form;
  fixed_rows_ = form->rowCount();
  column->addWidget(new QLabel(tr("Or drag the red handle on the driven point in the view."), w));
  column->addStretch(1);
}

DrivePanel::~DrivePanel() = default;

void DrivePanel::showForces(const DeviceState& state) {
  try {
    const haptics::DeviceData data = haptics::device_data(state.preset(), state.mechanism().info());
    const haptics::Measures h = haptics::measures(state.mechanism().jacobian(state.actuators(), state.task()), data,
                                                  haptics::TorqueRating::Continuous);
    // Which torque, and where the ratings come from (the preset, parameters or defaults).
    // A motor driving a slide: its force there.
    const haptics::Rating& first = data.actuators.front();
    const QString rating =
        first.lead_m_per_rev
            ? tr(" (continuous %1 N per slide)").arg(number(first.continuous_torque_Nm / data.metres_per_motor_radian(0)))
            : tr(" (continuous torque %1 N·m)").arg(number(first.continuous_torque_Nm));
    force_iso_label_->setText(number(h.force_iso_N) + " N" + rating);
    force_max_label_->setText((std::isfinite(h.force_max_N) ? number(h.force_max_N) + " N" : QString::fromUtf8("∞ (singular)")) +
                              rating);
    force_iso_label_->setToolTip(force_iso_label_->toolTip().section("\n", 0, 0) + "\n" + qs(data.source));
  } catch (const std::invalid_argument& e) {  // e.g. a preset without a physical length unit
    force_iso_label_->setText(tr("n/a: %1").arg(qs(e.what())));
    force_max_label_->setText(tr("n/a"));
  }
}

Drive DrivePanel::setDrive(Drive drive, const std::vector<std::string>& inputs) {
  const bool fk = drive == Drive::Actuators && drive_box_->isEnabled();
  {
    const QSignalBlocker block(drive_box_);
    drive_box_->setCurrentIndex(fk ? 1 : 0);
  }
  // The panel that drives is shown; the other one's values are in the read-outs.
  bool any_task = false;
  for (const auto& c : task_controls_) {
    const bool in_plane = !(planar_ && c->quantity.name == "z");
    const bool input = in_plane && (!fk || std::find(inputs.begin(), inputs.end(), c->quantity.name) != inputs.end());
    c->set_enabled(input);
    any_task = any_task || input;
  }
  for (const auto& c : actuator_controls_) c->set_enabled(fk);
  task_group_->setVisible(any_task);
  actuator_group_->setVisible(fk);
  return fk ? Drive::Actuators : Drive::Task;
}

void DrivePanel::showValues(const DeviceState& state) {
  for (std::size_t k = 0; k < task_controls_.size(); ++k) task_controls_[k]->set(state.task()(Eigen::Index(k)));
  for (std::size_t k = 0; k < actuator_controls_.size(); ++k) actuator_controls_[k]->set(state.actuators()(Eigen::Index(k)));
  const QSignalBlocker block(branch_box_);
  branch_box_->setCurrentIndex(state.branch());
}

void DrivePanel::showRanges(const MechanismInfo& info) {
  for (std::size_t k = 0; k < task_controls_.size(); ++k) task_controls_[k]->set_range(info.task[k].range);
  for (std::size_t k = 0; k < actuator_controls_.size(); ++k) actuator_controls_[k]->set_range(info.actuators[k].range);
}

QString DrivePanel::showReadouts(const DeviceState& state) {
  const MechanismInfo& info = state.mechanism().info();
  QString problem;
  QStringList task, actuators;
  for (std::size_t k = 0; k < info.task.size(); ++k) task << value_text(info.task[k], state.task()(Eigen::Index(k)));
  for (std::size_t k = 0; k < info.actuators.size(); ++k) {
    double v = state.actuators()(Eigen::Index(k));
    if (info.actuators[k].unit == "rad") v = std::remainder(v, 2 * std::numbers::pi);
    actuators << value_text(info.actuators[k], v);
  }
  auto lines = [](const QStringList& items) {
    QString text;
    // Three to a line, each kept whole where a narrow dock wraps the line.
    for (int i = 0; i < items.size(); ++i)
      text += (i == 0 ? "" : i % 3 == 0 ? "\n" : ", ") + QString(items[i]).replace(' ', QChar::Nbsp);
    return text;
  };
  task_label_->setText(lines(task));
  actuator_label_->setText(lines(actuators));
  try {
    const Measures m = state.mechanism().measures(state.actuators(), state.task());
    for (std::size_t k = 0; k < measure_labels_.size(); ++k) {
      const double v = k < m.values.size() ? m.values[k] : NAN;
      measure_labels_[k]->setText(std::isfinite(v) ? number(v) : QString::fromUtf8("∞ (singular)"));
    }
    // In the units of J = dx/dq's rows over its columns' (e.g. cm³/rad³).
    const Eigen::MatrixXd J = state.mechanism().jacobian(state.actuators(), state.task());
    const QString unit = determinant_unit(info, int(J.rows()), int(J.cols()));
    det_label_->setText(J.rows() != J.cols() ? tr("n/a (J is %1×%2)").arg(J.rows()).arg(J.cols())
                                             : number(m.det) + (unit.isEmpty() ? QString() : " " + unit));
    showForces(state);
    const SingularityReport s = state.mechanism().nearest_singularity(state.actuators(), state.task());
    singular_label_->setText(QString("%1, %2 %3")
                                 .arg(qs(info.singular_sets.at(s.nearest).title), number(s.distance, 3),
                                      qs(info.length_unit)));
  } catch (const std::exception& e) {
    problem = qs(e.what());
  }
  branch_label_->setText(qs(info.branches.at(state.branch())));
  while (state_form_->rowCount() > fixed_rows_) state_form_->removeRow(fixed_rows_);
  for (const auto& [label, text] : state.mechanism().readouts(state.actuators(), state.task())) {
    auto* value = new QLabel(qs(text));
    value->setTextInteractionFlags(Qt::TextSelectableByMouse);
    value->setWordWrap(true);
    state_form_->addRow(qs(label), value);
  }
  return problem;
}

void DrivePanel::showStatus(const QString& text, bool ok) {
  status_label_->setText(text);
  status_label_->setStyleSheet(ok ? "color: #1b5e20" : "color: #b00020");
}

}  // namespace linkscape::gui
