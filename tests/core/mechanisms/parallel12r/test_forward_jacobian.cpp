#include <gtest/gtest.h>

#include <vector>

#include "core/mechanisms/parallel12r/parallel12r.h"
#include "tests/core/mechanisms/parallel12r/reference_12r.h"

using namespace linkscape;
using namespace linkscape::parallel12r;
using linkscape::testing::ConfigurationSampler;
using linkscape::testing::paper_forward;
using linkscape::testing::make_12r;

TEST(Forward, MatchesPrintedEquations11To13) {
  // Against the printed equations in long double: 1 - sin^2 a sin^2 t as
  // printed cancels near the actuator plane in double, the code's form does not.
  ConfigurationSampler sample(1, 0.0);
  for (const Model& m : {make_12r(1, 1), make_12r(15, 15), make_12r(0.7, 1.9)}) {
    for (int i = 0; i < 2000; ++i) {
      const Eigen::Vector3d q = sample();
      const Eigen::Vector3d expected = linkscape::testing::paper_forward_in<long double>(m.L1, m.L2, q.x(), q.y(), q.z());
      EXPECT_LT((forward(m, q) - expected).norm(), 1e-14 * m.reach());
    }
  }
}

TEST(Forward, BatchEqualsSingle) {
  const Model m = make_12r(1.3, 0.8);
  ConfigurationSampler sample(2);
  std::vector<Eigen::Vector3d> q(500), p(500);
  for (auto& v : q) v = sample();
  forward(m, q, p);
  for (std::size_t i = 0; i < q.size(); ++i) EXPECT_EQ(p[i], forward(m, q[i]));
  std::vector<Eigen::Vector3d> too_small(3);
  EXPECT_THROW(forward(m, q, too_small), std::invalid_argument);
}

TEST(Forward, EndpointLiesInThePlaneNormalToN) {
  // Both link directions are perpendicular to n = (cos a, sin a, 0).
  const Model m = make_12r(1, 2);
  ConfigurationSampler sample(3, 0.0);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d q = sample();
    const Eigen::Vector3d n(std::cos(q.x()), std::sin(q.x()), 0);
    EXPECT_NEAR(forward(m, q).dot(n), 0.0, 1e-14);
  }
}

TEST(Forward, NonFiniteAnglesThrow) {
  EXPECT_THROW(forward(make_12r(1, 1), Eigen::Vector3d(0, NAN, 0)), std::invalid_argument);
  EXPECT_THROW(jacobian(make_12r(1, 1), Eigen::Vector3d(INFINITY, 0, 0)), std::invalid_argument);
}

TEST(Jacobian, AnalyticMatchesCentralDifferences) {
  // Central differences with h = 1e-6 have truncation error ~h^2 |D'''| and
  // round-off ~eps/h, about 1e-10 relative here; 1e-7 leaves margin for
  // configurations with larger third derivatives.
  ConfigurationSampler sample(4, 0.1);
  for (const Model& m : {make_12r(1, 1), make_12r(15, 15), make_12r(0.6, 1.4)}) {
    for (int i = 0; i < 3000; ++i) {
      const Eigen::Vector3d q = sample();
      const Eigen::Matrix3d J = jacobian(m, q);
      const Eigen::Matrix3d Jfd = jacobian_central_difference(m, q, 1e-6);
      EXPECT_LT((J - Jfd).norm(), 1e-7 * (1.0 + J.norm())) << q.transpose();
    }
  }
}

TEST(Jacobian, DeterminantMatchesEquation18) {
  ConfigurationSampler sample(5, 0.0);
  for (const Model& m : {make_12r(1, 1), make_12r(2, 0.5)}) {
    for (int i = 0; i < 5000; ++i) {
      const Eigen::Vector3d q = sample();
      const double det = jacobian(m, q).determinant();
      const double eq18 = jacobian_determinant_eq18(m, q);
      EXPECT_NEAR(det, eq18, 1e-11 * std::max(1.0, std::abs(eq18))) << q.transpose();
    }
  }
}

TEST(Jacobian, PrintedEquation17IsWrongAndOursIsNot) {
  // Eq. 17 as printed: common factor 1/(d_b^3 d_g^3) with entries carrying
  // single powers d_g, d_b. Entries differ from the true derivatives by the
  // factors d^2, so the printed matrix is off wherever sin(alpha) != 0.
  const Model m = make_12r(1, 1);
  const Eigen::Vector3d q(0.6, 0.9, -0.4);
  const double sa = std::sin(q.x()), ca = std::cos(q.x());
  const double sb = std::sin(q.y()), cb = std::cos(q.y()), sg = std::sin(q.z()), cg = std::cos(q.z());
  const double db = std::sqrt(1 - sa * sa * sb * sb), dg = std::sqrt(1 - sa * sa * sg * sg);
  Eigen::Matrix3d printed;
  printed << -(dg * ca * cb + db * ca * cg), dg * sa * ca * ca * sb, db * sa * ca * ca * sg,
      -(dg * sa * cb * cb * cb + db * sa * cg * cg * cg), -dg * ca * ca * ca * sb, -db * ca * ca * ca * sg,
      -(dg * sa * sb * cb * cb + db * sa * sg * cg * cg), dg * ca * cb, db * ca * cg;
  printed /= db * db * db * dg * dg * dg;
  const Eigen::Matrix3d fd = jacobian_central_difference(m, q);
  EXPECT_GT((printed - fd).norm() / fd.norm(), 0.01);
  EXPECT_LT((jacobian(m, q) - fd).norm() / fd.norm(), 1e-8);
}
