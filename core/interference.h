// Distances between links modelled as capsules (a segment swept by a ball):
// the closest points of two segments in closed form (Ericson, Real-Time
// Collision Detection, 5.1.9), and the clearance of two capsules.
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <vector>

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

// One link of a device as a capsule at a pose (base frame).
struct Link {
  Capsule capsule;
  std::string name;   // "leg 1 thigh"
  int leg = 0;        // links of one leg are not checked against each other: they meet at its joints
  bool chain = true;  // a leg's moving link; else fixed to the base or to the platform
};

// A device's links at one pose and the pair that sets its clearance: what
// the view draws (Mechanism::link_capsules).
struct LinkCapsules {
  std::vector<Link> links;
  std::array<int, 2> closest{-1, -1};  // indices into links; -1 where no pair is checked
  SegmentPair axes;                    // the closest points of that pair's segments
  double clearance = std::numeric_limits<double>::infinity();  // that pair's gap (length unit); < 0: they overlap
  bool has_pair() const { return closest[0] >= 0; }
  // The closest points of the pair's surfaces, from links[closest[0]] to
  // links[closest[1]]: the segment the gap spans (the two cross where the
  // links overlap). Throws std::logic_error where there is no pair.
  std::array<Eigen::Vector3d, 2> gap() const;
};

// Makes links a and b the closest pair: their closest points and clearance.
// Throws std::invalid_argument for an index outside links or a == b.
void set_closest(LinkCapsules& capsules, int a, int b);

}  // namespace linkscape::interference
