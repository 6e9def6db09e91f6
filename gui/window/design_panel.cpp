#include "gui/window/design_panel.h"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGridLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <numbers>
#include <stdexcept>

#include "core/csv.h"
#include "gui/window/device_state.h"
#include "gui/window/quantity_control.h"

namespace linkscape::gui {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

DesignPanel::DesignPanel(const DeviceState& state, QWidget* preset_chooser, QWidget* parent) : QWidget(parent) {
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

void DesignPanel::showDesign(const Mechanism& device) {
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
