// The 6-RUS hexapod of assets/mechanisms/hexapod-rus.json (one group of six
// copies alternating mirror-image legs through (-1)^k) against its closed
// forms written here from the geometry alone (none of it calls the solver):
//
//   leg k (pair n = floor(k/2), sign m = (-1)^k): motor at B_k = R r_k, r_k the
//   unit vector at 120n - m sb/2 deg, its axis u_k = m t_k (t_k = z x r_k);
//   elbow E_k(q) = B_k + a (cos q r_k + sin q (u_k x r_k)) = B_k + a (cos q r_k - m sin q z);
//   platform joint P_k = p + Rz Ry Rx r (cos, sin, 0) at 120n - m (60 - sp/2) deg;
//   rod |P_k - E_k| = b.
//   IK: d = P_k - B_k: (d.r_k) cos q - m (d.z) sin q = (|d|^2 + a^2 - b^2) / (2a),
//       two angles; the file's rule keeps the one where
//       ((E_k - B_k) x (P_k - E_k)) . u_k has the sign of -m.
//   J:  f_k = P_k - E_k: f_k . (v + w x (P_k - p)) = f_k . (u_k x (E_k - B_k)) qdot_k,
//       Jx = [f_k^T, ((P_k - p) x f_k)^T], Jq = diag(f_k . (u_k x (E_k - B_k))), J = Jx^-1 Jq.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <optional>
#include <random>

#include "described_devices_support.h"

using namespace linkscape;
using namespace linkscape::described_test;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

struct Hexapod {
  double R = 0, r = 0, a = 0, b = 0, sb = 0, sp = 0, travel = 0;

  static Hexapod from_file() {
    const auto j = read_asset("hexapod-rus.json");
    const auto p = j.at("parameters");
    return {p.at("R").get<double>(),  p.at("r").get<double>(),  p.at("a").get<double>(), p.at("b").get<double>(),
            p.at("sb").get<double>(), p.at("sp").get<double>(), j.at("actuator_limits_deg").at("q1").at(1).get<double>() * kDeg};
  }
  static double mirror(int k) { return k % 2 ? -1.0 : 1.0; }
  static Vector3d radial(double deg) { return {std::cos(deg * kDeg), std::sin(deg * kDeg), 0}; }
  Vector3d r_of(int k) const { return radial(120 * (k / 2) - mirror(k) * sb / 2); }
  Vector3d axis(int k) const { return mirror(k) * Vector3d::UnitZ().cross(r_of(k)); }
  Vector3d motor(int k) const { return R * r_of(k); }
  Vector3d elbow(int k, double q) const { return motor(k) + a * (std::cos(q) * r_of(k) - mirror(k) * std::sin(q) * Vector3d::UnitZ()); }
  static Matrix3d rotation(const Vector6d& x) {
    return (Eigen::AngleAxisd(x(5), Vector3d::UnitZ()) * Eigen::AngleAxisd(x(4), Vector3d::UnitY()) *
            Eigen::AngleAxisd(x(3), Vector3d::UnitX()))
        .toRotationMatrix();
  }
  Vector3d joint(int k, const Vector6d& x) const {
    return x.head<3>() + rotation(x) * (r * radial(120 * (k / 2) - mirror(k) * (60 - sp / 2)));
  }
  // The design's branch of every leg, or nullopt where a leg cannot reach.
  std::optional<Vector6d> ik(const Vector6d& x) const {
    Vector6d q;
    for (int k = 0; k < 6; ++k) {
      const Vector3d d = joint(k, x) - motor(k);
      const double B = d.dot(r_of(k)), C = -mirror(k) * d.z(), K = (d.squaredNorm() + a * a - b * b) / (2 * a);
      const double rho = std::hypot(B, C);
      if (!(std::abs(K) <= rho)) return std::nullopt;
      for (double s : {1.0, -1.0}) {
        const double t = std::atan2(C, B) + s * std::acos(K / rho);
        const Vector3d e = elbow(k, t);
        if ((e - motor(k)).cross(joint(k, x) - e).dot(axis(k)) * -mirror(k) > 0) q(k) = std::remainder(t, 2 * std::numbers::pi);
      }
    }
    return q;
  }
  Matrix6d jacobian(const Vector6d& x, const Vector6d& q) const {
    Matrix6d Jx, Jq = Matrix6d::Zero();
    for (int k = 0; k < 6; ++k) {
      const Vector3d e = elbow(k, q(k)), p = joint(k, x), f = p - e;
      Jx.row(k) << f.transpose(), (p - x.head<3>()).cross(f).transpose();
      Jq(k, k) = f.dot(axis(k).cross(e - motor(k)));
    }
    return Jx.inverse() * Jq;
  }
};

TEST(HexapodRusDevice, MirrorImageCopiesMatchTheGeometry) {
  const Hexapod g = Hexapod::from_file();
  const auto m = load_device("hexapod-rus.json");
  const Vector6d home = m->home_task();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  Verdicts v;
  double worst_q = 0, worst_j = 0;
  for (int i = 0; i < 3000; ++i) {
    Vector6d x = home;
    for (int c = 0; c < 6; ++c) x(c) += (c < 3 ? 4.0 : 0.3) * unit(rng);
    const std::optional<Vector6d> q = g.ik(x);
    const IkResult res = m->inverse(x);
    if (!v.check(res, q.has_value(), q && (q->array().abs() <= g.travel).all(), i)) continue;
    for (int k = 0; k < 6; ++k) worst_q = std::max(worst_q, std::abs(angle_difference(res.solutions[0].q(k), (*q)(k))));
    const Matrix6d expected = g.jacobian(x, *q);
    worst_j = std::max(worst_j, (m->jacobian(res.solutions[0].q, x) - expected).norm() / expected.norm());
  }
  RecordProperty("worst_q_rad", scientific(worst_q));
  RecordProperty("worst_J_relative", scientific(worst_j));
  EXPECT_GT(v.ok, 300);
  EXPECT_GT(v.out_of_limits + v.unreachable, 300);
  EXPECT_LE(worst_q, 1e-12);
  EXPECT_LE(worst_j, 1e-9);
}

// At home the six legs are alike: the pairs' mirror images give one crank
// angle to every motor.
TEST(HexapodRusDevice, HomeIsSymmetric) {
  const auto m = load_device("hexapod-rus.json");
  const VectorXd q = m->home_actuators();
  for (int k = 1; k < 6; ++k) EXPECT_NEAR(q(k), q(0), 1e-12) << k;
}

}  // namespace
