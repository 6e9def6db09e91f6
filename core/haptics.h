// Haptic measures of any device, from its Jacobian J = dx/dq and its
// actuators' ratings (docs/haptic-measures.md gives every formula and its
// check):
//   force_iso   the largest force the driven point can exert in EVERY
//               direction with each |tau_i| <= its torque limit   (N)
//   force_max   the largest force in SOME direction                (N)
//   resolution  the largest displacement one encoder count on any one
//               actuator produces                                  (mm)
//   inertia     the largest rotor inertia reflected to the driven point,
//               where every actuator's rotor inertia is given       (kg)
// The force is a pure force at the driven point: statics tau = J_p^T F with
// J_p the position rows of J (three; two, in its plane, for a planar device). For a device with more task coordinates
// (PATHOS-II: orientation and grip) this is the force with zero moment and
// zero grip force; the actuators must then hold the moment too, which the
// same torques do. Links are massless: inertia is the rotors' alone.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/actuator_data.h"
#include "core/mechanism.h"

namespace linkscape {

struct Preset;

namespace haptics {

// One actuator's ratings, every value present (inertia optional). A
// prismatic actuator is a rotary motor with these ratings driving its slide.
struct Rating {
  double peak_torque_Nm = 0;
  double continuous_torque_Nm = 0;
  double encoder_counts_per_rev = 0;
  std::optional<double> rotor_inertia_kgm2;
  std::optional<double> lead_m_per_rev;  // set for a prismatic actuator: travel per motor revolution
};

struct DeviceData {
  std::vector<Rating> actuators;  // per info().actuators
  std::string source;             // from the preset, or that Linkscape's defaults were used
  bool defaults = false;          // true where the numbers are Linkscape's defaults, not the device's
  double metres_per_length_unit = 0.01;
  // The rows of J that place the driven point: 3 (x, y, z), or 2 (x, y)
  // for a planar device (MechanismInfo::plane_z), whose forces lie in its plane.
  int position_rows = 3;
  bool has_inertia() const;       // every actuator's rotor inertia is given
  // Metres of the driven point per motor radian, per unit of J's column i:
  // the length unit for a revolute actuator, lead / 2 pi for a prismatic one.
  double metres_per_motor_radian(std::size_t i) const;
};

enum class TorqueRating { Continuous, Peak };
// "continuous" / "peak"; throws std::invalid_argument otherwise.
TorqueRating parse_torque_rating(const std::string& text);
const char* to_string(TorqueRating rating);

// The physical length units: mm, cm, m, in (what meshes may be written in).
const std::vector<std::string>& length_units();
bool is_length_unit(const std::string& unit);

// Metres per unit of a preset length unit: m, cm, mm, in. Throws
// std::invalid_argument for another (e.g. "unit": forces need a real length).
double metres_per(const std::string& length_unit);

// The preset's actuator data for `info`'s actuators, every value filled:
// per-actuator entries override "all". A preset without "actuator_data"
// gets kDefaultRating, with source saying so. Throws std::invalid_argument
// naming the key for an unknown actuator or a missing value.
DeviceData device_data(const Preset& preset, const MechanismInfo& info);
// Linkscape's default rating, of the order of a 40 mm direct-drive DC motor
// with a 500-line quadrature encoder; not from any paper. A prismatic
// actuator's default drives its slide by a capstan of 1 cm radius.
Rating default_rating(bool prismatic = false);

struct Measures {
  double force_iso_N = 0;
  double force_max_N = 0;      // +inf where J_p loses rank (a force the structure holds)
  double resolution_mm = 0;
  std::optional<double> inertia_kg;  // where DeviceData::has_inertia(); +inf where J_p loses rank
};

// The measures of J (task rows x actuator columns, as Mechanism::jacobian
// gives it: task lengths in the device's unit per rad of a revolute
// actuator, per length unit of a prismatic one; the first
// data.position_rows rows the position). Throws std::invalid_argument for a
// J whose size does not match data.
Measures measures(const Eigen::MatrixXd& J, const DeviceData& data, TorqueRating rating);

// The haptic fields: name, title and unit, in this order; "inertia" only
// where the data has inertias.
struct FieldInfo {
  std::string name, title, unit;
  bool larger_is_better;
};
std::vector<FieldInfo> field_infos(const DeviceData& data);
// All four, inertia included.
const std::vector<FieldInfo>& all_field_infos();
// Whether `name` is one of the haptic field names (inertia included).
bool is_haptic_field(const std::string& name);

// Adds the haptic fields to `field` (sampled by mechanism.compute_field with
// the same fixed_task and ik): per reachable sample, IK through the
// interface in the field's branch, then J. Samples that are not reachable
// hold values that fail every criterion: forces 0, resolution and inertia
// +inf. Returns false if cancelled.
bool add_fields(Field& field, const Mechanism& mechanism, const DeviceData& data, TorqueRating rating,
                const Eigen::VectorXd& fixed_task, const IkOptions& ik, int threads, const FieldProgress& progress);

// compute_field followed by add_fields (when with_haptics); nullopt if cancelled.
std::optional<Field> sample_field(const Mechanism& mechanism, const Grid& grid, const Eigen::VectorXd& fixed_task,
                                  const IkOptions& ik, int threads, const FieldProgress& progress,
                                  const DeviceData* data = nullptr,
                                  TorqueRating rating = TorqueRating::Continuous);

}  // namespace haptics
}  // namespace linkscape
