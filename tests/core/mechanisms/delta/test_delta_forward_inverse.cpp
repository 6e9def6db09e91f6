// Forward and inverse kinematics of the Delta: round trips, closed form
// against Newton, FK against an independent long-double trilateration,
// unreachable targets and the model's boundary checks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/mechanisms/delta/delta.h"
#include "tests/core/mechanisms/delta/delta_test_support.h"

using namespace linkscape;
using namespace linkscape::delta;
using linkscape::delta::test_support::angle_distance;
using linkscape::delta::test_support::ConfigurationSampler;
using Eigen::Vector3d;

namespace {

// Angle accuracy of the IK is eps * size / |dF_i/dq_i| per leg; configurations
// whose forearm is within this sine of the elbow's motion plane are counted
// apart (position accuracy is checked for every one).
constexpr double kWellConditionedLeg = 1e-3;

double smallest_serial_index(const Model& m, const Vector3d& q, const Vector3d& p) {
  const SingularityReport s = nearest_singularity(m, q, p);
  return std::min({s.serial_index[0], s.serial_index[1], s.serial_index[2]});
}

struct RoundTrip {
  int assembled = 0, angle_checked = 0;
  double worst_position = 0.0, worst_angle = 0.0;
};

// q in range -> FK -> IK of q's own branch -> FK: the position must come
// back to 1e-9 of the size, the angles to 1e-9 rad away from type I.
RoundTrip round_trip(const Model& m, unsigned seed, int count) {
  ConfigurationSampler sample(m, seed);
  RoundTrip r;
  for (int k = 0; k < count; ++k) {
    const Vector3d q = sample();
    const FkResult fk = forward(m, q);
    EXPECT_TRUE(fk.p_base_platform.allFinite());
    if (fk.status != Status::Ok) continue;  // no platform, or two modes within tolerance
    ++r.assembled;
    IkOptions options;
    options.branch = branch_of(m, q, fk.p_base_platform);
    const IkResult ik = inverse(m, fk.p_base_platform, IkMethod::Closed, options);
    EXPECT_EQ(ik.status, Status::Ok) << q.transpose();
    EXPECT_EQ(ik.branch, options.branch);
    EXPECT_LE(ik.residual, 1e-12 * m.size());
    const FkResult back = forward(m, ik.q_actuated);
    const double position_error = (back.p_base_platform - fk.p_base_platform).norm();
    r.worst_position = std::max(r.worst_position, position_error);
    EXPECT_LE(position_error, 1e-9 * m.size()) << q.transpose();
    if (smallest_serial_index(m, q, fk.p_base_platform) > kWellConditionedLeg) {
      ++r.angle_checked;
      const double angle_error = angle_distance(ik.q_actuated, q);
      r.worst_angle = std::max(r.worst_angle, angle_error);
      EXPECT_LE(angle_error, 1e-9) << q.transpose();
    }
  }
  return r;
}

}  // namespace

TEST(DeltaInverse, ClosedFormRoundTripsOneHundredThousandConfigurations) {
  const Model m;
  const int count = 100000;
  const RoundTrip r = round_trip(m, 1, count);
  // Within the preset's ranges every configuration assembles, and nearly all
  // lie away from type I.
  EXPECT_EQ(r.assembled, count);
  EXPECT_GT(r.angle_checked, r.assembled * 99 / 100);
  RecordProperty("assembled", r.assembled);
  RecordProperty("angle_checked", r.angle_checked);
  RecordProperty("worst_position_over_size", test_support::scientific(r.worst_position / m.size()));
  RecordProperty("worst_angle_rad", test_support::scientific(r.worst_angle));
}

TEST(DeltaInverse, ClosedFormRoundTripsOverTheFullCircleOfEveryActuator) {
  // Every arm angle, so elbows in, platforms above the base and configurations
  // near both singular sets all occur.
  Model m;
  m.q_limits.fill({-std::numbers::pi, std::numbers::pi});
  const int count = 100000;
  const RoundTrip r = round_trip(m, 2, count);
  EXPECT_GT(r.assembled, count / 2);
  EXPECT_GT(r.angle_checked, r.assembled * 9 / 10);
  RecordProperty("assembled", r.assembled);
  RecordProperty("angle_checked", r.angle_checked);
  RecordProperty("worst_position_over_size", test_support::scientific(r.worst_position / m.size()));
  RecordProperty("worst_angle_rad", test_support::scientific(r.worst_angle));
}

TEST(DeltaInverse, EveryBranchClosesAndReportsItsElbows) {
  const Model m;
  const Vector3d p = home_position(m) + Vector3d(1.0, -2.0, 1.5);
  for (int branch = 0; branch < kBranchCount; ++branch) {
    IkOptions options;
    options.branch = branch;
    const IkResult ik = inverse(m, p, IkMethod::Closed, options);
    ASSERT_NE(ik.status, Status::Unreachable);
    EXPECT_LE(ik.residual, 1e-12 * m.size()) << branch;
    EXPECT_EQ(branch_of(m, ik.q_actuated, p), branch);
    // Elbow out: the elbow farther from the z axis than elbow in (platform below).
    for (int i = 0; i < kLegCount; ++i) {
      IkOptions other = options;
      other.branch = branch ^ (1 << i);
      const IkResult flipped = inverse(m, p, IkMethod::Closed, other);
      const double rho_this = elbow_position(m, i, ik.q_actuated(i)).head<2>().norm();
      const double rho_flipped = elbow_position(m, i, flipped.q_actuated(i)).head<2>().norm();
      if ((branch >> i) & 1) EXPECT_LT(rho_this, rho_flipped);
      else EXPECT_GT(rho_this, rho_flipped);
    }
  }
}

TEST(DeltaInverse, NewtonAgreesWithTheClosedForm) {
  const Model m;
  ConfigurationSampler sample(m, 3);
  std::uniform_real_distribution<double> nudge(-0.05, 0.05);
  int compared = 0, total_iterations = 0, most_iterations = 0;
  while (compared < 10000) {
    const Vector3d q = sample();
    const FkResult fk = forward(m, q);
    if (fk.status != Status::Ok) continue;
    if (smallest_serial_index(m, q, fk.p_base_platform) < 0.05) continue;  // Newton's basin shrinks there
    IkOptions options;
    options.branch = branch_of(m, q, fk.p_base_platform);
    const IkResult closed = inverse(m, fk.p_base_platform, IkMethod::Closed, options);
    options.seed = q + Vector3d(nudge(sample.rng()), nudge(sample.rng()), nudge(sample.rng()));
    const IkResult newton = inverse(m, fk.p_base_platform, IkMethod::Newton, options);
    ASSERT_EQ(newton.status, Status::Ok) << q.transpose();
    EXPECT_EQ(newton.method, IkMethod::Newton);
    EXPECT_EQ(newton.branch, closed.branch);
    ASSERT_LE(angle_distance(newton.q_actuated, closed.q_actuated), 1e-11) << q.transpose();
    EXPECT_LE(newton.residual, 1e-12 * m.size());
    EXPECT_GT(newton.iterations, 0);
    total_iterations += newton.iterations;
    most_iterations = std::max(most_iterations, newton.iterations);
    ++compared;
  }
  RecordProperty("mean_iterations", test_support::scientific(double(total_iterations) / compared));
  RecordProperty("most_iterations", most_iterations);
}

TEST(DeltaInverse, NewtonFromHomeFindsTheWorkingBranchNearHome) {
  const Model m;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> offset(-3.0, 3.0);
  for (int k = 0; k < 1000; ++k) {
    const Vector3d p = home_position(m) + Vector3d(offset(rng), offset(rng), offset(rng));
    const IkResult closed = inverse(m, p, IkMethod::Closed);
    const IkResult newton = inverse(m, p, IkMethod::Newton);  // seeded at home_pose
    ASSERT_EQ(closed.status, Status::Ok);
    ASSERT_EQ(newton.status, Status::Ok);
    EXPECT_EQ(newton.branch, 0);
    EXPECT_LE(angle_distance(newton.q_actuated, closed.q_actuated), 1e-11);
  }
}

TEST(DeltaInverse, UnreachableTargetsAreReportedAndNeverNaN) {
  const Model m;
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> coordinate(-3.0 * m.size(), 3.0 * m.size());
  int unreachable = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vector3d p(coordinate(rng), coordinate(rng), coordinate(rng));
    for (IkMethod method : {IkMethod::Closed, IkMethod::Newton}) {
      for (int branch : {0, 5}) {
        IkOptions options;
        options.branch = branch;
        const IkResult ik = inverse(m, p, method, options);
        ASSERT_TRUE(ik.q_actuated.allFinite()) << p.transpose();
        ASSERT_TRUE(std::isfinite(ik.residual)) << p.transpose();
        double worst_leg = std::numeric_limits<double>::infinity();
        for (int i = 0; i < kLegCount; ++i) worst_leg = std::min(worst_leg, leg_margin(m, i, p));
        if (worst_leg < -kSingularTolerance * m.size()) {
          ASSERT_EQ(ik.status, Status::Unreachable) << p.transpose();
          // The closest approach misses by the margin: the residual says how far.
          EXPECT_NEAR(ik.residual, -worst_leg, 1e-9 * m.size());
          if (method == IkMethod::Closed && branch == 0) ++unreachable;
        } else {
          ASSERT_NE(ik.status, Status::Unreachable) << p.transpose();
        }
      }
    }
  }
  EXPECT_GT(unreachable, 10000);  // the box is mostly outside the workspace
}

TEST(DeltaInverse, LegMarginIsTheClosestApproachOfTheElbowCircle) {
  // Independent of the closed form: sweep the arm angle and find how close
  // the forearm length can come to Lb; leg_margin must match its sign and,
  // outside, its size (the closest approach is the nearest or farthest elbow).
  const Model m;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> coordinate(-m.size(), m.size());
  constexpr int kSamples = 20000;  // angle step 3e-4 rad
  for (int k = 0; k < 200; ++k) {
    const Vector3d p(coordinate(rng), coordinate(rng), coordinate(rng) - 0.5 * m.size());
    for (int i = 0; i < kLegCount; ++i) {
      const Vector3d C = p + m.r * leg_radial(i);
      double closest = std::numeric_limits<double>::infinity();
      for (int s = 0; s < kSamples; ++s) {
        const double q = -std::numbers::pi + 2 * std::numbers::pi * s / kSamples;
        closest = std::min(closest, std::abs((C - elbow_position(m, i, q)).norm() - m.Lb));
      }
      const double margin = leg_margin(m, i, p);
      if (margin < 0) EXPECT_NEAR(closest, -margin, 1e-7 * m.size());
      else EXPECT_LT(closest, 1e-3 * m.size());  // a crossing exists: sampled near zero
    }
  }
}

TEST(DeltaForward, ClosedFormMatchesLongDoubleTrilateration) {
  const Model m;
  ConfigurationSampler sample(m, 6);
  int matched = 0, tight = 0;
  double worst_tight = 0.0;
  for (int k = 0; k < 20000; ++k) {
    const Vector3d q = sample();
    std::array<test_support::Vector3ld, 2> reference;
    const bool exists = test_support::reference_forward(m, q, reference);
    const FkResult fk = forward(m, q);
    if (!exists) {
      ASSERT_EQ(fk.status, Status::Unreachable) << q.transpose();
      continue;
    }
    ASSERT_EQ(fk.status, Status::Ok) << q.transpose();
    // The pair of solutions is the same; which one is "working" is checked
    // below by the sign of det Jx, also from the reference.
    const Vector3d r0 = reference[0].cast<double>(), r1 = reference[1].cast<double>();
    const double e_same = std::max((fk.p_base_platform - r0).norm(), (fk.p_other_mode - r1).norm());
    const double e_swap = std::max((fk.p_base_platform - r1).norm(), (fk.p_other_mode - r0).norm());
    const double error = std::min(e_same, e_swap);
    const Vector3d working = e_same < e_swap ? r0 : r1;
    const double separation = (r0 - r1).norm();
    // Rounding grows like size^2 / separation near type II.
    ASSERT_LE(error, 1e-13 * m.size() * std::max(1.0, m.size() / separation)) << q.transpose();
    if (separation > 1e-3 * m.size()) {
      ++tight;
      worst_tight = std::max(worst_tight, error / m.size());
    }
    Eigen::Matrix3d Jx;
    for (int i = 0; i < 3; ++i)
      Jx.row(i) = (working - test_support::reference_sphere_centre(m, i, q(i)).cast<double>()).transpose();
    EXPECT_LT(Jx.determinant(), 0.0) << q.transpose();
    ++matched;
  }
  EXPECT_GT(matched, 10000);
  EXPECT_GT(tight, matched * 99 / 100);
  RecordProperty("worst_error_over_size", test_support::scientific(worst_tight));
}

TEST(DeltaForward, NewtonAgreesWithTheClosedFormAndFindsTheMirrorFromTheOtherSide) {
  const Model m;
  ConfigurationSampler sample(m, 7);
  std::uniform_real_distribution<double> nudge(-0.5, 0.5);
  int compared = 0, total_iterations = 0, most_iterations = 0;
  while (compared < 10000) {
    const Vector3d q = sample();
    const FkResult closed = forward(m, q);
    if (closed.status != Status::Ok) continue;
    if (nearest_singularity(m, q, closed.p_base_platform).parallel_index < 0.05) continue;
    FkOptions options;
    options.seed = closed.p_base_platform + Vector3d(nudge(sample.rng()), nudge(sample.rng()), nudge(sample.rng()));
    const FkResult newton = forward(m, q, FkMethod::Newton, options);
    ASSERT_EQ(newton.status, Status::Ok) << q.transpose();
    EXPECT_EQ(newton.assembly_mode, 0);
    ASSERT_LE((newton.p_base_platform - closed.p_base_platform).norm(), 1e-12 * m.size());
    EXPECT_LE((newton.p_other_mode - closed.p_other_mode).norm(), 1e-11 * m.size());
    total_iterations += newton.iterations;
    most_iterations = std::max(most_iterations, newton.iterations);
    // Seeded beyond the mirror plane, Newton lands in the other mode.
    options.seed = closed.p_other_mode;
    const FkResult mirror = forward(m, q, FkMethod::Newton, options);
    ASSERT_EQ(mirror.status, Status::Ok);
    EXPECT_EQ(mirror.assembly_mode, 1);
    EXPECT_LE((mirror.p_base_platform - closed.p_other_mode).norm(), 1e-12 * m.size());
    ++compared;
  }
  RecordProperty("mean_iterations", test_support::scientific(double(total_iterations) / compared));
  RecordProperty("most_iterations", most_iterations);
}

TEST(DeltaForward, NewtonReportsUnreachableAndRunningOutOfIterations) {
  const Model m;
  const Vector3d q_apart = test_support::unassemblable_configuration(m, 8);
  // Independently: the long-double trilateration finds no point either.
  std::array<test_support::Vector3ld, 2> none;
  EXPECT_FALSE(test_support::reference_forward(m, q_apart, none)) << q_apart.transpose();
  EXPECT_EQ(forward(m, q_apart, FkMethod::Newton).status, Status::Unreachable);
  FkOptions one;
  one.max_iterations = 1;
  one.seed = home_position(m) + Vector3d(4, 4, 4);
  const FkResult short_run = forward(m, home_pose(m), FkMethod::Newton, one);
  EXPECT_EQ(short_run.status, Status::NotConverged);
  EXPECT_TRUE(short_run.p_base_platform.allFinite());
}

TEST(DeltaForward, ReportsActuatorRanges) {
  const Model m;
  Vector3d q = home_pose(m);
  ASSERT_EQ(forward(m, q).status, Status::Ok);
  q(1) = m.q_limits[1].hi + 0.01;
  const FkResult fk = forward(m, q);
  EXPECT_EQ(fk.status, Status::OutOfLimits);
  IkOptions options;
  options.branch = branch_of(m, q, fk.p_base_platform);
  EXPECT_EQ(inverse(m, fk.p_base_platform, IkMethod::Closed, options).status, Status::OutOfLimits);
  // Ranges hold modulo 2 pi.
  Vector3d wrapped = home_pose(m);
  wrapped(2) += 2 * std::numbers::pi;
  EXPECT_EQ(forward(m, wrapped).status, Status::Ok);
}

TEST(DeltaModel, ParametersRangesAndBadInput) {
  const Model m = Model::from_parameters({{"R", 10}, {"r", 3}, {"La", 7}, {"Lb", 20}},
                                         {{"q2", {-10, 80}}}, "cm");
  EXPECT_DOUBLE_EQ(m.R, 10);
  EXPECT_DOUBLE_EQ(m.Lb, 20);
  EXPECT_NEAR(m.q_limits[1].hi, 80 * std::numbers::pi / 180, 1e-15);
  EXPECT_EQ(m.to_parameters().size(), Model::parameter_names().size());
  for (const auto& name : Model::parameter_names()) EXPECT_TRUE(m.to_parameters().contains(name)) << name;

  EXPECT_THROW(Model::from_parameters({{"L1", 1}}, {}, "cm"), std::invalid_argument);
  EXPECT_THROW(Model::from_parameters({}, {{"q4", {0, 1}}}, "cm"), std::invalid_argument);
  EXPECT_THROW(Model::from_parameters({{"Lb", -1}}, {}, "cm"), std::invalid_argument);
  EXPECT_THROW(Model::from_parameters({{"La", 0}}, {}, "cm"), std::invalid_argument);
  EXPECT_THROW(Model::from_parameters({{"r", -0.1}}, {}, "cm"), std::invalid_argument);
  EXPECT_THROW(Model::from_parameters({{"R", NAN}}, {}, "cm"), std::invalid_argument);
  EXPECT_THROW(Model::from_parameters({}, {{"q1", {10, -10}}}, "cm"), std::invalid_argument);
  EXPECT_THROW(Model::from_parameters({}, {{"q1", {-200, 200}}}, "cm"), std::invalid_argument);

  const Model d;
  const Vector3d nan(NAN, 0, 0);
  EXPECT_THROW(inverse(d, nan), std::invalid_argument);
  EXPECT_THROW(forward(d, nan), std::invalid_argument);
  IkOptions bad_branch;
  bad_branch.branch = 8;
  EXPECT_THROW(inverse(d, home_position(d), IkMethod::Closed, bad_branch), std::invalid_argument);
  IkOptions bad_tolerance;
  bad_tolerance.tolerance = 0;
  EXPECT_THROW(inverse(d, home_position(d), IkMethod::Newton, bad_tolerance), std::invalid_argument);
  EXPECT_THROW(leg_margin(d, 3, home_position(d)), std::invalid_argument);
  EXPECT_THROW(leg_inverse(d, -1, home_position(d), false), std::invalid_argument);
  EXPECT_EQ(parse_ik_method("newton"), IkMethod::Newton);
  EXPECT_EQ(parse_fk_method(to_string(FkMethod::Closed)), FkMethod::Closed);
  EXPECT_THROW(parse_ik_method("paper"), std::invalid_argument);
  EXPECT_THROW(parse_fk_method(""), std::invalid_argument);
}
