// The Design panel: the preset chooser, one slider per design parameter
// the device shows, and the actuators' travel where the device takes
// limits. Built from the device's description; the sliders' ranges come
// from the preset's device and stay while the design changes.
#pragma once

#include <QWidget>
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/mechanism.h"

class QDoubleSpinBox;

namespace linkscape::gui {

class DeviceState;
struct QuantityControl;

class DesignPanel : public QWidget {
  Q_OBJECT

 public:
  // `preset_chooser` heads the panel (mechanism_actions.h).
  DesignPanel(const DeviceState& state, QWidget* preset_chooser, QWidget* parent = nullptr);
  ~DesignPanel() override;

  // The sliders and travel boxes show `device`'s design (quietly).
  void showDesign(const Mechanism& device);
  // Whether the panel edits actuator travel.
  bool editsLimits() const { return !limit_boxes_.empty(); }
  // Throws std::invalid_argument for a parameter outside its slider's range
  // (it would be clamped), naming it and the range.
  void checkParameters(const std::map<std::string, double>& parameters) const;

 signals:
  void parametersEdited(const std::map<std::string, double>& parameters);
  // Every actuator's travel in degrees, by name.
  void limitsEdited(const std::map<std::string, std::array<double, 2>>& limits_deg);

 private:
  std::vector<std::unique_ptr<QuantityControl>> parameter_controls_;
  std::map<std::string, std::array<QDoubleSpinBox*, 2>> limit_boxes_;  // per actuator: min, max (degrees)
};

}  // namespace linkscape::gui
