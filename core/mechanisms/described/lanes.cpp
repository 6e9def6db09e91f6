// The lane kernel's constants (lanes.h): what the kernel can express, decided
// once per field, and each point leg's closed form in the base frame.
#include "core/mechanisms/described/lanes.h"

#include <cmath>

#include "core/mechanisms/described/chain.h"

namespace linkscape::described {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

bool point_leg(LegPattern p, bool planar) {
  if (planar) return p == LegPattern::PlanarDyad;
  return p == LegPattern::CrankRod || p == LegPattern::SlideRod || p == LegPattern::Extensible;
}

bool parallel(const Vector3d& a, const Vector3d& b, double& sign) {
  sign = a.dot(b) >= 0 ? 1.0 : -1.0;
  return a.normalized().cross(b.normalized()).norm() <= 1e-12;
}

// Fills `out` (when given) and returns "" where the kernel expresses the
// device, else why not.
std::string build(const Kinematics& kin, const VectorXd& fixed, int branch, LaneDevice* out) {
  const Model& m = kin.model();
  if (!m.extras.empty()) return "extras";
  if (kin.has_capsules()) return "link capsules";
  LaneDevice device;
  device.size = m.size;
  device.branch = branch;
  device.planar = m.planar;
  for (const TaskCoordinate& t : m.task)
    if (t.platform_coordinate >= 0) device.coordinate.push_back(t.platform_coordinate);
  const int driven = int(device.coordinate.size());
  if (m.planar) {
    if (!m.free[0] || !m.free[1] || !(driven == 2 || (driven == 3 && m.free[5])))
      return "a planar task other than x, y (and rz)";
  } else {
    const bool translations = m.free[0] && m.free[1] && m.free[2];
    const bool rotations = m.free[3] && m.free[4] && m.free[5];
    if (!translations || !(driven == 3 || (driven == 6 && rotations)))
      return "a task other than x, y, z (and rx, ry, rz)";
  }
  if (int(m.legs.size()) != driven || int(m.actuators.size()) != driven) return "a leg count other than the task's";
  VectorXd at_origin = fixed;
  at_origin.head(m.planar ? 2 : 3).setZero();
  const PlatformPose pose = kin.pose(at_origin);
  for (std::size_t i = 0; i < m.legs.size(); ++i) {
    const Leg& l = m.legs[i];
    const ClosedFormLeg* form = kin.closed_form(int(i));
    const std::string leg = l.label() + ": ";
    if (!form || !point_leg(form->pattern, m.planar) || l.actuators.size() != 1)
      return leg + (m.planar ? "not a planar dyad" : "not a point leg (crank-rod, slide-rod, extensible)");
    if (kin.passive_rank(int(i)) != (m.planar ? 2 : 5)) return leg + "holds more than one wrench";
    LaneLeg g;
    // A planar dyad is a crank and rod in the plane.
    g.pattern = form->pattern == LegPattern::PlanarDyad ? LegPattern::CrankRod : form->pattern;
    const Isometry3d anchor = kin.anchor(int(i), pose);
    g.anchor_offset = anchor.translation();
    g.end_offset = (anchor * form->tail.inverse()).translation();
    g.leg_base = l.base.translation();
    g.reach = kin.reach(int(i));
    const Eigen::Matrix3d R = form->base.linear();
    const Vector3d a = R * form->actuator_axis;
    g.actuator_centre = form->base.translation();
    g.axis = a;
    const Step& ball = l.steps[std::size_t(form->ball_step)];
    g.universal = form->ball_joints == 2;
    // The ball's link in its own frame: the rod, or an extensible leg's slide.
    Vector3d link = form->rod.translation();
    Eigen::Matrix3d before_ball = R * form->after_actuator.linear();  // a crank's at q = 0
    if (g.pattern == LegPattern::CrankRod) {
      const Vector3d p0 = form->base * form->after_actuator.translation();
      g.origin = g.actuator_centre + a * a.dot(p0 - g.actuator_centre);
      g.rho = (p0 - g.origin).norm();
      g.u = (p0 - g.origin) / g.rho;
      g.v = a.cross(g.u);
    } else if (g.pattern == LegPattern::SlideRod) {
      g.origin = form->base * form->after_actuator.translation();
    } else {
      g.origin = g.actuator_centre;
      g.offset = form->offset;
      link = l.steps[std::size_t(form->actuator_step)].axis;
      before_ball = R;
    }
    g.rod = form->rod.translation().norm();
    if (g.universal) g.universal_axis = before_ball * ball.axis;
    const Actuator& act = m.actuators[std::size_t(l.actuators.front())];
    g.prismatic = act.prismatic;
    g.limited = act.limited;
    g.lo = act.range.lo;
    g.hi = act.range.hi;
    g.mid = 0.5 * (act.range.lo + act.range.hi);
    g.half_width = 0.5 * (act.range.hi - act.range.lo);
    g.cos_mid = std::cos(g.mid);
    g.sin_mid = std::sin(g.mid);
    g.cos_half_width = std::cos(g.half_width);
    g.sin_half_width = std::sin(g.half_width);
    // A turn's travel as the representative nearest its middle (within_travel's w, w +- 2 pi).
    if (g.limited && !g.prismatic && (std::abs(g.mid) > 2 * internal::kPi || g.half_width > internal::kPi))
      return leg + "a revolute travel wider than a turn or centred beyond two";
    auto point_of = [&](int step, LanePoint& p) {
      if (step == -2) p = LanePoint::Anchor;
      else if (step == form->actuator_step) p = LanePoint::Actuator;
      else if (step == form->ball_step || (g.universal && step == form->ball_step + 1)) p = LanePoint::Ball;
      else if (step == form->end_step) p = LanePoint::End;
      else return false;
      return true;
    };
    for (const BranchRule& r : l.rules) {
      LaneLeg::Rule rule;
      rule.triple = r.kind == BranchRule::Kind::Triple;
      // A triple's axis: the actuator's (an extensible leg's turns with its
      // ball), or in a plane any revolute's, the plane's normal whatever the joints.
      if (rule.triple && r.steps[0] != form->actuator_step) {
        if (!m.planar || r.steps[0] < 0) return leg + "a triple rule led by a joint other than the actuator";
        LegState rest;
        rest.values = VectorXd::Zero(l.variables);
        rest.spheres.assign(std::size_t(l.spheres), Eigen::Matrix3d::Identity());
        rule.axis = internal::walk(l, rest).step_axis[std::size_t(r.steps[0])];
        rule.fixed_axis = true;
      }
      if (r.kind == BranchRule::Kind::Angle) return leg + "an angle rule";
      for (int k = 0; k < (rule.triple ? 3 : 2); ++k)
        if (!point_of(r.steps[std::size_t(k)], rule.points[k]))
          return leg + "a branch rule on other joints than the actuator, ball, end and anchor";
      rule.direction = r.direction;
      rule.wanted = r.fixed_sign != 0 ? r.fixed_sign : ((branch >> r.free_index) & 1) ? -1 : 1;
      g.rules.push_back(rule);
    }
    for (const JointLimit& j : l.limits) {
      LaneLeg::Cone cone;
      cone.half_angle_deg = j.half_angle * 180 / internal::kPi;
      const bool spherical_ball = ball.kind == Step::Kind::Spherical && j.step == form->ball_step;
      if (j.kind != JointLimit::Kind::Cone || !(spherical_ball || j.step == form->end_step))
        return leg + "a joint limit other than a ball joint's cone";
      if (spherical_ball) {
        cone.at_ball = true;
        cone.fixed = before_ball * j.axis;
        if (!parallel(j.link_axis, link, cone.along)) return leg + "a cone whose link is not along the rod";
      } else {
        cone.at_ball = false;
        cone.fixed = anchor.linear() * form->tail.linear().transpose() * j.link_axis;
        if (!parallel(form->rod.linear() * j.axis, link, cone.along)) return leg + "a cone whose socket is not along the rod";
      }
      g.cones.push_back(cone);
      device.cones = true;
    }
    device.legs.push_back(g);
  }
  if (out) *out = std::move(device);
  return "";
}

}  // namespace

std::string lanes_refusal(const Kinematics& kin) { return build(kin, kin.model().home, 0, nullptr); }

std::optional<LaneDevice> lane_device(const Kinematics& kin, const VectorXd& fixed, int branch) {
  LaneDevice d;
  if (!build(kin, fixed, branch, &d).empty()) return std::nullopt;
  return d;
}

}  // namespace linkscape::described
