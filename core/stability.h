// Stability sweeps: approach each singular set of a device along a path, eps
// = 1e-1 down to 1e-12, and record for every method the error, the residual,
// the iterations and the status, beside the error a first-order analysis
// predicts (Mechanism::stability_sweeps). The default sweeps of any device
// are in core/generic_methods.cpp; devices with higher-precision references
// run their own (core/mechanisms/<name>/stability.h).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/method_harness.h"
#include "core/status.h"

namespace linkscape::stability {

// The paths of the devices' own sweeps. The 12R's
// (core/mechanisms/parallel12r/stability.h):
enum class SweepPath {
  CosAlpha,     // joint path alpha = pi/2 - eps: cos(alpha) -> 0, endpoint -> actuator plane y = 0
  BetaGamma,    // joint path gamma = beta - eps: fully stretched (outer sphere, at distance ~ eps^2)
  BetaGammaPi,  // joint path gamma = beta - pi + eps: fully folded (inner sphere)
  ZAxis,        // Cartesian: distance eps (L1 + L2) from the z axis, y > 0
  OuterSphere,  // Cartesian: |D| = (1 - eps) (L1 + L2)
  InnerSphere,  // Cartesian: |D| = |L1 - L2| + eps (L1 + L2)
  // PATHOS-II (core/mechanisms/pathos2/stability.h). Leg joint paths, eps an angle (rad):
  LegStretched,  // t3 = -eps: l2 and l3 in line, |a - l1 z| -> l2 + l3 (sin t3 -> 0)
  LegFolded,     // t3 = -(pi - eps): folded, |a - l1 z| -> |l2 - l3| (sin t3 -> 0)
  LegElbow,      // t2 = eps: c1x = w sin t2 -> 0 (sin t2 -> 0)
  // Pose paths from the home pose along a seeded direction of (x, y, z,
  // rx, ry, rz) (1 cm : 0.1 rad), s = s* (1 - eps), s* the first crossing:
  Reach,          // s*: the first leg becomes unreachable (the workspace boundary)
  ActuatedSingular,  // s*: det J_qdot_from_twist changes sign (the 6x6 J singular)
};
// "cos-alpha", "beta=gamma", "beta=gamma+pi", "z-axis", "outer-sphere", "inner-sphere";
// "leg-stretched", "leg-folded", "leg-elbow", "reach-boundary", "J-singular".
std::string_view to_string(SweepPath path);
// eps is an angle (rad) on joint paths, a distance / (L1 + L2) on Cartesian ones.
bool is_joint_path(SweepPath path);

struct SweepOptions {
  double eps_max = 1e-1;
  double eps_min = 1e-12;
  int steps_per_decade = 1;
  int base_points = 3;  // generic starting points per path (seeded)
  unsigned seed = 7;
  methods::SolverLimits ik;  // of the iterative IK methods (default seeds)
};

struct SweepRow {
  std::string mechanism;  // the device's preset mechanism name
  SweepPath path = SweepPath::CosAlpha;
  std::string path_name;  // the singular set's name where `path` does not apply (devices' own sweeps)
  int base_point = 0;
  double eps = 0;
  double distance = 0;  // Cartesian distance of the target from the singular set, length unit
  double cond = 0;      // c(J) at the reference solution (+inf if none; NaN: the default sweeps, no ok solution)
  double sigma_min = 0; // smallest singular value of J there, length unit per rad (NaN: not measured)
  double predicted = 0; // u B(q) / sigma_min for ik; u c(J) for conditioning; NaN for jacobian
  std::string family;   // "ik", "jacobian", "conditioning"
  std::string method;
  Status status = Status::Ok;
  double error = 0;     // ik: joint error (rad); others: relative; NaN if status != ok or no reference
  // Of an ik row's error: "rad", or "relative" where the sweep has no
  // reference and the residual over the size stands for it (the default sweeps).
  std::string ik_error_unit = "rad";
  double residual = 0;  // ik: |forward(q) - target| (length unit), NaN with no ok solution; 0 otherwise
  int iterations = 0;
};
// The row's path_name, else to_string(path).
std::string path_label(const SweepRow& row);

// The eps of a sweep: eps_max down to eps_min, steps_per_decade per decade.
// Throws std::invalid_argument for bad options.
std::vector<double> sweep_eps(const SweepOptions& options);

}  // namespace linkscape::stability
