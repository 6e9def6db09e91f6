#include "core/mechanisms/delta/stops.h"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace linkscape::delta {
namespace {

using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = 180.0 / kPi;

double angle_between(const Vector3d& a, const Vector3d& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

}  // namespace

namespace {

// The sockets' axes as cosine and sine pairs, and the legs' radial units:
// computed once per call of joint_stops rather than per leg.
struct Sockets {
  double elbow_cos, elbow_sin, wrist_cos, wrist_sin;
  explicit Sockets(const Model& m)
      : elbow_cos(std::cos(m.elbow_axis)), elbow_sin(std::sin(m.elbow_axis)), wrist_cos(std::cos(m.wrist_axis)),
        wrist_sin(std::sin(m.wrist_axis)) {}
};

BallAngles angles_at(const Model& m, const Sockets& k, const Vector3d& e, double q, const Vector3d& p) {
  const Vector3d z = Vector3d::UnitZ();
  // The upper arm's frame Rz(phi) Ry(q): x along the arm, z normal to it in the leg's plane.
  const double c = std::cos(q), s = std::sin(q);
  const Vector3d arm = c * e - s * z, normal = s * e + c * z;
  const Vector3d rod = p + (m.r - m.R) * e - m.La * arm;  // C_i - B_i
  BallAngles out;
  out.elbow = angle_between(k.elbow_cos * arm - k.elbow_sin * normal, rod);
  out.wrist = angle_between(rod, -k.wrist_cos * e - k.wrist_sin * z);
  return out;
}

}  // namespace

BallAngles ball_angles(const Model& m, int leg, double q, const Vector3d& p) {
  return angles_at(m, Sockets(m), leg_radial(leg), q, p);
}

JointStops joint_stops(const Model& m, const Vector3d& q, const Vector3d& p) {
  JointStops out;
  if (!m.has_cones()) return out;
  const Sockets sockets(m);
  for (int leg = 0; leg < kLegCount; ++leg) {
    const BallAngles a = angles_at(m, sockets, leg_radial(leg), q(leg), p);
    const double angles[] = {a.elbow, a.wrist}, limits[] = {m.elbow_cone, m.wrist_cone};
    for (int joint = 0; joint < 2; ++joint) {
      if (!(limits[joint] < kPi)) continue;
      const double margin = (limits[joint] - angles[joint]) * kDeg;
      if (margin < out.margin_deg)
        out.margin_deg = margin, out.leg = leg, out.joint = joint, out.angle_deg = angles[joint] * kDeg,
        out.limit_deg = limits[joint] * kDeg;
    }
  }
  return out;
}

std::string stop_reason(const JointStops& s) {
  if (s.hold()) return "";
  char text[96];
  // As the described Delta names its joints (assets/mechanisms/delta-described.json).
  std::snprintf(text, sizeof text, "leg %d ball joint %s%d at %.1f deg beyond its %.1f deg cone", s.leg + 1,
                s.joint == 0 ? "elbow" : "wrist", s.leg + 1, s.angle_deg, s.limit_deg);
  return text;
}

}  // namespace linkscape::delta
