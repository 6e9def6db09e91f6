// Speed against accuracy of the numerical methods used for the 12R mechanism
// (parallel-12r), measured the same way every time: time per evaluation is
// the median over repeated passes on a warm cache, error is measured against
// a reference computed in higher precision from the same equations (11-13).
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
//
// The table is plain data so the command line (linkscape bench) and the
// window can both chart it.
#pragma once

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <functional>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

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
// Singular values of J from a long-double Jacobi SVD (descending).
Eigen::Vector3d reference_singular_values(const Eigen::Matrix3d& J);

// Alternative differentiations of Eqs. 11-13 (steps in rad).
Eigen::Matrix3d jacobian_forward_difference(const parallel12r::Model& model, const Eigen::Vector3d& q_actuated,
                                            double step);
// Complex-step: Im f(q + i h e_k) / h; no subtractive cancellation, exact to
// rounding for any tiny h.
Eigen::Matrix3d jacobian_complex_step(const parallel12r::Model& model, const Eigen::Vector3d& q_actuated,
                                      double step = 1e-30);
// c(J) from the eigenvalues of J^T J (the normal equations): squares c, so
// its relative error grows like u c^2. Kept as the method not to use.
double condition_number_normal_equations(const Eigen::Matrix3d& J);

// Step sizes that balance truncation and rounding for unit-scale angles.
inline constexpr double kForwardDifferenceStep = 1.4901161193847656e-08;  // sqrt(u)
inline constexpr double kCentralDifferenceStep = 6.0554544523933395e-06;  // cbrt(u)

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

struct MethodRow {
  std::string mechanism = "parallel-12r";  // or "pathos2" (core/pathos2_methods.h)
  std::string family;     // "ik", "jacobian", "conditioning", "field"; pathos2: "leg-ik", "fk", ...
  std::string method;     // e.g. "planar", "central-difference", "c<3 volume"
  std::string parameter;  // e.g. "h=6.1e-06", "N=64"; empty if none
  std::size_t samples = 0;   // evaluations whose error was measured
  std::size_t failures = 0;  // evaluations with a non-ok status (not in the error statistics)
  double seconds_per_evaluation = 0;  // median over repeats; per field for "field"
  double error_median = 0, error_p99 = 0, error_max = 0;
  std::string error_unit;  // "rad" or "relative"
};

struct HarnessOptions {
  std::size_t samples = 20000;  // workspace targets (uniform in the reach shell)
  unsigned seed = 20240611;
  int repeats = 5;              // timed passes after one warm-up pass
  bool include_field = true;
  std::vector<int> field_resolutions = {16, 32, 64, 128};  // samples per axis of the cube +-(L1 + L2)
  int field_reference_resolution = 256;                    // reference for the c < 3 volume and extents
  double cond_threshold = 3.0;                             // "well conditioned" means c(J) < this
  parallel12r::IkOptions ik;
  // Optional, for a window: progress(fraction done, stage) is called on the
  // calling thread before each stage; a raised cancel flag stops between
  // stages and the rows measured so far are returned.
  std::function<void(double, const std::string&)> progress;
  const std::atomic<bool>* cancel = nullptr;
};

// Seeded targets uniform in the shell |L1 - L2| < |p| < L1 + L2 (the
// reachable set for full actuator ranges).
std::vector<Eigen::Vector3d> workspace_targets(const parallel12r::Model& model, std::size_t count, unsigned seed);

// Runs every method family; rows are grouped by family, methods in a fixed
// order. Throws std::invalid_argument for bad options.
std::vector<MethodRow> run_method_harness(const parallel12r::Model& model, const HarnessOptions& options = {});

// Indices of the rows of `family` (of `mechanism`, or of any mechanism if
// empty) on the Pareto front of (time, median error): no other row of the
// family is at least as fast and as accurate and strictly better in one. In
// increasing time.
std::vector<std::size_t> pareto_front(const std::vector<MethodRow>& rows, const std::string& family,
                                      const std::string& mechanism = "");

// Shared by every harness (and the bench command): the median wall time of
// `repeats` timed runs of `pass` after one warm-up run, in seconds.
double median_pass_seconds(int repeats, const std::function<void()>& pass);
// The value at `fraction` (0..1) of the sorted errors, NaN if there are none.
double percentile(std::vector<double> errors, double fraction);
// Sets row.samples and the median, 99th percentile and maximum error.
void fill_statistics(MethodRow& row, const std::vector<double>& errors);

}  // namespace linkscape::methods
