// The vectorised 12R planar kernel (core/mechanisms/parallel12r/field_simd.cpp)
// against the scalar reference (planar::sample, tested in test_field.cpp), on
// every SIMD target this CPU runs, and the exact x mirror the vectorised field
// uses.
//
// What "agrees" means, sample by sample:
// - status, reachable, method_used and iterations are identical, and so is
//   every infinity (c(J) and residual);
// - the reach margin and residual are computed operation for operation as in
//   the scalar kernel: the stored floats are the roundings of values within
//   1e-14 of the reach of the scalar ones (the range check's arctangents are
//   Highway's, a few ulps from libm's);
// - c(J) is stored as the rounding of a value within kCondTolerance of the
//   scalar double: 1e-12 relative, plus where two eigenvalues l_i > l_j of
//   J^T J nearly coincide, 64 ulps times (l_i + l_j) / (l_i - l_j), capped at
//   1e-7: condition_number_fast takes l1 from cos(acos(r) / 3), flat in r
//   where l1 = l2, and l2 from a quadratic with a double root where l2 = l3,
//   so the last bits of their inputs (the vector path's polynomial for
//   cos(acos(r) / 3), products by reciprocals) move c(J) by that much there
//   (docs/performance.md). In
//   practice the stored floats are identical except very near those sets,
//   where they may differ by one float ulp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/mechanisms/parallel12r/field.h"
#include "core/mechanisms/parallel12r/planar_kernel.h"
#include "core/simd.h"
#include "tests/core/simd_targets.h"

using namespace linkscape;
using simd_test::row_through;
using simd_test::rounds_near;
using simd_test::rounds_within;
using simd_test::Tally;
using simd_test::TargetLimit;
using Eigen::Vector3d;
namespace planar = parallel12r::planar;

namespace {

constexpr double kPi = std::numbers::pi;

struct Case {
  std::string name;
  parallel12r::Model model;
  Grid grid;
  int branch = 0;
};

parallel12r::Model lengths(double L1, double L2) {
  parallel12r::Model m;
  m.L1 = L1;
  m.L2 = L2;
  return m;
}

// Grids over the singular sets, the reach spheres, range limits, scales and
// random boxes, each with a name for the failure messages.
std::vector<Case> cases() {
  std::vector<Case> out;
  // The default box at a resolution where every row has a tail (37 = 4 * 8 + 5).
  {
    const auto m = lengths(15, 15);
    out.push_back({"box 37^3", m, Grid::box(Vector3d::Constant(-30), Vector3d::Constant(30), {37, 37, 37})});
  }
  // Cell centres exactly on y = 0, x = 0, z = 0 and on both reach spheres
  // (radii 0.5 and 1.5, spacing 0.125): the singular band and the boundary.
  {
    const auto m = lengths(1, 0.5);
    const Grid g = Grid::box(Vector3d::Constant(-1.5625), Vector3d::Constant(1.5625), {25, 25, 25});
    out.push_back({"spheres and planes, branch 0", m, g, 0});
    out.push_back({"spheres and planes, branch 1", m, g, 1});
    out.push_back({"x-slice through the spheres", m, Grid::slice(Axis::X, 0.0, -1.5625, 1.5625, -1.5625, 1.5625, 25, 25)});
  }
  // Rows that cross the singular band: |y| from 0 to 1e-7 reach (c up to 1e9,
  // across kMaxTrustedCondition), along y and along x; the z axis (rho = 0);
  // the outer and inner spheres within a few tolerances.
  {
    const auto m = lengths(1.25, 0.75);
    out.push_back({"rows across y = 0", m, Grid::box({-1.5, -2e-7, -0.4}, {1.5, 2e-7, 0.4}, {19, 41, 5})});
    out.push_back({"y row near y = 0", m, row_through({0.9, 0, 0.3}, 1, 1.3e-12, 97)});
    out.push_back({"z axis", m, row_through({0, 0, 0}, 2, 0.031, 129)});
    out.push_back({"near the z axis", m, row_through({1e-13, 1e-13, 1.0}, 0, 7e-13, 45)});
    out.push_back({"outer sphere", m, row_through({0, 2, 0}, 1, 1.1e-12, 61)});
    out.push_back({"inner sphere", m, row_through({0.3, 0.4, 0}, 0, 0.9e-12, 61)});
    // Where c(J) crosses kMaxTrustedCondition: found by bisection on y, then
    // a row whose c(J) steps by about 1e-8 relative across it.
    const planar::UnitModel unit = planar::unit_model(m);
    const auto trusted = [&](double y) { return planar::sample(unit, {0.9, y, 0.3}, 0, false).status == Status::Ok; };
    double lo = 1e-12, hi = 1e-2;  // singular at lo, trusted at hi
    for (int k = 0; k < 200 && hi - lo > 1e-3 * lo; ++k) (trusted(std::sqrt(lo * hi)) ? hi : lo) = std::sqrt(lo * hi);
    out.push_back({"c(J) across kMaxTrustedCondition", m, row_through({0.9, hi, 0.3}, 1, 1e-8 * hi, 301)});
  }
  // Around the c(J) = 1 optimum of L1 = L2 (home pose, endpoint (0, 1, 1)),
  // where all singular values coincide: the quadratic's double root.
  for (double extent : {1e-3, 1e-6, 1e-9}) {
    out.push_back({"around c = 1, extent " + std::to_string(extent), lengths(1, 1),
                   Grid::box(Vector3d(-extent, 1 - extent, 1 - extent), Vector3d(extent, 1 + extent, 1 + extent), {16, 9, 9})});
  }
  // Where the two largest and the two smallest singular values of J coincide
  // (L1 = L2 = 1, branch 0; found by minimising the gap over a random
  // search): c(J) takes the last bits of cos(acos(r) / 3) and the
  // quadratic's double root there.
  out.push_back({"sigma_1 = sigma_2", lengths(1, 1),
                 Grid::box(Vector3d(9.772797e-9, 0.318628177816464, 1.377851982) - Vector3d::Constant(1e-7),
                           Vector3d(9.772797e-9, 0.318628177816464, 1.377851982) + Vector3d::Constant(1e-7), {24, 24, 24})});
  out.push_back({"sigma_2 = sigma_3", lengths(1, 1),
                 Grid::box(Vector3d(-6.2581653504e-5, -1.410815544, -0.097977017290829) - Vector3d::Constant(1e-7),
                           Vector3d(-6.2581653504e-5, -1.410815544, -0.097977017290829) + Vector3d::Constant(1e-7), {24, 24, 24})});
  // Actuator ranges: symmetric alpha (the mirror holds), asymmetric alpha (it
  // does not), a range end at alpha = 0 that the x = 0 samples hit exactly,
  // and tight beta / gamma ranges.
  {
    auto m = lengths(1, 1);
    m.alpha_limits = {-0.6, 0.6};
    m.beta_limits = {-2.0, 2.5};
    out.push_back({"symmetric alpha range", m, Grid::box(Vector3d::Constant(-2.1), Vector3d::Constant(2.1), {32, 30, 28})});
    m.alpha_limits = {-0.3, 0.7};
    out.push_back({"asymmetric alpha range", m, Grid::box(Vector3d::Constant(-2.1), Vector3d::Constant(2.1), {32, 30, 28}), 1});
    m.alpha_limits = {0.0, 1.2};
    m.beta_limits = {-kPi, kPi};
    m.gamma_limits = {-1.0, 1.0};
    out.push_back({"alpha range ending at 0", m, Grid::box(Vector3d::Constant(-2.1), Vector3d::Constant(2.1), {33, 30, 28})});
  }
  // Scales from the smallest to the largest accepted length.
  for (double scale : {parallel12r::kMinLength, 1e-12, 1.0, 1e12, parallel12r::kMaxLength / 4}) {
    const auto m = lengths(1.5 * scale, scale);
    const double r = 2.5 * scale;
    std::ostringstream name;
    name << "scale " << scale;
    out.push_back({name.str(), m, Grid::box(Vector3d::Constant(-r), Vector3d::Constant(r), {23, 22, 21})});
  }
  // Random designs, boxes, ranges and branches.
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 12; ++k) {
    auto m = lengths(0.2 + 2 * unit(rng), 0.2 + 2 * unit(rng));
    if (k % 3 == 1) {
      const double a = 1.5 * unit(rng);
      m.alpha_limits = {-a, a};
      m.gamma_limits = {-kPi + 2 * unit(rng), kPi};
    } else if (k % 3 == 2) {
      m.alpha_limits = {-1.5 * unit(rng), 1.5 * unit(rng)};
      m.beta_limits = {-3 * unit(rng), 3 * unit(rng)};
    }
    const double r = 1.2 * m.reach();
    const Vector3d lo(-r * unit(rng), -r * unit(rng), -r * unit(rng)), hi(r * unit(rng), r * unit(rng), r * unit(rng));
    const std::array<int, 3> dims{1 + int(40 * unit(rng)), 1 + int(40 * unit(rng)), 1 + int(20 * unit(rng))};
    out.push_back({"random " + std::to_string(k), m, Grid::box(lo - Vector3d::Constant(0.01), hi, dims), k % 2});
  }
  return out;
}

// The c(J) tolerance at p: 1e-12, widened where two eigenvalues of J^T J
// nearly coincide (from the planar IK's J at p).
double cond_tolerance(const parallel12r::Model& m, const Vector3d& p, int branch) {
  const parallel12r::IkResult ik = parallel12r::inverse(m, p, parallel12r::IkMethod::Planar);
  for (const auto& s : ik.solutions) {
    if (s.branch != branch) continue;
    return 1e-12 + simd_test::coincident_eigenvalue_allowance(parallel12r::jacobian(m, s.q_actuated));
  }
  return 1e-12;
}

// Compares f (computed by a vectorised kernel) with planar::sample at every
// sample; returns the number of failures (the first few are reported).
int compare_with_reference(const Case& c, const Field& f, const std::string& label, Tally& tally) {
  const Grid& g = c.grid;
  const bool check_limits = !planar::full_ranges(c.model);
  const planar::UnitModel unit = planar::unit_model(c.model);
  const double reach = c.model.reach();
  int failures = 0;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vector3d p = g.point(i, j, k);
        const std::size_t idx = g.index(i, j, k);
        const planar::Sample s = planar::sample(unit, p, c.branch, check_limits);
        const FieldSample want = planar::to_field_sample(s);
        ++tally.samples;
        ++tally.by_status[int(s.status)];
        bool ok = f.status[idx] == want.status && f.reachable[idx] == want.reachable &&
                  f.method_used[idx] == want.method_used && f.iterations[idx] == want.iterations;
        ok = ok && rounds_within(f.reach_margin[idx], s.reach_margin, 1e-14 * reach) &&
             rounds_within(f.residual[idx], s.residual, 1e-14 * reach);
        if (ok && !rounds_near(f.cond[idx], s.cond, 1e-12)) {
          ++tally.wide_cond;
          ok = rounds_near(f.cond[idx], s.cond, cond_tolerance(c.model, p, c.branch));
        }
        if (!ok && ++failures <= 5)
          ADD_FAILURE() << label << ", " << c.name << ": sample (" << i << ", " << j << ", " << k << ") at "
                        << p.transpose() << ": status " << int(f.status[idx]) << " vs " << int(want.status)
                        << ", cond " << f.cond[idx] << " vs " << s.cond << ", margin " << f.reach_margin[idx]
                        << " vs " << s.reach_margin << ", residual " << f.residual[idx] << " vs " << s.residual;
      }
  return failures;
}

Field field_of(const Case& c, PlanarKernel kernel) {
  FieldRequest r;
  r.grid = c.grid;
  r.branch = c.branch;
  r.kernel = kernel;
  return *compute_field(c.model, r);
}

}  // namespace

TEST(FieldSimd, ScalarKernelFieldIsThePointwiseReference) {
  for (const Case& c : cases()) {
    const Field f = field_of(c, PlanarKernel::Scalar);
    const planar::UnitModel unit = planar::unit_model(c.model);
    for (int k = 0; k < c.grid.dims[2]; ++k)
      for (int j = 0; j < c.grid.dims[1]; ++j)
        for (int i = 0; i < c.grid.dims[0]; ++i) {
          const std::size_t idx = c.grid.index(i, j, k);
          const FieldSample s = planar::to_field_sample(
              planar::sample(unit, c.grid.point(i, j, k), c.branch, !planar::full_ranges(c.model)));
          ASSERT_TRUE(f.cond[idx] == s.cond && f.status[idx] == s.status && f.reach_margin[idx] == s.reach_margin &&
                      f.residual[idx] == s.residual)
              << c.name << " " << i << " " << j << " " << k;
        }
  }
}

TEST(FieldSimd, EveryTargetAgreesWithTheScalarKernel) {
  const std::vector<std::string> targets = simd::available_targets();
  ASSERT_FALSE(targets.empty());
  const std::vector<Case> all = cases();
  for (const std::string& target : targets) {
    const TargetLimit limit(target);
    ASSERT_EQ(simd::current_target(), target);
    Tally tally;
    for (const Case& c : all)
      for (PlanarKernel kernel : {PlanarKernel::Vector, PlanarKernel::VectorMirrored}) {
        const std::string label = target + (kernel == PlanarKernel::Vector ? " vector" : " vector-mirrored");
        EXPECT_EQ(compare_with_reference(c, field_of(c, kernel), label, tally), 0) << label << ", " << c.name;
      }
    // The cases reach every status the planar kernel gives, and c(J) rarely
    // needs more than 1e-12.
    for (Status s : {Status::Ok, Status::Unreachable, Status::Singular, Status::OutOfLimits})
      EXPECT_GT(tally.by_status[int(s)], 100) << target << " " << to_string(s);
    EXPECT_LT(tally.wide_cond, tally.samples / 1000) << target;
    RecordProperty(target + " comparisons", std::to_string(tally.samples));
    RecordProperty(target + " c(J) over 1e-12", std::to_string(tally.wide_cond));
  }
}

// As on a machine with only the baseline instruction set (SSE2: Highway's
// portable target, SCALAR with GCC 12 or EMU128): the field as the
// application computes it (default kernel) still agrees.
TEST(FieldSimd, BaselineTargetAloneAgrees) {
  const std::string baseline = simd::available_targets().back();
  EXPECT_TRUE(baseline == "SCALAR" || baseline == "EMU128") << baseline;
  const TargetLimit limit("baseline");
  EXPECT_EQ(simd::current_target(), baseline);
  Tally tally;
  for (const Case& c : cases()) {
    FieldRequest r;
    r.grid = c.grid;
    r.branch = c.branch;
    EXPECT_EQ(compare_with_reference(c, *compute_field(c.model, r), baseline, tally), 0) << c.name;
  }
  EXPECT_GT(tally.by_status[int(Status::Ok)], 1000);
}

// The planar kernel is odd in x with alpha -> -alpha: sample(-x, y, z) has
// the bits of sample(x, y, z) wherever the alpha range is symmetric.
TEST(FieldSimd, MirrorInXIsExactForSymmetricAlphaRanges) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int solved = 0, limited = 0;
  for (int trial = 0; trial < 200000; ++trial) {
    auto m = lengths(1 + 0.9 * unit(rng), 1 + 0.9 * unit(rng));
    if (trial % 2) {
      const double a = 1.5 * std::abs(unit(rng));
      m.alpha_limits = {-a, a};
      m.beta_limits = {-3 * std::abs(unit(rng)), 3 * std::abs(unit(rng))};
    }
    const double r = 1.1 * m.reach();
    // Some targets within 1e-6 of the y = 0 plane, where c(J) is large.
    const Vector3d p(r * unit(rng), r * unit(rng) * (trial % 5 == 0 ? 1e-6 : 1), r * unit(rng));
    const int branch = trial % 3 == 0;
    const bool check_limits = !planar::full_ranges(m);
    const planar::Sample a = planar::sample(planar::unit_model(m), p, branch, check_limits);
    const planar::Sample b = planar::sample(planar::unit_model(m), Vector3d(-p.x(), p.y(), p.z()), branch, check_limits);
    ASSERT_TRUE(a.status == b.status && std::memcmp(&a.cond, &b.cond, sizeof(double)) == 0 &&
                a.reach_margin == b.reach_margin && a.residual == b.residual)
        << p.transpose() << " branch " << branch << ": " << a.cond << " vs " << b.cond;
    solved += a.status == Status::Ok;
    limited += a.status == Status::OutOfLimits;
  }
  EXPECT_GT(solved, 40000);
  EXPECT_GT(limited, 10000);
}

// On a grid whose x coordinates are exact mirrors, the vectorised field is
// symmetric bit for bit, so computing half of each row and mirroring it
// changes nothing; with an asymmetric alpha range it is not symmetric, and
// the mirrored kernel must not (and does not) use the shortcut.
TEST(FieldSimd, MirroredKernelEqualsTheFullOneBitForBit) {
  for (const bool symmetric : {true, false}) {
    Case c{"mirror", lengths(1.3, 0.8), Grid::box(Vector3d::Constant(-2.2), Vector3d::Constant(2.2), {44, 23, 21})};
    c.model.alpha_limits = symmetric ? parallel12r::Interval{-0.9, 0.9} : parallel12r::Interval{-0.5, 0.9};
    const Field full = field_of(c, PlanarKernel::Vector), mirrored = field_of(c, PlanarKernel::VectorMirrored);
    const int n = c.grid.dims[0];
    int asymmetric_samples = 0;
    for (int k = 0; k < c.grid.dims[2]; ++k)
      for (int j = 0; j < c.grid.dims[1]; ++j)
        for (int i = 0; i < n; ++i) {
          const std::size_t idx = c.grid.index(i, j, k), mirror = c.grid.index(n - 1 - i, j, k);
          ASSERT_EQ(std::memcmp(&full.cond[idx], &mirrored.cond[idx], sizeof(float)), 0);
          ASSERT_EQ(full.status[idx], mirrored.status[idx]);
          ASSERT_EQ(full.reach_margin[idx], mirrored.reach_margin[idx]);
          ASSERT_EQ(full.residual[idx], mirrored.residual[idx]);
          const bool same = full.status[idx] == full.status[mirror] &&
                            std::memcmp(&full.cond[idx], &full.cond[mirror], sizeof(float)) == 0 &&
                            full.reach_margin[idx] == full.reach_margin[mirror];
          if (symmetric) {
            ASSERT_TRUE(same) << i << " " << j << " " << k;
          }
          asymmetric_samples += !same;
        }
    if (!symmetric) {
      EXPECT_GT(asymmetric_samples, 100);
    }
  }
}

TEST(FieldSimd, KernelAndTargetSwitchesRejectUnknownNames) {
  EXPECT_THROW(simd::limit_targets("AVX9"), std::invalid_argument);
  try {
    simd::limit_targets("nonsense");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(simd::available_targets().front()), std::string::npos) << e.what();
  }
  const Case c{"box", lengths(1, 1), Grid::box(Vector3d::Constant(-2), Vector3d::Constant(2), {9, 9, 9})};
  FieldRequest r;
  r.grid = c.grid;
  ::setenv("LINKSCAPE_FIELD_KERNEL", "fastest", 1);
  EXPECT_THROW(compute_field(c.model, r), std::invalid_argument);
  ::setenv("LINKSCAPE_FIELD_KERNEL", "scalar", 1);
  const Field from_environment = *compute_field(c.model, r);
  ::unsetenv("LINKSCAPE_FIELD_KERNEL");
  const Field scalar = field_of(c, PlanarKernel::Scalar);
  for (std::size_t i = 0; i < scalar.cond.size(); ++i) ASSERT_EQ(from_environment.cond[i], scalar.cond[i]);
}
