// The argument checks and angle wrapping PATHOS-II's kinematics share
// (pathos2.cpp: the model and IK; forward.cpp: FK). Internal to
// core/mechanisms/pathos2.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "core/mechanisms/pathos2/pathos2.h"

namespace linkscape::pathos2::checks {

// An angle in (-pi, pi].
inline double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * std::numbers::pi);  // [-pi, pi]
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

inline void require_finite(double v, std::string_view what) {
  if (!std::isfinite(v)) {
    std::ostringstream msg;
    msg << "pathos2: " << what << " must be finite, got " << v;
    throw std::invalid_argument(msg.str());
  }
}

inline void require_positive(double v, std::string_view what) {
  require_finite(v, what);
  if (v <= 0.0) {
    std::ostringstream msg;
    msg << "pathos2: " << what << " must be > 0, got " << v;
    throw std::invalid_argument(msg.str());
  }
}

// A finite pose, a positive grip and a proper rotation.
inline void require_pose(const Pose& pose) {
  if (!pose.p_world_E.allFinite() || !pose.R_world_E.allFinite())
    throw std::invalid_argument("pathos2: pose must be finite");
  require_positive(pose.h0, "grip h0");
  const double err = (pose.R_world_E.transpose() * pose.R_world_E - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (err > 1e-6 || pose.R_world_E.determinant() < 0.0) {
    std::ostringstream msg;
    msg << "pathos2: R_world_E must be a rotation (|R^T R - I| = " << err << ")";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace linkscape::pathos2::checks
