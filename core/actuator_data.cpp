#include "core/actuator_data.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace linkscape {

const std::vector<MotorParameter>& motor_parameters() {
  static const std::vector<MotorParameter> list{
      {"continuous_torque_Nm", &ActuatorRating::continuous_torque_Nm, "N m", "Motor torque it can hold without overheating"},
      {"peak_torque_Nm", &ActuatorRating::peak_torque_Nm, "N m", "Motor torque for short pulses"},
      {"gear_ratio", &ActuatorRating::gear_ratio, "", "Motor turns per joint turn (1: direct drive)"},
      {"encoder_counts_per_rev", &ActuatorRating::encoder_counts_per_rev, "counts", "Encoder counts per motor turn"},
      {"rotor_inertia_kgm2", &ActuatorRating::rotor_inertia_kgm2, "kg m^2", "Rotor inertia about the motor axis"},
      {"lead_m_per_rev", &ActuatorRating::lead_m_per_rev, "m", "Slide travel per output turn (prismatic actuators)"},
  };
  return list;
}

const MotorParameter* motor_parameter(const std::string& name) {
  for (const MotorParameter& p : motor_parameters())
    if (name == p.name) return &p;
  return nullptr;
}

void check_rating(const std::string& where, double value) {
  if (!std::isfinite(value) || !(value > 0)) {
    std::ostringstream text;
    text << where << " must be a positive finite number, got " << value;
    throw std::invalid_argument(text.str());
  }
}

}  // namespace linkscape
