// PATHOS-II fields: every sample equals the pointwise IK and Jacobian, the
// reach margin changes sign exactly where the pose IK starts to fail, and
// the device's three-fold symmetry shows in the field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <sstream>

#include "core/mechanisms/pathos2/field.h"

using namespace linkscape;
using namespace linkscape::pathos2;
using Eigen::Vector3d;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

pathos2::FieldRequest home_request(const Model& m, Grid grid) {
  pathos2::FieldRequest r;
  r.grid = grid;
  r.rpy = Vector3d(0, 0, 30 * kDeg);  // Table 3 orientation
  r.h0 = m.h0;
  return r;
}

}  // namespace

TEST(Pathos2Field, SamplesEqualPointwiseIkAndJacobian) {
  const Model m;
  const Grid g = Grid::box({-10, -10, 12.5}, {10, 10, 32.5}, {9, 9, 9});
  const Field f = *pathos2::compute_field(m, home_request(m, g));
  ASSERT_EQ(f.cond_orientation.size(), g.size());
  EXPECT_EQ(f.mechanism, "pathos2");
  int reachable = 0;
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i) {
        const std::size_t s = g.index(i, j, k);
        const Vector3d p = g.point(i, j, k);
        const Pose pose = Pose::from_xyz_rpy(p.x(), p.y(), p.z(), 0, 0, 30 * kDeg, m.h0);
        const PoseIkResult ik = inverse(m, pose);
        EXPECT_EQ(f.status[s], std::uint8_t(ik.status));
        EXPECT_EQ(f.reachable[s], ik.status == Status::Ok);
        if (ik.status != Status::Ok) {
          EXPECT_TRUE(std::isinf(f.cond[s]) && std::isinf(f.cond_orientation[s]));
          continue;
        }
        ++reachable;
        const JacobianResult J = jacobian(m, pose);
        EXPECT_NEAR(f.cond[s], J.cond_p, 1e-5 * J.cond_p);
        EXPECT_NEAR(f.cond_orientation[s], J.cond_o, 1e-5 * J.cond_o);
        EXPECT_LT(f.residual[s], 1e-9);  // the solved legs close
      }
  EXPECT_GT(reachable, 50);  // 76 of the 729: the workspace is about an 11.5 cm ball (docs)
}

TEST(Pathos2Field, ReachMarginChangesSignWhereTheIkStartsToFail) {
  // March outward from the home pose along random directions: the margin is
  // positive while every leg solves and negative once one does not.
  const Model m;
  const Geometry g = make_geometry(m);
  pathos2::FieldRequest req = home_request(m, Grid{});
  std::mt19937 rng(11);
  std::normal_distribution<double> n;
  int crossings = 0;
  for (int ray = 0; ray < 200; ++ray) {
    const Vector3d dir = Vector3d(n(rng), n(rng), n(rng)).normalized();
    double previous_margin = 1.0;
    for (double t = 0.0; t < 30.0; t += 0.05) {
      const Vector3d p = Vector3d(0, 0, m.l0 / 2) + t * dir;
      const FieldSample s = sample_position(g, p, req);
      const bool solvable = s.status == std::uint8_t(Status::Ok) || s.status == std::uint8_t(Status::Singular);
      if (s.status == std::uint8_t(Status::Unreachable)) {
        EXPECT_LT(s.reach_margin, 1e-6) << "ray " << ray << " t " << t;
        if (previous_margin > 0) ++crossings;
        break;
      }
      if (solvable) {
        EXPECT_GT(s.reach_margin, -1e-6) << "ray " << ray << " t " << t;
      }
      // Continuous: a 0.5 mm step moves the margin by at most a few times that.
      EXPECT_LT(std::abs(s.reach_margin - previous_margin), t == 0.0 ? 1e9 : 0.5) << "ray " << ray;
      previous_margin = s.reach_margin;
    }
  }
  EXPECT_GT(crossings, 150);  // most rays leave the workspace within 30 cm
}

TEST(Pathos2Field, ThreeFoldSymmetry) {
  // Base joints and plate attachments repeat every 120 deg about z, so a
  // position rotated by 120 deg with the orientation conjugated by the same
  // rotation (Rz(120) Rz(30) Rz(-120) = Rz(30): unchanged) is the same
  // configuration with the legs permuted: same status and conditioning.
  const Model m;
  const Geometry g = make_geometry(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-6, 6);
  int compared = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Vector3d p(u(rng), u(rng), m.l0 / 2 + u(rng));
    const pathos2::FieldRequest a = home_request(m, Grid{}), b = a;
    const Vector3d q = Eigen::AngleAxisd(120 * kDeg, Vector3d::UnitZ()) * p;
    const FieldSample sa = sample_position(g, p, a), sb = sample_position(g, q, b);
    EXPECT_EQ(sa.status, sb.status);
    if (sa.status != std::uint8_t(Status::Ok)) continue;
    EXPECT_NEAR(sa.cond, sb.cond, 1e-4 * sa.cond);
    EXPECT_NEAR(sa.cond_orientation, sb.cond_orientation, 1e-4 * sa.cond_orientation);
    EXPECT_NEAR(sa.reach_margin, sb.reach_margin, 1e-4);
    ++compared;
  }
  EXPECT_GT(compared, 100);
}

TEST(Pathos2Field, BadRequestsAreRefused) {
  const Model m;
  pathos2::FieldRequest r = home_request(m, Grid::box({-1, -1, 20}, {1, 1, 22}, {4, 4, 4}));
  r.h0 = 0;
  EXPECT_THROW(pathos2::compute_field(m, r), std::invalid_argument);
  r.h0 = 7;
  r.memory_limit_bytes = 10;
  EXPECT_THROW(pathos2::compute_field(m, r), std::invalid_argument);
  std::atomic<bool> cancel{true};
  r.memory_limit_bytes = std::size_t(1) << 30;
  EXPECT_FALSE(pathos2::compute_field(m, r, FieldProgress{{}, &cancel}).has_value());
}

// The per-point fast path (sample_oriented: rotation built once,
// IkDetail::Field: no angles but those a limit needs, sqrt for hypot in the
// reach margin; the vector kernel hands its doubtful lanes to it; the vector
// kernel itself is test_field_simd.cpp's) against the reference
// (sample_position per point), with and without joint limits, at random
// orientations and grips, over boxes that cross the reach boundary: cond(Jp),
// cond(Jo), status and reachable bit for bit. The closure residual (taken
// from the legs' cosines and sines rather than their angles) is rounding
// noise, about 1e-15 cm: within 1e-12 (l2 + l3). The reach margin differs
// where an ulp of |a - l1 z| moves the c1x root's c1y = sqrt(l3^2 - e^2)
// near e = +-l3 by up to sqrt(u) l3 (the reference is as far from the exact
// value there): within 1e-7 (l2 + l3). Both with the same infinities.
TEST(Pathos2Field, FastPathEqualsTheReference) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  const auto same_bits = [](const auto& a, const auto& b) {
    if (a.size() != b.size()) return false;
    return std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0;
  };
  std::size_t ok = 0, limited = 0;
  double worst_residual = 0, worst_margin = 0;
  for (int c = 0; c < 8; ++c) {
    Model m;
    if (c % 2 == 1) {  // limits that bind inside the workspace
      m.cone_limit = (30 + 40 * unit(rng)) * kDeg;
      m.t2_limit = (60 + 60 * unit(rng)) * kDeg;
      m.t3_limit = (60 + 60 * unit(rng)) * kDeg;
    }
    pathos2::FieldRequest r = home_request(m, Grid::box({-12, -12, 10}, {12, 12, 35}, {13, 12, 11}));
    r.rpy = Vector3d(0.4 * (unit(rng) - 0.5), 0.4 * (unit(rng) - 0.5), unit(rng));
    r.h0 = m.h0 * (0.8 + 0.4 * unit(rng));
    r.kernel = FieldKernel::Scalar;
    const Field reference = *pathos2::compute_field(m, r);
    const Geometry g = make_geometry(m);
    const Pose oriented = Pose::from_xyz_rpy(0, 0, 0, r.rpy.x(), r.rpy.y(), r.rpy.z(), r.h0);
    const GlobularOffsets offsets = globular_offsets(g, oriented);
    Field fast;
    for (int k = 0; k < r.grid.dims[2]; ++k)
      for (int j = 0; j < r.grid.dims[1]; ++j)
        for (int i = 0; i < r.grid.dims[0]; ++i) {
          const FieldSample s = sample_oriented(g, oriented, offsets, r.grid.point(i, j, k));
          fast.cond.push_back(s.cond);
          fast.cond_orientation.push_back(s.cond_orientation);
          fast.reach_margin.push_back(s.reach_margin);
          fast.residual.push_back(s.residual);
          fast.status.push_back(s.status);
          fast.reachable.push_back(s.reachable);
        }
    EXPECT_TRUE(same_bits(fast.cond, reference.cond)) << c;
    EXPECT_TRUE(same_bits(fast.cond_orientation, reference.cond_orientation)) << c;
    ASSERT_EQ(fast.reach_margin.size(), reference.reach_margin.size());
    for (std::size_t i = 0; i < fast.reach_margin.size(); ++i) {
      const double f = fast.reach_margin[i], ref = reference.reach_margin[i];
      ASSERT_EQ(std::isinf(f), std::isinf(ref)) << c << " " << i;
      if (std::isinf(f)) continue;
      worst_margin = std::max(worst_margin, std::abs(f - ref));
      ASSERT_LE(std::abs(f - ref), 1e-7 * (m.l2 + m.l3)) << c << " " << i;
    }
    ASSERT_EQ(fast.residual.size(), reference.residual.size());
    for (std::size_t i = 0; i < fast.residual.size(); ++i) {
      ASSERT_EQ(std::isinf(fast.residual[i]), std::isinf(reference.residual[i])) << c << " " << i;
      if (std::isinf(fast.residual[i])) continue;
      worst_residual = std::max(worst_residual, double(std::abs(fast.residual[i] - reference.residual[i])));
      ASSERT_LE(std::abs(fast.residual[i] - reference.residual[i]), 1e-12 * (m.l2 + m.l3)) << c << " " << i;
    }
    EXPECT_TRUE(same_bits(fast.status, reference.status)) << c;
    EXPECT_TRUE(same_bits(fast.reachable, reference.reachable)) << c;
    for (std::uint8_t s : fast.status) {
      ok += s == std::uint8_t(Status::Ok);
      limited += s == std::uint8_t(Status::OutOfLimits);
    }
  }
  EXPECT_GT(ok, 100u);
  EXPECT_GT(limited, 10u);
  std::ostringstream worst;
  worst << std::scientific << worst_residual;
  RecordProperty("largest_residual_difference_cm", worst.str());
  worst.str("");
  worst << std::scientific << worst_margin;
  RecordProperty("largest_reach_margin_difference_cm", worst.str());
}
