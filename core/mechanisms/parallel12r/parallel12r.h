// The 10-link, 12-revolute-joint parallel hand controller of Adelstein, Ho and
// Kazerooni (seed paper 001), preset name "parallel-12r".
//
// Conventions (docs/mechanisms/parallel-12r.md derives and checks each one):
// - Base frame: origin at the common centre of the spherical loops, actuator A
//   on the z axis, actuators B and C on the x axis. Lengths are in the model's
//   length unit, angles in radians.
// - q_actuated = (alpha, beta, gamma), alpha in (-pi/2, pi/2) (Eq. 14).
// - Endpoint D = L1 u(alpha, beta) + L2 u(alpha, gamma) with
//   u(alpha, t) = (-sin a cos t, cos a cos t, cos a sin t) / d(t),
//   d(t) = sqrt(1 - sin^2 a sin^2 t)                     (Eqs. 11-13).
//   The equations pair L1 with beta and L2 with gamma; we follow them.
// - Assembly branch 0 has sin(beta - gamma) > 0, branch 1 has it < 0.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/range.h"
#include "core/status.h"

namespace linkscape::parallel12r {

inline constexpr std::string_view kMechanismName = "parallel-12r";

using Interval = Range;  // core/range.h

// Accepted link lengths, in the model's length unit. The kinematics work in
// lengths divided by a power of two near the reach, so results do not depend
// on scale; the bounds come from the fields, which store lengths (reach
// margin, residual) as float (normal range 1.2e-38 .. 3.4e38).
inline constexpr double kMinLength = 1e-30;
inline constexpr double kMaxLength = 1e30;

struct Model {
  double L1 = 1.0;  // link along u(alpha, beta), length unit
  double L2 = 1.0;  // link along u(alpha, gamma), length unit
  std::string length_unit = "unit";
  // Actuator ranges (rad). alpha is further restricted to (-pi/2, pi/2).
  Interval alpha_limits{-1.5707963267948966, 1.5707963267948966};
  Interval beta_limits{-3.141592653589793, 3.141592653589793};
  Interval gamma_limits{-3.141592653589793, 3.141592653589793};

  double reach() const { return L1 + L2; }
  // Whether (alpha, beta, gamma) lies within the actuator ranges.
  bool within_limits(const Eigen::Vector3d& q) const {
    return alpha_limits.contains(q.x()) && beta_limits.contains(q.y()) && gamma_limits.contains(q.z());
  }
  double inner_reach() const { return L1 > L2 ? L1 - L2 : L2 - L1; }
  // Throws std::invalid_argument for a length outside [kMinLength,
  // kMaxLength] (or not finite) or an empty range.
  void validate() const;

  // Builds a model from named parameters ("L1", "L2") and ranges
  // ("alpha", "beta", "gamma" in degrees). Throws std::invalid_argument
  // naming an unknown parameter.
  static Model from_parameters(const std::map<std::string, double>& parameters,
                               const std::map<std::string, Interval>& limits_deg,
                               std::string length_unit);
  static std::vector<std::string> parameter_names() { return {"L1", "L2"}; }
};

// ---- Forward geometry and Jacobian ---------------------------------------

// Endpoint D in the base frame (Eqs. 11-13). Throws on non-finite angles.
Eigen::Vector3d forward(const Model& model, const Eigen::Vector3d& q_actuated);
// Batched form: p_base_endpoint[i] = forward(q_actuated[i]). Sizes must match.
void forward(const Model& model, std::span<const Eigen::Vector3d> q_actuated,
             std::span<Eigen::Vector3d> p_base_endpoint);

// J = dD/dq (length unit per rad), derived analytically (printed Eq. 17 has
// wrong d-powers; see the docs).
Eigen::Matrix3d jacobian(const Model& model, const Eigen::Vector3d& q_actuated);
// Central differences with the given step (rad), for checking.
Eigen::Matrix3d jacobian_central_difference(const Model& model, const Eigen::Vector3d& q_actuated,
                                            double step = 1e-6);
// det J as printed in Eq. 18.
double jacobian_determinant_eq18(const Model& model, const Eigen::Vector3d& q_actuated);

// ---- Inverse kinematics ---------------------------------------------------

enum class IkMethod {
  Paper,               // Eqs. 14-16, corrected, then one Newton step (docs)
  Planar,              // planar two-link reduction in the plane normal to n(alpha)
  Newton,              // Newton-Raphson with backtracking, from a seed
  DampedLeastSquares,  // Levenberg-Marquardt damping, from a seed
  Fallback,            // Planar; where its candidate misses the tolerance, Newton
                       // seeded from that candidate (IkSolution::method says which)
};
std::string_view to_string(IkMethod method);
// Accepts "paper", "planar", "newton", "dls", "fallback". Throws std::invalid_argument.
IkMethod parse_ik_method(std::string_view name);

struct IkOptions {
  // Numerical methods start here; without it they start from the home pose of
  // each branch in the target's half-space (see docs).
  std::optional<Eigen::Vector3d> seed;
  int max_iterations = 100;
  // A solution is accepted when |forward(q) - target| <= tolerance * reach.
  double tolerance = 1e-10;
};

struct IkSolution {
  Eigen::Vector3d q_actuated = Eigen::Vector3d::Zero();
  int branch = 0;
  Status status = Status::Ok;
  double residual = 0.0;  // |forward(q) - target|, length unit
  int iterations = 0;     // Newton steps: 0 for planar, 0 or 1 for paper
  // The method that produced this solution: the requested one, except under
  // Fallback, where it is Planar or Newton (seeded from the planar candidate).
  IkMethod method = IkMethod::Planar;
};

struct IkResult {
  Status status = Status::Unreachable;  // Ok if any solution is Ok
  std::vector<IkSolution> solutions;    // at most one per branch, branch order
};

// Throws std::invalid_argument for a non-finite target or invalid model.
IkResult inverse(const Model& model, const Eigen::Vector3d& p_base_endpoint, IkMethod method,
                 const IkOptions& options = {});

int branch_of(const Eigen::Vector3d& q_actuated);
// Home pose of a branch (the c(J) = 1 optimum for L1 = L2): branch 0 is
// (0, pi/2, 0), branch 1 is (0, 0, pi/2).
Eigen::Vector3d home_pose(int branch);

// Relative distance below which a target counts as on a singular set. Every
// method reports such a target `singular`; a solution is given there only if
// it meets the tolerance (with status Singular).
inline constexpr double kSingularTolerance = 1e-12;

// ---- Conditioning and singularities ---------------------------------------

enum class SingularSet {
  ActuatorPlane,  // cos(alpha) = 0: endpoint in the x-z plane (y = 0); the
                  // static singularities d_beta = 0, d_gamma = 0 lie here too
  Stretched,      // beta = gamma: outer reach sphere |D| = L1 + L2
  Folded,         // beta = gamma +- pi: inner sphere |D| = |L1 - L2|
  ZAxis,          // L1 c(beta)/d_beta + L2 c(gamma)/d_gamma = 0: x = y = 0
};
std::string_view to_string(SingularSet set);

struct SingularityReport {
  SingularSet nearest = SingularSet::ActuatorPlane;
  double distance = 0.0;              // Cartesian distance to `nearest`, length unit
  std::array<double, 4> distances{};  // per SingularSet, same order
  double static_measure = 1.0;        // min(d_beta, d_gamma): 0 at a static singularity
};
SingularityReport nearest_singularity(const Model& model, const Eigen::Vector3d& q_actuated);

// c(J) of a configuration, computed in double, has relative error up to
// ~90 u c: J's entries are rounded, and near the actuator plane the z-axis
// factor of det J cancels (measured against mpmath and long double, see
// docs/mechanisms/parallel-12r.md). Up to this c it is within 1e-6 (5e-7
// measured); beyond it double cannot resolve c(J) (at c ~ 1e26 it came out
// half the true value, det J with the wrong sign), and the configuration is
// reported singular.
inline constexpr double kMaxTrustedCondition = 5e7;

struct Conditioning {
  double cond = 0.0;  // sigma_max / sigma_min; +inf when singular
  double det = 0.0;   // det J (length unit^3 / rad^3); 0 when singular
  // Singular where J is singular to working precision: c(J) above
  // kMaxTrustedCondition (cond = +inf, det = 0).
  Status status = Status::Ok;
};
Conditioning conditioning(const Model& model, const Eigen::Vector3d& q_actuated);

// ---- Skeleton for drawing -------------------------------------------------
// Links are numbered as in the paper (1 = ground ... 10); index k-1 holds link
// k. Each link is rigid: its geometry is fixed in its own frame and a pose
// moves it by link_frames[k-1]. Spherical links are great-circle arcs on
// spheres of radius inner_radius (loop I) and outer_radius (loop II) around
// the common centre; loop III is the planar parallelogram.

struct SkeletonStyle {
  double inner_radius = 0.0;            // 0: 0.26 * min(L1, L2)
  double outer_radius = 0.0;            // 0: 0.36 * min(L1, L2)
  double motor_length = 0.0;            // 0: 0.14 * min(L1, L2)
  double parallelogram_fraction = 0.4;  // side of link 4 as a fraction of L1
  int arc_samples = 24;
};

inline constexpr int kLinkCount = 10;
inline constexpr int kJointCount = 12;

struct JointDefinition {
  std::string name;  // "A", "B", "C", "2-3", ...
  int link_a = 0;    // paper link numbers
  int link_b = 0;
  // The joint as seen from each of its two links, in that link's frame.
  Eigen::Vector3d point_in_a, axis_in_a, point_in_b, axis_in_b;
};

struct LinkShape {
  std::vector<std::vector<Eigen::Vector3d>> polylines;  // in the link's frame
};

struct Skeleton {
  std::array<Eigen::Isometry3d, kLinkCount> link_frames;  // base <- link
  std::array<Eigen::Vector3d, kJointCount> joint_positions;  // base frame, from link_a
  std::array<Eigen::Vector3d, kJointCount> joint_axes;       // base frame, unit
  Eigen::Vector3d endpoint;                                  // D, from link 10
};

std::array<JointDefinition, kJointCount> joint_definitions(const Model& model,
                                                           const SkeletonStyle& style = {});
std::array<LinkShape, kLinkCount> link_shapes(const Model& model, const SkeletonStyle& style = {});
Skeleton skeleton(const Model& model, const Eigen::Vector3d& q_actuated,
                  const SkeletonStyle& style = {});
// Point of link 10 that is the endpoint D, in link 10's frame.
Eigen::Vector3d endpoint_in_link10(const Model& model);

}  // namespace linkscape::parallel12r
