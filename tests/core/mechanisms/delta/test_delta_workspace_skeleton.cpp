// Reach margin, home pose, the shipped preset and the drawing skeleton.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>

#include "core/mechanisms/delta/delta.h"
#include "tests/core/mechanisms/delta/delta_test_support.h"

using namespace linkscape;
using namespace linkscape::delta;
using linkscape::delta::test_support::ConfigurationSampler;
using Eigen::Vector3d;

namespace {

Vector3d random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return Vector3d(n(rng), n(rng), n(rng)).normalized();
}

bool all_legs_reach(const Model& m, const Vector3d& p) {
  const IkResult ik = inverse(m, p);
  return ik.status != Status::Unreachable;
}

}  // namespace

TEST(DeltaReachMargin, SignAgreesWithTheInverseKinematics) {
  const Model m;
  std::mt19937_64 rng(31);
  // A box around home a little larger than the workspace within the ranges.
  std::uniform_real_distribution<double> offset(-0.6 * m.size(), 0.6 * m.size());
  const double tol = kSingularTolerance * m.size();
  int inside = 0, out_of_range = 0;
  for (int k = 0; k < 50000; ++k) {
    const Vector3d p = home_position(m) + Vector3d(offset(rng), offset(rng), offset(rng));
    const int branch = k % 2 ? int(rng() % kBranchCount) : 0;  // half on the working branch
    const ReachMargin margin = reach_margin(m, p, branch);
    ASSERT_TRUE(std::isfinite(margin.value));
    EXPECT_DOUBLE_EQ(margin.value, std::min(margin.geometric, margin.limits));
    IkOptions options;
    options.branch = branch;
    const IkResult ik = inverse(m, p, IkMethod::Closed, options);
    if (margin.geometric < -tol) {
      EXPECT_EQ(ik.status, Status::Unreachable);
    } else if (margin.geometric > tol) {
      ASSERT_NE(ik.status, Status::Unreachable);
      // The limits part is zero exactly where an angle leaves its range.
      EXPECT_EQ(ik.status == Status::OutOfLimits, margin.limits < 0) << p.transpose();
      if (margin.value > 0) ++inside;
      if (margin.limits < 0) ++out_of_range;
    }
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(out_of_range, 1000);
}

TEST(DeltaReachMargin, GeometricMarginIsTheDistanceToTheBoundaryInside) {
  // Inside, every point closer than the margin is reachable, and the margin is
  // 1-Lipschitz with a unit gradient: it is the Euclidean distance to the
  // boundary of the workspace without actuator ranges.
  const Model m;
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> xy(-m.size(), m.size()), z(-1.5 * m.size(), 0.0);
  int tested = 0;
  while (tested < 500) {
    const Vector3d p(xy(rng), xy(rng), z(rng));
    const double margin = reach_margin(m, p).geometric;
    if (margin < 1e-3 * m.size()) continue;
    ++tested;
    for (int k = 0; k < 100; ++k) {
      const Vector3d step = random_unit(rng);
      const Vector3d inner = p + 0.999 * margin * step;
      ASSERT_TRUE(all_legs_reach(m, inner)) << p.transpose();
      EXPECT_LE(std::abs(reach_margin(m, inner).geometric - margin), 0.999 * margin * (1 + 1e-12));
    }
    const double h = 1e-6 * m.size();
    Vector3d gradient;
    for (int k = 0; k < 3; ++k)
      gradient(k) = (reach_margin(m, p + h * Vector3d::Unit(k)).geometric -
                     reach_margin(m, p - h * Vector3d::Unit(k)).geometric) / (2 * h);
    EXPECT_NEAR(gradient.norm(), 1.0, 1e-6) << p.transpose();
    // Straight down the gradient the boundary is exactly `margin` away.
    const Vector3d towards_edge = -gradient.normalized();
    EXPECT_TRUE(all_legs_reach(m, p + 0.999 * margin * towards_edge));
    EXPECT_FALSE(all_legs_reach(m, p + 1.001 * margin * towards_edge));
  }
}

TEST(DeltaReachMargin, ContinuousAcrossTheBoundary) {
  const Model m;
  std::mt19937_64 rng(33);
  int crossings = 0;
  for (int k = 0; k < 200; ++k) {
    const Vector3d from = home_position(m);
    const Vector3d to = from + 2 * m.size() * random_unit(rng);
    double previous = reach_margin(m, from, 0).value;
    for (int s = 1; s <= 20000; ++s) {
      const double current = reach_margin(m, from + (to - from) * (s / 20000.0), 0).value;
      // 4 size / 20000 per step: La dq jumps by at most La sqrt(2 step / La) near a fold.
      EXPECT_LT(std::abs(current - previous), 0.05 * m.size());
      if ((current < 0) != (previous < 0)) ++crossings;
      previous = current;
    }
  }
  EXPECT_GE(crossings, 200);
}

TEST(DeltaHome, IsTheLargestMarginOnTheAxisAndAssembles) {
  const Model m;
  const Vector3d p = home_position(m);
  EXPECT_EQ(p.x(), 0.0);
  EXPECT_EQ(p.y(), 0.0);
  EXPECT_LT(p.z(), 0.0);
  const double margin = reach_margin(m, p).geometric;
  EXPECT_NEAR(margin, std::min(m.La, m.Lb), 1e-12 * m.size());
  for (double dz : {-1e-3, 1e-3, -0.1, 0.1})
    EXPECT_LT(reach_margin(m, p + Vector3d(0, 0, dz)).geometric, margin);
  const Vector3d q = home_pose(m);
  EXPECT_DOUBLE_EQ(q(0), q(1));
  EXPECT_DOUBLE_EQ(q(0), q(2));
  const FkResult fk = forward(m, q);
  EXPECT_EQ(fk.status, Status::Ok);  // the preset's ranges contain home
  EXPECT_LT((fk.p_base_platform - p).norm(), 1e-12 * m.size());
  EXPECT_EQ(branch_of(m, q, p), 0);
  EXPECT_EQ(jacobian(m, q).status, Status::Ok);
}

TEST(DeltaPreset, WorkspaceHoldsACubeOfAHapticDevicesSize) {
  // docs/mechanisms/delta.md: within the ranges the working branch holds a
  // cube of about 9.9 cm below home (measured on a 0.1 cm search); check a
  // 9.5 cm cube centred at z = -16 cm on a 21^3 grid, with c(J) finite.
  const Model m;
  const double side = 9.5, centre_z = -16.0;
  double worst_cond = 0.0;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j)
      for (int k = 0; k <= 20; ++k) {
        const Vector3d p(side * (i / 20.0 - 0.5), side * (j / 20.0 - 0.5), centre_z + side * (k / 20.0 - 0.5));
        ASSERT_GT(reach_margin(m, p).value, 0.0) << p.transpose();
        const IkResult ik = inverse(m, p);
        ASSERT_EQ(ik.status, Status::Ok);
        const JacobianResult J = jacobian(m, ik.q_actuated, p);
        ASSERT_EQ(J.status, Status::Ok);
        EXPECT_LT(J.det_Jx, 0.0);  // the working assembly mode throughout
        worst_cond = std::max(worst_cond, J.cond);
      }
  RecordProperty("worst_cond", test_support::scientific(worst_cond));
}

TEST(DeltaPreset, ShippedFileIsTheModelsDefaultAndReadsBack) {
  std::ifstream in(std::string(LINKSCAPE_TEST_ASSETS) + "/mechanisms/delta.json");
  ASSERT_TRUE(in) << "assets/mechanisms/delta.json";
  const nlohmann::json doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc.at("mechanism").get<std::string>(), kMechanismName);
  std::map<std::string, double> parameters;
  for (const auto& [key, value] : doc.at("parameters").items()) parameters[key] = value.get<double>();
  std::map<std::string, Interval> limits_deg;
  for (const auto& [key, value] : doc.at("actuator_limits_deg").items())
    limits_deg[key] = {value.at(0).get<double>(), value.at(1).get<double>()};
  const Model preset = Model::from_parameters(parameters, limits_deg, doc.at("length_unit").get<std::string>());
  const Model defaults;
  EXPECT_EQ(preset.length_unit, defaults.length_unit);
  EXPECT_EQ(preset.to_parameters(), defaults.to_parameters());
  for (int i = 0; i < kLegCount; ++i) {
    EXPECT_NEAR(preset.q_limits[i].lo, defaults.q_limits[i].lo, 1e-15);
    EXPECT_NEAR(preset.q_limits[i].hi, defaults.q_limits[i].hi, 1e-15);
  }
  EXPECT_EQ(preset.length_unit, "cm");  // as the other presets
}

TEST(DeltaSkeleton, EveryJointClosesAtEveryPose) {
  const Model m;
  ConfigurationSampler sample(m, 41);
  const auto joints = joint_definitions(m);
  const auto shapes = body_shapes(m);
  // Axis of each revolute joint in body b's frame, from the first pose.
  std::array<Vector3d, kJointCount> axis_in_b;
  bool first = true;
  int poses = 0;
  while (poses < 10000) {
    const Vector3d q = sample();
    const FkResult fk = forward(m, q);
    if (fk.status != Status::Ok) continue;
    ++poses;
    const Skeleton sk = skeleton(m, q);
    EXPECT_LT((sk.p_base_platform - fk.p_base_platform).norm(), 1e-15 * m.size() + 1e-300);
    for (int j = 0; j < kJointCount; ++j) {
      const JointDefinition& d = joints[j];
      const Eigen::Isometry3d& A = sk.X_world_body[d.body_a];
      const Eigen::Isometry3d& B = sk.X_world_body[d.body_b];
      ASSERT_LT((A * d.point_in_a - B * d.point_in_b).norm(), 1e-12 * m.size()) << d.name;
      EXPECT_LT((sk.joint_positions[j] - A * d.point_in_a).norm(), 1e-12 * m.size());
      EXPECT_NEAR(sk.joint_axes[j].norm(), 1.0, 1e-12);
      if (d.type == JointType::Revolute) {
        const Vector3d in_b = B.linear().transpose() * (A.linear() * d.axis_in_a);
        if (first) axis_in_b[j] = in_b;
        else EXPECT_LT((in_b - axis_in_b[j]).norm(), 1e-12) << d.name;
      }
    }
    first = false;
    for (int b = 0; b < kBodyCount; ++b)
      EXPECT_LT((sk.X_world_body[b].linear().transpose() * sk.X_world_body[b].linear() - Eigen::Matrix3d::Identity())
                    .norm(),
                1e-12);
    for (int i = 0; i < kLegCount; ++i) {
      // The drawn links have the model's lengths at the joint positions.
      EXPECT_NEAR((sk.joint_positions[3 + i] - sk.joint_positions[i]).norm(), m.La, 1e-12 * m.size());
      EXPECT_NEAR((sk.joint_positions[6 + i] - sk.joint_positions[3 + i]).norm(), m.Lb, 1e-12 * m.size());
      EXPECT_LT((sk.joint_positions[6 + i] - (fk.p_base_platform + m.r * leg_radial(i))).norm(), 1e-12 * m.size());
    }
  }
  EXPECT_EQ(shapes[0].name, "base");
  EXPECT_NEAR((shapes[1].polylines[0].back() - shapes[1].polylines[0].front()).norm(), m.La, 1e-15);
  EXPECT_NEAR((shapes[4].polylines[0].back() - shapes[4].polylines[0].front()).norm(), m.Lb, 1e-15);
  EXPECT_THROW(skeleton(m, home_pose(m), home_position(m) + Vector3d(1, 0, 0)), std::invalid_argument);
  EXPECT_THROW(skeleton(m, test_support::unassemblable_configuration(m, 9)), std::invalid_argument);
}
