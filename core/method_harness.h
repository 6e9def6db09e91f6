// Speed against accuracy of numerical methods, measured the same way for every
// device: time per evaluation is the median over repeated passes on a warm
// cache, error is measured against a reference the device computes in higher
// precision or builds from its own forward kinematics (Mechanism::measure_methods,
// Mechanism::stability_sweeps). Each device's harness documents its families
// and what "error" means in each (core/mechanisms/<name>/methods.h; the
// default one: core/generic_methods.cpp).
//
// The table is plain data so the command line (linkscape bench) and the
// window can both chart it.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace linkscape::methods {

// ---- What several devices' harnesses share ----------------------------------

// Singular values of a 3x3 J from a long-double Jacobi SVD (descending).
Eigen::Vector3d reference_singular_values(const Eigen::Matrix3d& J);
// c(J) from the eigenvalues of J^T J (the normal equations): squares c, so
// its relative error grows like u c^2. Kept as the method not to use.
double condition_number_normal_equations(const Eigen::Matrix3d& J);

// Step sizes that balance truncation and rounding for unit-scale angles.
inline constexpr double kForwardDifferenceStep = 1.4901161193847656e-08;  // sqrt(u)
inline constexpr double kCentralDifferenceStep = 6.0554544523933395e-06;  // cbrt(u)

// ---- The table ---------------------------------------------------------------

struct MethodRow {
  std::string mechanism;  // the device's preset mechanism name
  std::string family;     // e.g. "ik", "fk", "jacobian", "conditioning", "field", "leg-ik"
  std::string method;     // e.g. "planar", "central-difference", "c<3 volume"
  std::string parameter;  // e.g. "h=6.1e-06", "N=64"; empty if none
  std::size_t samples = 0;   // evaluations whose error was measured
  std::size_t failures = 0;  // evaluations with a non-ok status (not in the error statistics)
  double seconds_per_evaluation = 0;  // median over repeats; per field for "field"
  double error_median = 0, error_p99 = 0, error_max = 0;
  std::string error_unit;  // "rad", a length unit (slides' IK), "rad or cm" (both), or "relative"
};

// When an iterative IK method stops (the defaults of every device's IK).
struct SolverLimits {
  double tolerance = 1e-10;  // accept when the residual <= tolerance * the device's size
  int max_iterations = 100;
};

struct HarnessOptions {
  std::size_t samples = 20000;  // workspace targets or poses
  unsigned seed = 20240611;
  int repeats = 5;              // timed passes after one warm-up pass
  // Devices that time their fields: the field family, at these samples per
  // axis of the device's box against a reference resolution.
  bool include_field = true;
  std::vector<int> field_resolutions = {16, 32, 64, 128};
  int field_reference_resolution = 256;  // reference for the well-conditioned volume and extents
  double cond_threshold = 3.0;           // "well conditioned" means the main measure < this
  SolverLimits ik;
  // Optional, for a window: progress(fraction done, stage) is called on the
  // calling thread before each stage; a raised cancel flag stops between
  // stages and the rows measured so far are returned.
  std::function<void(double, const std::string&)> progress;
  const std::atomic<bool>* cancel = nullptr;
};

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
