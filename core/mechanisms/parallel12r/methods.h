// Speed against accuracy of the numerical methods of the 12R hand controller
// (parallel-12r), measured as every harness is (core/method_harness.h): error
// against a reference computed in higher precision from the same equations
// (11-13).
//
// Families and what "error" means in each:
//   ik            joint error max_k |q_k - q*_k| (rad), q* the reference
//                 solution of the same branch (Newton on Eqs. 11-13 in long
//                 double, polished from the planar closed form)
//   jacobian      |J - J*|_F / |J*|_F, J* the analytic J in long double
//   conditioning  |c - c*| / c*, c* from a long-double Jacobi SVD of the same J
//   field         relative error of the reachable and c < 3 volumes and of
//                 the c < 3 extents against grid resolution (one row per
//                 resolution; time is per field on all threads)
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <optional>
#include <vector>

#include "core/method_harness.h"
#include "core/mechanisms/parallel12r/parallel12r.h"
#include "core/status.h"

namespace linkscape::methods {

// ---- References in higher precision --------------------------------------

// A solution of forward(q) = target found by Newton's method (with
// backtracking) on Eqs. 11-13 evaluated entirely in long double (x87
// extended, unit roundoff u_ld = 5.4e-20, 2^11 times finer than double): its
// joint error is about u_ld (L1 + L2) / sigma_min(J), 2000 times below what
// any double method can reach at the same point.
struct ReferenceSolution {
  bool converged = false;  // residual <= 1e3 u_ld (L1 + L2 + pi |J|_F)
  std::array<long double, 3> q{};           // alpha, beta, gamma (rad), alpha in (-pi/2, pi/2]
  Eigen::Vector3d q_actuated = Eigen::Vector3d::Zero();  // q rounded to double
  int branch = 0;
  long double residual = 0;                  // |forward(q) - target| in long double, length unit
  int iterations = 0;
};
// Starts from `seed` (rad). Throws std::invalid_argument for non-finite input.
ReferenceSolution reference_inverse(const parallel12r::Model& model, const Eigen::Vector3d& target,
                                    const Eigen::Vector3d& seed);

// Reference solutions of both branches of a target, seeded from the planar
// closed form's candidates (whatever their status) and, for the branch of
// `hint`, from `hint`. A branch is missing where no seed converges.
struct IkReference {
  std::array<std::optional<ReferenceSolution>, 2> branch;
};
IkReference reference_ik(const parallel12r::Model& model, const Eigen::Vector3d& target,
                         const std::optional<Eigen::Vector3d>& hint = std::nullopt);

// Joint error of q against a reference, in rad: max over the three angles of
// the wrapped difference, also allowing the equivalent (alpha + pi, beta + pi,
// gamma + pi). Computed in long double.
double joint_error(const Eigen::Vector3d& q_actuated, const ReferenceSolution& reference);

// The analytic Jacobian evaluated in long double, rounded to double.
Eigen::Matrix3d reference_jacobian(const parallel12r::Model& model, const Eigen::Vector3d& q_actuated);

// Alternative differentiations of Eqs. 11-13 (steps in rad).
Eigen::Matrix3d jacobian_forward_difference(const parallel12r::Model& model, const Eigen::Vector3d& q_actuated,
                                            double step);
// Complex-step: Im f(q + i h e_k) / h; no subtractive cancellation, exact to
// rounding for any tiny h.
Eigen::Matrix3d jacobian_complex_step(const parallel12r::Model& model, const Eigen::Vector3d& q_actuated,
                                      double step = 1e-30);

// The scale B(q) (length unit) of the smallest backward error a solver working
// in double can reach at q, in units of u = 2^-53: the rounding of the
// target (L1 + L2) and of the angles (pi |J|_F); forward() evaluates
// d^2 = cos^2 a + sin^2 a cos^2 t, which does not cancel near the actuator
// plane. An Ok IK solution's joint error is documented as at most
// (residual + u B) / sigma_min(J) to first order.
double backward_error_scale(const parallel12r::Model& model, const Eigen::Vector3d& q_actuated);

// ---- One IK evaluation against the reference ------------------------------

struct IkMeasurement {
  Status status = Status::NotConverged;  // Ok if any returned solution is Ok
  double error = 0;      // largest joint error over the Ok solutions (rad); NaN if none
  double residual = 0;   // largest residual over the Ok solutions, length unit
  int iterations = 0;    // largest iteration count over all solutions
  int solutions_ok = 0;  // Ok solutions returned (0, 1 or 2)
  // Fallback only: how many Ok solutions came from Newton rather than planar.
  int from_newton = 0;
};
// Solves `target` with `method` and compares every Ok solution with the
// reference of its branch (a solution whose branch has no reference counts
// as error NaN and is reported in status NotConverged).
IkMeasurement measure_ik(const parallel12r::Model& model, const Eigen::Vector3d& target, const IkReference& reference,
                         parallel12r::IkMethod method, const parallel12r::IkOptions& options = {});

// ---- The harness -----------------------------------------------------------

// The 12R IK options of a harness's or a sweep's solver limits.
parallel12r::IkOptions ik_options(const SolverLimits& limits);

// Seeded targets uniform in the shell |L1 - L2| < |p| < L1 + L2 (the
// reachable set for full actuator ranges).
std::vector<Eigen::Vector3d> workspace_targets(const parallel12r::Model& model, std::size_t count, unsigned seed);

// Runs every method family (rows with mechanism "parallel-12r"); rows are
// grouped by family, methods in a fixed order; the fields sample the cube
// +-(L1 + L2). Throws std::invalid_argument for bad options.
std::vector<MethodRow> run_method_harness(const parallel12r::Model& model, const HarnessOptions& options = {});

}  // namespace linkscape::methods
