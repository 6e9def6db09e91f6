#include "core/mechanisms/described/reach.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace linkscape::described {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
using Kind = Step::Kind;
}  // namespace

Range chain_reach(const Leg& leg, std::size_t first) {
  double sum = 0, longest = 0;
  for (std::size_t i = first; i < leg.steps.size(); ++i) {
    const Step& step = leg.steps[i];
    if (step.kind == Kind::Prismatic) return {0.0, kInf};  // IK solves without the travel
    const double length = step.kind == Kind::Fixed ? step.transform.translation().norm() : 0.0;
    sum += length;
    longest = std::max(longest, length);
  }
  return {std::max(0.0, 2 * longest - sum), sum};
}

FirstJoint first_joint(const Leg& leg) {
  FirstJoint f;
  f.frame = leg.base;
  while (f.step < leg.steps.size() && leg.steps[f.step].kind == Kind::Fixed) f.frame = f.frame * leg.steps[f.step++].transform;
  return f;
}

FirstJointReach first_joint_reach(const Leg& leg) {
  FirstJointReach r;
  const FirstJoint first = first_joint(leg);
  const Eigen::Isometry3d& T = first.frame;
  std::size_t i = first.step;
  if (i == leg.steps.size()) return r;
  const Step& joint = leg.steps[i++];
  // The links between the first joint and the next one, in the joint's frame at zero.
  Eigen::Isometry3d links = Eigen::Isometry3d::Identity();
  while (i < leg.steps.size() && leg.steps[i].kind == Kind::Fixed) links = links * leg.steps[i++].transform;
  const Eigen::Vector3d carried = T.linear() * links.translation();  // P - the joint's point, at zero
  r.rest = chain_reach(leg, i);
  if (std::isinf(r.rest.hi)) return r;  // a slide further on: no bound
  r.centre = T.translation();
  switch (joint.kind) {
    case Kind::Revolute: {
      r.motion = FirstJointReach::Motion::Turn;
      r.axis = T.linear() * joint.axis;
      r.height = carried.dot(r.axis);
      r.radius = (carried - r.height * r.axis).norm();
      break;
    }
    case Kind::Spherical:
      r.motion = FirstJointReach::Motion::Ball;
      r.radius = carried.norm();
      break;
    case Kind::Prismatic:
      r.motion = FirstJointReach::Motion::Slide;
      r.axis = T.linear() * joint.axis;
      r.centre += carried;
      break;
    case Kind::Fixed:
      break;
  }
  return r;
}

double FirstJointReach::outside(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d w = p - centre;
  // The nearest and farthest points of P's path from p: the end is within
  // [rest.lo, rest.hi] of one of them, so (triangle rule) at least
  // nearest - rest.hi and rest.lo - farthest from p.
  double nearest = 0, farthest = kInf;
  switch (motion) {
    case Motion::None:
      return -kInf;
    case Motion::Turn: {
      const double along = w.dot(axis), z = along - height;
      const double rho = (w - along * axis).norm();
      nearest = std::hypot(z, rho - radius);
      farthest = std::hypot(z, rho + radius);
      break;
    }
    case Motion::Ball: {
      const double n = w.norm();
      nearest = std::abs(n - radius);
      farthest = n + radius;
      break;
    }
    case Motion::Slide:
      nearest = (w - w.dot(axis) * axis).norm();
      break;
  }
  return std::max(nearest - rest.hi, rest.lo - farthest);
}

}  // namespace linkscape::described
