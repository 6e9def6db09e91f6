// Condition number of a 3x3 Jacobian, c(J) = sigma_max / sigma_min.
// Every form scales J by a power of two first (exact), so the result does not
// depend on J's scale and holds for any finite J; +inf for a singular, zero or
// non-finite J.
#pragma once

#include <Eigen/Core>

namespace linkscape {

// Closed form without iteration: with K the cofactor matrix of J (columns
// c1 x c2, c2 x c0, c0 x c1), sigma_max(K) = sigma_max * sigma_mid, so
//   c(J) = sqrt(lambda_max(J^T J) * lambda_max(K^T K)) / |det J|.
// Only the largest eigenvalue of each symmetric matrix is needed, and the
// trigonometric cubic solution gives that one to full relative accuracy
// (the smaller roots are where it loses digits). Returns +inf if det J == 0.
double condition_number_closed_form(const Eigen::Matrix3d& J);

// Faster closed form with one eigenvalue solve: with lambda_1 = lambda_max(J^T J),
// lambda_2 lambda_3 = det^2 / lambda_1 and lambda_2 + lambda_3 =
// (|K|_F^2 - lambda_2 lambda_3) / lambda_1, a quadratic gives lambda_3.
// Relative error up to ~1e-8 where sigma_mid ~ sigma_min (the quadratic's
// double root), else as the closed form. The field engine uses it: fields
// store c(J) as float (6e-8 relative).
double condition_number_fast(const Eigen::Matrix3d& J);

// The closed form for a lower-triangular L (entries above the diagonal are
// ignored): det L is the product of the diagonal and the cofactor matrix is
// triangular too, so no determinant is formed by cancellation and the
// relative error stays ~u c (where the top two singular values coincide the
// largest eigenvalues are deflated, not taken from the trigonometric root,
// which loses ~sqrt(u) there). The reduction of a wide block B =
// L Q (orthonormal Q) ends here. Unlike the forms above it does not rescale:
// L's entries must be within ~1e+-70 of 1.
double condition_number_lower_triangular(const Eigen::Matrix3d& L);

// Reference: singular values from Eigen's Jacobi SVD.
double condition_number_svd(const Eigen::Matrix3d& J);

}  // namespace linkscape
