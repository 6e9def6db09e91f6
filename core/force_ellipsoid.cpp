#include "core/force_ellipsoid.h"

#include <Eigen/SVD>
#include <limits>
#include <stdexcept>
#include <string>

namespace linkscape::haptics {

namespace {
// J_p counts as rank deficient where its smallest scaled singular value is
// below this times its largest: the longest semi-axis would exceed 1e12
// times the shortest, beyond what double places (haptics.cpp's kRankTolerance).
constexpr double kRankTolerance = 1e-12;
}  // namespace

ForceEllipsoid force_ellipsoid(const Eigen::MatrixXd& J, const DeviceData& data, TorqueRating rating) {
  const Eigen::Index rows = data.position_rows, n = J.cols();
  if (J.rows() < rows || n != Eigen::Index(data.actuators.size()))
    throw std::invalid_argument("force ellipsoid: J is " + std::to_string(J.rows()) + "x" + std::to_string(n) +
                                ", expected " + std::to_string(rows) + " or more rows and one column per actuator (" +
                                std::to_string(data.actuators.size()) + ")");
  // A = J_p W^-1 in metres per motor radian per N m: |A^T F| is the torques' rated fraction.
  Eigen::MatrixXd A = J.topRows(rows);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Rating& r = data.actuators[std::size_t(i)];
    A.col(i) *= data.metres_per_motor_radian(std::size_t(i)) /
                (rating == TorqueRating::Peak ? r.peak_torque_Nm : r.continuous_torque_Nm);
  }
  // |A^T F|^2 = sum_k sigma_k^2 (u_k . F)^2: semi-axis 1 / sigma_k along u_k.
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullU);
  const Eigen::VectorXd sigma = svd.singularValues();  // descending; n < rows leaves the last ones out
  const double largest = sigma.size() ? sigma(0) : 0.0;
  ForceEllipsoid out;
  out.semi_axes_N.resize(rows);
  out.axes.resize(rows, rows);
  for (Eigen::Index k = 0; k < rows; ++k) {
    const Eigen::Index from = rows - 1 - k;  // the smallest sigma gives the largest semi-axis
    const double s = from < sigma.size() ? sigma(from) : 0.0;
    const bool bounded = s > kRankTolerance * largest && s > 0;
    out.semi_axes_N(k) = bounded ? 1.0 / s : std::numeric_limits<double>::infinity();
    if (!bounded) out.status = Status::Singular;
    out.axes.col(k) = svd.matrixU().col(from);
  }
  return out;
}

}  // namespace linkscape::haptics
