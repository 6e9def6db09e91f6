#include "core/mechanisms/described/reach.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace linkscape::described {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
using Kind = Step::Kind;

// The travel of the actuator a step drives, where `travel` is given and
// limits it; null otherwise.
const Range* travel_of(const Step& step, const std::vector<Actuator>* travel) {
  if (!travel || step.actuator < 0) return nullptr;
  const Actuator& a = (*travel)[std::size_t(step.actuator)];
  return a.limited ? &a.range : nullptr;
}

double length_of(const Eigen::Vector3d& v, bool in_plane) { return in_plane ? v.head<2>().norm() : v.norm(); }
}  // namespace

Range chain_reach(const Leg& leg, std::size_t first, const std::vector<Actuator>* travel, bool in_plane) {
  // Each link between its least and its most length: the end is at most
  // the sum of the most, at least any link's least less the others' most.
  std::vector<Range> links;
  for (std::size_t i = first; i < leg.steps.size(); ++i) {
    const Step& step = leg.steps[i];
    if (step.kind == Kind::Prismatic) {
      const Range* r = travel_of(step, travel);
      if (!r) return {0.0, kInf};  // IK solves without the travel
      const double least = r->lo <= 0 && r->hi >= 0 ? 0.0 : std::min(std::abs(r->lo), std::abs(r->hi));
      const double scale = length_of(step.axis, in_plane);  // a planar device turns its steps about z only
      links.push_back({scale * least, scale * std::max(std::abs(r->lo), std::abs(r->hi))});
    } else if (step.kind == Kind::Fixed) {
      const double length = length_of(step.transform.translation(), in_plane);
      links.push_back({length, length});
    }
  }
  double most = 0, least = 0;
  for (const Range& l : links) most += l.hi;
  for (const Range& l : links) least = std::max(least, l.lo - (most - l.hi));
  return {least, most};
}

FirstJoint first_joint(const Leg& leg) {
  FirstJoint f;
  f.frame = leg.base;
  while (f.step < leg.steps.size() && leg.steps[f.step].kind == Kind::Fixed) f.frame = f.frame * leg.steps[f.step++].transform;
  return f;
}

FirstJointReach first_joint_reach(const Leg& leg, const std::vector<Actuator>* travel, bool in_plane) {
  FirstJointReach r;
  const FirstJoint first = first_joint(leg);
  const Eigen::Isometry3d& T = first.frame;
  std::size_t i = first.step;
  if (i == leg.steps.size()) return r;
  const Step& joint = leg.steps[i++];
  // The links between the first joint and the next one, in the joint's frame at zero.
  Eigen::Isometry3d links = Eigen::Isometry3d::Identity();
  while (i < leg.steps.size() && leg.steps[i].kind == Kind::Fixed) links = links * leg.steps[i++].transform;
  Eigen::Vector3d carried = T.linear() * links.translation();  // P - the joint's point, at zero
  r.rest = chain_reach(leg, i, travel, in_plane);
  r.in_plane = in_plane;
  if (in_plane) {
    // A turn about the plane's normal or a slide along the plane, in it.
    const Eigen::Vector3d axis = T.linear() * joint.axis;
    const bool stays = (joint.kind == Kind::Revolute && std::abs(std::abs(axis.z()) - 1) < 1e-12) ||
                       (joint.kind == Kind::Prismatic && std::abs(axis.z()) < 1e-12);
    if (!stays) return r;
    carried.z() = 0;
  }
  if (const Range* values = travel_of(joint, travel)) r.values = *values;
  if (std::isinf(r.rest.hi)) return r;  // a slide further on: no bound
  r.centre = T.translation();
  switch (joint.kind) {
    case Kind::Revolute: {
      r.motion = FirstJointReach::Motion::Turn;
      r.axis = T.linear() * joint.axis;
      r.height = carried.dot(r.axis);
      r.radius = (carried - r.height * r.axis).norm();
      if (r.radius > 0) r.zero = (carried - r.height * r.axis) / r.radius;
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
  Eigen::Vector3d w = p - centre;
  if (in_plane) w.z() = 0;
  // The nearest and farthest points of P's path from p: the end is within
  // [rest.lo, rest.hi] of one of them, so (triangle rule) at least
  // nearest - rest.hi and rest.lo - farthest from p.
  double nearest = 0, farthest = kInf;
  switch (motion) {
    case Motion::None:
      return -kInf;
    case Motion::Turn: {
      const double along = w.dot(axis), z = along - height;
      const Eigen::Vector3d radial = w - along * axis;
      const double rho = radial.norm();
      // P at angle t: its distance from p grows with |t - the angle of p|
      // (modulo a turn); on an arc, the nearest and the farthest angle are
      // those of p and its opposite where the arc holds them, else an end.
      double near_turn = 0, far_turn = kPi;
      if (values.hi - values.lo < 2 * kPi) {
        const double at = std::atan2(radial.dot(axis.cross(zero)), radial.dot(zero));
        const auto apart = [&](double t, double from) { return std::abs(std::remainder(t - from, 2 * kPi)); };
        const auto within = [&](double from) {
          return values.contains(values.lo + std::fmod(std::fmod(from - values.lo, 2 * kPi) + 2 * kPi, 2 * kPi));
        };
        near_turn = within(at) ? 0.0 : std::min(apart(values.lo, at), apart(values.hi, at));
        far_turn = within(at + kPi) ? kPi : std::max(apart(values.lo, at), apart(values.hi, at));
      }
      const auto from_p = [&](double turn) {
        return std::sqrt(std::max(0.0, z * z + rho * rho + radius * radius - 2 * rho * radius * std::cos(turn)));
      };
      nearest = from_p(near_turn);
      farthest = from_p(far_turn);
      break;
    }
    case Motion::Ball: {
      const double n = w.norm();
      nearest = std::abs(n - radius);
      farthest = n + radius;
      break;
    }
    case Motion::Slide: {
      const double along = w.dot(axis);
      const double off = (w - along * axis).norm();
      nearest = std::hypot(off, along - std::clamp(along, values.lo, values.hi));
      if (std::isfinite(values.lo) && std::isfinite(values.hi))
        farthest = std::hypot(off, std::max(along - values.lo, values.hi - along));
      break;
    }
  }
  return std::max(nearest - rest.hi, rest.lo - farthest);
}

}  // namespace linkscape::described
