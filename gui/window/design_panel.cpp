#include "gui/window/design_panel.h"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QLabel>
#include <QLineEdit>
#include <QSignalBlocker>
#include <QVBoxLayout>
#include <algorithm>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "core/actuator_data.h"
#include "core/csv.h"
#include "core/haptics.h"
#include "gui/window/device_state.h"
#include "gui/window/quantity_control.h"

namespace linkscape::gui {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// The first actuator's motor's rating, on the motor's side of a reduction:
// a parameter where one is set, else the preset's (or Linkscape's default).
// Throws std::invalid_argument where the preset's data cannot be read.
std::optional<double> motor_value(const Preset& preset, const MechanismInfo& info, const MotorParameter& p) {
  if (const auto it = preset.parameters.find(p.name); it != preset.parameters.end()) return it->second;
  const haptics::Rating r = haptics::device_data(preset, info).actuators.front();
  const ActuatorDataSpec& spec = preset.actuator_data;
  const auto own = spec.per_actuator.find(info.actuators.front().name);
  const double n = own != spec.per_actuator.end() && own->second.gear_ratio ? *own->second.gear_ratio
                                                                            : spec.all.gear_ratio.value_or(1.0);
  const std::string name = p.name;
  if (name == "gear_ratio") return n;
  if (name == "continuous_torque_Nm") return r.continuous_torque_Nm / n;
  if (name == "peak_torque_Nm") return r.peak_torque_Nm / n;
  if (name == "encoder_counts_per_rev") return r.encoder_counts_per_rev / n;
  if (name == "rotor_inertia_kgm2" && r.rotor_inertia_kgm2) return *r.rotor_inertia_kgm2 / (n * n);
  if (name == "lead_m_per_rev") return r.lead_m_per_rev;
  return std::nullopt;
}

}  // namespace

DesignPanel::DesignPanel(const DeviceState& state, QWidget* preset_chooser, QWidget* parent)
    : QWidget(parent), state_(&state) {
  const MechanismInfo& info = state.mechanism().info();
  auto* form = new QFormLayout(this);
  form->addRow(tr("Preset"), preset_chooser);
  auto* title = new QLabel(qs(info.title), this);
  title->setWordWrap(true);
  form->addRow(title);
  for (const Quantity& q : info.parameters) {
    if (!q.in_panel) continue;
    const std::string name = q.name;
    parameter_controls_.push_back(make_control(this, form, q, [this, name] {
      for (const auto& c : parameter_controls_)
        if (c->quantity.name == name) emit parametersEdited({{name, c->value()}});
    }));
  }
  // The motors: one rating for every actuator, as --param sets it.
  auto* motors = new QGroupBox(tr("Motors"), this);
  motors->setObjectName("motorsGroup");
  auto* motor_form = new QFormLayout(motors);
  const bool prismatic = std::any_of(info.actuators.begin(), info.actuators.end(), [](const Quantity& a) { return a.unit != "rad"; });
  for (const MotorParameter& p : motor_parameters()) {
    if (std::string(p.name) == "lead_m_per_rev" && !prismatic) continue;
    auto* edit = new QLineEdit(motors);
    edit->setObjectName(qs(p.name) + "Edit");
    edit->setToolTip(tr("%1 (%2), for every actuator; the haptic fields, criteria and the Drive tab's forces use it")
                         .arg(qs(p.description), p.unit[0] ? qs(p.unit) : tr("a ratio")));
    motor_form->addRow(qs(p.name), edit);
    motor_edits_[p.name] = edit;
    connect(edit, &QLineEdit::editingFinished, this, [this, name = std::string(p.name), edit] {
      const auto value = parse_number(edit->text().trimmed().toStdString());
      try {
        if (!value) throw std::invalid_argument(name + " expects a number, got '" + edit->text().toStdString() + "'");
        Preset next = state_->preset();
        next.parameters[name] = *value;
        haptics::device_data(next, state_->mechanism().info());  // refuses a rating the others contradict
      } catch (const std::invalid_argument& e) {
        showMotors();  // back to the rating in force
        motor_note_->setStyleSheet("color: #b71c1c");
        motor_note_->setText(qs(e.what()));
        return;
      }
      if (state_->preset().parameters.count(name) && state_->preset().parameters.at(name) == *value) return;
      emit parametersEdited({{name, *value}});
    });
  }
  motor_note_ = new QLabel(motors);
  motor_note_->setObjectName("motorsNote");
  motor_note_->setWordWrap(true);
  motor_form->addRow(motor_note_);
  form->addRow(motors);
  showMotors();
  addStopSwitches(form);
  if (!state.takes_limits()) return;
  auto* grid = new QGridLayout;
  int row = 0;
  for (const Quantity& a : info.actuators) {
    grid->addWidget(new QLabel(qs(a.name), this), row, 0);
    for (int k = 0; k < 2; ++k) {
      auto* box = spin(this, -360, 360, (k == 0 ? a.range.lo : a.range.hi) / kDeg, 1, QString::fromUtf8(" °"));
      box->setObjectName(qs(a.name) + (k == 0 ? "MinBox" : "MaxBox"));
      box->setToolTip(k == 0 ? tr("Lower end of the actuator's travel") : tr("Upper end of the actuator's travel"));
      limit_boxes_[a.name][k] = box;
      grid->addWidget(box, row, 1 + k);
      connect(box, &QDoubleSpinBox::editingFinished, this, [this] {
        std::map<std::string, std::array<double, 2>> limits;
        for (const auto& [name, boxes] : limit_boxes_) limits[name] = {boxes[0]->value(), boxes[1]->value()};
        emit limitsEdited(limits);
      });
    }
    ++row;
  }
  form->addRow(tr("Actuator travel"), grid);
}

DesignPanel::~DesignPanel() = default;

void DesignPanel::addStopSwitches(QFormLayout* form) {
  const StopChecks stated = stated_stops(state_->preset());
  if (!stated.joint_limits && !stated.interference) return;
  auto* group = new QGroupBox(tr("Stops"), this);
  group->setObjectName("stopsGroup");
  auto* layout = new QVBoxLayout(group);
  const auto add = [&](bool states, const QString& text, const QString& tip, const char* name) -> QCheckBox* {
    if (!states) return nullptr;
    auto* box = new QCheckBox(text, group);
    box->setObjectName(name);
    box->setToolTip(tip);
    layout->addWidget(box);
    connect(box, &QCheckBox::toggled, this, [this] {
      StopChecks checks = state_->preset().checks;
      if (joint_limits_box_) checks.joint_limits = joint_limits_box_->isChecked();
      if (interference_box_) checks.interference = interference_box_->isChecked();
      emit stopChecksEdited(checks);
    });
    return box;
  };
  joint_limits_box_ = add(stated.joint_limits, tr("Passive-joint limits"),
                          tr("A pose with a passive joint beyond its limit is out of limits; off, the device is "
                             "taken as stating no limits (as --joint-limits off)"),
                          "jointLimitsCheck");
  interference_box_ = add(stated.interference, tr("Link interference"),
                          tr("A pose where two links overlap is out of limits; off, the device is taken as giving "
                             "its links no radius (as --interference off)"),
                          "interferenceCheck");
  form->addRow(group);
  showStops();
}

void DesignPanel::showStops() {
  const auto show = [](QCheckBox* box, bool on) {
    if (!box) return;
    const QSignalBlocker block(box);
    box->setChecked(on);
  };
  show(joint_limits_box_, state_->preset().checks.joint_limits);
  show(interference_box_, state_->preset().checks.interference);
}

void DesignPanel::showMotors() {
  const Preset& preset = state_->preset();
  const MechanismInfo& info = state_->mechanism().info();
  try {
    for (const MotorParameter& p : motor_parameters()) {
      const auto it = motor_edits_.find(p.name);
      if (it == motor_edits_.end()) continue;
      const std::optional<double> v = motor_value(preset, info, p);
      const QSignalBlocker block(it->second);
      it->second->setText(v ? number(*v, 6) : QString());
      it->second->setPlaceholderText(v ? QString() : tr("not given"));
    }
    motor_note_->setStyleSheet("");
    motor_note_->setText(qs(haptics::device_data(preset, info).source));
  } catch (const std::invalid_argument& e) {  // e.g. a preset whose actuator data lacks a value
    motor_note_->setStyleSheet("color: #b71c1c");
    motor_note_->setText(qs(e.what()));
  }
}

void DesignPanel::showDesign(const Mechanism& device) {
  showMotors();
  showStops();
  const auto p = device.parameters();
  for (const auto& c : parameter_controls_)
    if (p.count(c->quantity.name)) c->set(p.at(c->quantity.name));
  for (const Quantity& a : device.info().actuators) {
    const auto it = limit_boxes_.find(a.name);
    if (it == limit_boxes_.end()) continue;
    for (int k = 0; k < 2; ++k) {
      const QSignalBlocker block(it->second[k]);
      it->second[k]->setValue((k == 0 ? a.range.lo : a.range.hi) / kDeg);
    }
  }
}

void DesignPanel::checkParameters(const std::map<std::string, double>& parameters) const {
  for (const auto& c : parameter_controls_) {
    const auto it = parameters.find(c->quantity.name);
    if (it != parameters.end() &&
        (it->second * c->scale < c->box->minimum() || it->second * c->scale > c->box->maximum()))
      throw std::invalid_argument("session: " + c->quantity.name + " = " + format_number(it->second) +
                                  " is outside the window's range [" + format_number(c->box->minimum() / c->scale) +
                                  ", " + format_number(c->box->maximum() / c->scale) + "] for this preset");
  }
}

}  // namespace linkscape::gui
