// The planar 3-RRR of assets/mechanisms/three-rrr.json against its closed
// forms written here from the geometry alone (none of it calls the solver):
//
//   base joints B_k = Rb (cos 120k, sin 120k); platform joints
//   P_k = (x, y) + Rot(phi) rp (cos 120k, sin 120k); the crank's absolute
//   angle t_k = 120k + q_k, elbow E_k = B_k + a (cos t_k, sin t_k), |P_k - E_k| = b.
//   IK: with D = |P_k - B_k|, t_k = atan2(P_k - B_k) +- acos((a^2 + D^2 - b^2) / (2 a D)),
//       the branch + the one where (E_k - B_k) x (P_k - E_k) > 0 (the file's triple rule).
//   J:  |P_k - E_k|^2 = b^2 differentiated: f_k = P_k - E_k,
//       f_k . (v + w z x (P_k - p)) = f_k . (z x (E_k - B_k)) qdot_k, so
//       Jx = [f_k^T, f_k . (z x (P_k - p))], Jq = diag(f_k . (z x (E_k - B_k))), J = Jx^-1 Jq.
//   Reach: leg k closes iff |a - b| <= D <= a + b.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <optional>
#include <random>

#include "described_devices_support.h"

using namespace linkscape;
using namespace linkscape::described_test;
using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {

struct ThreeRrr {
  double Rb = 0, rp = 0, a = 0, b = 0;

  static ThreeRrr from_file() {
    const auto j = read_asset("three-rrr.json").at("parameters");
    return {j.at("Rb").get<double>(), j.at("rp").get<double>(), j.at("a").get<double>(), j.at("b").get<double>()};
  }
  Vector2d base(int k) const { return Rb * unit_at(120 * k * kDeg); }
  Vector2d joint(int k, const Vector3d& pose) const {
    return pose.head<2>() + rp * unit_at(120 * k * kDeg + pose.z());
  }
  // Crank angles (q, relative to the leg's base frame) on the + branch, or nullopt.
  std::optional<Vector3d> ik(const Vector3d& pose) const {
    Vector3d q;
    for (int k = 0; k < 3; ++k) {
      const Vector2d d = joint(k, pose) - base(k);
      const double D = d.norm(), c = (a * a + D * D - b * b) / (2 * a * D);
      if (!(std::abs(c) <= 1)) return std::nullopt;
      for (double s : {1.0, -1.0}) {
        const double t = std::atan2(d.y(), d.x()) + s * std::acos(c);
        const Vector2d e = a * unit_at(t), f = joint(k, pose) - base(k) - e;
        if (e.x() * f.y() - e.y() * f.x() > 0) q(k) = std::remainder(t - 120 * k * kDeg, 2 * std::numbers::pi);
      }
    }
    return q;
  }
  Matrix3d jacobian(const Vector3d& pose, const Vector3d& q) const {
    Matrix3d Jx, Jq = Matrix3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const Vector2d e = a * unit_at(120 * k * kDeg + q(k)), p = joint(k, pose), f = p - base(k) - e;
      const Vector2d r = p - pose.head<2>();
      Jx.row(k) << f.x(), f.y(), f.x() * -r.y() + f.y() * r.x();
      Jq(k, k) = f.x() * -e.y() + f.y() * e.x();
    }
    return Jx.inverse() * Jq;
  }
};

TEST(ThreeRrrDevice, InverseKinematicsAndJacobianMatchTheGeometry) {
  const ThreeRrr g = ThreeRrr::from_file();
  const auto m = load_device("three-rrr.json");
  ASSERT_EQ(m->info().task.size(), 4u);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> pos(-4, 4), turn(-0.6, 0.6);
  int solved = 0, unreachable = 0;
  double worst_q = 0, worst_j = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vector3d pose(pos(rng), pos(rng), turn(rng));
    const std::optional<Vector3d> q = g.ik(pose);
    IkOptions o;
    o.branch = 0;
    const IkResult r = m->inverse(planar_task(pose), o);
    if (!q) {
      EXPECT_EQ(r.status, Status::Unreachable) << "pose " << i;
      ++unreachable;
      continue;
    }
    if (r.status == Status::Singular) continue;  // Jx or a leg near singular: compared elsewhere
    ASSERT_EQ(r.status, Status::Ok) << "pose " << i;
    ++solved;
    for (int k = 0; k < 3; ++k) worst_q = std::max(worst_q, std::abs(angle_difference(r.solutions[0].q(k), (*q)(k))));
    const Eigen::MatrixXd J = m->jacobian(r.solutions[0].q, planar_task(pose));
    const Matrix3d expected = g.jacobian(pose, *q);
    worst_j = std::max(worst_j, (J - expected).norm() / expected.norm());
  }
  RecordProperty("worst_q_rad", scientific(worst_q));
  RecordProperty("worst_J_relative", scientific(worst_j));
  EXPECT_GT(solved, 1000);
  EXPECT_GT(unreachable, 100);
  EXPECT_LE(worst_q, 1e-12);
  EXPECT_LE(worst_j, 1e-9);
}

TEST(ThreeRrrDevice, ConditionNumberAtHomeIsTheGeometrys) {
  const ThreeRrr g = ThreeRrr::from_file();
  const auto m = load_device("three-rrr.json");
  const Vector3d home(0, 0, 0);
  const Vector3d q = *g.ik(home);
  const Measures meas = m->measures(m->home_actuators(), m->home_task());
  ASSERT_EQ(meas.status, Status::Ok);
  EXPECT_NEAR(meas.values[0], svd_condition(g.jacobian(home, q)), 1e-9 * meas.values[0]);
}

}  // namespace
