// The force ellipsoid (core/force_ellipsoid.h) against its definition: the
// semi-axes against the singular values of the force map built here by a
// pseudo-inverse, its surface on the unit sphere of rated-torque fractions,
// and its place in the torque polytope whose measures haptics::measures
// gives (force_iso, force_max), on random Jacobians and shipped devices.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "core/force_ellipsoid.h"
#include "core/haptics.h"
#include "core/preset.h"

namespace linkscape::haptics {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

DeviceData data_for(int rows, std::vector<double> torques_Nm, double metres_per_unit) {
  DeviceData d;
  d.position_rows = rows;
  d.metres_per_length_unit = metres_per_unit;
  for (double t : torques_Nm) {
    Rating r;
    r.continuous_torque_Nm = t;
    r.peak_torque_Nm = 3 * t;
    r.encoder_counts_per_rev = 2000;
    d.actuators.push_back(r);
  }
  return d;
}

// The force map M = (W^-1 J_p^T)^+ in N per unit torque fraction, built
// from the definition (J_p in metres per radian).
MatrixXd force_map(const MatrixXd& J, const DeviceData& d) {
  MatrixXd B = J.topRows(d.position_rows).transpose() * d.metres_per_length_unit;  // tau = B F
  for (Eigen::Index i = 0; i < B.rows(); ++i) B.row(i) /= d.actuators[std::size_t(i)].continuous_torque_Nm;
  return B.completeOrthogonalDecomposition().pseudoInverse();
}

struct Case {
  int rows, actuators;
};

class ForceEllipsoidRandom : public ::testing::TestWithParam<Case> {};

// Spatial with three and four actuators, planar with two and three; J
// with an extra task row below the position rows (an orientation).
TEST_P(ForceEllipsoidRandom, SemiAxesAreTheForceMapsSingularValues) {
  const auto [rows, n] = GetParam();
  std::mt19937 rng(17 + rows * 10 + n);
  std::uniform_real_distribution<double> u(-1, 1), torque(0.05, 0.5);
  for (int trial = 0; trial < 200; ++trial) {
    const MatrixXd J = MatrixXd::NullaryExpr(rows + 1, n, [&] { return 20 * u(rng); });  // cm per rad
    std::vector<double> torques;
    for (int i = 0; i < n; ++i) torques.push_back(torque(rng));
    const DeviceData d = data_for(rows, torques, 0.01);
    const ForceEllipsoid e = force_ellipsoid(J, d, TorqueRating::Continuous);
    ASSERT_EQ(e.status, Status::Ok);
    const MatrixXd M = force_map(J, d);
    const VectorXd sigma = Eigen::JacobiSVD<MatrixXd>(M).singularValues();
    for (int k = 0; k < rows; ++k) EXPECT_NEAR(e.semi_axes_N(k), sigma(k), 1e-9 * sigma(0)) << "trial " << trial;
    // Each semi-axis's end needs exactly the rated torques' unit fraction.
    MatrixXd B = J.topRows(rows).transpose() * 0.01;
    for (int i = 0; i < n; ++i) B.row(i) /= torques[std::size_t(i)];
    for (int k = 0; k < rows; ++k) {
      EXPECT_NEAR(e.axes.col(k).norm(), 1, 1e-12);
      EXPECT_NEAR((B * (e.semi_axes_N(k) * e.axes.col(k))).norm(), 1, 1e-9);
    }
    // Inside the torque polytope: the ball of force_iso holds the smallest
    // semi-axis and is held by sqrt(n) times it; force_max bounds the largest.
    const Measures m = measures(J, d, TorqueRating::Continuous);
    const double smallest = e.semi_axes_N(rows - 1);
    EXPECT_LE(smallest, m.force_iso_N * (1 + 1e-12));
    EXPECT_LE(m.force_iso_N, std::sqrt(double(n)) * smallest * (1 + 1e-12));
    EXPECT_LE(e.semi_axes_N(0), m.force_max_N * (1 + 1e-12));
    // With as many actuators as rows it touches every face |tau_i| = tau_max_i:
    // its support along face i's normal b_i is 1.
    if (n == rows)
      for (int i = 0; i < n; ++i) {
        const VectorXd in_axes = e.axes.transpose() * B.row(i).transpose();
        EXPECT_NEAR(in_axes.cwiseProduct(e.semi_axes_N).norm(), 1, 1e-9);
      }
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, ForceEllipsoidRandom, ::testing::Values(Case{3, 3}, Case{3, 4}, Case{2, 2}, Case{2, 3}),
                         [](const auto& info) {
                           return std::to_string(info.param.rows) + "rows" + std::to_string(info.param.actuators) +
                                  "actuators";
                         });

// Orthogonal columns: the polytope is a box whose inscribed ball is the
// ellipsoid's smallest axis, force_iso exactly.
TEST(ForceEllipsoid, OrthogonalColumnsGiveForceIsoAsTheSmallestAxis) {
  MatrixXd J = MatrixXd::Zero(3, 3);
  J.diagonal() << 4.0, 10.0, 6.0;  // cm per rad
  const DeviceData d = data_for(3, {0.2, 0.3, 0.1}, 0.01);
  const ForceEllipsoid e = force_ellipsoid(J, d, TorqueRating::Continuous);
  const Measures m = measures(J, d, TorqueRating::Continuous);
  // tau_i / (J_ii m): 5, 3, 1.667 N; largest first.
  EXPECT_NEAR(e.semi_axes_N(0), 5.0, 1e-12);
  EXPECT_NEAR(e.semi_axes_N(1), 3.0, 1e-12);
  EXPECT_NEAR(e.semi_axes_N(2), m.force_iso_N, 1e-12);
  EXPECT_NEAR(std::abs(e.axes(2, 2)), 1.0, 1e-12);  // the weakest direction is z
  // Peak torque: three times as large.
  EXPECT_NEAR(force_ellipsoid(J, d, TorqueRating::Peak).semi_axes_N(2), 3 * m.force_iso_N, 1e-12);
}

TEST(ForceEllipsoid, RankLossIsSingular) {
  MatrixXd J(3, 3);
  J << 1, 2, 3, 0, 1, 1, 1, 3, 4;  // column 3 = column 1 + column 2
  const ForceEllipsoid e = force_ellipsoid(J, data_for(3, {0.2, 0.2, 0.2}, 0.01), TorqueRating::Continuous);
  EXPECT_EQ(e.status, Status::Singular);
  EXPECT_TRUE(std::isinf(e.semi_axes_N(0)));
  EXPECT_TRUE(std::isfinite(e.semi_axes_N(2)));
  // Fewer actuators than rows: a direction no torque holds.
  EXPECT_EQ(force_ellipsoid(MatrixXd::Ones(3, 2), data_for(3, {0.2, 0.2}, 0.01), TorqueRating::Continuous).status,
            Status::Singular);
}

TEST(ForceEllipsoid, AJacobianOfTheWrongSizeIsRefused) {
  EXPECT_THROW(force_ellipsoid(MatrixXd::Ones(3, 2), data_for(3, {0.2, 0.2, 0.2}, 0.01), TorqueRating::Continuous),
               std::invalid_argument);
  EXPECT_THROW(force_ellipsoid(MatrixXd::Ones(2, 3), data_for(3, {0.2, 0.2, 0.2}, 0.01), TorqueRating::Continuous),
               std::invalid_argument);
}

// At the shipped devices' home poses, with their own ratings and units.
TEST(ForceEllipsoid, ShippedDevicesAtHomeAgreeWithTheirMeasures) {
  for (const char* name : {"falcon", "delta", "parallel-12r", "five-bar", "pathos2"}) {
    const Preset preset = load_preset(name);
    const auto m = make_mechanism(preset);
    const DeviceData d = device_data(preset, m->info());
    const MatrixXd J = m->jacobian(m->home_actuators(), m->home_task());
    const ForceEllipsoid e = force_ellipsoid(J, d, TorqueRating::Continuous);
    ASSERT_EQ(e.status, Status::Ok) << name;
    ASSERT_EQ(e.semi_axes_N.size(), d.position_rows) << name;
    MatrixXd M = J.topRows(d.position_rows).transpose();
    for (Eigen::Index i = 0; i < M.rows(); ++i)
      M.row(i) *= d.metres_per_motor_radian(std::size_t(i)) / d.actuators[std::size_t(i)].continuous_torque_Nm;
    const VectorXd sigma =
        Eigen::JacobiSVD<MatrixXd>(M.completeOrthogonalDecomposition().pseudoInverse()).singularValues();
    for (int k = 0; k < d.position_rows; ++k) EXPECT_NEAR(e.semi_axes_N(k), sigma(k), 1e-9 * sigma(0)) << name;
    const Measures h = measures(J, d, TorqueRating::Continuous);
    EXPECT_LE(e.semi_axes_N(d.position_rows - 1), h.force_iso_N * (1 + 1e-12)) << name;
    EXPECT_LE(e.semi_axes_N(0), h.force_max_N * (1 + 1e-12)) << name;
  }
}

}  // namespace
}  // namespace linkscape::haptics
