// A closed interval: a parameter's span, an actuator's travel, a preset's
// actuator limits.
#pragma once

namespace linkscape {

struct Range {
  double lo = 0.0;
  double hi = 0.0;
  bool contains(double v) const { return v >= lo && v <= hi; }
};

}  // namespace linkscape
