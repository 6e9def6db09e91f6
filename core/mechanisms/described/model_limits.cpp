// Reading what bounds a described device beyond its actuators' travel: the
// passive joints' limits and the links' capsules
// (docs/described-mechanisms.md, "Joint limits" and "Link interference").
#include <cmath>

#include "core/mechanisms/described/model.h"
#include "core/mechanisms/described/reader.h"

namespace linkscape::described::reader {

void read_capsule(const json& step, Evaluator& eval, const std::string& where, const Isometry3d& before,
                  const Isometry3d& after, LinkCapsule::On on, int frame, std::vector<LinkCapsule>& out) {
  if (!step.contains("radius")) {
    if (step.contains("link")) fail(where, "a link's \"link\" name needs its \"radius\"");
    return;
  }
  LinkCapsule c;
  c.on = on;
  c.frame = frame;
  c.a = before.translation();
  c.b = after.translation();
  c.radius = eval.number(step.at("radius"), where + ".radius");
  if (!(c.radius > 0)) fail(where + ".radius", "a link's radius must be positive, got " + std::to_string(c.radius));
  c.name = replace_hash(string_or(step, "link", "", where), eval.hash_number());
  out.push_back(c);
}

namespace {

// A revolute step's range in radians, at most a turn wide.
Range angle_range(const json& value, Evaluator& eval, const std::string& where) {
  const Range r = eval.range(value, where, kPi / 180);
  if (r.hi - r.lo > 2 * kPi + 1e-12)
    fail(where, "a joint's range spans at most 360 deg, got " + std::to_string((r.hi - r.lo) * 180 / kPi));
  return r;
}

}  // namespace

void read_joint_limits(const json& step, const std::string& type, bool actuated, Evaluator& eval,
                       const std::string& where, Leg& leg, std::size_t first_step) {
  const std::string& name = leg.steps[first_step].joint;
  auto limit_range = [&](std::size_t s, const Range& r, const std::string& label) {
    JointLimit l;
    l.step = int(s);
    l.range = r;
    l.label = label;
    leg.limits.push_back(l);
  };
  if (type == "revolute") {
    // An actuator's range is its travel (Model::actuators), not a passive limit.
    if (!actuated && step.contains("range_deg"))
      limit_range(first_step, angle_range(step.at("range_deg"), eval, where + ".range_deg"), "joint " + name);
  } else if (type == "prismatic") {
    if (!actuated && step.contains("range"))
      fail(where + ".range",
           "a passive prismatic joint's range is not modelled (passive limits are angles: revolute, universal, "
           "spherical)");
  } else if (type == "universal" && step.contains("ranges_deg")) {
    const json& ranges = step.at("ranges_deg");
    if (!ranges.is_array() || ranges.size() != 2)
      fail(where + ".ranges_deg", "must be two ranges [[lo, hi], [lo, hi]] (null: that axis unlimited)");
    for (std::size_t h = 0; h < 2; ++h) {
      if (ranges[h].is_null()) continue;
      const std::string at = where + ".ranges_deg[" + std::to_string(h) + "]";
      limit_range(first_step + h, angle_range(ranges[h], eval, at),
                  "universal joint " + name + " (axis " + std::to_string(h + 1) + ")");
    }
  } else if (type == "spherical" && step.contains("cone")) {
    const std::string at = where + ".cone";
    const json& cone = step.at("cone");
    check_keys(cone, {"axis", "link_axis", "half_angle_deg"}, at);
    JointLimit l;
    l.kind = JointLimit::Kind::Cone;
    l.step = int(first_step);
    l.sphere = leg.spheres - 1;
    l.axis = eval.unit_axis(require(cone, "axis", at), at + ".axis");
    l.link_axis = cone.contains("link_axis") ? eval.unit_axis(cone.at("link_axis"), at + ".link_axis") : l.axis;
    const double half = eval.number(require(cone, "half_angle_deg", at), at + ".half_angle_deg");
    if (!(half > 0 && half < 180))
      fail(at + ".half_angle_deg", "a cone's half angle must lie in (0, 180) deg, got " + std::to_string(half));
    l.half_angle = half * kPi / 180;
    l.label = "ball joint " + name;
    leg.limits.push_back(l);
  }
}

}  // namespace linkscape::described::reader

namespace linkscape::described {

bool Model::has_joint_limits() const {
  for (const Leg& l : legs)
    if (!l.limits.empty()) return true;
  return false;
}

void switch_off_stops(Model& model, const StopChecks& checks) {
  for (Leg& l : model.legs) {
    if (!checks.joint_limits) l.limits.clear();
    if (!checks.interference) l.capsules.clear();
  }
}

bool Model::has_capsules() const {
  for (const Leg& l : legs)
    if (!l.capsules.empty()) return true;
  return false;
}

}  // namespace linkscape::described
