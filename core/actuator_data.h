// Actuator ratings as a preset gives them (key "actuator_data"): torque
// limits, encoder counts and rotor inertia at each actuated joint. The
// haptic measures (core/haptics.h) read them; a preset without them gets
// Linkscape's labelled defaults there.
//
// Units: torques in N·m, encoder counts per revolution of the actuated
// joint, rotor inertia in kg·m² about the joint axis. A motor behind a
// reduction of ratio n is entered at the joint: torques times n, counts
// times n, inertia times n². A prismatic actuator is a rotary motor with
// these ratings driving the slide: lead_m_per_rev metres of travel per
// motor revolution (a screw's lead, or 2 pi times a capstan's radius).
#pragma once

#include <map>
#include <optional>
#include <string>

namespace linkscape {

struct ActuatorRating {
  std::optional<double> peak_torque_Nm;
  std::optional<double> continuous_torque_Nm;
  std::optional<double> encoder_counts_per_rev;
  std::optional<double> rotor_inertia_kgm2;  // optional: no reflected inertia without it
  std::optional<double> lead_m_per_rev;      // prismatic actuators only (m per revolution)
};

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
