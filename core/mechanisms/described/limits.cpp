// What bounds a described device's assembly beyond its actuators' travel:
// its passive joints' limits and its links' interference
// (docs/described-mechanisms.md, "Joint limits" and "Link interference").
#include <cmath>
#include <cstdio>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/kinematics.h"

namespace linkscape::described {

using internal::kInf;
using internal::kPi;
using Eigen::Vector3d;

namespace {

constexpr double kDeg = 180 / kPi;

// The angle of a limited joint, degrees: a revolute's as the representative
// nearest its range's middle, a ball joint's the angle between its socket's
// and its link's axes.
double joint_angle_deg(const JointLimit& l, const Leg& leg, const LegState& s) {
  if (l.kind == JointLimit::Kind::Cone) {
    const Vector3d link = s.spheres[std::size_t(l.sphere)] * l.link_axis;
    return std::atan2(l.axis.cross(link).norm(), l.axis.dot(link)) * kDeg;
  }
  const double v = s.values(leg.steps[std::size_t(l.step)].variable);
  const double mid = 0.5 * (l.range.lo + l.range.hi);
  return (mid + std::remainder(v - mid, 2 * kPi)) * kDeg;
}

double joint_margin_deg(const JointLimit& l, double angle_deg) {
  if (l.kind == JointLimit::Kind::Cone) return l.half_angle * kDeg - angle_deg;
  return std::min(angle_deg - l.range.lo * kDeg, l.range.hi * kDeg - angle_deg);
}

std::string degrees(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f deg", v);
  return text;
}

// The leg's capsules in the base frame, appended to `out`.
void leg_capsules(const Leg& leg, const LegState& s, const PlatformPose& pose,
                  std::vector<interference::Capsule>& out) {
  thread_local internal::Chain chain;
  bool walked = false;
  for (const LinkCapsule& c : leg.capsules) {
    Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
    if (c.on == LinkCapsule::On::Platform) {
      frame = pose.bodies[std::size_t(leg.platform)];
    } else if (c.on == LinkCapsule::On::Chain) {
      if (!walked) internal::walk_into(leg, s, chain);
      walked = true;
      frame = c.frame < 0 ? leg.base : chain.step_frame[std::size_t(c.frame)];
    }
    out.push_back({frame * c.a, frame * c.b, c.radius});
  }
}

}  // namespace

std::vector<std::vector<interference::Capsule>> Kinematics::capsules(const PlatformPose& pose,
                                                                     const std::vector<LegState>& legs) const {
  std::vector<std::vector<interference::Capsule>> out(model_.legs.size());
  for (std::size_t l = 0; l < model_.legs.size(); ++l) leg_capsules(model_.legs[l], legs[l], pose, out[l]);
  return out;
}

bool Kinematics::leg_limits_hold(int leg, const LegState& state) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  for (const JointLimit& j : l.limits)
    if (joint_margin_deg(j, joint_angle_deg(j, l, state)) < 0) return false;
  return true;
}

Stops Kinematics::stops(const PlatformPose& pose, const std::vector<LegState>& legs) const {
  Stops out;
  const std::size_t n = model_.legs.size();
  if (has_joint_limits_)
    for (std::size_t l = 0; l < n; ++l) {
      const Leg& leg = model_.legs[l];
      for (std::size_t j = 0; j < leg.limits.size(); ++j) {
        const double m = joint_margin_deg(leg.limits[j], joint_angle_deg(leg.limits[j], leg, legs[l]));
        if (m < out.joint_margin_deg) {
          out.joint_margin_deg = m;
          out.joint_leg = int(l);
          out.joint_limit = int(j);
        }
      }
    }
  if (!has_capsules_) return out;
  // Every chain link against the links of the other legs (chain, base and
  // platform): a leg's own links meet at its joints by construction.
  thread_local std::vector<interference::Capsule> world;
  thread_local std::vector<std::size_t> first;  // per leg: its first capsule in `world`
  world.clear();
  first.assign(n + 1, 0);
  for (std::size_t l = 0; l < n; ++l) {
    first[l] = world.size();
    leg_capsules(model_.legs[l], legs[l], pose, world);
  }
  first[n] = world.size();
  for (std::size_t l = 0; l < n; ++l)
    for (std::size_t i = 0; i < model_.legs[l].capsules.size(); ++i) {
      if (model_.legs[l].capsules[i].on != LinkCapsule::On::Chain) continue;
      for (std::size_t m = 0; m < n; ++m) {
        if (m == l) continue;
        for (std::size_t j = 0; j < model_.legs[m].capsules.size(); ++j) {
          // A pair of chain links once, from the lower leg.
          if (model_.legs[m].capsules[j].on == LinkCapsule::On::Chain && m < l) continue;
          const double gap = interference::clearance(world[first[l] + i], world[first[m] + j]);
          if (gap < out.clearance) {
            out.clearance = gap;
            out.pair = {int(l), int(i), int(m), int(j)};
          }
        }
      }
    }
  return out;
}

Stops Kinematics::stops(const PlatformPose& pose, const PoseSolution& solved) const {
  thread_local std::vector<LegState> states;
  states.resize(solved.legs.size());
  for (std::size_t l = 0; l < solved.legs.size(); ++l) states[l] = solved.legs[l].state;
  return stops(pose, states);
}

std::string Kinematics::stop_reason(const Stops& s, const std::vector<LegState>& legs) const {
  if (s.joint_margin_deg < 0) {
    const Leg& leg = model_.legs[std::size_t(s.joint_leg)];
    const JointLimit& l = leg.limits[std::size_t(s.joint_limit)];
    const double angle = joint_angle_deg(l, leg, legs[std::size_t(s.joint_leg)]);
    // No commas: the text may stand in a CSV cell.
    const std::string limit = l.kind == JointLimit::Kind::Cone
                                  ? degrees(l.half_angle * kDeg) + " cone"
                                  : "range " + degrees(l.range.lo * kDeg) + " to " + degrees(l.range.hi * kDeg);
    return leg.label() + " " + l.label + " at " + degrees(angle) + " beyond its " + limit;
  }
  if (s.clearance < 0) {
    const auto name = [&](int leg, int capsule) {
      const Leg& l = model_.legs[std::size_t(leg)];
      return l.label() + " " + l.capsules[std::size_t(capsule)].name;
    };
    char overlap[64];
    std::snprintf(overlap, sizeof overlap, " (overlap %.3g %s)", -s.clearance, model_.length_unit.c_str());
    return name(s.pair[0], s.pair[1]) + " hits " + name(s.pair[2], s.pair[3]) + overlap;
  }
  return "";
}

}  // namespace linkscape::described
