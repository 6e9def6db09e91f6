// The Novint Falcon of assets/mechanisms/falcon.json, solved by the generic
// solver for described devices, against its closed-form inverse kinematics
// written here from the published geometry alone (R. E. Stamper's model as the
// libnifalcon driver states it; docs/mechanisms/falcon.md), in long double:
//
//   leg i at phi_i = 90 + tilt - 120 i deg: u = (cos phi, sin phi, 0),
//   v = (-sin phi, cos phi, 0); for the grip centre p,
//     pu = u.p - r,  pv = v.p - s,  pw = p_z;
//     theta3 = acos((pv + f) / b),  K = d + e + b sin theta3;
//     (pu + c - a cos theta1)^2 + (pw - a sin theta1)^2 = K^2, solved in
//     t = tan(theta1 / 2): l2 t^2 + l1 t + l0 = 0, the root
//     t = -(l1 + sqrt(l1^2 - 4 l0 l2)) / (2 l2) (the knee outward).
//   theta1 is the motor angle (q), from u towards z.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <optional>
#include <random>

#include "described_devices_support.h"

using namespace linkscape;
using namespace linkscape::described_test;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {

struct Geometry {
  long double a, b, c, d, e, f, r, s, tilt_deg;
};

Geometry read_geometry() {
  const nlohmann::json p = read_asset("falcon.json")["parameters"];
  return {p["a"], p["b"], p["c"], p["d"], p["e"], p["f"], p["r"], p["s"], p["tilt"]};
}

// The motor angles for a grip centre, or nothing where a leg cannot reach.
std::optional<Vector3d> closed_form_ik(const Geometry& g, const Vector3d& p) {
  Vector3d q;
  for (int i = 0; i < 3; ++i) {
    const long double phi = (90.0L + g.tilt_deg - 120.0L * i) * std::numbers::pi_v<long double> / 180.0L;
    const long double pu = std::cos(phi) * p.x() + std::sin(phi) * p.y() - g.r;
    const long double pv = -std::sin(phi) * p.x() + std::cos(phi) * p.y() - g.s;
    const long double pw = p.z();
    const long double c3 = (pv + g.f) / g.b;
    if (std::abs(c3) > 1) return std::nullopt;
    const long double k = g.d + g.e + g.b * std::sqrt(1 - c3 * c3);
    const long double u = pu + g.c;
    // (u - a cos)^2 + (pw - a sin)^2 = k^2  ->  A + B cos + C sin = 0
    const long double A = u * u + pw * pw + g.a * g.a - k * k, B = -2 * g.a * u, C = -2 * g.a * pw;
    const long double l0 = A + B, l1 = 2 * C, l2 = A - B;
    const long double disc = l1 * l1 - 4 * l0 * l2;
    if (disc < 0) return std::nullopt;
    q[i] = double(2 * std::atan(-(l1 + std::sqrt(disc)) / (2 * l2)));
  }
  return q;
}

class FalconDevice : public ::testing::Test {
 protected:
  Geometry g = read_geometry();
  std::shared_ptr<const Mechanism> m = load_device("falcon.json");
};

TEST_F(FalconDevice, InverseKinematicsMatchesTheClosedForm) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> xy(-40, 40), z(90, 160);
  int compared = 0;
  double worst = 0;
  for (int k = 0; k < 400; ++k) {
    const Vector3d p(xy(rng), xy(rng), z(rng));
    const auto expected = closed_form_ik(g, p);
    if (!expected) continue;
    const IkResult r = m->inverse(p);
    if (r.status == Status::OutOfLimits) continue;  // the stops are assumed, the closed form has none
    ASSERT_EQ(r.status, Status::Ok) << p.transpose();
    const VectorXd& q = r.solutions.front().q;
    for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(angle_difference(q[i], (*expected)[i])));
    ++compared;
  }
  EXPECT_GT(compared, 300);
  EXPECT_LT(worst, 1e-9);
}

TEST_F(FalconDevice, ForwardKinematicsFromHomeReturnsTheGripCentre) {
  // From the default seed (home), up to 7 cm away: the parallelogram legs'
  // closure loses rank on the way, where one Gauss-Newton run would stall.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> xy(-40, 40), z(90, 160);
  int solved = 0;
  for (int k = 0; k < 60; ++k) {
    const Vector3d p(xy(rng), xy(rng), z(rng));
    const auto q = closed_form_ik(g, p);
    if (!q) continue;
    const FkResult f = m->forward(*q);
    ASSERT_EQ(f.status, Status::Ok) << p.transpose();
    EXPECT_LT((f.x.head<3>() - p).norm(), 1e-8) << p.transpose();
    ++solved;
  }
  EXPECT_GT(solved, 40);
}

TEST_F(FalconDevice, JacobianIsTheInverseOfTheClosedFormsDerivative) {
  const Vector3d p(-15.0, 20.0, 125.0);
  const IkResult r = m->inverse(p);
  ASSERT_EQ(r.status, Status::Ok);
  const VectorXd q = r.solutions.front().q;
  // dq/dx of the closed form by central differences; J = dx/dq is its inverse.
  Matrix3d dq_dx;
  const double h = 1e-4;
  for (int j = 0; j < 3; ++j) {
    const Vector3d step = Vector3d::Unit(j) * h;
    dq_dx.col(j) = (*closed_form_ik(g, p + step) - *closed_form_ik(g, p - step)) / (2 * h);
  }
  const Eigen::MatrixXd J = m->jacobian(q, p);
  EXPECT_LT((J * dq_dx - Matrix3d::Identity()).norm(), 1e-6);
  const Measures measures = m->measures(q, p);
  EXPECT_EQ(measures.status, Status::Ok);
  EXPECT_NEAR(measures.values[0], svd_condition(J), 1e-9 * svd_condition(J));
}

TEST_F(FalconDevice, AGripCentreBeyondTheLegsIsUnreachable) {
  const Vector3d far(0, 0, 400);
  ASSERT_FALSE(closed_form_ik(g, far));
  EXPECT_EQ(m->inverse(far).status, Status::Unreachable);
}

}  // namespace
