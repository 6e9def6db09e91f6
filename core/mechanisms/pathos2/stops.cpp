#include "core/mechanisms/pathos2/stops.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace linkscape::pathos2 {
namespace {

using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = 180.0 / kPi;

std::string one_decimal(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", v);
  return text;
}

}  // namespace

bool has_joint_limits(const Model& m) { return m.cone_limit < kPi || m.t2_limit < kPi || m.t3_limit < kPi; }
bool has_capsules(const Model& m) { return m.link_radius > 0.0; }

std::string capsule_name(int index) {
  if (index == kGripCapsule) return "grip";
  if (index < 0 || index > kGripCapsule) throw std::invalid_argument("pathos2: no capsule " + std::to_string(index));
  return "leg " + std::to_string(index / 3 + 1) + " link " + std::to_string(index % 3 + 1);
}

int Stops::leg_at_fault() const {
  if (joint_margin_deg < 0) return joint_leg;
  if (clearance < 0) return pair[0] < kGripCapsule ? pair[0] / 3 : pair[1] / 3;
  return -1;
}

std::vector<interference::Capsule> capsules(const Geometry& g, const Pose& pose, const PoseIkResult& ik) {
  const Model& m = g.model;
  std::vector<interference::Capsule> out;
  out.reserve(kGripCapsule + 1);
  for (int i = 0; i < kLegCount; ++i) {
    const LegSolution& leg = ik.legs[i];
    if (leg.status == Status::Unreachable) throw std::invalid_argument("pathos2: leg " + std::to_string(i + 1) + " does not assemble");
    const Eigen::Matrix3d& R = g.R_world_B[i];
    const Vector3d r1 = g.p_world_B[i], r2 = r1 + m.l1 * R.col(2);
    // Rz(t1) Ry(t2) e_z: the direction of link 2 in the leg frame.
    const Vector3d r3 = r2 + m.l2 * (R * Vector3d(leg.cos_t1 * leg.sin_t2, leg.sin_t1 * leg.sin_t2, leg.cos_t2));
    out.push_back({r1, r2, m.link_radius});
    out.push_back({r2, r3, m.link_radius});
    out.push_back({r3, ik.p_world_globular[i], m.link_radius});
  }
  if (m.grip_radius > 0.0) {
    const Vector3d half = std::max(pose.h0 - m.grip_radius, 0.0) * pose.R_world_E.col(2);
    out.push_back({pose.p_world_E - half, pose.p_world_E + half, m.grip_radius});
  }
  return out;
}

Stops stops(const Geometry& g, const Pose& pose, const PoseIkResult& ik) {
  const Model& m = g.model;
  Stops out;
  const auto limit = [&](int leg, int joint, double angle, double limit) {
    if (!(limit < kPi)) return;
    const double margin = (limit - angle) * kDeg;
    if (margin < out.joint_margin_deg)
      out.joint_margin_deg = margin, out.joint_leg = leg, out.joint = joint, out.joint_angle_deg = angle * kDeg,
      out.joint_limit_deg = limit * kDeg;
  };
  for (int i = 0; i < kLegCount; ++i) {
    const LegSolution& leg = ik.legs[i];
    limit(i, 0, leg.t5, m.cone_limit);
    limit(i, 1, std::abs(leg.t2), m.t2_limit);
    limit(i, 2, std::abs(leg.t3), m.t3_limit);
  }
  if (!has_capsules(m)) return out;
  thread_local std::vector<interference::Capsule> world;
  world = capsules(g, pose, ik);
  // A bounding ball per capsule skips the pairs that cannot be closer than
  // the closest so far: the result is the full search's, pair for pair.
  std::array<Vector3d, kGripCapsule + 1> centre;
  std::array<double, kGripCapsule + 1> bound{};
  for (std::size_t c = 0; c < world.size(); ++c) {
    centre[c] = 0.5 * (world[c].a + world[c].b);
    bound[c] = 0.5 * (world[c].b - world[c].a).norm() + world[c].radius;
  }
  const auto check = [&](int a, int b) {
    if ((centre[a] - centre[b]).norm() - bound[a] - bound[b] >= out.clearance) return;
    const double gap = interference::clearance(world[a], world[b]);
    if (gap < out.clearance) out.clearance = gap, out.pair = {a, b};
  };
  for (int a = 0; a < kGripCapsule; ++a)
    for (int b = 3 * (a / 3 + 1); b < kGripCapsule; ++b)
      if (a % 3 != 0 || b % 3 != 0) check(a, b);  // two R1 links are both fixed to the base
  if (world.size() > std::size_t(kGripCapsule))
    for (int a = 0; a < kGripCapsule; ++a)
      if (a % 3 != 2) check(a, kGripCapsule);  // link 3 ends on a top plate, beside the grip
  return out;
}

std::string stop_reason(const Stops& s) {
  if (s.joint_margin_deg < 0) {
    static const char* const joints[] = {"globular joint", "R2", "R3"};
    const std::string limit = s.joint == 0 ? one_decimal(s.joint_limit_deg) + " deg cone"
                                           : "range +-" + one_decimal(s.joint_limit_deg) + " deg";
    return "leg " + std::to_string(s.joint_leg + 1) + " " + joints[s.joint] + " at " + one_decimal(s.joint_angle_deg) +
           " deg beyond its " + limit;
  }
  if (s.clearance < 0) {
    char overlap[48];
    std::snprintf(overlap, sizeof overlap, " (overlap %.3g cm)", -s.clearance);
    return capsule_name(s.pair[0]) + " hits " + capsule_name(s.pair[1]) + overlap;
  }
  return "";
}

}  // namespace linkscape::pathos2
