// Jacobian of the Delta against finite differences, the determinant relation,
// the three-fold and mirror symmetry of c(J), and honest statuses at and near
// each singular set.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/conditioning.h"
#include "core/mechanisms/delta/delta.h"
#include "tests/core/mechanisms/delta/delta_test_support.h"

using namespace linkscape;
using namespace linkscape::delta;
using linkscape::delta::test_support::angle_distance;
using linkscape::delta::test_support::ConfigurationSampler;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

struct Assembled {
  Vector3d q, p;
};

// Configurations in range that assemble (FK Ok) with c(J) at most max_cond.
std::vector<Assembled> sample_assembled(const Model& m, unsigned seed, int count, double max_cond) {
  ConfigurationSampler sample(m, seed);
  std::vector<Assembled> out;
  while (int(out.size()) < count) {
    const Vector3d q = sample();
    const FkResult fk = forward(m, q);
    if (fk.status != Status::Ok) continue;
    if (jacobian(m, q, fk.p_base_platform).cond > max_cond) continue;
    out.push_back({q, fk.p_base_platform});
  }
  return out;
}

double relative_max_error(const Matrix3d& a, const Matrix3d& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / b.lpNorm<Eigen::Infinity>();
}

Matrix3d rot_z(double angle) { return Eigen::AngleAxisd(angle, Vector3d::UnitZ()).toRotationMatrix(); }

// Leg i's elbow bit moves to leg (i + shift) mod 3.
int rotate_branch(int branch, int shift) {
  int out = 0;
  for (int i = 0; i < kLegCount; ++i)
    if ((branch >> i) & 1) out |= 1 << ((i + shift) % kLegCount);
  return out;
}

}  // namespace

TEST(DeltaJacobian, MatchesCentralDifferencesOfTheForwardKinematics) {
  const Model m;
  double worst = 0.0;
  for (const Assembled& c : sample_assembled(m, 11, 10000, 1e3)) {
    const JacobianResult J = jacobian(m, c.q, c.p);
    ASSERT_EQ(J.status, Status::Ok);
    const Matrix3d fd = jacobian_central_difference(m, c.q, 1e-6);
    const double e = relative_max_error(J.J_task_from_actuated, fd);
    worst = std::max(worst, e);
    // Step 1e-6 rad: truncation ~1e-12, rounding ~1e-10 of |J| at c(J) <= 1e3.
    ASSERT_LT(e, 1e-6) << c.q.transpose();
  }
  RecordProperty("worst_relative_error", test_support::scientific(worst));
}

TEST(DeltaJacobian, InverseMatchesCentralDifferencesOfTheInverseKinematics) {
  const Model m;
  const double h = 1e-6 * m.size();
  for (const Assembled& c : sample_assembled(m, 12, 5000, 1e3)) {
    const JacobianResult J = jacobian(m, c.q, c.p);
    IkOptions options;
    options.branch = branch_of(m, c.q, c.p);
    Matrix3d fd;
    for (int k = 0; k < 3; ++k) {
      const Vector3d dp = h * Vector3d::Unit(k);
      const IkResult plus = inverse(m, c.p + dp, IkMethod::Closed, options);
      const IkResult minus = inverse(m, c.p - dp, IkMethod::Closed, options);
      ASSERT_NE(plus.status, Status::Unreachable);
      ASSERT_NE(minus.status, Status::Unreachable);
      Vector3d dq = plus.q_actuated - minus.q_actuated;
      for (int i = 0; i < 3; ++i) dq(i) = std::remainder(dq(i), 2 * std::numbers::pi);
      fd.col(k) = dq / (2 * h);
    }
    ASSERT_LT(relative_max_error(J.J_actuated_from_task, fd), 1e-6) << c.q.transpose();
  }
}

TEST(DeltaJacobian, DeterminantRelationAndInverse) {
  const Model m;
  for (const Assembled& c : sample_assembled(m, 13, 10000, 1e4)) {
    const JacobianResult J = jacobian(m, c.q, c.p);
    // det J = -det Jq / det Jx, against the determinant of the matrix itself.
    EXPECT_NEAR(J.det_J, J.J_task_from_actuated.determinant(), 1e-10 * std::abs(J.det_J));
    EXPECT_NEAR(J.det_J, -J.Jq_diagonal.prod() / J.Jx.determinant(), 1e-10 * std::abs(J.det_J));
    EXPECT_NEAR(J.det_Jx, J.Jx.determinant(), 1e-10 * std::abs(J.det_Jx));
    // The working mode has det Jx < 0.
    EXPECT_LT(J.det_Jx, 0.0);
    // J is the inverse of dq/dp and satisfies Jx J + Jq = 0.
    const Matrix3d product = J.J_task_from_actuated * J.J_actuated_from_task;
    EXPECT_LT((product - Matrix3d::Identity()).lpNorm<Eigen::Infinity>(), 1e-12 * J.cond);
    const Matrix3d closure = J.Jx * J.J_task_from_actuated + Matrix3d(J.Jq_diagonal.asDiagonal());
    EXPECT_LT(closure.lpNorm<Eigen::Infinity>(), 1e-12 * J.cond * J.Jq_diagonal.cwiseAbs().maxCoeff());
    // c(J) is sigma_max / sigma_min of J itself.
    EXPECT_NEAR(J.cond, condition_number_svd(J.J_task_from_actuated), 1e-9 * J.cond);
  }
}

TEST(DeltaJacobian, ConditionNumberIsInvariantUnderTheDevicesSymmetries) {
  // Rotating the target by 120 degrees about z maps leg i's problem onto leg
  // i + 1's: the angles permute and c(J) cannot change. Mirroring y -> -y
  // swaps legs 2 and 3 (0-based 1 and 2) and keeps leg 1.
  const Model m;
  std::mt19937_64 rng(14);
  std::uniform_int_distribution<int> branch_pick(0, kBranchCount - 1);
  double worst = 0.0;
  for (const Assembled& c : sample_assembled(m, 14, 20000, 1e6)) {
    const int branch = branch_pick(rng) & branch_of(m, c.q, c.p);  // mostly elbows out
    IkOptions options;
    options.branch = branch;
    const IkResult ik = inverse(m, c.p, IkMethod::Closed, options);
    ASSERT_NE(ik.status, Status::Unreachable);
    const double cond = jacobian(m, ik.q_actuated, c.p).cond;
    for (int shift : {1, 2}) {
      const Vector3d p_rotated = rot_z(shift * 2 * std::numbers::pi / 3) * c.p;
      IkOptions rotated_options;
      rotated_options.branch = rotate_branch(branch, shift);
      const IkResult rotated = inverse(m, p_rotated, IkMethod::Closed, rotated_options);
      ASSERT_NE(rotated.status, Status::Unreachable);
      for (int i = 0; i < kLegCount; ++i)
        ASSERT_NEAR(std::remainder(rotated.q_actuated((i + shift) % 3) - ik.q_actuated(i), 2 * std::numbers::pi),
                    0.0, 1e-11);
      const double rotated_cond = jacobian(m, rotated.q_actuated, p_rotated).cond;
      worst = std::max(worst, std::abs(rotated_cond - cond) / cond);
      ASSERT_NEAR(rotated_cond, cond, 1e-9 * cond) << c.q.transpose();
    }
    const Vector3d p_mirrored(c.p.x(), -c.p.y(), c.p.z());
    IkOptions mirrored_options;
    mirrored_options.branch = (branch & 1) | ((branch >> 1) & 1) << 2 | ((branch >> 2) & 1) << 1;
    const IkResult mirrored = inverse(m, p_mirrored, IkMethod::Closed, mirrored_options);
    EXPECT_NEAR(mirrored.q_actuated(0), ik.q_actuated(0), 1e-11);
    EXPECT_NEAR(mirrored.q_actuated(1), ik.q_actuated(2), 1e-11);
    EXPECT_NEAR(jacobian(m, mirrored.q_actuated, p_mirrored).cond, cond, 1e-9 * cond);
  }
  RecordProperty("worst_relative_difference", test_support::scientific(worst));
}

// ---- Type I: a leg's forearm normal to its elbow's motion ----------------------

TEST(DeltaSingular, SerialSetOfEachLegGetsSingularThenOkInsideAndUnreachableOutside) {
  const Model m;
  ConfigurationSampler sample(m, 21);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  const double tol = kSingularTolerance * m.size();
  const double delta = 1e-6 * m.size();
  int tested[kLegCount] = {0, 0, 0};
  while (std::min({tested[0], tested[1], tested[2]}) < 200) {
    const Vector3d q = sample();
    const int leg = int(sample.rng()() % kLegCount);
    // Forearm in the plane of the arm and the motor axis: dF/dq = 0.
    const Vector3d arm = (elbow_position(m, leg, q(leg)) - motor_position(m, leg)) / m.La;
    const double beta = angle(sample.rng());
    const Vector3d forearm = std::cos(beta) * arm + std::sin(beta) * leg_motor_axis(leg);
    const Vector3d p = elbow_position(m, leg, q(leg)) + m.Lb * forearm - m.r * leg_radial(leg);
    bool others_fine = true;
    for (int i = 0; i < kLegCount; ++i)
      if (i != leg && leg_margin(m, i, p) < 1e-2 * m.size()) others_fine = false;
    if (!others_fine) continue;
    ++tested[leg];

    ASSERT_LE(std::abs(leg_margin(m, leg, p)), 10 * tol);
    // The two elbows merge: both branches of the leg are Singular and agree.
    IkOptions out, in;
    in.branch = 1 << leg;
    const IkResult ik_out = inverse(m, p, IkMethod::Closed, out);
    const IkResult ik_in = inverse(m, p, IkMethod::Closed, in);
    for (const IkResult* ik : {&ik_out, &ik_in}) {
      ASSERT_EQ(ik->status, Status::Singular) << p.transpose();
      EXPECT_EQ(ik->leg_status[leg], Status::Singular);
      EXPECT_TRUE(ik->q_actuated.allFinite());
      EXPECT_LE(ik->residual, 1e-12 * m.size());
    }
    EXPECT_LT(angle_distance(ik_out.q_actuated, ik_in.q_actuated), 1e-5);
    EXPECT_LT(std::abs(std::remainder(ik_out.q_actuated(leg) - q(leg), 2 * std::numbers::pi)), 1e-5);
    EXPECT_EQ(inverse(m, p, IkMethod::Newton, out).status, Status::Singular);
    const JacobianResult J = jacobian(m, ik_out.q_actuated, p);
    EXPECT_EQ(J.status, Status::Singular);
    EXPECT_TRUE(std::isinf(J.cond));
    const SingularityReport at = nearest_singularity(m, ik_out.q_actuated, p);
    EXPECT_EQ(at.nearest, static_cast<SingularSet>(leg));
    EXPECT_LE(at.distance, 10 * tol);
    EXPECT_LT(at.serial_index[leg], 1e-5);

    // Along the forearm the margin changes at unit rate: the leg margin is a
    // Euclidean distance. The elbow is the circle's nearest point to the
    // joint when the joint lies beyond it in the leg's plane, else the farthest.
    const bool nearest = m.La + m.Lb * std::cos(beta) > 0;
    const Vector3d inward = nearest ? -forearm : forearm;
    EXPECT_NEAR(leg_margin(m, leg, p + delta * inward), delta, 1e-9 * m.size());
    EXPECT_NEAR(leg_margin(m, leg, p - delta * inward), -delta, 1e-9 * m.size());

    const IkResult inside = inverse(m, p + delta * inward);
    EXPECT_TRUE(inside.status == Status::Ok || inside.status == Status::OutOfLimits) << to_string(inside.status);
    const JacobianResult J_inside = jacobian(m, inside.q_actuated, p + delta * inward);
    EXPECT_EQ(J_inside.status, Status::Ok);
    EXPECT_TRUE(std::isfinite(J_inside.cond));
    EXPECT_GT(J_inside.cond, 100.0);  // ~ 1 / sqrt(delta / size)
    const SingularityReport near = nearest_singularity(m, inside.q_actuated, p + delta * inward);
    EXPECT_EQ(near.nearest, static_cast<SingularSet>(leg));
    EXPECT_NEAR(near.distance, delta, 1e-9 * m.size());

    const IkResult outside = inverse(m, p - delta * inward);
    EXPECT_EQ(outside.status, Status::Unreachable);
    EXPECT_EQ(outside.leg_status[leg], Status::Unreachable);
    EXPECT_TRUE(outside.q_actuated.allFinite());
    EXPECT_NEAR(outside.residual, delta, 1e-9 * m.size());
  }
}

// ---- Type II: the three forearms coplanar ------------------------------------

namespace {

long double circumradius_gap(const Model& m, const Vector3d& q12, long double q3) {
  using test_support::Vector3ld;
  const Vector3ld c0 = test_support::reference_sphere_centre(m, 0, q12(0));
  const Vector3ld c1 = test_support::reference_sphere_centre(m, 1, q12(1));
  const Vector3ld c2 = test_support::reference_sphere_centre(m, 2, q3);
  const Vector3ld a = c0 - c2, b = c1 - c2;
  return static_cast<long double>(m.Lb) - a.norm() * b.norm() * (a - b).norm() / (2.0L * a.cross(b).norm());
}

}  // namespace

TEST(DeltaSingular, ParallelSetGetsSingularForwardAndRegularInverse) {
  // Within the preset's ranges the forearms never become coplanar; with the
  // ranges opened to the full circle they do.
  Model m;
  m.q_limits.fill({-std::numbers::pi, std::numbers::pi});
  ConfigurationSampler sample(m, 22);
  const double lo = m.q_limits[2].lo, hi = m.q_limits[2].hi;
  int tested = 0;
  for (int attempt = 0; attempt < 100000 && tested < 200; ++attempt) {
    const Vector3d q12 = sample();
    // Scan q3 over its range for a sign change of Lb - circumradius.
    const int steps = 400;
    long double a = lo, ga = circumradius_gap(m, q12, a);
    bool found = false;
    long double b = a, gb = ga;
    for (int k = 1; k <= steps && !found; ++k) {
      b = lo + (hi - lo) * k / steps;
      gb = circumradius_gap(m, q12, b);
      if ((ga < 0) != (gb < 0)) found = true;
      else a = b, ga = gb;
    }
    if (!found) continue;
    for (int k = 0; k < 80; ++k) {  // bisection in long double
      const long double mid = 0.5L * (a + b), gm = circumradius_gap(m, q12, mid);
      if ((gm < 0) == (ga < 0)) a = mid, ga = gm;
      else b = mid, gb = gm;
    }
    const long double feasible_side = ga >= 0 ? a : b, infeasible_side = ga >= 0 ? b : a;
    const long double direction = feasible_side > infeasible_side ? 1.0L : -1.0L;
    const Vector3d q_star(q12(0), q12(1), double(feasible_side));
    const FkResult fk = forward(m, q_star);
    if (fk.status == Status::Unreachable) continue;  // rounding put it a hair outside
    ++tested;

    // The two assembly modes merge: FK says Singular, J is singular.
    ASSERT_EQ(fk.status, Status::Singular) << q_star.transpose();
    EXPECT_LT((fk.p_base_platform - fk.p_other_mode).norm(), 1e-5 * m.size());
    EXPECT_LE(fk.residual, 1e-9 * m.size());
    const JacobianResult J = jacobian(m, q_star, fk.p_base_platform);
    EXPECT_EQ(J.status, Status::Singular);
    EXPECT_TRUE(std::isinf(J.cond));
    const SingularityReport at = nearest_singularity(m, q_star, fk.p_base_platform);
    EXPECT_LT(at.distances[3], 1e-5 * m.size());  // over the full circle a leg may be as close
    EXPECT_LT(at.parallel_index, 1e-5);

    // The inverse problem stays regular there: each leg has its own solution.
    IkOptions options;
    options.branch = branch_of(m, q_star, fk.p_base_platform);
    const IkResult ik = inverse(m, fk.p_base_platform, IkMethod::Closed, options);
    EXPECT_TRUE(ik.status == Status::Ok || ik.status == Status::OutOfLimits) << to_string(ik.status);
    EXPECT_LT(angle_distance(ik.q_actuated, q_star), 1e-6);

    // Slightly inside: Ok, the modes 2h apart, h the reported distance, c(J) large.
    const Vector3d q_near(q12(0), q12(1), double(feasible_side + direction * 1e-6L));
    const FkResult near = forward(m, q_near);
    ASSERT_EQ(near.status, Status::Ok);
    const JacobianResult J_near = jacobian(m, q_near, near.p_base_platform);
    EXPECT_EQ(J_near.status, Status::Ok);
    EXPECT_GT(J_near.cond, 100.0);
    const SingularityReport report = nearest_singularity(m, q_near, near.p_base_platform);
    EXPECT_NEAR(report.distances[3], 0.5 * (near.p_base_platform - near.p_other_mode).norm(), 1e-9 * m.size());
    EXPECT_LT(report.distances[3], 0.05 * m.size());
    // Slightly outside: no platform position.
    const Vector3d q_beyond(q12(0), q12(1), double(infeasible_side - direction * 1e-6L));
    const FkResult beyond = forward(m, q_beyond);
    EXPECT_EQ(beyond.status, Status::Unreachable);
    EXPECT_TRUE(beyond.p_base_platform.allFinite());
    const JacobianResult J_beyond = jacobian(m, q_beyond);
    EXPECT_EQ(J_beyond.status, Status::Unreachable);
    EXPECT_THROW(nearest_singularity(m, q_beyond), std::invalid_argument);
  }
  EXPECT_EQ(tested, 200);
}

TEST(DeltaSingular, DistancesAreTheLegMarginsAndHalfTheAssemblyGap) {
  const Model m;
  for (const Assembled& c : sample_assembled(m, 23, 5000, 1e12)) {
    const SingularityReport s = nearest_singularity(m, c.q, c.p);
    for (int i = 0; i < kLegCount; ++i) EXPECT_DOUBLE_EQ(s.distances[i], std::abs(leg_margin(m, i, c.p)));
    const FkResult fk = forward(m, c.q);
    EXPECT_NEAR(s.distances[3], 0.5 * (fk.p_base_platform - fk.p_other_mode).norm(), 1e-12 * m.size());
    EXPECT_DOUBLE_EQ(s.distance, *std::min_element(s.distances.begin(), s.distances.end()));
    EXPECT_GE(s.parallel_index, 0.0);
    EXPECT_LE(s.parallel_index, 1.0);
  }
  EXPECT_THROW(jacobian(m, home_pose(m), home_position(m) + Vector3d(0, 0, 1)), std::invalid_argument);
}

// Every forearm parallel: the three spheres' centres coincide where
// R - r + La cos q = 0 (a platform wider than the base), and the platform
// may lie anywhere on the sphere of radius Lb about them. FK had returned
// that centre, which closes no leg (and the device's read-outs threw);
// IK there had been ok with c(J) 4e15, the rounding of the pose its digits.
TEST(DeltaSingular, EveryForearmParallelIsSingularForwardAndInverse) {
  Model m;
  m.R = 5;
  m.r = 9;
  for (Interval& range : m.q_limits) range = {-std::numbers::pi, std::numbers::pi};
  const double q0 = std::acos(-(m.R - m.r) / m.La);
  const Vector3d q = Vector3d::Constant(q0);
  const FkResult fk = forward(m, q);
  EXPECT_EQ(fk.status, Status::Singular);
  EXPECT_LE(fk.residual, 1e-12 * m.size()) << "the point given closes every leg";
  const JacobianResult j = jacobian(m, q, fk.p_base_platform);
  EXPECT_EQ(j.status, Status::Singular);
  EXPECT_TRUE(std::isinf(j.cond));
  // The same pose through IK: the elbows of q0, c(J) not finite.
  bool found = false;
  for (int branch = 0; branch < kBranchCount; ++branch) {
    IkOptions options;
    options.branch = branch;
    const IkResult ik = inverse(m, fk.p_base_platform, IkMethod::Closed, options);
    if (angle_distance(ik.q_actuated, q) > 1e-6) continue;
    found = true;
    EXPECT_EQ(jacobian(m, ik.q_actuated, fk.p_base_platform).status, Status::Singular);
  }
  EXPECT_TRUE(found) << "an IK branch has the elbows of q0";
  // A degree away the forearms part and the device holds.
  const Vector3d apart = q + Vector3d(0, 0.02, -0.02);
  const FkResult near = forward(m, apart);
  ASSERT_EQ(near.status, Status::Ok);
  EXPECT_EQ(jacobian(m, apart, near.p_base_platform).status, Status::Ok);
}
