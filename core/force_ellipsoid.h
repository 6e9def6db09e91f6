// The force ellipsoid of a device at a pose, as the view draws it: the
// forces F (N) at the driven point whose actuator torques tau = J_p^T F
// satisfy sum_i (tau_i / tau_max_i)^2 <= 1, the image of the unit ball of
// rated-torque fractions under the force map M = (W^-1 J_p^T)^+ (that is
// J_p^-T W where the actuators are as many as J_p's rows), W = diag(tau_max).
// J_p and the ratings are those of haptics::measures.
//
// Its semi-axes are M's singular values. It lies inside the polytope of
// forces with every |tau_i| <= tau_max_i, whose inscribed ball has radius
// force_iso and whose farthest vertex is at force_max, so
//   smallest semi-axis <= force_iso <= sqrt(n) * smallest semi-axis,
//   largest semi-axis <= force_max,
// with n actuators; with as many actuators as rows it is that polytope's
// largest inscribed ellipsoid and touches each of its faces.
#pragma once

#include <Eigen/Core>

#include "core/haptics.h"
#include "core/status.h"

namespace linkscape::haptics {

struct ForceEllipsoid {
  Status status = Status::Ok;   // Singular where J_p loses rank: a semi-axis is unbounded (+inf)
  Eigen::VectorXd semi_axes_N;  // largest first, one per position row (3; 2 in a planar device's plane)
  Eigen::MatrixXd axes;         // rows x rows, column k the unit direction of semi-axis k (base frame)
};

// Throws std::invalid_argument for a J whose size does not match data (as measures()).
ForceEllipsoid force_ellipsoid(const Eigen::MatrixXd& J, const DeviceData& data, TorqueRating rating);

}  // namespace linkscape::haptics
