#include <gtest/gtest.h>

#include <numbers>

#include "core/mechanisms/parallel12r/parallel12r.h"
#include "tests/core/mechanisms/parallel12r/reference_12r.h"

using namespace linkscape;
using namespace linkscape::parallel12r;
using linkscape::testing::ConfigurationSampler;
using linkscape::testing::paper_forward;
using linkscape::testing::make_12r;

namespace {


const IkMethod kAllMethods[] = {IkMethod::Paper, IkMethod::Planar, IkMethod::Newton,
                                IkMethod::DampedLeastSquares};

double angle_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Eigen::Vector3d d = a - b;
  for (int k = 0; k < 3; ++k) d(k) = std::remainder(d(k), 2 * std::numbers::pi);
  return d.norm();
}

// Round trip for the closed forms: every configuration's own branch must come
// back, and every solution returned must reproduce the target through the
// independent Eqs. 11-13.
void check_closed_form_round_trip(const Model& m, IkMethod method, unsigned seed, int count) {
  ConfigurationSampler sample(seed);
  int found_own_branch = 0;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d q = sample();
    const Eigen::Vector3d p = forward(m, q);
    const IkResult r = inverse(m, p, method);
    ASSERT_EQ(r.status, Status::Ok) << to_string(method) << " q=" << q.transpose();
    ASSERT_EQ(r.solutions.size(), 2u);
    for (const IkSolution& s : r.solutions) {
      const Eigen::Vector3d back = paper_forward(m.L1, m.L2, s.q_actuated.x(), s.q_actuated.y(),
                                                 s.q_actuated.z());
      EXPECT_LT((back - p).norm(), 1e-9 * p.norm()) << to_string(method);
      EXPECT_EQ(s.branch, branch_of(s.q_actuated));
      if (s.branch == branch_of(q)) {
        // Angle error <= cond(J) * residual / |J|; 1e-6 rad covers cond up to ~1e6.
        if (angle_distance(s.q_actuated, q) < 1e-6) ++found_own_branch;
      }
    }
    EXPECT_NE(r.solutions[0].branch, r.solutions[1].branch);
  }
  // Configurations extremely close to the z axis lose angle accuracy (not
  // position accuracy); allow a handful.
  EXPECT_GE(found_own_branch, count - count / 1000) << to_string(method);
}

}  // namespace

TEST(Inverse, PlanarRoundTripsTenThousandConfigurations) {
  check_closed_form_round_trip(make_12r(1, 1), IkMethod::Planar, 21, 10000);
  check_closed_form_round_trip(make_12r(15, 15), IkMethod::Planar, 22, 10000);
  check_closed_form_round_trip(make_12r(1.0, 1.7), IkMethod::Planar, 23, 10000);
}

TEST(Inverse, PaperRoundTripsTenThousandConfigurations) {
  check_closed_form_round_trip(make_12r(1, 1), IkMethod::Paper, 31, 10000);
  check_closed_form_round_trip(make_12r(15, 15), IkMethod::Paper, 32, 10000);
  check_closed_form_round_trip(make_12r(1.0, 1.7), IkMethod::Paper, 33, 10000);
}

TEST(Inverse, NumericalMethodsRoundTripFromNearbySeeds) {
  // Seeded within 0.1 rad of the answer, both iterative methods must land on
  // a true solution to full accuracy. Near singular sets Newton's basin
  // shrinks with the condition number, so this covers target and seed both
  // with c(J) <= 50 (the singular neighbourhoods are swept separately).
  for (IkMethod method : {IkMethod::Newton, IkMethod::DampedLeastSquares}) {
    for (const Model& m : {make_12r(1, 1), make_12r(1.0, 1.7)}) {
      ConfigurationSampler sample(41, 0.15);
      std::mt19937_64 rng(42);
      std::uniform_real_distribution<double> jitter(-0.1 / std::sqrt(3.0), 0.1 / std::sqrt(3.0));
      int tried = 0;
      for (int i = 0; i < 10000; ++i) {
        const Eigen::Vector3d q = sample();
        if (conditioning(m, q).cond > 50) continue;
        const Eigen::Vector3d p = forward(m, q);
        IkOptions options;
        options.seed = q + Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
        if (conditioning(m, *options.seed).cond > 50) continue;
        ++tried;
        const IkResult r = inverse(m, p, method, options);
        ASSERT_EQ(r.status, Status::Ok) << to_string(method) << " q=" << q.transpose()
                                        << " seed=" << options.seed->transpose() << " got="
                                        << r.solutions.at(0).q_actuated.transpose();
        ASSERT_EQ(r.solutions.size(), 1u);
        const IkSolution& s = r.solutions[0];
        const Eigen::Vector3d back = paper_forward(m.L1, m.L2, s.q_actuated.x(), s.q_actuated.y(),
                                                   s.q_actuated.z());
        EXPECT_LT((back - p).norm(), 1e-9 * p.norm());
        EXPECT_GT(s.iterations, 0);
      }
      EXPECT_GT(tried, 9000);
    }
  }
}

TEST(Inverse, NumericalMethodsFromDefaultSeedsAgreeWithPlanar) {
  // Without a seed they start from each branch's home pose; whatever they
  // return must be a true solution and match the planar solution of its branch.
  const Model m = make_12r(1, 1);
  ConfigurationSampler sample(51, 0.2);
  for (IkMethod method : {IkMethod::Newton, IkMethod::DampedLeastSquares}) {
    int ok = 0;
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3d p = forward(m, sample());
      const IkResult planar = inverse(m, p, IkMethod::Planar);
      const IkResult r = inverse(m, p, method);
      for (const IkSolution& s : r.solutions) {
        if (s.status != Status::Ok) continue;
        ++ok;
        EXPECT_LT(angle_distance(s.q_actuated, planar.solutions[s.branch].q_actuated), 1e-6);
      }
    }
    EXPECT_GT(ok, 2000) << to_string(method);  // more than one branch on average
  }
}

TEST(Inverse, AllMethodsAgreeOnTheFigure5Optimum) {
  const Model m = make_12r(1, 1);
  for (IkMethod method : kAllMethods) {
    const IkResult r = inverse(m, {0.0, 1.0, 1.0}, method);
    ASSERT_EQ(r.status, Status::Ok) << to_string(method);
    for (const IkSolution& s : r.solutions) {
      const Eigen::Vector3d expected = s.branch == 0 ? home_pose(0) : home_pose(1);
      EXPECT_LT(angle_distance(s.q_actuated, expected), 1e-7) << to_string(method);
    }
  }
}

TEST(Inverse, UnreachableTargetsAreReportedNotNaN) {
  const Model m = make_12r(1, 0.6);
  for (IkMethod method : kAllMethods) {
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 1.7, 0.1), Eigen::Vector3d(0.1, 0.2, 0.05),
                                     Eigen::Vector3d(5, 5, 5)}) {
      const IkResult r = inverse(m, p, method);
      EXPECT_EQ(r.status, Status::Unreachable) << to_string(method) << " " << p.transpose();
      EXPECT_TRUE(r.solutions.empty());
    }
  }
}

TEST(Inverse, SingularTargetsAreReported) {
  const Model m = make_12r(1, 1);
  for (IkMethod method : {IkMethod::Paper, IkMethod::Planar}) {
    // Actuator plane y = 0, z axis, outer sphere.
    EXPECT_EQ(inverse(m, {0.5, 0.0, 0.5}, method).status, Status::Singular) << to_string(method);
    EXPECT_EQ(inverse(m, {0.0, 0.0, 1.0}, method).status, Status::Singular) << to_string(method);
    const IkResult stretched = inverse(m, Eigen::Vector3d(0.3, 1.0, 0.4).normalized() * 2.0, method);
    EXPECT_EQ(stretched.status, Status::Singular) << to_string(method);
    ASSERT_EQ(stretched.solutions.size(), 1u) << to_string(method);
    EXPECT_NEAR(std::sin(stretched.solutions[0].q_actuated.y() - stretched.solutions[0].q_actuated.z()),
                0.0, 1e-6);
  }
  for (IkMethod method : {IkMethod::Newton, IkMethod::DampedLeastSquares}) {
    const IkResult r = inverse(m, {0.0, 0.0, 1.0}, method);
    EXPECT_NE(r.status, Status::Ok) << to_string(method);
  }
}

TEST(Inverse, NearSingularTargetsStillSolveAccurately) {
  // 1e-9 away from each singular set the closed forms still return exact
  // positions (accuracy in angles degrades with the condition number).
  const Model m = make_12r(1, 1);
  const Eigen::Vector3d targets[] = {{0.5, 1e-9, 0.5}, {1e-9, 1e-9, 1.0},
                                     Eigen::Vector3d(0.3, 1.0, 0.4).normalized() * (2.0 - 1e-9)};
  for (IkMethod method : {IkMethod::Paper, IkMethod::Planar}) {
    for (const auto& p : targets) {
      const IkResult r = inverse(m, p, method);
      for (const IkSolution& s : r.solutions)
        if (s.status == Status::Ok) {
          EXPECT_LT(s.residual, 1e-10) << to_string(method) << " " << p.transpose();
        }
      // Either a solution within tolerance or an explicit non-ok status.
      EXPECT_TRUE(r.status == Status::Ok || r.status == Status::NotConverged) << to_string(method);
    }
  }
}

TEST(Inverse, JointLimitsGiveOutOfLimits) {
  Model m = make_12r(1, 1);
  m.beta_limits = {-0.1, 0.1};
  const IkResult r = inverse(m, {0.0, 1.0, 1.0}, IkMethod::Planar);
  ASSERT_EQ(r.solutions.size(), 2u);
  // Branch 0 has beta = pi/2 (outside), branch 1 has beta = 0 (inside).
  EXPECT_EQ(r.solutions[0].status, Status::OutOfLimits);
  EXPECT_EQ(r.solutions[1].status, Status::Ok);
  EXPECT_EQ(r.status, Status::Ok);
}

TEST(Inverse, BadInputThrows) {
  EXPECT_THROW(inverse(make_12r(1, 1), {NAN, 0, 0}, IkMethod::Planar), std::invalid_argument);
  EXPECT_THROW(inverse(make_12r(-1, 1), {0, 1, 0}, IkMethod::Planar), std::invalid_argument);
  EXPECT_THROW(inverse(make_12r(1, 0), {0, 1, 0}, IkMethod::Paper), std::invalid_argument);
  EXPECT_THROW(inverse(make_12r(1, INFINITY), {0, 1, 0}, IkMethod::Paper), std::invalid_argument);
  IkOptions bad;
  bad.tolerance = 0;
  EXPECT_THROW(inverse(make_12r(1, 1), {0, 1, 1}, IkMethod::Newton, bad), std::invalid_argument);
  EXPECT_THROW(parse_ik_method("bogus"), std::invalid_argument);
  EXPECT_EQ(parse_ik_method("dls"), IkMethod::DampedLeastSquares);
}

TEST(Singularities, NearestSetAndDistance) {
  const Model m = make_12r(1, 1);
  // Near the actuator plane: 0.01 above it, far from the other sets.
  const Eigen::Vector3d q_plane = inverse(m, {0.5, 0.01, 0.6}, IkMethod::Planar).solutions[0].q_actuated;
  auto r = nearest_singularity(m, q_plane);
  EXPECT_EQ(r.nearest, SingularSet::ActuatorPlane);
  EXPECT_NEAR(r.distance, 0.01, 1e-14);
  // Near the z axis. The axis lies in the plane y = 0, so the plane is never
  // farther; the axis distance is reported alongside.
  r = nearest_singularity(m, inverse(m, {0.001, 0.002, 1.2}, IkMethod::Planar).solutions[0].q_actuated);
  EXPECT_NEAR(r.distances[static_cast<int>(SingularSet::ZAxis)], std::hypot(0.001, 0.002), 1e-14);
  EXPECT_NEAR(r.distance, 0.002, 1e-14);
  // Almost stretched.
  r = nearest_singularity(m, {0.1, 0.5, 0.5 + 1e-4});
  EXPECT_EQ(r.nearest, SingularSet::Stretched);
  EXPECT_LT(r.distance, 1e-7);
  // Almost folded, with unequal links so the inner sphere is not the centre.
  r = nearest_singularity(make_12r(1, 0.6), {0.1, 0.5, 0.5 + std::numbers::pi - 1e-4});
  EXPECT_EQ(r.nearest, SingularSet::Folded);
  EXPECT_LT(r.distance, 1e-7);
  // At the optimum every distance is order one.
  r = nearest_singularity(m, home_pose(0));
  EXPECT_GT(r.distance, 0.5);
  EXPECT_DOUBLE_EQ(r.static_measure, 1.0);
}
