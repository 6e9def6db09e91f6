// Condition number of a 3x3 Jacobian, c(J) = sigma_max / sigma_min.
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

// Reference: singular values from Eigen's Jacobi SVD.
double condition_number_svd(const Eigen::Matrix3d& J);

}  // namespace linkscape
