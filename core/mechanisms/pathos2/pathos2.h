// PATHOS-II (seed paper 003, Kim and Chung): a 7-DOF parallel haptic device
// with six legs R1-R2-R3-globular between two base plates and two top plates
// held parallel at +-h0 (the grip). Preset name "pathos2".
//
// Conventions (docs/mechanisms/pathos2.md derives and checks each one):
// - Lengths in cm, angles in radians (the preset stores degrees).
// - World W: origin at the centre of the lower base plate, Z toward the upper
//   base plate at Z = l0.
// - End effector E: origin midway between the top plates, z_E along the plate
//   normal, x_E toward the globular joints of legs 1 and 4 (plate_phase = 0).
//   Pose: p_world_E, R_world_E = Rz(rz) Ry(ry) Rx(rx), grip h0.
// - Leg i = 1..6 (index i-1 in arrays), k = (i-1) mod 3. Legs 1-3 stand on
//   the lower plate, legs 4-6 hang from the upper plate (Eq. 1 with L = l0,
//   theta_b1 = pi). Base frame of leg i:
//     B_i = Tz(L) Rx(theta_b1) Rz(base_phase + 120 deg k) Tz(db)
//           Ry(tilt_sign theta_t) Tx(lx)
//   and the leg chain Rz(t1) Tz(l1) Ry(t2) Tz(l2) Rx(t3) Tz(l3) ends at the
//   globular centre; the globular joint is Rz(t4) Ry(t5) Rz(t6). Attachment
//   in E: A_i = Rx(theta_b1) Tz(-h0) Rz(plate_phase + 120 deg k) Tx(lp) Ry(theta_g).
// - Leg branch: Eq. 14's sign of c1y (elbow, +1 or -1); the sign of c1x is
//   always + (this ties the actuator angle to its zero: (t1, t2, t3) and
//   (t1 + pi, -t2, -t3) place the links identically).
// - q_active = (t1 of legs 1..6), rad.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/status.h"

namespace linkscape::pathos2 {

inline constexpr std::string_view kMechanismName = "pathos2";
inline constexpr int kLegCount = 6;

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Accepted lengths (cm): l0, lb, l1, l2, l3, h0 in [kMinLength, kMaxLength],
// |lp|, |db|, |lx| <= kMaxLength. Results do not depend on scale (the
// Jacobian is formed in lengths divided by a power of two near l2 + l3); the
// bounds come from the fields, which store lengths as float.
inline constexpr double kMinLength = 1e-30;
inline constexpr double kMaxLength = 1e30;

struct Model {
  // Table 1 / Table 3 values; lengths cm, angles rad.
  double l0 = 45.0;   // distance between base plates (Table 3; Table 1 has 50)
  double lb = 10.0;   // radius of the active joints R1 on the base plates
  double l1 = 7.0;    // R1 -> R2, along the R1 axis
  double l2 = 14.0;   // R2 -> R3
  double l3 = 6.0;    // R3 -> globular centre
  double lp = 2.0;    // radius of the globular centres on the top plates
  double h0 = 7.0;    // default grip: half the distance between top plates
  double theta_t = 0.5235987755982988;  // tilt of the R1 axis from the plate normal
  double theta_g = 0.0;                 // tilt of the globular joint's axis
  double db = 5.773502691896257;        // Tz(db) of B_i (choice: lb tan theta_t)
  double lx = 11.547005383792516;       // Tx(lx) of B_i (paper: lb / cos theta_t)
  double tilt_sign = 1.0;               // +1: R1 axis leans outward (choice)
  double base_phase = 0.0;              // angle of leg 1's R1 on the base plate
  double plate_phase = 0.0;             // angle of leg 1's globular joint on its plate
  // Eq. 14 sign of c1y per leg (choice: mirror-symmetric assembly).
  std::array<int, kLegCount> branch{+1, +1, +1, -1, -1, -1};
  // Joint limits (rad): globular cone (max t5), |t2|, |t3|. pi = no limit.
  double cone_limit = 3.141592653589793;
  double t2_limit = 3.141592653589793;
  double t3_limit = 3.141592653589793;
  // Link interference (stops.h): the radius of every leg link's capsule and
  // of the grip volume's between the top plates, cm; 0: not checked. Stated
  // by a preset's "stops" block, not parameters.
  double link_radius = 0.0;
  double grip_radius = 0.0;

  // Throws std::invalid_argument for non-finite values, l0, lb, l1, l2, l3,
  // h0 outside [kMinLength, kMaxLength], negative lp, |lp|, |db| or |lx|
  // above kMaxLength, |tilt_sign| != 1, a branch not +-1, a limit outside
  // (0, pi], or a radius negative or above kMaxLength.
  void validate() const;

  // Paper names: l0 lb l1 l2 l3 lp h0 db lx (cm); theta_t theta_g base_phase
  // plate_phase cone_limit t2_limit t3_limit (deg); tilt_sign, branch_1 ..
  // branch_6 (+-1). Missing keys keep the defaults above, except that db and
  // lx default to lb tan(theta_t) and lb / cos(theta_t) of the given values.
  // Throws std::invalid_argument naming an unknown key, then validates.
  static Model from_parameters(const std::map<std::string, double>& parameters);
  static std::vector<std::string> parameter_names();
  // The model as named parameters (inverse of from_parameters).
  std::map<std::string, double> to_parameters() const;
};

// Top-plate pose. h0 is the grip (half the distance between the top plates).
struct Pose {
  Eigen::Vector3d p_world_E = Eigen::Vector3d::Zero();  // cm
  Eigen::Matrix3d R_world_E = Eigen::Matrix3d::Identity();
  double h0 = 7.0;  // cm

  // R = Rz(rz) Ry(ry) Rx(rx), angles rad.
  static Pose from_xyz_rpy(double x, double y, double z, double rx, double ry, double rz,
                           double h0);
  // (rx, ry, rz) with R = Rz Ry Rx, ry in [-pi/2, pi/2].
  Eigen::Vector3d rpy() const;
};

// Table 3: p = (0, 0, l0 / 2), R = Rz(30 deg), grip = model.h0.
Pose home_pose(const Model& model);

// ---- Precomputed geometry (the hot path takes this, not the Model) -------

// Leg frames and attachment directions of a model; build once, share between
// threads. make_geometry validates the model.
struct Geometry {
  Model model;
  std::array<Eigen::Matrix3d, kLegCount> R_world_B;   // base frame of each leg
  std::array<Eigen::Vector3d, kLegCount> p_world_B;   // R1 position, cm
  // Attachment in E = side * (0, 0, -h0) + in_plate: position of the globular
  // centre without the grip term, the grip sign, and the z axis of A_i.
  std::array<Eigen::Vector3d, kLegCount> p_E_attach_plate;
  std::array<double, kLegCount> grip_side;  // -1 lower plate (legs 1-3), +1 upper
  std::array<Eigen::Matrix3d, kLegCount> R_E_A;  // orientation of A_i in E
};
Geometry make_geometry(const Model& model);

// ---- Inverse kinematics ---------------------------------------------------

struct LegSolution {
  Status status = Status::Unreachable;
  double t1 = 0.0, t2 = 0.0, t3 = 0.0;  // R1 (active), R2, R3, rad
  double t4 = 0.0, t5 = 0.0, t6 = 0.0;  // globular joint Rz Ry Rz, t5 in [0, pi]
  Eigen::Vector3d p_B_globular = Eigen::Vector3d::Zero();  // a of Eq. 2, leg frame
  // Leg-only Jacobian determinant da/d(t1,t2,t3) = l2 l3 w sin t2 sin t3 (cm^3).
  double det = 0.0;
  // Eq. 14's c1y = +-sqrt(l3^2 - (c2z - l2)^2) (cm), 0 where |a - l1 z| is
  // out of reach; set by the pose IK, which the reach margin reuses.
  double c1y = 0.0;
  // cos and sin of t1..t3, kept so the Jacobian needs no trigonometry.
  double cos_t1 = 1.0, sin_t1 = 0.0, cos_t2 = 1.0, sin_t2 = 0.0, cos_t3 = 1.0, sin_t3 = 0.0;
};

// A leg counts as singular when |c1x c1y| (det / l2, cm^2) is below this
// fraction of (l2 + l3)^2: one part in 1e10 is far below any pose a user sets
// by hand and well above the rounding of the closed form (~1e-15).
inline constexpr double kLegSingularTolerance = 1e-10;
// Roots (Eq. 14's c1y^2 and c1x^2) that are negative by no more than this
// fraction of (l2 + l3)^2 are rounding, not unreachability (a stretched leg).
inline constexpr double kRootSlack = 1e-12;

// Closed-form leg IK (Eqs. 8-14 corrected): a = Rz(t1)[Tz(l1) + Ry(t2){Tz(l2)
// + Rx(t3) Tz(l3)}] for one branch (sign of c1y). Unreachable if |a - l1 z|
// is outside [|l2 - l3|, l2 + l3] or the c1x root is imaginary; Singular if
// sin t2 or sin t3 is (numerically) zero. Does not check joint limits.
LegSolution leg_inverse(double l1, double l2, double l3, const Eigen::Vector3d& p_B_globular,
                        int branch);
// Forward chain of Eq. 2: globular centre in the leg frame.
Eigen::Vector3d leg_forward(double l1, double l2, double l3, double t1, double t2, double t3);

struct PoseIkResult {
  Status status = Status::Unreachable;  // first failing leg's status, else Ok
  Vector6d q_active = Vector6d::Zero();  // t1 of each leg, rad
  std::array<LegSolution, kLegCount> legs;
  int failing_leg = -1;  // 0-based index of the first leg that is not Ok
  std::array<Eigen::Vector3d, kLegCount> p_world_globular;  // globular centres
};

// Full: every angle. ActiveOnly: t1 (and the cos/sin fields) only, the
// passive angles stay 0; statuses and limit checks are the same (limits are
// tested on cosines). Maps and searches use ActiveOnly. Field: what a field
// sample needs, the cos/sin fields, and t2, t3, t5 only where a limit on
// them is set (for its margin), bit for bit as Full; the other angles stay 0;
// it checks only that the position is finite (the caller checks the rest).
enum class IkDetail { Full, ActiveOnly, Field };

// Full pose IK: every leg's active and passive angles (Eqs. 2-18) and joint
// limits (OutOfLimits). Throws std::invalid_argument on a non-finite pose or a
// non-positive grip.
PoseIkResult inverse(const Geometry& geometry, const Pose& pose, IkDetail detail = IkDetail::Full);
// Where the globular centres sit relative to E at one orientation and grip:
// R_world_E (p_E_attach_plate + grip_side h0 z), per leg (cm). A field's
// samples share them (inverse_field_sample).
using GlobularOffsets = std::array<Eigen::Vector3d, kLegCount>;
GlobularOffsets globular_offsets(const Geometry& geometry, const Pose& pose);
// inverse(geometry, pose, IkDetail::Field) for a pose whose orientation and
// grip gave `offsets`, bit for bit the same.
PoseIkResult inverse_field_sample(const Geometry& geometry, const Pose& pose, const GlobularOffsets& offsets);
PoseIkResult inverse(const Model& model, const Pose& pose);

// ---- Jacobian and conditioning --------------------------------------------

// The 6x6 J counts as singular where kappa, the 1-norm condition number of
// the dimensionless M = J_qdot_from_twist diag(s I, I) (s the power of two
// nearest below l2 + l3), exceeds this: cond_p and cond_o have relative error
// up to ~4 u kappa (measured), so beyond it double cannot give them to 1e-6
// (docs/mechanisms/pathos2.md).
inline constexpr double kMaxJacobianCondition = 1e9;

struct JacobianResult {
  // Ok, Singular (kappa > kMaxJacobianCondition), or the IK's status.
  // J_qdot_from_twist is filled when singular too.
  Status status = Status::Singular;
  // Platform twist [v_world_E (cm/s); omega_world (rad/s)] from actuator rates.
  Matrix6d J_twist_from_qdot = Matrix6d::Zero();
  // Its inverse: stacked rows qdot_i = g_i . v + (rho_i x g_i) . omega.
  Matrix6d J_qdot_from_twist = Matrix6d::Zero();
  double cond_p = 0.0;  // sigma_max / sigma_min of the 3x6 block Jp; +inf if singular
  double cond_o = 0.0;  // same for Jo
};

// J = [Jp; Jo] (Eq. 22) at a solved pose. ik must come from inverse() of the
// same geometry and pose; a non-Ok IK gives that status and infinite cond.
JacobianResult jacobian(const Geometry& geometry, const Pose& pose, const PoseIkResult& ik);
JacobianResult jacobian(const Model& model, const Pose& pose);

// cond of a 3x6 block, sigma_max / sigma_min, at any scale: B^T reduced to a
// triangle by modified Gram-Schmidt, then conditioning.h's triangular closed
// form (relative error ~u c). +inf if rank deficient, zero or not finite.
double block_condition_number(const Eigen::Matrix<double, 3, 6>& block);

// ---- Forward kinematics ---------------------------------------------------

// Nine sensors: (t1, t2, t3) of legs 1, 5 and 6 (rad).
struct NineSensors {
  Eigen::Vector3d leg1 = Eigen::Vector3d::Zero();
  Eigen::Vector3d leg5 = Eigen::Vector3d::Zero();
  Eigen::Vector3d leg6 = Eigen::Vector3d::Zero();
};
NineSensors sensors_of(const PoseIkResult& ik);

struct FkResult {
  Status status = Status::NotConverged;
  Pose pose;
  double residual = 0.0;  // nine-sensor: |P - P1| - sqrt(3) lp (cm); numeric: max |dq| (rad)
  int iterations = 0;     // 0 for the closed form
};

// Closed-form forward kinematics from nine sensors (Eqs. 19-20 corrected:
// r = lp, h = 2 h0; Eq. 20's rank-2 system plus the sphere |P - P1|^2 = 3 lp^2,
// root chosen by the plate's handedness). Unreachable if the sensor data are
// inconsistent with any top plate. Needs lp > 0 and plate_phase/theta_g as
// in the model. Throws on non-finite sensors.
FkResult forward_nine_sensors(const Geometry& geometry, const NineSensors& sensors);
FkResult forward_nine_sensors(const Model& model, const NineSensors& sensors);

// `pose` moved by a small twist: translation by its first three entries (cm),
// rotation about the world axes by the last three (rad, axis-angle).
Pose step_pose(const Pose& pose, const Vector6d& twist);

struct FkOptions {
  int max_iterations = 30;
  double tolerance = 1e-12;      // on max |q(x) - q_active| (rad)
  double damping = 1e-6;         // Levenberg-Marquardt lambda (scaled by |M|^2; fades below a 1e-6 rad residual)
  double max_step_cm = 2.0;      // trust region per iteration, translation
  double max_step_rad = 0.2;     //   and rotation
};

// Numerical forward kinematics from the six active angles and the grip:
// damped Newton on the pose starting at `seed` (tracking use: pass the last
// pose). NotConverged when the iteration stalls, leaves the reachable set
// or runs out of iterations, never a pose whose actuator angles miss the
// tolerance.
FkResult forward_numeric(const Geometry& geometry, const Vector6d& q_active, double h0,
                         const Pose& seed, const FkOptions& options = {});
FkResult forward_numeric(const Model& model, const Vector6d& q_active, double h0,
                         const Pose& seed, const FkOptions& options = {});

// ---- Mobility ---------------------------------------------------------------

struct GraphLink {
  std::string name;
};
struct GraphJoint {
  std::string name;
  int link_a = 0, link_b = 0;  // indices into links
  int dof = 1;
};
struct MechanismGraph {
  std::vector<GraphLink> links;  // links[0] is the ground (both base plates)
  std::vector<GraphJoint> joints;
};
// Links and joints of the device; with lock_grip the two top plates are one
// link and the prismatic grip joint disappears.
MechanismGraph mechanism_graph(bool lock_grip = false);
// Freudenstein-Maki / Grubler: F = 6 (L - J - 1) + sum f_i. Throws if a joint
// names a link that does not exist.
int mobility(const MechanismGraph& graph);

// ---- Skeleton for drawing ---------------------------------------------------

struct LegSkeleton {
  Eigen::Vector3d r1, r2, r3, globular;  // joint positions, world, cm
  Eigen::Vector3d r1_axis, r2_axis, r3_axis;  // unit, world
};
struct Skeleton {
  std::array<std::vector<Eigen::Vector3d>, 2> base_plates;  // polygons through the R1 joints
  std::array<LegSkeleton, kLegCount> legs;
  std::array<std::array<Eigen::Vector3d, 3>, 2> top_plates;  // lower (-h0), upper (+h0) triangles
  Eigen::Vector3d p_world_E = Eigen::Vector3d::Zero();
};
// Throws std::invalid_argument if ik is not Ok (the drawing would be a lie).
Skeleton skeleton(const Geometry& geometry, const Pose& pose, const PoseIkResult& ik);
Skeleton skeleton(const Model& model, const Pose& pose);

}  // namespace linkscape::pathos2
