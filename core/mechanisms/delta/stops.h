// The Delta's passive-joint limits (docs/mechanisms/delta.md, "Ball-joint
// cones"): the ball joints at each end of the forearm rod, each within a cone
// round an axis fixed in the link it is mounted on. The described Delta
// (assets/mechanisms/delta-described.json) states the same cones; a preset
// states them in its "stops" block (make_mechanism(Preset)).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>

#include "core/mechanisms/delta/delta.h"

namespace linkscape::delta {

// The angles between the forearm and each socket's axis at (q, p), rad: the
// elbow's socket axis turns with the upper arm (elbow_axis from the arm,
// towards -z at q = 0), the wrist's is fixed in the platform (wrist_axis
// below the platform's plane, inwards).
struct BallAngles {
  double elbow = 0.0, wrist = 0.0;
};
BallAngles ball_angles(const Model& model, int leg, double q_leg, const Eigen::Vector3d& p_base_platform);

struct JointStops {
  double margin_deg = std::numeric_limits<double>::infinity();  // nearest cone's half angle minus its angle; < 0 beyond
  int leg = -1;    // 0-based
  int joint = -1;  // 0 elbow, 1 wrist
  double angle_deg = 0.0, limit_deg = 0.0;
  bool hold() const { return margin_deg >= 0; }
};
// The cones' margins at a configuration that closes (q, p); +inf where the
// model states no cone.
JointStops joint_stops(const Model& model, const Eigen::Vector3d& q_actuated, const Eigen::Vector3d& p_base_platform);
// "leg 2 ball joint elbow2 at 63.5 deg beyond its 60.0 deg cone"; "" where they hold.
std::string stop_reason(const JointStops& stops);

}  // namespace linkscape::delta
