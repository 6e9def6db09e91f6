// The lane kernel's constants (lanes.h): what the kernel can express, decided
// once per field, and each point leg's closed form in the base frame.
#include "core/mechanisms/described/lanes.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

#include "core/grid_mirror.h"
#include "core/mechanisms/described/chain.h"

namespace linkscape::described {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

bool point_leg(LegPattern p, bool planar) {
  if (planar) return p == LegPattern::PlanarDyad || p == LegPattern::SlideRod || p == LegPattern::Extensible;
  return p == LegPattern::CrankRod || p == LegPattern::SlideRod || p == LegPattern::Extensible ||
         p == LegPattern::CrankParallelogram || p == LegPattern::ThreeRevolute;
}

// A crank-parallelogram's constants (closed_form.h) in its actuator's frame,
// its links from the chain at rest; "" or why the lanes cannot serve it.
std::string parallelogram(const Leg& l, const ClosedFormLeg& form, const Eigen::Isometry3d& anchor, LaneLeg& g) {
  const ClosedFormLeg::Parallelogram& P = form.parallelogram;
  const Isometry3d N = form.base.inverse() * anchor * form.tail.inverse();
  const Vector3d A = form.actuator_axis;
  if (!((N.linear() * A - A).norm() <= 1e-12)) return "the end turned off the motor axis";
  g.parallelogram = true;
  g.frame = form.base.linear();
  g.end_local = g.frame.transpose() * (g.end_offset - g.actuator_centre);
  g.local_axis = A;
  g.across = P.across;
  g.thigh = P.thigh;
  LegState rest;
  rest.values = VectorXd::Zero(l.variables);
  rest.spheres.assign(std::size_t(l.spheres), Eigen::Matrix3d::Identity());
  const internal::Chain c = internal::walk(l, rest);
  const auto at = [&](int step) { return g.frame.transpose() * (c.step_centre[std::size_t(step)] - g.actuator_centre); };
  g.knee_rest = at(P.knee_step);
  g.to_upper = at(P.upper_step) - at(P.knee_step);
  g.side_link = at(P.lower_step) - at(P.upper_step);
  g.to_grip = at(form.end_step) - at(P.lower_step);
  g.upper_axis = l.steps[std::size_t(P.upper_step)].axis;
  g.knee_sign = P.knee_sign;
  g.lower_sign = P.lower_sign;
  g.grip_sign = P.grip_sign;
  g.height = P.height;
  g.side = P.side;
  g.bar = P.bar;
  g.cos_phase = std::cos(P.phase);
  g.sin_phase = std::sin(P.phase);
  g.cos_thigh_phase = std::cos(P.thigh_phase);
  g.sin_thigh_phase = std::sin(P.thigh_phase);
  const Vector3d n = N.linear() * P.across;  // closed_form.cpp's level: the turn of n about A
  const Vector3d nn = n - A * A.dot(n);
  const double level = std::atan2(A.dot(P.across.cross(nn)), P.across.dot(nn));
  g.cos_level = std::cos(level);
  g.sin_level = std::sin(level);
  return "";
}

// A three-revolute leg's constants (closed_form.cpp's three_revolute) in its
// actuator's frame; "" or why the lanes cannot serve it.
std::string three_revolute(const Leg& l, const ClosedFormLeg& form, double size, LaneLeg& g) {
  g.three = true;
  g.frame = form.base.linear();
  g.origin = form.base * form.after_actuator.translation();
  g.local_axis = form.actuator_axis;
  g.second_axis = l.steps[std::size_t(form.second_step)].axis;
  g.third_axis = l.steps[std::size_t(form.third_step)].axis;
  g.second_link = form.second_link;
  g.third_link = form.third_link;
  const Vector3d &a3 = g.third_axis, &t2 = g.second_link, &t3 = g.third_link;
  const double A = t2.dot(a3) * a3.dot(t3), sum = t2.squaredNorm() + t3.squaredNorm();
  g.harmonic_b = t2.dot(t3) - A;
  g.harmonic_c = t2.dot(a3.cross(t3));
  g.harmonic_k0 = 0.5 * sum + A;
  const double R = std::hypot(g.harmonic_b, g.harmonic_c);
  g.nearest = std::sqrt(std::max(0.0, sum + 2 * (A - R)));
  g.farthest = std::sqrt(sum + 2 * (A + R));
  // The closed form's own degenerate designs (its numerical fallback).
  if (!(R > 1e-9 * size * size)) return "a third joint that does not change the leg's reach";
  const double c = g.local_axis.dot(g.second_axis);
  if (!(1 - c * c > 1e-6)) return "a second joint's axis along the actuator's";
  if (!l.limits.empty()) return "a joint limit on a three-revolute leg";
  for (const BranchRule& r : l.rules)
    if (r.kind != BranchRule::Kind::Angle || (r.steps[0] != form.second_step && r.steps[0] != form.third_step))
      return "a branch rule on a three-revolute leg other than an angle rule on its second or third joint";
  return "";
}

// The leg's link capsules on the bodies the lanes place, appended to
// `device.capsules`; "" or the capsule they cannot place.
std::string capsules(const Leg& l, int leg, const ClosedFormLeg& form, const PlatformPose& pose, LaneDevice& device) {
  const Eigen::Matrix3d R = form.base.linear();
  for (const LinkCapsule& k : l.capsules) {
    LaneCapsule c;
    c.leg = leg;
    c.radius = k.radius;
    c.reach = 0.5 * (k.b - k.a).norm() + k.radius;
    if (device.capsules.size() == kMaxLaneCapsules) return "more than " + std::to_string(kMaxLaneCapsules) + " link capsules";
    c.a = R * k.a;
    c.b = R * k.b;
    if ((k.b - k.a).norm() <= 1e-9 * device.size) return "a link capsule of no length (" + k.name + ")";
    if (k.on == LinkCapsule::On::Base) {
      c.body = LaneBody::Fixed;
      c.a = k.a;
      c.b = k.b;
    } else if (k.on == LinkCapsule::On::Platform) {
      c.body = LaneBody::Platform;
      c.a = pose.bodies[std::size_t(l.platform)] * k.a;
      c.b = pose.bodies[std::size_t(l.platform)] * k.b;
    } else if (k.frame < 0) {
      c.body = LaneBody::Fixed;
      c.a = l.base * k.a;
      c.b = l.base * k.b;
    } else if (k.frame == form.actuator_step && (form.pattern == LegPattern::PlanarDyad || form.pattern == LegPattern::CrankParallelogram)) {
      c.body = LaneBody::Crank;
    } else if (form.pattern == LegPattern::CrankParallelogram && k.frame == form.parallelogram.knee_step) {
      c.body = LaneBody::Knee;
    } else if (form.pattern == LegPattern::CrankParallelogram && k.frame == form.parallelogram.upper_step) {
      c.body = LaneBody::Shin;
    } else if (form.pattern == LegPattern::CrankParallelogram && k.frame == form.parallelogram.lower_step) {
      c.body = LaneBody::Ankle;
    } else {
      return "a link capsule on a body the lanes do not place (" + k.name + ")";
    }
    device.capsules.push_back(c);
  }
  return "";
}

// The pairs Kinematics::stops checks: every chain link against the links of
// the other legs, a pair of chain links once.
void capsule_pairs(const Model& m, LaneDevice& device) {
  std::vector<int> first(m.legs.size() + 1, 0);
  for (std::size_t l = 0; l < m.legs.size(); ++l) first[l + 1] = first[l] + int(m.legs[l].capsules.size());
  for (std::size_t l = 0; l < m.legs.size(); ++l)
    for (std::size_t i = 0; i < m.legs[l].capsules.size(); ++i) {
      if (m.legs[l].capsules[i].on != LinkCapsule::On::Chain) continue;
      for (std::size_t o = 0; o < m.legs.size(); ++o) {
        if (o == l) continue;
        for (std::size_t j = 0; j < m.legs[o].capsules.size(); ++j) {
          if (m.legs[o].capsules[j].on == LinkCapsule::On::Chain && o < l) continue;
          device.pairs.push_back({first[l] + int(i), first[o] + int(j)});
        }
      }
    }
}

bool parallel(const Vector3d& a, const Vector3d& b, double& sign) {
  sign = a.dot(b) >= 0 ? 1.0 : -1.0;
  return a.normalized().cross(b.normalized()).norm() <= 1e-12;
}

// The index of `value` in `sizes`, added where new; -1 past kMaxLaneSizes.
int size_index(std::vector<double>& sizes, double value) {
  for (std::size_t i = 0; i < sizes.size(); ++i)
    if (sizes[i] == value) return int(i);
  if (sizes.size() == kMaxLaneSizes) return -1;
  sizes.push_back(value);
  return int(sizes.size()) - 1;
}

// ---- The mirror in y -----------------------------------------------------------
// Reflecting y (S = diag(1, -1, 1)) maps a point leg onto its partner when
// every constant reflects: points and the directions fixed on bodies (a
// slide's axis, cones' sockets) as S x; a crank's axis as sigma S a: -S a
// (a turn's axis: the partner turns through the same angles, over the same
// travel, its circle's u, v as S u, S v) or S a (the angles negated, the
// travel too, v as -S v; the 6-RUS hexapod's alternate cranks). A triple
// product (b - a) x (c - b) . axis of the candidate's axis takes the sign
// -sigma (a slide's and an extensible leg's axis: sigma = +1), a rule along
// a direction d the sign tau of its partner's d = tau S d.

Vector3d reflect(const Vector3d& v) { return {v.x(), -v.y(), v.z()}; }

bool near(const Vector3d& a, const Vector3d& b, double tolerance) { return (a - b).norm() <= tolerance; }
bool near(double a, double b, double tolerance) { return a == b || std::abs(a - b) <= tolerance; }  // infinite reach too

// Whether leg b is leg a reflected in y, within `tolerance` of the size
// (lengths) or of 1 (directions, angles).
bool reflects(const LaneLeg& a, const LaneLeg& b, double size, double tolerance) {
  const double at = tolerance * size;
  if (a.parallelogram || a.three || b.parallelogram || b.three || !a.stops.empty() || !b.stops.empty()) return false;
  if (a.pattern != b.pattern || a.prismatic != b.prismatic || a.limited != b.limited || a.universal != b.universal)
    return false;
  const bool crank = a.pattern == LegPattern::CrankRod;
  // A crank's axis reflects as a turn's (-S a: the same angles) or as a
  // direction (S a: the angles negated, its partner's travel too); a
  // slide's and an extensible leg's as a direction.
  const double sigma = crank && near(-reflect(a.axis), b.axis, tolerance) ? -1 : 1;
  for (const auto& [x, y] : {std::pair{a.anchor_offset, b.anchor_offset}, {a.end_offset, b.end_offset},
                             {a.leg_base, b.leg_base}, {a.actuator_centre, b.actuator_centre}, {a.origin, b.origin}})
    if (!near(reflect(x), y, at)) return false;
  if (!near(sigma * reflect(a.axis), b.axis, tolerance)) return false;
  if (crank && !(near(reflect(a.u), b.u, tolerance) && near(-sigma * reflect(a.v), b.v, tolerance))) return false;
  if (a.universal && !(near(reflect(a.universal_axis), b.universal_axis, tolerance) ||
                       near(-reflect(a.universal_axis), b.universal_axis, tolerance)))
    return false;
  for (const auto& [x, y, scale] : {std::tuple{a.reach.lo, b.reach.lo, at}, {a.reach.hi, b.reach.hi, at},
                                    {a.rho, b.rho, at}, {a.rod, b.rod, at}, {a.offset, b.offset, at},
                                    {a.slide_start, b.slide_start, at}})
    if (!near(x, y, scale)) return false;
  // The travel: the same, or negated with the angles.
  const double travel = a.prismatic ? at : tolerance;
  const bool negated = crank && sigma > 0;
  if (a.limited && (negated ? !(near(-a.hi, b.lo, travel) && near(-a.lo, b.hi, travel))
                            : !(near(a.lo, b.lo, travel) && near(a.hi, b.hi, travel))))
    return false;
  if (a.rules.size() != b.rules.size() || a.cones.size() != b.cones.size()) return false;
  for (std::size_t k = 0; k < a.rules.size(); ++k) {
    const LaneLeg::Rule &r = a.rules[k], &s = b.rules[k];
    if (r.triple != s.triple || r.angle || s.angle || r.fixed_axis || s.fixed_axis) return false;
    if (!std::equal(std::begin(r.points), std::end(r.points), std::begin(s.points))) return false;
    if (r.triple) {
      if (s.wanted != -sigma * r.wanted) return false;
    } else {
      const double tau = s.wanted * r.wanted;
      if (!near(tau * reflect(r.direction), s.direction, tolerance)) return false;
    }
  }
  for (std::size_t k = 0; k < a.cones.size(); ++k) {
    const LaneLeg::Cone &c = a.cones[k], &e = b.cones[k];
    if (c.at_ball != e.at_ball || c.along != e.along || !near(c.half_angle_deg, e.half_angle_deg, tolerance * 180) ||
        !near(reflect(c.fixed), e.fixed, tolerance))
      return false;
  }
  return true;
}

// Whether reflecting y maps the device onto itself: a permutation of its
// legs, each onto a partner that reflects it (with its capsules, in order),
// and a fixed orientation the reflection keeps (rx = rz = 0: S R(rx, ry, rz)
// S = R(-rx, ry, -rz), and the rates of rx and rz change sign). The extras
// reach the lanes only through the anchors and the platform's capsules,
// compared here.
bool mirrored(const LaneDevice& device, double rx, double rz) {
  constexpr double kTolerance = 1e-12;  // of the size: cos 120 degrees' rounding passes
  if (device.planar || !(std::abs(rx) <= kTolerance && std::abs(rz) <= kTolerance)) return false;
  const std::size_t n = device.legs.size();
  std::vector<std::vector<const LaneCapsule*>> capsules(n);
  for (const LaneCapsule& c : device.capsules) {
    if (c.body != LaneBody::Fixed && c.body != LaneBody::Platform) return false;
    capsules[std::size_t(c.leg)].push_back(&c);
  }
  const auto capsules_reflect = [&](std::size_t i, std::size_t j) {
    if (capsules[i].size() != capsules[j].size()) return false;
    for (std::size_t k = 0; k < capsules[i].size(); ++k) {
      const LaneCapsule &c = *capsules[i][k], &e = *capsules[j][k];
      if (c.body != e.body || !near(c.radius, e.radius, kTolerance * device.size) ||
          !near(reflect(c.a), e.a, kTolerance * device.size) || !near(reflect(c.b), e.b, kTolerance * device.size))
        return false;
    }
    return true;
  };
  std::vector<bool> taken(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t j = 0;
    while (j < n && (taken[j] || !reflects(device.legs[i], device.legs[j], device.size, kTolerance) || !capsules_reflect(i, j))) ++j;
    if (j == n) return false;
    taken[j] = true;
  }
  return true;
}

// A crank-rod leg whose only rule is a triple on its actuator, ball and end
// (or an anchor there), about the actuator's axis: with e_k the crank's
// direction and t_k = axis x e_k, the triple is rho (end - origin) . t_k =
// -sign_k rho R sin(alpha) for the closed form's candidates q = phi + sign_k
// alpha (alpha in [0, pi]), so its sign is the candidate's, opposite, wherever
// it is not zero (sin(alpha) = 0: both candidates one, the band the scalar
// path decides). The candidate the branch keeps, or -1.
int branch_candidate(const LaneLeg& g) {
  if (g.pattern != LegPattern::CrankRod || g.rules.size() != 1) return -1;
  const LaneLeg::Rule& r = g.rules.front();
  const bool at_end = r.points[2] == LanePoint::End || (r.points[2] == LanePoint::Anchor && g.anchor_offset == g.end_offset);
  if (!r.triple || r.angle || r.fixed_axis || r.points[0] != LanePoint::Actuator || r.points[1] != LanePoint::Ball || !at_end)
    return -1;
  return r.wanted > 0 ? 1 : 0;
}

// Fills `out` (when given) and returns "" where the kernel expresses the
// device, else why not.
std::string build(const Kinematics& kin, const VectorXd& fixed, int branch, LaneDevice* out) {
  const Model& m = kin.model();
  // The extras move only the platform bodies' frames (model.h): fixed in a
  // field like the rotation, they leave each anchor at p plus a constant.
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
      return leg + (m.planar ? "not a planar dyad, slide-rod or extensible leg"
                             : "not a point leg (crank-rod, slide-rod, extensible), crank-parallelogram or three-revolute");
    const bool four_bar = form->pattern == LegPattern::CrankParallelogram;
    const bool three = form->pattern == LegPattern::ThreeRevolute;
    // A parallelogram leg holds two wrenches: its row is the actuator's
    // twist off its four passive twists (Kinematics::jacobian), in a task of translations.
    if (kin.passive_rank(int(i)) != (m.planar ? 2 : four_bar ? 4 : 5)) return leg + "holds more than one wrench";
    if (four_bar && driven != 3) return leg + "a crank-parallelogram in a task with rotations";
    LaneLeg g;
    // A planar dyad is a crank and rod in the plane.
    g.pattern = form->pattern == LegPattern::PlanarDyad ? LegPattern::CrankRod : form->pattern;
    const Isometry3d anchor = kin.anchor(int(i), pose);
    g.anchor_offset = anchor.translation();
    g.end_offset = (anchor * form->tail.inverse()).translation();
    g.leg_base = l.base.translation();
    g.reach = kin.reach(int(i));
    const auto square = [](double v) { return v > 0 ? v * v : -1.0; };
    g.far_out2 = square(g.reach.hi + 2e-9 * m.size);
    g.far_in2 = square(g.reach.hi + 0.5e-9 * m.size);
    g.near_out2 = square(g.reach.lo - 2e-9 * m.size);
    g.near_in2 = square(g.reach.lo - 0.5e-9 * m.size);
    const Eigen::Matrix3d R = form->base.linear();
    const Vector3d a = R * form->actuator_axis;
    g.actuator_centre = form->base.translation();
    g.axis = a;
    if (const std::string why = capsules(l, int(i), *form, pose, device); !why.empty()) return leg + why;
    if (four_bar) {
      if (const std::string why = parallelogram(l, *form, anchor, g); !why.empty()) return leg + why;
      g.pattern = LegPattern::CrankParallelogram;
    }
    if (three)
      if (const std::string why = three_revolute(l, *form, m.size, g); !why.empty()) return leg + why;
    const Step no_ball;
    const Step& ball = four_bar || three ? no_ball : l.steps[std::size_t(form->ball_step)];
    g.universal = form->ball_joints == 2;
    // The ball's link in its own frame: the rod, or an extensible leg's slide.
    Vector3d link = form->rod.translation();
    Eigen::Matrix3d before_ball = R * form->after_actuator.linear();  // a crank's at q = 0
    if (four_bar) {
      g.origin = g.actuator_centre;
    } else if (three) {  // its constants set above
    } else if (g.pattern == LegPattern::CrankRod) {
      const Vector3d p0 = form->base * form->after_actuator.translation();
      g.origin = g.actuator_centre + a * a.dot(p0 - g.actuator_centre);
      g.rho = (p0 - g.origin).norm();
      g.u = (p0 - g.origin) / g.rho;
      g.v = a.cross(g.u);
      g.ball_link = before_ball * link;
      g.ball_normal = before_ball * ball.axis;
      double sign = 1;
      if (m.planar && !parallel(g.ball_normal, a, sign)) return leg + "an elbow not parallel to its crank";
    } else if (g.pattern == LegPattern::SlideRod) {
      g.origin = form->base * form->after_actuator.translation();
    } else {
      g.origin = g.actuator_centre;
      g.offset = form->offset;
      link = l.steps[std::size_t(form->actuator_step)].axis;
      g.slide_start = link.dot(form->after_actuator.translation());
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
    if (g.limited && !g.prismatic) g.width = size_index(device.travel_widths, g.half_width);
    // A turn's travel as the representative nearest its middle (within_travel's w, w +- 2 pi).
    if (g.limited && !g.prismatic && (std::abs(g.mid) > 2 * internal::kPi || g.half_width > internal::kPi))
      return leg + "a revolute travel wider than a turn or centred beyond two";
    const ClosedFormLeg::Parallelogram& P = form->parallelogram;
    auto point_of = [&](int step, LanePoint& p) {
      if (step == -2) p = LanePoint::Anchor;
      else if (step == form->actuator_step) p = LanePoint::Actuator;
      else if (!four_bar && (step == form->ball_step || (g.universal && step == form->ball_step + 1))) p = LanePoint::Ball;
      else if (step == form->end_step) p = LanePoint::End;
      else if (four_bar && step == P.knee_step) p = LanePoint::Knee;
      else if (four_bar && step == P.upper_step) p = LanePoint::Upper;
      else if (four_bar && step == P.lower_step) p = LanePoint::Lower;
      else return false;
      return true;
    };
    // The passive revolutes whose angles the lanes know: a planar dyad's
    // ball (elbow), a parallelogram's knee, upper, lower and grip joints, a
    // three-revolute leg's second and third.
    auto joint_of = [&](int step, LaneJoint& j) {
      if (m.planar && step == form->ball_step) j = LaneJoint::Ball;
      else if (three && step == form->second_step) j = LaneJoint::Second;
      else if (three && step == form->third_step) j = LaneJoint::Third;
      else if (four_bar && step == P.knee_step) j = LaneJoint::Knee;
      else if (four_bar && step == P.upper_step) j = LaneJoint::Upper;
      else if (four_bar && step == P.lower_step) j = LaneJoint::Lower;
      else if (four_bar && step == form->end_step) j = LaneJoint::Grip;
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
      rule.wanted = r.fixed_sign != 0 ? r.fixed_sign : ((branch >> r.free_index) & 1) ? -1 : 1;
      if (r.kind == BranchRule::Kind::Angle) {
        // Its angle in closed form: a parallelogram's joints, a three-revolute leg's.
        rule.angle = true;
        if (!(four_bar || three) || !joint_of(r.steps[0], rule.joint))
          return leg + "an angle rule on a joint other than a parallelogram's or a three-revolute leg's";
        g.rules.push_back(rule);
        continue;
      }
      for (int k = 0; k < (rule.triple ? 3 : 2); ++k)
        if (!point_of(r.steps[std::size_t(k)], rule.points[k]))
          return leg + "a branch rule on other joints than the actuator, ball, end and anchor";
      rule.direction = r.direction;
      g.rules.push_back(rule);
    }
    g.branch_candidate = branch_candidate(g);
    for (const JointLimit& j : l.limits) {
      if (j.kind == JointLimit::Kind::Range) {
        LaneLeg::Stop stop;
        if (!joint_of(j.step, stop.joint)) return leg + "a revolute stop on a joint other than a planar elbow or a parallelogram's";
        constexpr double kDeg = 180 / internal::kPi;
        stop.lo_deg = j.range.lo * kDeg;
        stop.hi_deg = j.range.hi * kDeg;
        stop.mid = 0.5 * (j.range.lo + j.range.hi);
        stop.cos_mid = std::cos(stop.mid);
        stop.sin_mid = std::sin(stop.mid);
        g.stops.push_back(stop);
        device.cones = true;
        continue;
      }
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
      cone.size = size_index(device.cone_sizes, cone.half_angle_deg);
      g.cones.push_back(cone);
      device.cones = true;
    }
    device.legs.push_back(g);
  }
  capsule_pairs(m, device);
  std::array<double, 6> platform = m.fixed;  // as Kinematics::pose_into
  for (std::size_t i = 0; i < m.task.size(); ++i)
    if (m.task[i].platform_coordinate >= 0) platform[std::size_t(m.task[i].platform_coordinate)] = fixed(Eigen::Index(i));
  device.mirror_y = mirrored(device, platform[3], platform[5]);
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

bool lanes_mirror_holds(const LaneDevice& device, const Grid& g) {
  return device.mirror_y && detail::mirrors_in_y(g);
}

}  // namespace linkscape::described
