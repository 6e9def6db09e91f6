#include "core/mechanisms/described/skeleton.h"

#include <algorithm>
#include <cmath>

namespace linkscape::described {

using Eigen::Vector3d;
using Eigen::VectorXd;

Skeleton::Skeleton(const Kinematics& kin) {
  const Model& m = kin.model();
  SkeletonModel& sk = model;
  sk.scale = m.size / 3;
  // The base: a ring through the legs' bases at each height (PATHOS-II's
  // two plates, not one ring zigzagging between them), in the legs' order,
  // where each height holds three or more.
  Body ground{"base", {}, {}, true};
  std::vector<Vector3d> bases;
  for (const Leg& l : m.legs) bases.push_back(l.base.translation());
  std::vector<std::vector<Vector3d>> rings;
  for (const Vector3d& p : bases) {
    auto ring = std::find_if(rings.begin(), rings.end(),
                             [&](const auto& r) { return std::abs(r.front().z() - p.z()) <= 1e-9 * m.size; });
    if (ring == rings.end()) rings.push_back({p});
    else ring->push_back(p);
  }
  // Bases at many heights (a tilted base): one ring through them all.
  if (std::any_of(rings.begin(), rings.end(), [](const auto& r) { return r.size() < 3; })) rings = {bases};
  for (std::vector<Vector3d>& ring : rings) {
    if (ring.size() < 2) continue;
    if (ring.size() >= 3) ring.push_back(ring.front());
    ground.polylines.push_back(ring);
  }
  sk.bodies.push_back(ground);
  for (std::size_t leg = 0; leg < m.legs.size(); ++leg) {
    const Leg& l = m.legs[leg];
    // Zero-state frames give each link's geometry in its own frame.
    LegState zero;
    zero.values = VectorXd::Zero(l.variables);
    zero.spheres.assign(std::size_t(l.spheres), Eigen::Matrix3d::Identity());
    const Kinematics::LegDrawing d = kin.draw_leg(int(leg), zero);
    int body = 0;  // the ground until the first joint
    std::vector<Vector3d> line{l.base.translation()};
    Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
    for (std::size_t s = 0; s < l.steps.size(); ++s) {
      const Step& step = l.steps[s];
      if (step.kind == Step::Kind::Fixed) {
        line.push_back(frame.inverse() * d.frames[s].translation());
        continue;
      }
      const bool second_half = s > 0 && l.steps[s - 1].kind != Step::Kind::Fixed && l.steps[s - 1].joint == step.joint;
      if (second_half) {
        link_bodies_.back().step = int(s);
        continue;
      }
      if (line.size() >= 2) sk.bodies[std::size_t(body)].polylines.push_back(line);
      const Eigen::Isometry3d before_frame = s == 0 ? l.base : d.frames[s - 1];
      const Vector3d joint_point = frame.inverse() * before_frame.translation();
      Joint j;
      j.name = step.joint;
      j.type = step.kind == Step::Kind::Revolute
                   ? (s + 1 < l.steps.size() && l.steps[s + 1].joint == step.joint ? JointType::Universal
                                                                                     : JointType::Revolute)
               : step.kind == Step::Kind::Prismatic ? JointType::Prismatic
                                                    : JointType::Spherical;
      // The joint, drawn with the body before it.
      j.body = body;
      j.p_body_joint = joint_point;
      j.axis_body_joint = frame.linear().transpose() * before_frame.linear() * step.axis;
      j.actuated = step.actuator >= 0;
      if (j.actuated) j.label = step.name;
      sk.joints.push_back(j);
      // A new link after the joint.
      sk.bodies.push_back({l.name + ":" + step.joint, {}, {}, false});
      const int previous = body;
      body = int(sk.bodies.size()) - 1;
      link_bodies_.push_back({int(leg), int(s), body});
      frame = d.frames[s];
      line = {Vector3d::Zero()};
      if (step.kind == Step::Kind::Prismatic) {
        // A slide drawn telescopic: a sleeve on the body before it, a rod on
        // the body after, each as long as the shortest travel, so the leg
        // shows whole at any extension.
        const Actuator* act = step.actuator >= 0 ? &m.actuators[std::size_t(step.actuator)] : nullptr;
        const double length = act && act->range.lo > 0 ? act->range.lo : 0.5 * m.size;
        sk.bodies[std::size_t(previous)].polylines.push_back({joint_point, joint_point + length * j.axis_body_joint});
        sk.bodies[std::size_t(body)].polylines.push_back({Vector3d::Zero(), -length * step.axis});
      }
    }
    if (line.size() >= 2) sk.bodies[std::size_t(body)].polylines.push_back(line);
  }
  platform_body_ = int(sk.bodies.size());
  for (std::size_t b = 0; b < m.platform_names.size(); ++b) {
    Body plate{m.platform_names[b], {}, {}, false};
    std::vector<Vector3d> corners;
    for (const Leg& l : m.legs)
      if (l.platform == int(b)) corners.push_back(l.anchor.translation());
    if (corners.size() >= 3) plate.faces.push_back(corners);
    else if (corners.size() == 2) plate.polylines.push_back(corners);
    sk.bodies.push_back(plate);
  }
}

SkeletonPose Skeleton::pose(const Kinematics& kin, const PoseSolution& assembly, const PlatformPose& platform,
                            const std::string& failing_leg) const {
  SkeletonPose p;
  const std::size_t bodies = std::size_t(platform_body_) + kin.model().platform_names.size();
  p.X_world_body.assign(bodies, Eigen::Isometry3d::Identity());
  p.states.assign(bodies, BodyState::Normal);
  std::vector<Kinematics::LegDrawing> drawings;
  for (std::size_t leg = 0; leg < kin.model().legs.size(); ++leg)
    drawings.push_back(kin.draw_leg(int(leg), assembly.legs[leg].state));
  for (const LinkBody& lb : link_bodies_) {
    p.X_world_body[std::size_t(lb.body)] = drawings[std::size_t(lb.leg)].frames[std::size_t(lb.step)];
    if (!failing_leg.empty() && failing_leg == kin.model().legs[std::size_t(lb.leg)].name)
      p.states[std::size_t(lb.body)] = BodyState::Failing;
  }
  for (std::size_t b = 0; b < platform.bodies.size(); ++b)
    p.X_world_body[std::size_t(platform_body_) + b] = platform.bodies[b];
  p.p_world_endpoint = platform.p;
  return p;
}

}  // namespace linkscape::described
