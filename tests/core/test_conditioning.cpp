// The condition numbers of a 3x3 Jacobian every device uses (core/conditioning.h).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "core/conditioning.h"

using namespace linkscape;

TEST(Conditioning, ClosedFormMatchesSvdOnRandomMatrices) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    Eigen::Matrix3d J;
    for (int k = 0; k < 9; ++k) J(k / 3, k % 3) = n(rng);
    const double svd = condition_number_svd(J);
    // Both are backward stable: relative error ~ 1e-16 * cond each.
    EXPECT_NEAR(condition_number_closed_form(J), svd, svd * (1e-13 + 1e-14 * svd));
  }
}

TEST(Conditioning, ClosedFormStaysAccurateNearSingularity) {
  // diag(1, 1, eps) rotated: cond = 1/eps exactly.
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (double eps : {1e-3, 1e-6, 1e-9, 1e-12}) {
    const Eigen::Matrix3d J = Q * Eigen::Vector3d(1.0, 0.5, eps).asDiagonal() * Q.transpose();
    EXPECT_NEAR(condition_number_closed_form(J) * eps, 1.0, 1e-13 + 1e-14 / eps) << eps;
  }
}

TEST(Conditioning, SingularAndIsotropicEdgeCases) {
  EXPECT_TRUE(std::isinf(condition_number_closed_form(Eigen::Matrix3d::Zero())));
  Eigen::Matrix3d rank2 = Eigen::Matrix3d::Identity();
  rank2(2, 2) = 0;
  EXPECT_TRUE(std::isinf(condition_number_closed_form(rank2)));
  EXPECT_DOUBLE_EQ(condition_number_closed_form(2.5 * Eigen::Matrix3d::Identity()), 1.0);
}
