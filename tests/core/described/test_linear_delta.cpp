// The linear Delta of assets/mechanisms/linear-delta.json against its closed
// forms written here from the geometry alone (none of it calls the solver):
//
//   columns at C_k = R (cos 120k, sin 120k, 0), carriages at C_k + h_k z;
//   platform joints P_k = p + r (cos 120k, sin 120k, 0); rods |P_k - C_k - h_k z| = L,
//   each below its carriage (the file's "along" rule).
//   IK: rho_k = the horizontal distance |P_k - C_k|_xy; h_k = P_k.z + sqrt(L^2 - rho_k^2)
//       (unreachable where rho_k > L; out of limits where h_k leaves [lo, hi]).
//   J:  f_k = P_k - (C_k + h_k z); f_k . pdot = f_k.z hdot_k: Jx = [f_k^T], Jq = diag(f_k.z),
//       J = Jx^-1 Jq.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <optional>
#include <random>

#include "described_devices_support.h"

using namespace linkscape;
using namespace linkscape::described_test;
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

struct LinearDelta {
  double R = 0, r = 0, L = 0, lo = 0, hi = 0;

  static LinearDelta from_file() {
    const auto j = read_asset("linear-delta.json").at("parameters");
    return {j.at("R").get<double>(), j.at("r").get<double>(), j.at("L").get<double>(), j.at("lo").get<double>(),
            j.at("hi").get<double>()};
  }
  static Vector3d ring(double radius, int k) { return radius * Vector3d(std::cos(120 * k * kDeg), std::sin(120 * k * kDeg), 0); }
  std::optional<Vector3d> ik(const Vector3d& p) const {
    Vector3d h;
    for (int k = 0; k < 3; ++k) {
      const Vector3d d = p + ring(r, k) - ring(R, k);
      const double rho2 = d.x() * d.x() + d.y() * d.y();
      if (rho2 > L * L) return std::nullopt;
      h(k) = d.z() + std::sqrt(L * L - rho2);
    }
    return h;
  }
  Matrix3d jacobian(const Vector3d& p, const Vector3d& h) const {
    Matrix3d Jx, Jq = Matrix3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const Vector3d f = p + ring(r, k) - ring(R, k) - h(k) * Vector3d::UnitZ();
      Jx.row(k) = f.transpose();
      Jq(k, k) = f.z();
    }
    return Jx.inverse() * Jq;
  }
};

TEST(LinearDeltaDevice, InverseKinematicsStatusesAndJacobianMatchTheGeometry) {
  const LinearDelta g = LinearDelta::from_file();
  const auto m = load_device("linear-delta.json");
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> across(-g.R, g.R), height(g.lo - g.L, g.hi);
  Verdicts v;
  double worst_q = 0, worst_j = 0;
  for (int i = 0; i < 6000; ++i) {
    const Vector3d p(across(rng), across(rng), height(rng));
    const std::optional<Vector3d> h = g.ik(p);
    const IkResult res = m->inverse(p);
    if (!v.check(res, h.has_value(), h && (h->array() >= g.lo).all() && (h->array() <= g.hi).all(), i)) continue;
    worst_q = std::max(worst_q, (res.solutions[0].q - *h).cwiseAbs().maxCoeff());
    const Matrix3d expected = g.jacobian(p, *h);
    worst_j = std::max(worst_j, (m->jacobian(res.solutions[0].q, p) - expected).norm() / expected.norm());
  }
  RecordProperty("worst_q_cm", scientific(worst_q));
  RecordProperty("worst_J_relative", scientific(worst_j));
  EXPECT_GT(v.ok, 500);
  EXPECT_GT(v.out_of_limits, 100);
  EXPECT_GT(v.unreachable, 100);
  EXPECT_LE(worst_q, 1e-12 * g.L);
  EXPECT_LE(worst_j, 1e-9);
}

// The rod above its carriage is another device. Near the top of the travel
// the design's branch (rod below) needs a carriage above its travel while
// the other branch has one within it: the closed form decides out-of-limits
// on the design's branch, the leg named, whatever a solver's seeds would
// find first; the numerical reference agrees.
TEST(LinearDeltaDevice, TheOtherBranchIsDecided) {
  const LinearDelta g = LinearDelta::from_file();
  const auto m = load_device("linear-delta.json");
  // Rod below: h = z + sqrt(L^2 - rho^2) must lie in [lo, hi]; a platform
  // above hi leaves only the rod-above carriage positions, inside the travel.
  const Vector3d p(0, 0, g.hi - 1);
  ASSERT_TRUE(g.ik(p));
  EXPECT_GT((*g.ik(p))(0), g.hi);
  const IkResult res = m->inverse(p);
  EXPECT_EQ(res.status, Status::OutOfLimits);
  EXPECT_EQ(res.failing_part, "1");
  IkOptions numeric;
  numeric.method = "newton";
  EXPECT_EQ(m->inverse(p, numeric).status, Status::OutOfLimits);
}

}  // namespace
