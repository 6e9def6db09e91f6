// The planar 3-RPR of assets/mechanisms/three-rpr.json against its closed
// forms written here from the geometry alone (none of it calls the solver):
//
//   base pivots B_k = Rb (cos 120k, sin 120k); platform joints
//   P_k = (x, y) + Rot(phi) rp (cos(120k + 60), sin(120k + 60)); the slide
//   d_k runs from B_k to P_k.
//   IK: d_k = |P_k - B_k|, within the travel [lo, hi] or out of limits.
//   J:  d_k^2 = |P_k - B_k|^2 differentiated: u_k = (P_k - B_k) / d_k,
//       qdot_k = u_k . (v + w z x (P_k - p)), so J^-1 has the rows
//       [u_k^T, u_k . (z x (P_k - p))] and J = (J^-1)^-1.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "described_devices_support.h"

using namespace linkscape;
using namespace linkscape::described_test;
using Eigen::Matrix3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {

struct ThreeRpr {
  double Rb = 0, rp = 0, lo = 0, hi = 0;

  static ThreeRpr from_file() {
    const auto j = read_asset("three-rpr.json").at("parameters");
    return {j.at("Rb").get<double>(), j.at("rp").get<double>(), j.at("lo").get<double>(), j.at("hi").get<double>()};
  }
  Vector2d base(int k) const { return Rb * unit_at(120 * k * kDeg); }
  Vector2d joint(int k, const Vector3d& pose) const {
    return pose.head<2>() + rp * unit_at((120 * k + 60) * kDeg + pose.z());
  }
  Vector3d ik(const Vector3d& pose) const {
    Vector3d d;
    for (int k = 0; k < 3; ++k) d(k) = (joint(k, pose) - base(k)).norm();
    return d;
  }
  bool within_travel(const Vector3d& d) const { return d.minCoeff() >= lo && d.maxCoeff() <= hi; }
  Matrix3d jacobian(const Vector3d& pose) const {
    Matrix3d inverse;
    for (int k = 0; k < 3; ++k) {
      const Vector2d p = joint(k, pose), u = (p - base(k)).normalized(), r = p - pose.head<2>();
      inverse.row(k) << u.x(), u.y(), u.x() * -r.y() + u.y() * r.x();
    }
    return inverse.inverse();
  }
};

TEST(ThreeRprDevice, InverseKinematicsAndJacobianMatchTheGeometry) {
  const ThreeRpr g = ThreeRpr::from_file();
  const auto m = load_device("three-rpr.json");
  ASSERT_EQ(m->info().task.size(), 4u);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> pos(-8, 8), turn(-0.8, 0.8);
  int solved = 0, outside = 0;
  double worst_q = 0, worst_j = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vector3d pose(pos(rng), pos(rng), turn(rng));
    const Vector3d d = g.ik(pose);
    const IkResult r = m->inverse(planar_task(pose), {});
    if (!g.within_travel(d)) {
      // A slide always closes its leg: beyond its travel the pose is out of limits, never unreachable.
      EXPECT_EQ(r.status, Status::OutOfLimits) << "pose " << i;
      ++outside;
      continue;
    }
    if (r.status == Status::Singular) continue;  // the legs' lines through one point: compared elsewhere
    ASSERT_EQ(r.status, Status::Ok) << "pose " << i;
    ++solved;
    worst_q = std::max(worst_q, (r.solutions[0].q - d).cwiseAbs().maxCoeff() / d.maxCoeff());
    const Eigen::MatrixXd J = m->jacobian(r.solutions[0].q, planar_task(pose));
    const Matrix3d expected = g.jacobian(pose);
    worst_j = std::max(worst_j, (J - expected).norm() / expected.norm());
  }
  RecordProperty("worst_q_relative", scientific(worst_q));
  RecordProperty("worst_J_relative", scientific(worst_j));
  EXPECT_GT(solved, 500);
  EXPECT_GT(outside, 500);
  EXPECT_LE(worst_q, 1e-12);
  EXPECT_LE(worst_j, 1e-9);
}

TEST(ThreeRprDevice, ConditionNumberAtHomeIsTheGeometrys) {
  const ThreeRpr g = ThreeRpr::from_file();
  const auto m = load_device("three-rpr.json");
  const Vector3d home(0, 0, 0);
  const Measures meas = m->measures(m->home_actuators(), m->home_task());
  ASSERT_EQ(meas.status, Status::Ok);
  EXPECT_NEAR(meas.values[0], svd_condition(g.jacobian(home)), 1e-9 * meas.values[0]);
  EXPECT_NEAR((m->home_actuators() - g.ik(home)).norm(), 0, 1e-12);
}

}  // namespace
