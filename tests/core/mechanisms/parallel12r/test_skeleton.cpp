#include <gtest/gtest.h>

#include "core/mechanisms/parallel12r/parallel12r.h"
#include "tests/core/mechanisms/parallel12r/reference_12r.h"

using namespace linkscape::parallel12r;
using linkscape::testing::ConfigurationSampler;
using linkscape::testing::paper_forward;

// Each joint is defined in the frames of both links it connects. The loops
// close when, at every pose, the two links put the joint at the same point on
// the same axis; the chains through A and through B (or C) are independent,
// so this checks the passive angles of every loop.
TEST(Skeleton, EveryJointClosesAtEveryPose) {
  ConfigurationSampler sample(61, 0.02);
  for (double L2 : {1.0, 1.6}) {
    Model m;
    m.L2 = L2;
    const auto defs = joint_definitions(m);
    for (int i = 0; i < 5000; ++i) {
      const Eigen::Vector3d q = sample();
      const Skeleton sk = skeleton(m, q);
      for (const JointDefinition& j : defs) {
        const auto& Ta = sk.link_frames[j.link_a - 1];
        const auto& Tb = sk.link_frames[j.link_b - 1];
        EXPECT_LT((Ta * j.point_in_a - Tb * j.point_in_b).norm(), 1e-12) << j.name;
        EXPECT_LT((Ta.linear() * j.axis_in_a - Tb.linear() * j.axis_in_b).norm(), 1e-12) << j.name;
      }
    }
  }
}

TEST(Skeleton, EndpointIsForwardGeometry) {
  Model m;
  m.L1 = 15;
  m.L2 = 12;
  ConfigurationSampler sample(62);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d q = sample();
    EXPECT_LT((skeleton(m, q).endpoint - paper_forward(15, 12, q.x(), q.y(), q.z())).norm(), 1e-12);
  }
}

TEST(Skeleton, SphericalJointsPassThroughTheCentreAndPlanarAxesAreParallel) {
  Model m;
  const auto defs = joint_definitions(m);
  const Eigen::Vector3d q(0.3, 0.8, -0.5);
  const Skeleton sk = skeleton(m, q);
  const Eigen::Vector3d n(std::cos(q.x()), std::sin(q.x()), 0.0);
  for (int j = 0; j < kJointCount; ++j) {
    const bool planar = defs[j].name == "6-10" || defs[j].name == "10-9" || defs[j].name == "9-4";
    if (planar) {
      EXPECT_LT((sk.joint_axes[j] - n).norm(), 1e-12) << defs[j].name;
    } else {
      // The axis line through the joint point passes through the origin.
      EXPECT_LT(sk.joint_positions[j].cross(sk.joint_axes[j]).norm(), 1e-12) << defs[j].name;
    }
  }
}

TEST(Skeleton, HasTenLinksAndTwelveJoints) {
  Model m;
  const auto shapes = link_shapes(m);
  for (const LinkShape& s : shapes) EXPECT_FALSE(s.polylines.empty());
  const auto defs = joint_definitions(m);
  // Every paper link 1..10 appears in some joint; ground carries A, B, C.
  std::array<int, kLinkCount + 1> uses{};
  for (const auto& j : defs) {
    ++uses[j.link_a];
    ++uses[j.link_b];
  }
  for (int k = 1; k <= kLinkCount; ++k) EXPECT_GE(uses[k], 2) << "link " << k;
  EXPECT_EQ(uses[1], 3);                       // ground: A, B, C
  EXPECT_EQ(uses[4] + uses[5] + uses[6], 9);   // ternary links 4, 5, 6
}
