// Distances between links modelled as capsules (a segment swept by a ball):
// the closest points of two segments in closed form (Ericson, Real-Time
// Collision Detection, 5.1.9), and the clearance of two capsules.
#pragma once

#include <Eigen/Core>

namespace linkscape::interference {

struct SegmentPair {
  double distance = 0.0;
  Eigen::Vector3d on_a = Eigen::Vector3d::Zero(), on_b = Eigen::Vector3d::Zero();  // the closest points
};

// The closest points of segments [a0, a1] and [b0, b1] (either may be a point).
SegmentPair closest_points(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& b0,
                           const Eigen::Vector3d& b1);

struct Capsule {
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  double radius = 0.0;
};

// The gap between two capsules' surfaces: negative where they overlap (by
// how much), zero where they touch.
double clearance(const Capsule& p, const Capsule& q);

}  // namespace linkscape::interference
