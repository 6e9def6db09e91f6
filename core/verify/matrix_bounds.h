// Certified bounds on the singular values of matrices of any shape, for
// the described devices' certifier (their J is 3x3 or 6x6, their measure
// c(J) or the condition number of J's translational rows). Outward-rounded
// interval arithmetic throughout (interval.h).
#pragma once

#include <Eigen/Core>

#include "core/verify/interval.h"

namespace linkscape::verify {

// Bounds on a double matrix's largest and smallest singular values (of its
// min(rows, cols) ones): each holds for the exact matrix.
struct SpectrumBounds {
  double largest_lower = 0, largest_upper = kInf;
  double smallest_lower = 0, smallest_upper = kInf;
};
SpectrumBounds spectrum_bounds(const Eigen::MatrixXd& A);

// A bound on the spectral norm of every matrix whose entries are at most
// `magnitude`'s in absolute value: the smaller of the Frobenius norm and
// sqrt(|.|_1 |.|_inf).
double spectral_norm_bound(const Eigen::MatrixXd& magnitude);

// A certified bound on the spectral norm of I - A X (A square, X an
// approximate inverse).
double inverse_residual_bound(const Eigen::MatrixXd& A, const Eigen::MatrixXd& X);

}  // namespace linkscape::verify
