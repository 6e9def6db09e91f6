// Task volumes and criteria: what a designer asks of a device. A task is a
// sphere or an axis-aligned box of the driven point's position (the other
// task coordinates held fixed), and criteria are bounds on the measures
// every point of it must meet. docs/task-volumes.md describes the
// evaluation, the inscribed sphere and cube, and their convergence.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/haptics.h"
#include "core/mechanism.h"

namespace linkscape::task {

// ---- Criteria ---------------------------------------------------------------------

// "reach" (the point is reachable in the sampled branch), or a bound on a
// measure: "cond<3" (the device's first measure, also by its name, e.g.
// cond_jp; its other measures by name, e.g. "cond_jo<5"), "force_iso>2" (N), "force_max>5" (N),
// "resolution<0.5" (mm), "inertia<0.2" (kg). Every criterion includes reach.
struct Criterion {
  std::string text;      // as given
  std::string measure;   // "reach", "cond", a measure name or a haptic field name
  bool above = false;    // the value must exceed the threshold (forces) rather than stay below it
  double threshold = 0;  // in the measure's unit
  bool haptic() const { return haptics::is_haptic_field(measure); }
};

// Parses one criterion. Throws std::invalid_argument for a malformed text,
// a threshold no pose can meet (cond below 1, a force or threshold <= 0), or
// a bound on a measure's wrong side (cond>3).
Criterion parse_criterion(const std::string& text);
// Checks the criterion's measure against the device (its measures, and the
// haptic fields `data` provides). Throws std::invalid_argument listing the
// names it knows.
void check_criterion(const Criterion& c, const MechanismInfo& info, const haptics::DeviceData* data);

}  // namespace linkscape::task
