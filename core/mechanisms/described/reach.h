// Bounds on where a leg's end can be, decided before any solver runs: from
// its base (the triangle rule over its links) and about its first joint
// (the point that joint carries moves on a circle, a sphere or a line, and
// the rest of the chain reaches within a shell of that point).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "core/mechanisms/described/model.h"
#include "core/range.h"

namespace linkscape::described {

// The distance from the end of the steps before `first` to the leg's end:
// at least the longest link less all the others, at most their sum,
// whatever the joints do (unbounded with a slide). Given `travel` (the
// model's actuators), the actuated slides within their travel instead: a
// link of a length between the least and the most the travel gives.
// `in_plane`: a planar device's distances, in its plane.
Range chain_reach(const Leg& leg, std::size_t first = 0, const std::vector<Actuator>* travel = nullptr,
                  bool in_plane = false);

// The leg's end about its first joint: the point P the joint carries (the
// start of the next joint's links) moves on a circle about a revolute's
// axis, a sphere about a spherical joint or a line along a slide, and the
// rest of the chain keeps the end within `rest` of P.
struct FirstJointReach {
  enum class Motion { None, Turn, Ball, Slide };
  Motion motion = Motion::None;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the joint's point (Slide: a point of P's line)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // Turn, Slide: unit
  double radius = 0;  // Turn: the circle's; Ball: the sphere's
  double height = 0;  // Turn: the circle's plane along the axis from `centre`
  Eigen::Vector3d zero = Eigen::Vector3d::UnitX();  // Turn: P's direction from the axis at the joint's zero
  // The joint's values P takes (an actuator held within its travel: an arc,
  // a segment); unbounded otherwise.
  Range values{-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Range rest;
  bool in_plane = false;  // a planar device's: distances in its plane (a turn's axis its normal)
  // How far the end at p is outside the bound (> 0: the leg cannot reach p
  // and misses it by at least that much); -inf with no bound.
  double outside(const Eigen::Vector3d& p) const;
};

// A leg's first joint (its first step that is not fixed; `step` ==
// leg.steps.size() where it has none) and the frame it moves in, which no
// joint of the leg moves.
struct FirstJoint {
  std::size_t step = 0;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
};
FirstJoint first_joint(const Leg& leg);

// Motion None for a leg without joints or with a slide after its first joint.
// Given `travel` (the model's actuators), an actuated first joint within its
// travel, and the rest's slides too (chain_reach). `in_plane`: a planar
// device's, in its plane (Motion None where the joint leaves it).
FirstJointReach first_joint_reach(const Leg& leg, const std::vector<Actuator>* travel = nullptr,
                                  bool in_plane = false);

}  // namespace linkscape::described
