// The Design panel: the preset chooser, one slider per design parameter
// the device shows, the actuators' travel where the device takes limits,
// the motors' ratings (core/actuator_data.h: set for every actuator,
// as --param sets them), and switches for the stops the device states
// (passive-joint limits, link interference; as --joint-limits and
// --interference set them). Built from the device's description; the sliders' ranges come
// from the preset's device and stay while the design changes.
#pragma once

#include <QWidget>
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/mechanism.h"
#include "core/preset.h"

class QCheckBox;
class QDoubleSpinBox;
class QFormLayout;
class QLabel;
class QLineEdit;

namespace linkscape::gui {

class DeviceState;
struct QuantityControl;

class DesignPanel : public QWidget {
  Q_OBJECT

 public:
  // `preset_chooser` heads the panel (mechanism_actions.h).
  DesignPanel(const DeviceState& state, QWidget* preset_chooser, QWidget* parent = nullptr);
  ~DesignPanel() override;

  // The sliders, travel boxes and motor ratings show `device`'s design and
  // the state's preset (quietly).
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
  // The Stops group's switches: which stated stops the device checks.
  void stopChecksEdited(const StopChecks& checks);

 private:
  std::vector<std::unique_ptr<QuantityControl>> parameter_controls_;
  std::map<std::string, std::array<QDoubleSpinBox*, 2>> limit_boxes_;  // per actuator: min, max (degrees)
  const DeviceState* state_ = nullptr;
  std::map<std::string, QLineEdit*> motor_edits_;  // per rating
  QLabel* motor_note_ = nullptr;                   // where the ratings come from, or why an edit was refused
  void showMotors();
  // One per kind of stop the preset's device states (else none).
  QCheckBox* joint_limits_box_ = nullptr;
  QCheckBox* interference_box_ = nullptr;
  void addStopSwitches(QFormLayout* form);
  void showStops();
};

}  // namespace linkscape::gui
