#include "core/conditioning.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>

namespace linkscape {
namespace {

constexpr double kPi = 3.141592653589793;

// The largest eigenvalue of a symmetric 3x3 B (eigenvalues in [-2, 2])
// whose two largest nearly meet, given the smallest: those two are the
// eigenvalues of B on the plane orthogonal to the smallest's eigenvector, a
// 2x2 whose largest, mean + hypot, forms no cancellation. The smallest is
// about 3 below the others, so the cross products below are of order 1.
[[gnu::noinline]] double largest_of_a_close_pair(const Eigen::Matrix3d& B, double smallest) {
  const Eigen::Matrix3d N = B - smallest * Eigen::Matrix3d::Identity();
  // N's null vector, the smallest's eigenvector: the longest cross product of two rows.
  Eigen::Vector3d v = N.row(0).cross(N.row(1));
  for (const Eigen::Vector3d& w : {Eigen::Vector3d(N.row(0).cross(N.row(2))), Eigen::Vector3d(N.row(1).cross(N.row(2)))})
    if (w.squaredNorm() > v.squaredNorm()) v = w;
  v.normalize();
  int least;
  v.cwiseAbs().minCoeff(&least);
  const Eigen::Vector3d e1 = v.cross(Eigen::Vector3d::Unit(least)).normalized(), e2 = v.cross(e1);
  const double c11 = e1.dot(B * e1), c22 = e2.dot(B * e2), c12 = e1.dot(B * e2);
  return 0.5 * (c11 + c22) + std::hypot(0.5 * (c11 - c22), c12);
}

// Largest eigenvalue of a symmetric 3x3 A, within a few u |A|. A = q I + p B
// with eig(B) = 2 cos(phi + 2 pi k / 3), phi = acos(det(B) / 2) / 3 in
// [0, pi / 3]. The largest (k = 0) is flat in det B except where it meets
// the middle one (phi -> pi / 3): there acos's slope turns the ulps of det B
// into ~sqrt(u) (3e-9 in PATHOS-II's c(J) at its centred level poses, where
// two singular values coincide by symmetry). There the smallest (k = 1) is
// the flat one, and well apart from the other two: deflate by it.
double largest_eigenvalue(const Eigen::Matrix3d& A) {
  const double q = A.trace() / 3.0;
  const double off = A(0, 1) * A(0, 1) + A(0, 2) * A(0, 2) + A(1, 2) * A(1, 2);
  const double d0 = A(0, 0) - q, d1 = A(1, 1) - q, d2 = A(2, 2) - q;
  const double p = std::sqrt((d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * off) / 6.0);
  if (p == 0.0) return q;
  const Eigen::Matrix3d B = (A - q * Eigen::Matrix3d::Identity()) / p;
  const double phi = std::acos(std::clamp(B.determinant() / 2.0, -1.0, 1.0)) / 3.0;
  // Beyond 0.02 from pi / 3 the root is within ~0.2 |d det B| / 0.02 ~ 5e-15 of B's.
  if (phi < kPi / 3.0 - 0.02) return q + 2.0 * p * std::cos(phi);
  return q + p * largest_of_a_close_pair(B, 2.0 * std::cos(phi + 2.0 * kPi / 3.0));
}

// The power of two that scales J (exactly) so its largest entry is in
// [1, 2): c(J) does not depend on scale, and the products below (up to the
// sixth power of J's entries) then neither overflow nor underflow. 0 for a
// zero or non-finite J, which has no finite condition number.
inline double unit_scale(const Eigen::Matrix3d& J) {
  const double largest = J.cwiseAbs().maxCoeff();
  if (!(largest > 0.0) || !std::isfinite(largest)) return 0.0;
  // The power of two at or below `largest` is its exponent bits alone (a
  // subnormal `largest` has none: the library call); its reciprocal is exact.
  const double power = std::bit_cast<double>(std::bit_cast<std::uint64_t>(largest) & 0x7ff0000000000000ull);
  return power > 0.0 ? 1.0 / power : std::ldexp(1.0, -std::ilogb(largest));
}

}  // namespace

double condition_number_closed_form(const Eigen::Matrix3d& J_any_scale) {
  const double scale = unit_scale(J_any_scale);
  if (scale == 0.0) return std::numeric_limits<double>::infinity();
  const Eigen::Matrix3d J = J_any_scale * scale;
  Eigen::Matrix3d K;
  K.col(0) = J.col(1).cross(J.col(2));
  K.col(1) = J.col(2).cross(J.col(0));
  K.col(2) = J.col(0).cross(J.col(1));
  const double det = J.col(0).dot(K.col(0));
  if (det == 0.0 || !std::isfinite(det)) return std::numeric_limits<double>::infinity();
  const double s_max2 = largest_eigenvalue(J.transpose() * J);          // sigma_max^2
  const double s_max_mid2 = largest_eigenvalue(K.transpose() * K);      // (sigma_max sigma_mid)^2
  return std::sqrt(s_max2 * s_max_mid2) / std::abs(det);
}

double condition_number_fast(const Eigen::Matrix3d& J_any_scale) {
  const double scale = unit_scale(J_any_scale);
  if (scale == 0.0) return std::numeric_limits<double>::infinity();
  const Eigen::Matrix3d J = J_any_scale * scale;
  const Eigen::Vector3d k0 = J.col(1).cross(J.col(2)), k1 = J.col(2).cross(J.col(0)), k2 = J.col(0).cross(J.col(1));
  const double det = J.col(0).dot(k0);
  if (det == 0.0 || !std::isfinite(det)) return std::numeric_limits<double>::infinity();
  const double l1 = largest_eigenvalue(J.transpose() * J);
  const double product = det * det / l1;                                          // lambda_2 lambda_3
  const double sum = (k0.squaredNorm() + k1.squaredNorm() + k2.squaredNorm() - product) / l1;  // lambda_2 + lambda_3
  const double l2 = 0.5 * (sum + std::sqrt(std::max(0.0, sum * sum - 4.0 * product)));
  return std::sqrt(l1 * l2 / product);  // lambda_1 / lambda_3 with lambda_3 = product / lambda_2
}

double condition_number_lower_triangular(const Eigen::Matrix3d& L) {
  // L = [a 0 0; b c 0; d e f]; its cofactor matrix is [cf -bf be-cd; 0 af -ae; 0 0 ac].
  const double a = L(0, 0), b = L(1, 0), c = L(1, 1), d = L(2, 0), e = L(2, 1), f = L(2, 2);
  const double det = a * c * f;
  if (det == 0.0 || !std::isfinite(det)) return std::numeric_limits<double>::infinity();
  Eigen::Matrix3d S;  // L L^T
  S << a * a, a * b, a * d,  //
      a * b, b * b + c * c, b * d + c * e,  //
      a * d, b * d + c * e, d * d + e * e + f * f;
  const double k02 = b * e - c * d;
  Eigen::Matrix3d T;  // K^T K for the cofactor matrix K above
  T << c * c * f * f, -b * c * f * f, c * f * k02,  //
      -b * c * f * f, b * b * f * f + a * a * f * f, -b * f * k02 - a * a * e * f,  //
      c * f * k02, -b * f * k02 - a * a * e * f, k02 * k02 + a * a * e * e + a * a * c * c;
  return std::sqrt(largest_eigenvalue(S) * largest_eigenvalue(T)) / std::abs(det);
}

double condition_number_svd(const Eigen::Matrix3d& J_any_scale) {
  const double scale = unit_scale(J_any_scale);
  if (scale == 0.0) return std::numeric_limits<double>::infinity();
  const Eigen::Matrix3d J = J_any_scale * scale;
  const Eigen::Vector3d s = J.jacobiSvd().singularValues();
  if (s(2) == 0.0) return std::numeric_limits<double>::infinity();
  return s(0) / s(2);
}

}  // namespace linkscape
