// The Delta's skeleton for drawing: its joints, bodies and their frames at a
// configuration (core/mechanisms/delta/delta.h).
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/mechanisms/delta/delta.h"
#include "core/mechanisms/delta/delta_checks.h"

namespace linkscape::delta {
namespace {

using Eigen::Vector3d;
using checks::format_vector;
using checks::require_closure;
constexpr double kPi = std::numbers::pi;

}  // namespace

// ---- Skeleton -----------------------------------------------------------------

std::array<JointDefinition, kJointCount> joint_definitions(const Model& m) {
  m.validate();
  std::array<JointDefinition, kJointCount> joints;
  for (int i = 0; i < kLegCount; ++i) {
    const std::string n = std::to_string(i + 1);
    joints[i] = {"motor " + n, JointType::Revolute, 0, 1 + i, motor_position(m, i), Vector3d::Zero(),
                 leg_motor_axis(i)};
    joints[3 + i] = {"elbow " + n, JointType::Spherical, 1 + i, 4 + i, m.La * Vector3d::UnitX(), Vector3d::Zero(),
                     Vector3d::UnitY()};
    joints[6 + i] = {"platform " + n, JointType::Spherical, 7, 4 + i, m.r * leg_radial(i), m.Lb * Vector3d::UnitX(),
                     leg_motor_axis(i)};
  }
  return joints;
}

std::array<BodyShape, kBodyCount> body_shapes(const Model& m, const SkeletonStyle& style) {
  m.validate();
  const double motor = style.motor_length > 0.0 ? style.motor_length : 0.3 * m.La;
  const int n = std::max(3, style.circle_samples);
  std::array<BodyShape, kBodyCount> shapes;
  shapes[0].name = "base";
  std::vector<Vector3d> circle;
  for (int k = 0; k <= n; ++k) {
    const double a = 2.0 * kPi * k / n;
    circle.push_back(m.R * Vector3d(std::cos(a), std::sin(a), 0.0));
  }
  shapes[0].polylines.push_back(circle);
  std::vector<Vector3d> platform_outline;
  for (int i = 0; i < kLegCount; ++i) {
    const Vector3d A = motor_position(m, i), t = leg_motor_axis(i);
    shapes[0].polylines.push_back({A - 0.5 * motor * t, A + 0.5 * motor * t});
    shapes[1 + i] = {"arm " + std::to_string(i + 1), {{Vector3d::Zero(), m.La * Vector3d::UnitX()}}};
    shapes[4 + i] = {"forearm " + std::to_string(i + 1), {{Vector3d::Zero(), m.Lb * Vector3d::UnitX()}}};
    platform_outline.push_back(m.r * leg_radial(i));
  }
  platform_outline.push_back(platform_outline.front());
  shapes[7].name = "platform";
  shapes[7].polylines.push_back(platform_outline);
  for (int i = 0; i < kLegCount; ++i) shapes[7].polylines.push_back({Vector3d::Zero(), m.r * leg_radial(i)});
  return shapes;
}

Skeleton skeleton(const Model& m, const Vector3d& q, const Vector3d& p) {
  m.validate();
  require_closure(m, q, p, "skeleton");
  Skeleton sk;
  sk.p_base_platform = p;
  sk.X_world_body[0].setIdentity();
  for (int i = 0; i < kLegCount; ++i) {
    Eigen::Isometry3d arm = Eigen::Isometry3d::Identity();
    arm.translation() = motor_position(m, i);
    arm.linear() = (Eigen::AngleAxisd(leg_angle(i), Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(q(i), Vector3d::UnitY())).toRotationMatrix();
    sk.X_world_body[1 + i] = arm;

    const Vector3d B = elbow_position(m, i, q(i));
    const Vector3d x = (p + m.r * leg_radial(i) - B).normalized();
    Vector3d y = leg_motor_axis(i) - leg_motor_axis(i).dot(x) * x;
    y = y.norm() > 1e-9 ? Vector3d(y.normalized()) : x.unitOrthogonal();  // forearm along t_i: any normal
    Eigen::Isometry3d forearm = Eigen::Isometry3d::Identity();
    forearm.translation() = B;
    forearm.linear() << x, y, x.cross(y);
    sk.X_world_body[4 + i] = forearm;
  }
  sk.X_world_body[7].setIdentity();
  sk.X_world_body[7].translation() = p;
  const auto joints = joint_definitions(m);
  for (int j = 0; j < kJointCount; ++j) {
    const Eigen::Isometry3d& T = sk.X_world_body[joints[j].body_a];
    sk.joint_positions[j] = T * joints[j].point_in_a;
    sk.joint_axes[j] = T.linear() * joints[j].axis_in_a;
  }
  return sk;
}

Skeleton skeleton(const Model& m, const Vector3d& q) {
  const FkResult fk = forward(m, q);
  if (fk.status == Status::Unreachable || fk.status == Status::NotConverged)
    throw std::invalid_argument("delta: skeleton: no platform position for q = " + format_vector(q));
  return skeleton(m, q, fk.p_base_platform);
}

}  // namespace linkscape::delta
