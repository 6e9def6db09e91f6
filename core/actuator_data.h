// Actuator ratings as a preset gives them (key "actuator_data"): torque
// limits, encoder counts and rotor inertia at each actuated joint. The
// haptic measures (core/haptics.h) read them; a preset without them gets
// Linkscape's labelled defaults there.
//
// Units: torques in N·m, encoder counts per revolution of the motor, rotor
// inertia in kg·m² about its axis. A motor behind a reduction of ratio n
// (gear_ratio, default 1: the motor drives the joint directly) gives the
// joint n times its torques and counts and n² times its inertia. A
// prismatic actuator is a rotary motor with these ratings driving the
// slide: lead_m_per_rev metres of travel per revolution of the motor's
// output (a screw's lead, or 2 pi times a capstan's radius), after the
// reduction.
//
// The ratings are also design parameters (motor_parameters()): `--param
// continuous_torque_Nm=0.3`, sessions and `sweep --bounds` set one for every
// actuator, over the preset's actuator_data.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace linkscape {

struct ActuatorRating {
  std::optional<double> peak_torque_Nm;
  std::optional<double> continuous_torque_Nm;
  std::optional<double> encoder_counts_per_rev;
  std::optional<double> rotor_inertia_kgm2;  // optional: no reflected inertia without it
  std::optional<double> lead_m_per_rev;      // prismatic actuators only (m per revolution)
  std::optional<double> gear_ratio;          // motor turns per joint turn; unset: 1
};

// A rating as a design parameter: its name (the actuator_data key), unit and
// what it is.
struct MotorParameter {
  const char* name;
  std::optional<double> ActuatorRating::*field;
  const char* unit;
  const char* description;
};
// Every rating, in the order the Design tab shows them.
const std::vector<MotorParameter>& motor_parameters();
// The rating `name` names, or null.
const MotorParameter* motor_parameter(const std::string& name);
// Throws std::invalid_argument naming `where` unless `value` is a positive finite number.
void check_rating(const std::string& where, double value);

// The preset's "actuator_data" object:
//   "source": where the numbers come from (say "default" where a paper gives none),
//   "all": a rating for every actuator, "<actuator name>": values that override "all".
struct ActuatorDataSpec {
  bool given = false;  // the preset has the key
  std::string source;
  ActuatorRating all;
  std::map<std::string, ActuatorRating> per_actuator;
};

}  // namespace linkscape
