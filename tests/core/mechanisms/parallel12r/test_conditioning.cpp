// c(J) of the 12R: its conditioning report, and the 3x3 condition numbers
// (core/conditioning.h) over its workspace against long double.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>

#include "core/conditioning.h"
#include "core/mechanisms/parallel12r/parallel12r.h"
#include "tests/core/mechanisms/parallel12r/reference_12r.h"

using namespace linkscape;

TEST(Conditioning, MechanismReportMatchesSvd) {
  parallel12r::Model m;
  linkscape::testing::ConfigurationSampler sample(12);
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector3d q = sample();
    const auto c = parallel12r::conditioning(m, q);
    const Eigen::Matrix3d J = parallel12r::jacobian(m, q);
    const double svd = condition_number_svd(J);
    EXPECT_NEAR(c.cond, svd, svd * (1e-13 + 1e-14 * svd));
    EXPECT_DOUBLE_EQ(c.det, J.determinant());
  }
}

TEST(Conditioning, ClosedFormIsAtLeastAsAccurateAsSvdAgainstLongDouble) {
  // Reference: Jacobi SVD in long double. Over the 12R workspace the closed
  // form's worst relative error per decade of cond stays within 3x of the
  // double SVD's (measured: it is usually smaller).
  parallel12r::Model m;
  linkscape::testing::ConfigurationSampler sample(13, 0.0);
  double worst_closed = 0, worst_svd = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Matrix3d J = parallel12r::jacobian(m, sample());
    const Eigen::JacobiSVD<Eigen::Matrix<long double, 3, 3>> ref(J.cast<long double>());
    const double c = double(ref.singularValues()(0) / ref.singularValues()(2));
    if (!std::isfinite(c) || c > 1e8) continue;
    worst_closed = std::max(worst_closed, std::abs(condition_number_closed_form(J) - c) / (c * c));
    worst_svd = std::max(worst_svd, std::abs(condition_number_svd(J) - c) / (c * c));
  }
  EXPECT_LT(worst_closed, 3 * worst_svd + 1e-16);
}

TEST(Conditioning, FastFormIsWithinFloatPrecisionOfTheClosedForm) {
  // The field engine stores c(J) as float; the fast form must not add error
  // beyond that over the 12R workspace, including near the isotropic optimum.
  parallel12r::Model m;
  linkscape::testing::ConfigurationSampler sample(14, 0.0);
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Matrix3d J = parallel12r::jacobian(m, sample());
    const double c = condition_number_closed_form(J);
    if (!std::isfinite(c) || c > 1e7) continue;
    EXPECT_NEAR(condition_number_fast(J), c, c * (3e-8 + 1e-14 * c));
  }
  const Eigen::Matrix3d iso = parallel12r::jacobian(m, parallel12r::home_pose(0));
  EXPECT_NEAR(condition_number_fast(iso), 1.0, 3e-8);
}
