// Speed against accuracy of the PATHOS-II methods (pathos2.h beside this
// file), measured as every harness is (core/method_harness.h): time per
// evaluation is the median over repeated passes on a warm cache, error is
// measured against a reference computed in long double (x87 extended,
// u_ld = 5.4e-20) from the same equations, treating the model's precomputed
// leg frames (Geometry) as exact.
//
// Families (MethodRow::mechanism = "pathos2") and what "error" means:
//   leg-ik        joint error max_k |t_k - t*_k| (rad) of (t1, t2, t3) against
//                 a long-double Newton polish of the leg chain (Eq. 3)
//   fk            pose error max(|p - p*| / (l2 + l3), angle(R^T R*)) against
//                 the long-double FK of the same (double) sensor values
//   jacobian      |J - J*|_F / |J*|_F, J* = M*^-1 built in long double
//   conditioning  max over Jp, Jo of |c - c*| / c*, c* from a long-double
//                 Jacobi SVD of the same double blocks
// Units: cm, rad.
#pragma once

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <functional>
#include <cstddef>
#include <string>
#include <vector>

#include "core/method_harness.h"
#include "core/mechanisms/pathos2/pathos2.h"
#include "core/status.h"

namespace linkscape::pathos2_methods {

using pathos2::Geometry;
using pathos2::Matrix6d;
using pathos2::Pose;
using pathos2::Vector6d;

// ---- Leg IK ------------------------------------------------------------------

// Leg Jacobian da/d(t1, t2, t3) of Eq. 3 (leg frame, cm/rad).
Eigen::Matrix3d leg_jacobian(double l1, double l2, double l3, const Eigen::Vector3d& t);

struct LegNewtonOptions {
  int max_iterations = 50;
  double tolerance = 1e-12;  // on |a(t) - a| / (l1 + l2 + l3)
};
struct LegNewtonResult {
  Status status = Status::NotConverged;  // Ok, NotConverged (incl. the other branch), Singular
  Eigen::Vector3d t = Eigen::Vector3d::Zero();  // rad, normalised so that c1x >= 0 (as leg_inverse)
  double residual = 0;  // |a(t) - a|, cm
  int iterations = 0;
};
// Newton's method with backtracking on (t1, t2, t3) from `seed`. A solution
// on the other branch (sign of c1y) than `branch` is reported NotConverged.
LegNewtonResult leg_inverse_newton(double l1, double l2, double l3, const Eigen::Vector3d& a, int branch,
                                   const Eigen::Vector3d& seed, const LegNewtonOptions& options = {});

struct LegReference {
  bool converged = false;
  std::array<long double, 3> t{};  // rad, c1x >= 0
  long double residual = 0;        // cm
  int iterations = 0;
};
// Long-double Newton polish of the leg chain from `seed` (rad).
LegReference reference_leg_inverse(double l1, double l2, double l3, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& seed);
// max_k |t_k - t*_k| (wrapped), also allowing (t1 + pi, -t2, -t3).
double leg_joint_error(const Eigen::Vector3d& t, const LegReference& reference);

// ---- Forward kinematics --------------------------------------------------------

struct PoseReference {
  bool converged = false;
  Eigen::Matrix<long double, 3, 1> p = Eigen::Matrix<long double, 3, 1>::Zero();
  Eigen::Matrix<long double, 3, 3> R = Eigen::Matrix<long double, 3, 3>::Identity();
  long double residual = 0;
  int iterations = 0;
};
// The nine-sensor closed form evaluated in long double (same construction as
// pathos2::forward_nine_sensors).
PoseReference reference_nine_sensors(const Geometry& geometry, const pathos2::NineSensors& sensors);
// Newton in long double on the pose (residual q_active(pose) in long double,
// double Jacobian: iterative refinement) from `seed`.
PoseReference reference_forward(const Geometry& geometry, const Vector6d& q_active, double h0, const Pose& seed);
// max(|p - p*| / length_scale, angle of R^T R*).
double pose_error(const Pose& pose, const PoseReference& reference, double length_scale);

// ---- Jacobian and conditioning ----------------------------------------------------

// J = M^-1 in long double from reference leg angles; false if singular.
bool reference_jacobian(const Geometry& geometry, const Pose& pose, Matrix6d& J);
// J from finite differences of the pose IK (ActiveOnly) along twists of size
// `step` (cm and rad), inverted; false if any IK fails or M is singular.
bool jacobian_finite_difference(const Geometry& geometry, const Pose& pose, double step, bool central, Matrix6d& J);
// (cond Jp, cond Jo) from a double Jacobi SVD, and from a long-double one.
std::array<double, 2> condition_numbers_svd(const Matrix6d& J);
std::array<double, 2> reference_condition_numbers(const Matrix6d& J);

// ---- The harness ---------------------------------------------------------------------

struct HarnessOptions {
  std::size_t samples = 20000;  // poses (6 legs each for leg-ik)
  unsigned seed = 20240611;
  int repeats = 5;
  double radius_cm = 6.0;        // poses: home + uniform ball of this radius
  double max_rotation_rad = 0.35;  //   and a rotation of at most this angle
  // As methods::HarnessOptions: progress before each stage, cancel between stages.
  std::function<void(double, const std::string&)> progress;
  const std::atomic<bool>* cancel = nullptr;
};

// Seeded poses around home_pose whose IK is Ok (all legs).
std::vector<Pose> workspace_poses(const Geometry& geometry, std::size_t count, unsigned seed,
                                  double radius_cm = 6.0, double max_rotation_rad = 0.35);

// Rows with mechanism "pathos2": leg-ik closed-form, newton (home seed);
// fk nine-sensor, numeric (home seed), numeric-near (0.5 cm / 2 deg seed);
// jacobian analytic, central-difference, forward-difference; conditioning
// closed-form, svd. Throws std::invalid_argument for bad options.
std::vector<methods::MethodRow> run_pathos2_harness(const pathos2::Model& model, const HarnessOptions& options = {});

}  // namespace linkscape::pathos2_methods
