// Stability sweeps for the 12R mechanism: approach each singular set along a
// path, eps = 1e-1 down to 1e-12, and record for every method the error
// against a long-double reference, the residual, the iterations and the
// status. The prediction each IK error is compared with is the first-order
// error of a backward-stable solver, u B(q) / sigma_min(J) with u = 2^-53 and
// B = methods::backward_error_scale (the rounding of target, angles and
// Eqs. 11-13 in double), about u c(J) for unit-scale lengths away from the
// actuator plane.
#pragma once

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

#include "core/mechanisms/parallel12r/parallel12r.h"
#include "core/mechanisms/pathos2/pathos2.h"
#include "core/status.h"

namespace linkscape::stability {

enum class SweepPath {
  CosAlpha,     // joint path alpha = pi/2 - eps: cos(alpha) -> 0, endpoint -> actuator plane y = 0
  BetaGamma,    // joint path gamma = beta - eps: fully stretched (outer sphere, at distance ~ eps^2)
  BetaGammaPi,  // joint path gamma = beta - pi + eps: fully folded (inner sphere)
  ZAxis,        // Cartesian: distance eps (L1 + L2) from the z axis, y > 0
  OuterSphere,  // Cartesian: |D| = (1 - eps) (L1 + L2)
  InnerSphere,  // Cartesian: |D| = |L1 - L2| + eps (L1 + L2)
  // PATHOS-II (run_pathos2_sweeps). Leg joint paths, eps an angle (rad):
  LegStretched,  // t3 = -eps: l2 and l3 in line, |a - l1 z| -> l2 + l3 (sin t3 -> 0)
  LegFolded,     // t3 = -(pi - eps): folded, |a - l1 z| -> |l2 - l3| (sin t3 -> 0)
  LegElbow,      // t2 = eps: c1x = w sin t2 -> 0 (sin t2 -> 0)
  // Pose paths from the home pose along a seeded direction of (x, y, z,
  // rx, ry, rz) (1 cm : 0.1 rad), s = s* (1 - eps), s* the first crossing:
  Reach,          // s*: the first leg becomes unreachable (the workspace boundary)
  ActuatedSingular,  // s*: det J_qdot_from_twist changes sign (the 6x6 J singular)
};
inline constexpr SweepPath kAllPaths[] = {SweepPath::CosAlpha, SweepPath::BetaGamma,   SweepPath::BetaGammaPi,
                                          SweepPath::ZAxis,    SweepPath::OuterSphere, SweepPath::InnerSphere};
inline constexpr SweepPath kPathos2Paths[] = {SweepPath::LegStretched, SweepPath::LegFolded, SweepPath::LegElbow,
                                              SweepPath::Reach, SweepPath::ActuatedSingular};
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
  parallel12r::IkOptions ik;
};

struct SweepRow {
  std::string mechanism = "parallel-12r";  // or "pathos2"
  SweepPath path = SweepPath::CosAlpha;
  std::string path_name;  // the singular set's name where `path` does not apply (devices' own sweeps)
  int base_point = 0;
  double eps = 0;
  double distance = 0;  // Cartesian distance of the target from the singular set, length unit
  double cond = 0;      // c(J) at the reference solution (+inf if none)
  double sigma_min = 0; // smallest singular value of J there, length unit per rad
  double predicted = 0; // u B(q) / sigma_min for ik; u c(J) for conditioning; NaN for jacobian
  std::string family;   // "ik", "jacobian", "conditioning"
  std::string method;
  Status status = Status::Ok;
  double error = 0;     // ik: joint error (rad); others: relative; NaN if status != ok or no reference
  double residual = 0;  // ik: |forward(q) - target| (length unit); 0 otherwise
  int iterations = 0;
};
// The row's path_name, else to_string(path).
std::string path_label(const SweepRow& row);


// Runs every path. Methods: ik paper, planar, newton, dls, fallback (default
// seeds) and newton-near (seeded 1e-3 rad from the reference: Newton's own
// accuracy, apart from its basin); jacobian analytic, central-difference,
// forward-difference, complex-step; conditioning closed-form,
// closed-form-fast, svd, normal-equations. Throws std::invalid_argument for
// bad options.
std::vector<SweepRow> run_stability_sweeps(const parallel12r::Model& model, const SweepOptions& options = {});

// PATHOS-II paths (kPathos2Paths). Leg paths: family "ik", methods
// closed-form (pathos2::leg_inverse), newton (home-pose seed), newton-near
// (seeded 1e-3 rad from the reference); cond and sigma_min of the 3x3 leg
// Jacobian; predicted u (l1 + l2 + l3 + pi |J|_F) / sigma_min. Pose paths:
// family "fk" nine-sensor, numeric (home seed), numeric-near (seed 1e-3 cm,
// rad off), error the pose error of pathos2_methods::pose_error against the
// nearest exact solution; cond = cond(J_twist_from_qdot), sigma_min =
// 1 / |S J|_2 with S = diag(1 / (l2 + l3) I, I), predicted
// u sqrt(6) (pi + (l0 + l2 + l3) |M|_F) |S J|_2 (the rounding of the six
// angles and of their evaluation mapped through J); jacobian analytic,
// central-difference, forward-difference (predicted u cond(J)); conditioning
// closed-form, svd (predicted u max(cond Jp, cond Jo)). Throws
// std::invalid_argument for bad options.
std::vector<SweepRow> run_pathos2_sweeps(const pathos2::Model& model, const SweepOptions& options = {});

// The target, and the configuration on the path (joint paths) or nearest to
// it (Cartesian paths, from the planar closed form), of one sweep point.
struct SweepPoint {
  Eigen::Vector3d target;
  Eigen::Vector3d q_path;
  double distance = 0;
};
SweepPoint sweep_point(const parallel12r::Model& model, SweepPath path, double eps, int base_point, unsigned seed);

}  // namespace linkscape::stability
