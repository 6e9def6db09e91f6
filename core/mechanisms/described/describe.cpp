// The text of `linkscape describe FILE` (docs/described-mechanisms.md,
// "Checking a file: `linkscape describe`").
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/lanes.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/preset.h"

namespace linkscape::described {
namespace {

// Two passive revolutes one after the other, with no link between them and
// axes that cross, are taken as a universal joint: said, since the file
// names two joints.
std::string universal_note(const Leg& l) {
  std::string out;
  for (std::size_t i = 0; i + 1 < l.steps.size(); ++i)
    if (meets_as_universal(l, i))
      out += "    revolutes " + l.steps[i].name + " and " + l.steps[i + 1].name +
             " meet at one point with crossing axes: taken as one universal joint\n";
  return out;
}

std::string joint_name(const Leg& l, int step) { return step == -2 ? "anchor" : l.steps[std::size_t(step)].name; }

std::string rule_text(const Leg& l, const BranchRule& r) {
  std::ostringstream s;
  if (r.kind == BranchRule::Kind::Triple)
    s << "triple [" << joint_name(l, r.steps[0]) << ", " << joint_name(l, r.steps[1]) << ", " << joint_name(l, r.steps[2]) << "]";
  else if (r.kind == BranchRule::Kind::Angle)
    s << "angle " << joint_name(l, r.steps[0]);
  else
    s << "along [" << joint_name(l, r.steps[0]) << ", " << joint_name(l, r.steps[1]) << "] direction [" << r.direction.x()
      << ", " << r.direction.y() << ", " << r.direction.z() << "]";
  if (r.fixed_sign != 0) s << " sign " << (r.fixed_sign > 0 ? "+" : "-") << " (design)";
  else s << " free (branch bit " << r.free_index << ")";
  return s.str();
}

std::string limit_text(const JointLimit& l) {
  std::ostringstream s;
  s << l.label << ": ";
  if (l.kind == JointLimit::Kind::Cone) s << l.half_angle * 180 / M_PI << " deg cone";
  else s << l.range.lo * 180 / M_PI << " .. " << l.range.hi * 180 / M_PI << " deg";
  return s.str();
}

// The bound about the leg's first joint (reach.h), e.g. "within 17 .. 17 cm
// of a circle of radius 8 cm round q1's axis".
std::string first_joint_text(const Leg& l, const FirstJointReach& r, const std::string& unit) {
  using Motion = FirstJointReach::Motion;
  if (r.motion == Motion::None) return "";
  std::string joint;
  for (const Step& step : l.steps)
    if (step.kind != Step::Kind::Fixed) {
      joint = step.name;
      break;
    }
  std::ostringstream s;
  s << "within ";
  if (r.motion == Motion::Slide) s << r.rest.hi << " " << unit << " of the line along " << joint;
  else s << r.rest.lo << " .. " << r.rest.hi << " " << unit << " of ";
  if (r.motion == Motion::Turn && r.radius > 0) s << "a circle of radius " << r.radius << " " << unit << " round " << joint << "'s axis";
  if (r.motion == Motion::Turn && r.radius == 0) s << "a point on " << joint << "'s axis";
  if (r.motion == Motion::Ball) s << "a sphere of radius " << r.radius << " " << unit << " round " << joint;
  return s.str();
}

}  // namespace

std::string describe(const Preset& preset) {
  if (preset.description.empty())
    throw std::invalid_argument("describe: the preset has no \"description\" (only described devices can be described)");
  const Kinematics k(build_model(preset.description, preset.parameters, preset.limits_deg, preset.length_unit));
  const Model& m = k.model();
  const Mobility& mb = k.mobility();
  const std::string& unit = m.length_unit;
  std::ostringstream s;
  s << preset.title << "\n";
  s << "space: " << (m.planar ? "planar" : "spatial") << ", size " << m.size << " " << unit << " (" << m.size_text << ")\n";
  s << "mobility: " << mb.freedoms << " (Gruebler-Kutzbach " << mb.gruebler << ", " << mb.fixed << " held, " << mb.idle
    << " idle, closure rank " << mb.closure_rank << "); " << m.actuators.size() << " actuator(s)";
  if (!m.extras.empty()) s << ", " << m.extras.size() << " extra(s)";
  s << "\n";
  if (!mb.held_by_description_alone.empty()) {
    s << "  held by the description alone: ";
    for (std::size_t i = 0; i < mb.held_by_description_alone.size(); ++i)
      s << (i ? ", " : "") << mb.held_by_description_alone[i];
    s << " (the legs as written leave the platform free so: right for a point platform or parallelograms drawn as "
         "single rods; else the device needs legs that hold it)\n";
  }
  s << "branches: " << k.branches() << "\n";
  // Home is where every command and the window start: a home outside an
  // actuator's travel (a travel written in radians where degrees are read)
  // makes every pose out of limits.
  const PoseSolution home = k.inverse(m.home, 0, 1e-10);
  s << "home: " << to_string(home.status);
  for (Eigen::Index a = 0; a < home.q.size(); ++a) {
    const Actuator& act = m.actuators[std::size_t(a)];
    const double v = home.q(a);
    if (!act.limited || act.range.contains(v)) continue;
    const double scale = act.prismatic ? 1.0 : 180 / M_PI;
    s << "; " << act.name << " = " << v * scale << (act.prismatic ? " " + unit : " deg") << " is outside its travel "
      << act.range.lo * scale << " .. " << act.range.hi * scale << (act.prismatic ? " " + unit : " deg");
  }
  s << "\n";
  const int closed = k.closed_form_count();
  s << "legs: " << m.legs.size() << " (" << closed << " in closed form, " << m.legs.size() - std::size_t(closed)
    << " numeric)\n";
  for (std::size_t leg = 0; leg < m.legs.size(); ++leg) {
    const Leg& l = m.legs[leg];
    const ClosedFormLeg* form = k.closed_form(int(leg));
    s << "  " << l.label() << ": " << pattern_name(form ? form->pattern : LegPattern::Numeric);
    if (!form) s << " (its joints: " << joint_sequence(l) << "; the closed forms' steps: docs/described-mechanisms.md)";
    if (form && form->end_joints == 2) s << " (ending in a universal joint: it holds the orientation too)";
    s << "\n";
    s << universal_note(l);
    const Actuator& a = m.actuators[std::size_t(l.actuators.front())];
    s << "    actuator " << a.name << " (" << (a.prismatic ? "prismatic" : "revolute") << "), travel ";
    if (!a.limited) s << "a full turn";
    else if (a.prismatic) s << a.range.lo << " .. " << a.range.hi << " " << unit;
    else s << a.range.lo * 180 / M_PI << " .. " << a.range.hi * 180 / M_PI << " deg";
    s << "\n";
    if (l.rules.empty()) s << "    branch: none\n";
    for (const BranchRule& r : l.rules) s << "    branch: " << rule_text(l, r) << "\n";
    if (const std::string w = k.branch_warning(int(leg)); !w.empty()) s << "    warning: " << w << "\n";
    const Range& reach = k.reach(int(leg));
    s << "    reach: " << reach.lo << " .. ";
    if (std::isinf(reach.hi)) s << "unbounded";
    else s << reach.hi;
    s << " " << unit << " from its base to its anchor\n";
    const std::string about = first_joint_text(l, k.reach_about_first_joint(int(leg)), unit);
    if (!about.empty()) s << "    reach about its first joint: " << about << "\n";
    const SampledReach& sampled = k.sampled_reach(int(leg));
    if (!sampled.built) s << "    reach sampled within its travel: no (" << sampled.why_not << ")\n";
    else {
      s << "    reach sampled within its travel: " << sampled.samples << " samples of the " << sampled.joints
        << " joints that move its end; every assembly within " << std::setprecision(2)
        << sampled.travel.front().margin() << std::setprecision(6) << " " << unit << " of a sample's end\n";
    }
    if (!form) {  // what the numerical solver refuses near the reach's edge
      const TurnedReach& turned = k.turned_reach(int(leg));
      s << "    reach sampled about its first joint: ";
      if (!turned.built) s << "no (" << turned.why_not << ")\n";
      else
        s << turned.samples << " samples of the joints after it, as distance from its axis and height along it; "
          << "every assembly within " << std::setprecision(2) << turned.rest.margin() << std::setprecision(6) << " "
          << unit << " of one"
          << (turned.limited ? "; within the travel, the turns that bring them onto an anchor" : "") << "\n";
    }
    for (const JointLimit& j : l.limits) s << "    limit: " << limit_text(j) << "\n";
    for (const LinkCapsule& c : l.capsules)
      s << "    link: " << c.name << ", radius " << c.radius << " " << unit << ", length " << (c.b - c.a).norm() << " "
        << unit << "\n";
  }
  const std::string refusal = lanes_refusal(k);
  const int legs = int(m.legs.size());
  if (refusal.empty()) s << "field: lanes (the legs' closed forms in SIMD lanes; the scalar closed forms near thresholds)\n";
  else if (closed == 0) s << "field: the numerical solver, one pose at a time (no leg in closed form)\n";
  else if (closed < legs)
    s << "field: the closed forms of " << closed << " legs and the numerical solver for the others, one pose at a "
      << "time (not in lanes: " << refusal << ")\n";
  else s << "field: closed, one pose at a time (not in lanes: " << refusal << ")\n";
  if (!m.has_joint_limits()) s << "passive-joint limits: none stated\n";
  if (!m.has_capsules()) s << "links: none given a radius (no interference checked)\n";
  return s.str();
}

}  // namespace linkscape::described
