// The Delta parallel mechanism with rotary actuators (Clavel's Delta), the
// architecture of the most widely sold haptic devices. Preset name "delta".
//
// Three legs; leg i (0, 1, 2) stands at phi_i = 0, 120, 240 deg about z. Its
// motor on the base turns the upper arm (length La); a parallelogram forearm
// joins the elbow to the platform. The parallelogram keeps the platform's
// orientation fixed, so for the platform position it is exactly a single rod
// of length Lb with spherical joints at both ends, which is how it is modelled.
//
// Conventions (docs/mechanisms/delta.md derives and checks each one):
// - Base frame: origin at the centre of the motor-axis circle, z up; the motor
//   axes lie in the plane z = 0. The platform works below the base (z < 0).
//   Lengths are in the model's length unit (cm for the preset), angles in rad.
// - Leg i: radial unit e_i = (cos phi_i, sin phi_i, 0), motor axis direction
//   t_i = (-sin phi_i, cos phi_i, 0), motor (upper-arm pivot) A_i = R e_i.
// - q_actuated = (q1, q2, q3): q_i = 0 is the upper arm horizontal pointing
//   outward (along e_i); q_i > 0 turns it downward. Elbow
//   B_i = A_i + La (cos q_i e_i - sin q_i z).
// - The platform point p_base_platform is the platform centre; its joints are
//   C_i = p + r e_i, and each leg closes |C_i - B_i| = Lb.
// - Leg branch: elbow out (bit clear) or elbow in (bit set). Elbow out means
//   the elbow lies on the outward side of the line from A_i to the platform
//   joint as seen in the leg's plane, i.e. dF_i/dq_i < 0 (see Jq below); for a
//   platform below the base that is the elbow pointing away from the z axis.
//   The device branch is bit i for leg i: 0 = all elbows out (the default).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/range.h"
#include "core/status.h"

namespace linkscape::delta {

inline constexpr std::string_view kMechanismName = "delta";
inline constexpr int kLegCount = 3;
inline constexpr int kBranchCount = 8;  // 2^kLegCount elbow choices

// Tolerances are relative to Model::size(); a closed form's discriminant
// within kSingularTolerance * size() of zero counts as singular (see docs).
inline constexpr double kSingularTolerance = 1e-12;
// A c(J) beyond this is singular (a described device's Jx likewise).
inline constexpr double kSingularCondition = 1e12;

using Interval = Range;  // core/range.h

struct Model {
  // 3D Hapkit dimensions (docs/mechanisms/delta.md gives the source), cm.
  double R = 9.5;    // radius of the motor-axis circle (base)
  double r = 5.445;  // radius of the platform joints' circle
  double La = 8.0;   // upper arm: motor axis to elbow
  double Lb = 17.0;  // forearm (parallelogram): elbow to platform joint
  std::string length_unit = "cm";
  // Actuator ranges (rad), q1..q3. An angle counts as inside if some
  // q + 2 pi k lies in the range; hi - lo must not exceed 2 pi.
  // The preset's ranges, -45 to 90 deg (a choice; see the docs).
  std::array<Interval, kLegCount> q_limits{{{-0.7853981633974483, 1.5707963267948966},
                                            {-0.7853981633974483, 1.5707963267948966},
                                            {-0.7853981633974483, 1.5707963267948966}}};

  // The forearm's ball-joint cones (stops.h), rad: each socket's axis and
  // half angle; a half angle of pi states no cone. Set by a preset's "stops"
  // block, not parameters.
  double elbow_axis = 0.0, elbow_cone = 3.141592653589793;
  double wrist_axis = 0.0, wrist_cone = 3.141592653589793;
  bool has_cones() const { return elbow_cone < 3.141592653589793 || wrist_cone < 3.141592653589793; }

  // Reach of one leg, La + Lb: the scale every tolerance is relative to.
  double size() const { return La + Lb; }
  // Throws std::invalid_argument for a non-finite or non-positive R, La, Lb,
  // a negative r, a range that is not finite with lo < hi <= lo + 2 pi, a
  // cone's half angle outside (0, pi] or a non-finite axis.
  void validate() const;

  // Parameters "R", "r", "La", "Lb" (length unit), ranges "q1", "q2", "q3"
  // (degrees). Missing keys keep the defaults above. Throws
  // std::invalid_argument naming an unknown key, then validates.
  static Model from_parameters(const std::map<std::string, double>& parameters,
                               const std::map<std::string, Interval>& limits_deg,
                               std::string length_unit);
  static std::vector<std::string> parameter_names() { return {"R", "r", "La", "Lb"}; }
  std::map<std::string, double> to_parameters() const;
};

// ---- Leg geometry -----------------------------------------------------------

// Throw std::invalid_argument unless 0 <= leg < 3.
double leg_angle(int leg);                      // phi_i, rad
Eigen::Vector3d leg_radial(int leg);            // e_i
Eigen::Vector3d leg_motor_axis(int leg);        // t_i
Eigen::Vector3d motor_position(const Model& model, int leg);                   // A_i
Eigen::Vector3d elbow_position(const Model& model, int leg, double q_leg);     // B_i
// Centre of the sphere the platform centre lies on for this leg: B_i - r e_i.
Eigen::Vector3d sphere_centre(const Model& model, int leg, double q_leg);

// Signed reach margin of one leg (length unit): with d_min and d_max the
// smallest and largest distance from the platform joint C_i to the elbow's
// circle (centre A_i, radius La, in the leg's plane),
//   m_i = min(Lb - d_min, d_max - Lb).
// The leg reaches C_i iff m_i >= 0; m_i = 0 is the leg's serial (type I)
// singular surface; for m_i > 0 it is the Euclidean distance of p to that
// surface (wherever C_i is off the motor axis line).
double leg_margin(const Model& model, int leg, const Eigen::Vector3d& p_base_platform);

struct LegSolution {
  Status status = Status::Unreachable;  // Ok, Singular or Unreachable (no range check)
  // Unreachable: the angle of closest approach (elbow towards or away from
  // the platform joint), never NaN.
  double q = 0.0;
  double margin = 0.0;  // leg_margin, length unit
};
// Closed form for one leg and one elbow (tangent half-angle). Throws on a
// bad leg index or a non-finite target.
LegSolution leg_inverse(const Model& model, int leg, const Eigen::Vector3d& p_base_platform, bool elbow_in);

// ---- Inverse kinematics -----------------------------------------------------

enum class IkMethod {
  Closed,  // tangent half-angle per leg
  Newton,  // Newton on each leg's closure equation from a seed
};
std::string_view to_string(IkMethod method);
// Accepts "closed", "newton". Throws std::invalid_argument.
IkMethod parse_ik_method(std::string_view name);

struct IkOptions {
  int branch = 0;  // Closed: elbow choice per leg (bit i set = leg i elbow in)
  // Newton starts here; without it, at home_pose(model). The branch it ends
  // on is reported, not imposed.
  std::optional<Eigen::Vector3d> seed;
  int max_iterations = 50;
  // A solution is accepted when every leg closes to tolerance * size().
  double tolerance = 1e-12;
};

struct IkResult {
  // Unreachable if a leg cannot reach; Singular if a leg is within
  // kSingularTolerance of its serial singularity; NotConverged if the
  // closure misses the tolerance; OutOfLimits if an angle is outside its
  // range; else Ok. A type II (parallel) singularity does not affect IK.
  Status status = Status::Unreachable;
  // rad, in (-pi, pi]. Unreachable: a leg that cannot reach gets its angle
  // of closest approach (see LegSolution), so q is never NaN.
  Eigen::Vector3d q_actuated = Eigen::Vector3d::Zero();
  int branch = 0;          // branch_of(q, target); the requested one for Closed
  double residual = 0.0;   // max_i | |C_i - B_i| - Lb |, length unit
  int iterations = 0;      // 0 for Closed, the largest over the legs for Newton
  std::array<Status, kLegCount> leg_status{};  // Ok, Singular or Unreachable
  IkMethod method = IkMethod::Closed;
};

// Throws std::invalid_argument for a non-finite target or seed, an invalid
// model, a branch outside 0..7 or bad options.
IkResult inverse(const Model& model, const Eigen::Vector3d& p_base_platform, IkMethod method = IkMethod::Closed,
                 const IkOptions& options = {});

// Elbow bits of a configuration that closes at p (bit i set: leg i elbow in).
int branch_of(const Model& model, const Eigen::Vector3d& q_actuated, const Eigen::Vector3d& p_base_platform);

// ---- Forward kinematics -----------------------------------------------------

enum class FkMethod {
  Closed,  // intersection of the three spheres (|p - c_i| = Lb)
  Newton,  // Newton on the three closure equations from a seed
};
std::string_view to_string(FkMethod method);
// Accepts "closed", "newton". Throws std::invalid_argument.
FkMethod parse_fk_method(std::string_view name);

struct FkOptions {
  std::optional<Eigen::Vector3d> seed;  // Newton only; default: the home position
  int max_iterations = 50;
  double tolerance = 1e-12;  // relative to size(), on max_i | |p - c_i| - Lb |
};

struct FkResult {
  // Unreachable: the spheres have no common point (circumradius of their
  // centres > Lb). Singular: the two assembly modes coincide within
  // kSingularTolerance (type II), or the centres are degenerate.
  // NotConverged: Newton missed the tolerance. OutOfLimits: q outside a range.
  Status status = Status::Unreachable;
  Eigen::Vector3d p_base_platform = Eigen::Vector3d::Zero();
  // The other assembly mode: p mirrored in the plane of the sphere centres.
  Eigen::Vector3d p_other_mode = Eigen::Vector3d::Zero();
  // 0: working mode, det Jx < 0 (platform on the far side of the centres'
  // plane, below the base at home); 1: the other one. Closed always gives 0.
  int assembly_mode = 0;
  double residual = 0.0;  // max_i | |p - c_i| - Lb |, length unit
  int iterations = 0;     // 0 for Closed
  FkMethod method = FkMethod::Closed;
};

// Throws std::invalid_argument for non-finite angles or seed, bad options or
// an invalid model. Unreachable results carry p = the centres' circumcentre.
FkResult forward(const Model& model, const Eigen::Vector3d& q_actuated, FkMethod method = FkMethod::Closed,
                 const FkOptions& options = {});

// ---- Jacobian and conditioning ----------------------------------------------
// Closure F_i(p, q) = (|C_i - B_i(q_i)|^2 - Lb^2) / 2 = 0. Differentiating,
// Jx pdot + Jq qdot = 0 with Jx rows s_i^T, s_i = C_i - B_i, and
// Jq = diag(dF_i/dq_i) = diag(La s_i . (sin q_i e_i + cos q_i z)). Hence
// J = dp/dq = -Jx^-1 Jq and det J = -det Jq / det Jx.

struct JacobianResult {
  // Singular on a type I set (a leg margin within tolerance, or Jq_ii = 0) or
  // a type II set (FK discriminant Lb - circumradius within tolerance, or
  // det Jx = 0); then cond is +inf, J is zero if det Jx = 0 and J^-1 is zero
  // if some Jq_ii = 0. jacobian(model, q) without a platform position gives
  // the FK's status (Unreachable or NotConverged), zero matrices, cond = +inf.
  Status status = Status::Singular;
  Eigen::Matrix3d J_task_from_actuated = Eigen::Matrix3d::Zero();  // dp/dq, length unit / rad
  Eigen::Matrix3d J_actuated_from_task = Eigen::Matrix3d::Zero();  // dq/dp = -Jq^-1 Jx, rad / length
  Eigen::Matrix3d Jx = Eigen::Matrix3d::Zero();                    // rows s_i^T, length unit
  Eigen::Vector3d Jq_diagonal = Eigen::Vector3d::Zero();           // length unit^2 / rad
  double det_Jx = 0.0;
  double det_Jq = 0.0;
  double det_J = 0.0;  // -det_Jq / det_Jx (0 if det_Jx = 0)
  double cond = std::numeric_limits<double>::infinity();  // sigma_max / sigma_min of J
};

// At a configuration and the platform position it closes (from forward()).
// Throws std::invalid_argument if (q, p) does not close the legs to 1e-6 size.
JacobianResult jacobian(const Model& model, const Eigen::Vector3d& q_actuated, const Eigen::Vector3d& p_base_platform);
// Same, with p from the closed-form FK (working mode).
JacobianResult jacobian(const Model& model, const Eigen::Vector3d& q_actuated);
// Central differences of the closed-form FK with the given step (rad), for
// checking. Throws std::invalid_argument if an FK evaluation is Unreachable.
Eigen::Matrix3d jacobian_central_difference(const Model& model, const Eigen::Vector3d& q_actuated,
                                            double step = 1e-6);

// ---- Singular sets ------------------------------------------------------------

enum class SingularSet {
  Leg1Serial,  // type I: leg 1's forearm normal to its arm's motion (two elbows merge)
  Leg2Serial,
  Leg3Serial,
  Parallel,  // type II: det Jx = 0, the three forearms coplanar (two assembly modes merge)
};
std::string_view to_string(SingularSet set);

struct SingularityReport {
  SingularSet nearest = SingularSet::Parallel;
  double distance = 0.0;  // distances[nearest], length unit
  // Leg sets: |leg_margin| (Euclidean distance of p to the leg's serial
  // surface). Parallel: |h|, the distance of p to the plane of the three
  // sphere centres (half the gap between the two assembly modes).
  std::array<double, 4> distances{};
  // Dimensionless indices in [0, 1], 0 on the set: per leg |cos| of the angle
  // between the forearm and the elbow's direction of motion; for type II
  // |det| of the unit forearm directions.
  std::array<double, kLegCount> serial_index{};
  double parallel_index = 0.0;
};
// Throws std::invalid_argument as jacobian() does.
SingularityReport nearest_singularity(const Model& model, const Eigen::Vector3d& q_actuated,
                                      const Eigen::Vector3d& p_base_platform);
// With p from the closed-form FK; throws std::invalid_argument if it is Unreachable.
SingularityReport nearest_singularity(const Model& model, const Eigen::Vector3d& q_actuated);

// ---- Reach margin and home ----------------------------------------------------

struct ReachMargin {
  // min(geometric, limits): > 0 inside the branch's workspace within the
  // actuator ranges, 0 on its boundary, < 0 outside; length unit.
  double value = 0.0;
  // min_i leg_margin: the Euclidean distance to the boundary of the
  // workspace without ranges when inside; outside, minus a lower bound of it.
  double geometric = 0.0;
  // min over the legs of La times the angle to the nearer end of the range
  // (the arc the elbow can still travel), negative outside a range. A leg that
  // cannot reach uses its angle of closest approach, which the branch's angle
  // meets on the boundary, so the margin stays continuous.
  double limits = std::numeric_limits<double>::infinity();
};
// Throws std::invalid_argument for a non-finite target or a bad branch.
ReachMargin reach_margin(const Model& model, const Eigen::Vector3d& p_base_platform, int branch = 0);

// Home: the platform on the z axis below the base where the geometric reach
// margin is largest (|C_i' - A_i| = max(La, Lb) in each leg's plane), all
// elbows out. home_position gives p, home_pose its q.
Eigen::Vector3d home_position(const Model& model);
Eigen::Vector3d home_pose(const Model& model);

// ---- Skeleton for drawing -----------------------------------------------------
// Rigid bodies, each with polylines fixed in its own frame and a frame
// (base <- body) per pose: 0 base, 1..3 upper arms, 4..6 forearms (the
// parallelogram as its centre rod), 7 platform.
//   base:      identity;
//   arm i:     origin A_i, rotation Rz(phi_i) Ry(q_i) (x along the arm, y = t_i);
//   forearm i: origin B_i, x along C_i - B_i, y towards t_i;
//   platform:  origin p, identity rotation (the Delta only translates it).

inline constexpr int kBodyCount = 8;
inline constexpr int kJointCount = 9;

enum class JointType { Revolute, Spherical };

struct SkeletonStyle {
  double motor_length = 0.0;  // length of each drawn motor axis; 0: 0.3 * La
  int circle_samples = 48;    // base circle
};

struct JointDefinition {
  std::string name;  // "motor 1", "elbow 1", "platform 1", ...
  JointType type = JointType::Revolute;
  int body_a = 0;  // indices into the bodies above
  int body_b = 0;
  Eigen::Vector3d point_in_a, point_in_b;  // the joint centre in each body's frame
  // In body a's frame. Revolute: the joint axis. Spherical: a drawing hint,
  // the direction of the real parallelogram's bars (parallel to t_i).
  Eigen::Vector3d axis_in_a;
};

struct BodyShape {
  std::string name;
  std::vector<std::vector<Eigen::Vector3d>> polylines;  // in the body's frame
};

struct Skeleton {
  std::array<Eigen::Isometry3d, kBodyCount> X_world_body;     // base <- body
  std::array<Eigen::Vector3d, kJointCount> joint_positions;  // base frame, from body_a
  std::array<Eigen::Vector3d, kJointCount> joint_axes;       // base frame, unit
  Eigen::Vector3d p_base_platform = Eigen::Vector3d::Zero();
};

std::array<JointDefinition, kJointCount> joint_definitions(const Model& model);
std::array<BodyShape, kBodyCount> body_shapes(const Model& model, const SkeletonStyle& style = {});
// Throws std::invalid_argument if (q, p) does not close the legs to 1e-6 size.
Skeleton skeleton(const Model& model, const Eigen::Vector3d& q_actuated, const Eigen::Vector3d& p_base_platform);
// With p from the closed-form FK; throws std::invalid_argument if it is Unreachable.
Skeleton skeleton(const Model& model, const Eigen::Vector3d& q_actuated);

}  // namespace linkscape::delta
