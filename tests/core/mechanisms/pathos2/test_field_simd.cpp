// PATHOS-II's vectorised field kernel (core/mechanisms/pathos2/field_simd.cpp)
// against the reference (FieldKernel::Scalar: sample_position, the Full IK
// and jacobian per point), on every SIMD target this CPU runs and once with
// only the baseline target, over random designs (lengths, lp, theta_t,
// theta_g, phases, tilt, branches, and cone / t2 / t3 limits below pi in a
// third of them), random orientations and grips, boxes over reachable,
// out-of-limits, singular and unreachable samples, and rows across each
// status change found by bisection (steps of 1e-12 and 1e-8 of the size,
// the finer across the Jacobian's kappa = 1e9 where the change is there).
//
// What "agrees" means, sample by sample:
// - status, reachable, method_used and iterations are identical, and so is
//   every infinity (cond, cond_orientation, residual);
// - the reach margin and the residual are within 1e-13 S (S = l1 + l2 + l3)
//   plus a float's rounding: the kernel takes sqrt(x^2 + y^2) for hypot and
//   Highway's arctangent for the limit margins, and the residual (rounding
//   noise of the closure, about 1e-15 S) from the legs' cosines instead of
//   their angles; plus where a leg's c1y = sqrt(y) is near 0, 64 u S^2 / |c1y|
//   (at most sqrt(64 u) S): the reference takes c1y from hypot's rho, the
//   kernel from the IK's rho^2, and the square root magnifies their ulp;
// - cond(Jp) and cond(Jo) are stored as the roundings of values within
//   1e-12 + 16 u kappa relative of the reference's doubles (u = 2^-53, kappa
//   the 1-norm condition number of the dimensionless M, <= 1e9 where the
//   sample is Ok): near the Jacobian's singular set the reference's own
//   values are accurate only to about 4 u kappa (pathos2.h), and the
//   kernel's J differs from its J in the last bits. Where two singular
//   values of a block nearly coincide the kernel hands the sample to the
//   reference, so no allowance is needed there.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "core/mechanisms/pathos2/field.h"
#include "core/simd.h"
#include "tests/core/simd_targets.h"

namespace linkscape::pathos2 {
namespace {

using Eigen::Vector3d;
using simd_test::bisect;
using simd_test::field_of;
using simd_test::kUlp;
using simd_test::row_through;
using simd_test::rounds_near;
using simd_test::rounds_within;
using simd_test::TargetLimit;

constexpr double kPi = std::numbers::pi;

using Case = simd_test::FieldCase<Model, FieldRequest>;

Model random_model(std::mt19937_64& rng, int c) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Model m;
  m.l0 = 45 * (0.8 + 0.4 * unit(rng));
  m.lb = 10 * (0.6 + 0.8 * unit(rng));
  m.l1 = 7 * (0.4 + unit(rng));
  m.l2 = 14 * (0.5 + unit(rng));
  m.l3 = c % 5 == 3 ? m.l2 * (1.05 + 0.5 * unit(rng)) : 6 * (0.4 + unit(rng));  // l3 > l2: w = c2z < 0 somewhere
  m.lp = c % 7 == 0 ? 0.0 : 2 * (0.2 + 1.5 * unit(rng));
  m.h0 = 7 * (0.5 + unit(rng));
  m.theta_t = 0.5236 * (2.5 * unit(rng) - 0.5);
  m.theta_g = c % 4 == 0 ? 0.0 : 0.6 * (2 * unit(rng) - 1);
  m.db = m.lb * std::tan(m.theta_t);
  m.lx = m.lb / std::cos(m.theta_t);
  m.tilt_sign = c % 6 == 5 ? -1.0 : 1.0;
  m.base_phase = c % 2 ? 2 * kPi * unit(rng) : 0.0;
  m.plate_phase = c % 3 ? 2 * kPi * unit(rng) : 0.0;
  for (int& b : m.branch) b = unit(rng) < 0.5 ? 1 : -1;
  if (c % 3 == 1) {
    m.cone_limit = 0.4 + 1.5 * unit(rng);
    m.t2_limit = 0.6 + 2.4 * unit(rng);
    m.t3_limit = 0.6 + 2.4 * unit(rng);
  } else if (c % 6 == 2) {
    m.t3_limit = 0.3 + 2.8 * unit(rng);  // one limit alone
  } else if (c % 6 == 0) {
    m.cone_limit = 0.3 + 1.2 * unit(rng);
  }
  m.validate();
  return m;
}

double size_of(const Model& m) { return m.l1 + m.l2 + m.l3; }

// Rows of 61 samples across the point where the reference's status changes
// between a and b (found by bisection): steps of 1e-12 and 1e-8 of the size.
void add_rows_across_status_changes(const std::string& name, const Model& m, const FieldRequest& r, Vector3d a,
                                    Vector3d b, int axis, std::vector<Case>& out) {
  const Geometry g = make_geometry(m);
  const auto status = [&](const Vector3d& p) { return sample_position(g, p, r).status; };
  const std::uint8_t sa = status(a);
  if (sa == status(b)) return;
  bisect(a, b, [&](const Vector3d& p) { return status(p) == sa; }, 200, 1e-14 * size_of(m));
  // Across kappa = kMaxJacobianCondition where every leg solves on both sides.
  const auto ik_status = [&](const Vector3d& p) {
    return inverse(g, Pose::from_xyz_rpy(p.x(), p.y(), p.z(), r.rpy.x(), r.rpy.y(), r.rpy.z(), r.h0)).status;
  };
  const bool kappa = ik_status(a) == Status::Ok && ik_status(b) == Status::Ok;
  const Vector3d centre = 0.5 * (a + b);
  const double ulp = std::ldexp(1.0, std::ilogb(centre.cwiseAbs().maxCoeff()) - 52);  // of the largest coordinate
  for (double step : {1e-8 * size_of(m), 1e-12 * size_of(m), ulp}) {
    Case c{name + (kappa ? " (kappa)" : "") + (step == ulp ? " ulps" : step < 1e-10 * size_of(m) ? " fine" : " coarse"),
           m, r};
    c.request.grid = row_through(centre, axis, step, 61);
    out.push_back(c);
  }
}

// Rows across kappa = kMaxJacobianCondition between solved points a and b
// where det M changes sign: the singular crossing by bisection on the sign,
// then the status change next to it.
void add_rows_across_jacobian_singularities(const std::string& name, const Model& m, const FieldRequest& r, Vector3d a,
                                            Vector3d b, std::vector<Case>& out) {
  const Geometry g = make_geometry(m);
  // The sign of det M where every leg solves, 0 elsewhere.
  const auto sign = [&](const Vector3d& p) {
    const Pose pose = Pose::from_xyz_rpy(p.x(), p.y(), p.z(), r.rpy.x(), r.rpy.y(), r.rpy.z(), r.h0);
    const PoseIkResult ik = inverse(g, pose);
    if (ik.status != Status::Ok) return 0;
    const double det = jacobian(g, pose, ik).J_qdot_from_twist.determinant();
    return det > 0 ? 1 : det < 0 ? -1 : 0;
  };
  const int sa = sign(a), sb = sign(b);
  if (sa == 0 || sb == 0 || sa == sb) return;
  Vector3d lo = a, hi = b;
  for (int k = 0; k < 200 && (hi - lo).norm() > 1e-15 * size_of(m); ++k) {
    const Vector3d mid = 0.5 * (lo + hi);
    const int sm = sign(mid);
    if (sm == 0) return;  // out of the workspace on the way
    (sm == sa ? lo : hi) = mid;
  }
  add_rows_across_status_changes(name, m, r, a, 0.5 * (lo + hi), 0, out);
}

std::vector<Case> cases() {
  std::vector<Case> out;
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int c = 0; c < 24; ++c) {
    const Model m = random_model(rng, c);
    FieldRequest r;
    r.rpy = c % 4 == 0 ? Vector3d(0, 0, kPi / 6)
                       : Vector3d(0.5 * (2 * unit(rng) - 1), 0.5 * (2 * unit(rng) - 1), kPi * (2 * unit(rng) - 1));
    r.h0 = m.h0 * (0.6 + 0.8 * unit(rng));
    const double s = size_of(m);
    // A box over the workspace and beyond it (an odd count puts samples on
    // the vertical axis), and a tight one around its middle.
    const Vector3d centre(0.1 * s * (unit(rng) - 0.5), 0.1 * s * (unit(rng) - 0.5), 0.5 * m.l0);
    const Vector3d half = c % 3 == 2 ? Vector3d::Constant(0.9 * s) : Vector3d::Constant(0.3 * s);
    const int n = 13 + c % 4;
    r.grid = Grid::box(centre - half, centre + half, {n, n + 1, n - 1});
    out.push_back({"design " + std::to_string(c), m, r});
    // Rows across the status changes on random segments through the box,
    // from points where the legs solve (most of the box is out of reach).
    const auto random = [&]() -> Vector3d { return centre + half.cwiseProduct(Vector3d(2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1)); };
    const Geometry g = make_geometry(m);
    std::vector<Vector3d> solved;
    for (int k = 0; k < 2000 && solved.size() < 12; ++k) {
      const Vector3d p = random();
      if (sample_position(g, p, r).status != std::uint8_t(Status::Unreachable)) solved.push_back(p);
    }
    for (std::size_t k = 0; k < solved.size(); ++k)
      add_rows_across_status_changes("design " + std::to_string(c) + " change " + std::to_string(k), m, r, solved[k],
                                     random(), int(k % 3), out);
    for (std::size_t k = 0; k < solved.size(); ++k)
      for (std::size_t l = k + 1; l < solved.size(); ++l)
        add_rows_across_jacobian_singularities(
            "design " + std::to_string(c) + " change " + std::to_string(k) + "-" + std::to_string(l), m, r, solved[k],
            solved[l], out);
  }
  // The preset's design at Table 3's orientation: its box at a count with a
  // tail in every row, and rows along each axis through the home pose.
  const Model m;
  FieldRequest r;
  r.rpy = Vector3d(0, 0, kPi / 6);
  r.h0 = m.h0;
  r.grid = Grid::box(Vector3d(-15, -15, 7.5), Vector3d(15, 15, 37.5), {37, 37, 37});
  out.push_back({"preset, box 37^3", m, r});
  for (int axis = 0; axis < 3; ++axis) {
    r.grid = row_through(Vector3d(0, 0, m.l0 / 2), axis, 0.173, 203);
    out.push_back({"preset, axis " + std::to_string(axis), m, r});
  }
  // Scales: the preset's design shrunk and grown by powers of ten.
  for (double scale : {1e-8, 1e8}) {
    Model scaled = m;
    for (double* l : {&scaled.l0, &scaled.lb, &scaled.l1, &scaled.l2, &scaled.l3, &scaled.lp, &scaled.h0, &scaled.db,
                      &scaled.lx})
      *l *= scale;
    FieldRequest rs = r;
    rs.h0 = scaled.h0;
    rs.grid = Grid::box(Vector3d(-15, -15, 7.5) * scale, Vector3d(15, 15, 37.5) * scale, {17, 17, 17});
    out.push_back({"preset, scale " + std::to_string(scale), scaled, rs});
  }
  return out;
}

// kappa of the reference's M, as jacobian() takes it.
double kappa_of(const Model& m, const JacobianResult& J) {
  Matrix6d Mu = J.J_qdot_from_twist;
  Mu.leftCols<3>() *= std::ldexp(1.0, std::ilogb(m.l2 + m.l3));
  return Mu.cwiseAbs().colwise().sum().maxCoeff() * Mu.inverse().cwiseAbs().colwise().sum().maxCoeff();
}

// The reference's sample at p with what the tolerances need.
struct Reference {
  FieldSample sample;
  double cond_p = 0, cond_o = 0, kappa = 0, margin_slack = 0;
};

Reference reference_at(const Geometry& g, const Vector3d& p, const FieldRequest& r) {
  Reference ref;
  ref.sample = sample_position(g, p, r);
  const Model& m = g.model;
  const double s = size_of(m), delta = 64 * kUlp * s * s;
  const Pose pose = Pose::from_xyz_rpy(p.x(), p.y(), p.z(), r.rpy.x(), r.rpy.y(), r.rpy.z(), r.h0);
  const PoseIkResult ik = inverse(g, pose);
  ref.margin_slack = 1e-13 * s;
  for (const LegSolution& leg : ik.legs)
    ref.margin_slack = std::max(ref.margin_slack, delta / std::max(std::abs(leg.c1y), std::sqrt(delta)));
  if (ref.sample.status == std::uint8_t(Status::Ok)) {
    const JacobianResult J = jacobian(g, pose, ik);
    ref.cond_p = J.cond_p;
    ref.cond_o = J.cond_o;
    ref.kappa = kappa_of(m, J);
  }
  return ref;
}

// Counts of the samples compared, by status, and of the stored floats that
// differ from the reference's at all, and by more than 1e-12 relative.
struct Tally {
  long samples = 0, by_status[5] = {0, 0, 0, 0, 0};
  long floats = 0, differing[4] = {0, 0, 0, 0}, cond_over_1e12 = 0, kappa_over_1e6 = 0;
  // The largest differences from the reference: cond and cond_orientation
  // relative to its doubles, reach margin and residual to its floats / S.
  double cond_relative = 0, margin = 0, residual = 0;
};

// Compares f with the reference at every sample; returns the number of
// failures (the first few are reported).
int compare_with_reference(const Case& c, const Field& f, const std::string& label, Tally& tally) {
  const Grid& grid = c.request.grid;
  const Geometry g = make_geometry(c.model);
  const double s = size_of(c.model);
  int failures = 0;
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i) {
        const Vector3d p = grid.point(i, j, k);
        const std::size_t idx = grid.index(i, j, k);
        const Reference ref = reference_at(g, p, c.request);
        const FieldSample& want = ref.sample;
        ++tally.samples;
        ++tally.by_status[want.status];
        tally.floats += 4;
        tally.differing[0] += f.cond[idx] != want.cond;
        tally.differing[1] += f.cond_orientation[idx] != want.cond_orientation;
        tally.differing[2] += f.reach_margin[idx] != want.reach_margin;
        tally.differing[3] += f.residual[idx] != want.residual;
        tally.kappa_over_1e6 += ref.kappa > 1e6;
        if (std::isfinite(want.reach_margin))
          tally.margin = std::max(tally.margin, std::abs(double(f.reach_margin[idx]) - want.reach_margin) / s);
        if (std::isfinite(want.residual))
          tally.residual = std::max(tally.residual, std::abs(double(f.residual[idx]) - want.residual) / s);
        if (want.status == std::uint8_t(Status::Ok) && std::isfinite(ref.cond_p) && std::isfinite(ref.cond_o))
          tally.cond_relative = std::max({tally.cond_relative, std::abs(f.cond[idx] - ref.cond_p) / ref.cond_p,
                                          std::abs(f.cond_orientation[idx] - ref.cond_o) / ref.cond_o});
        bool ok = f.status[idx] == want.status && f.reachable[idx] == want.reachable &&
                  f.method_used[idx] == want.method_used && f.iterations[idx] == want.iterations;
        // want's floats are roundings themselves: the slack covers that too.
        ok = ok &&
             rounds_within(f.reach_margin[idx], want.reach_margin, ref.margin_slack + std::abs(want.reach_margin) * 0x1p-24) &&
             rounds_within(f.residual[idx], want.residual, 1e-13 * s + std::abs(want.residual) * 0x1p-24);
        if (want.status == std::uint8_t(Status::Ok)) {
          const bool close = rounds_near(f.cond[idx], ref.cond_p, 1e-12) &&
                             rounds_near(f.cond_orientation[idx], ref.cond_o, 1e-12);
          if (!close) {
            ++tally.cond_over_1e12;
            const double tolerance = 1e-12 + 16 * kUlp * ref.kappa;
            ok = ok && rounds_near(f.cond[idx], ref.cond_p, tolerance) &&
                 rounds_near(f.cond_orientation[idx], ref.cond_o, tolerance);
          }
        } else {
          ok = ok && f.cond[idx] == want.cond && f.cond_orientation[idx] == want.cond_orientation;
        }
        if (!ok && ++failures <= 5)
          ADD_FAILURE() << label << ", " << c.name << ": sample (" << i << ", " << j << ", " << k << ") at "
                        << p.transpose() << ": status " << int(f.status[idx]) << " vs " << int(want.status)
                        << ", cond " << f.cond[idx] << " vs " << ref.cond_p << ", cond_o " << f.cond_orientation[idx]
                        << " vs " << ref.cond_o << ", margin " << f.reach_margin[idx] << " vs " << want.reach_margin
                        << ", residual " << f.residual[idx] << " vs " << want.residual;
      }
  return failures;
}

void record(const std::string& target, const Tally& tally) {
  ::testing::Test::RecordProperty(target + " samples", std::to_string(tally.samples));
  ::testing::Test::RecordProperty(target + " floats", std::to_string(tally.floats));
  const long differing = tally.differing[0] + tally.differing[1] + tally.differing[2] + tally.differing[3];
  ::testing::Test::RecordProperty(target + " floats not identical", std::to_string(differing));
  ::testing::Test::RecordProperty(target + " cond over 1e-12", std::to_string(tally.cond_over_1e12));
  std::printf("%s: %ld samples (Ok %ld, %ld of them with kappa > 1e6; Unreachable %ld, Singular %ld, OutOfLimits "
              "%ld); %ld of %ld floats not identical (cond %ld, cond_orientation %ld, reach_margin %ld, residual "
              "%ld); %ld Ok samples with a cond over 1e-12 relative; largest differences: cond %.3g relative (the "
              "stored float's rounding included), reach margin %.3g S, residual %.3g S\n",
              target.c_str(), tally.samples, tally.by_status[int(Status::Ok)], tally.kappa_over_1e6,
              tally.by_status[int(Status::Unreachable)], tally.by_status[int(Status::Singular)],
              tally.by_status[int(Status::OutOfLimits)], differing, tally.floats, tally.differing[0],
              tally.differing[1], tally.differing[2], tally.differing[3], tally.cond_over_1e12, tally.cond_relative,
              tally.margin, tally.residual);
}

TEST(Pathos2FieldSimd, EveryTargetAgreesWithTheReference) {
  const std::vector<std::string> targets = simd::available_targets();
  ASSERT_FALSE(targets.empty());
  const std::vector<Case> all = cases();
  const auto changes =
      std::count_if(all.begin(), all.end(), [](const Case& c) { return c.name.find("change") != std::string::npos; });
  EXPECT_GT(changes, 100);  // rows across status changes
  RecordProperty("rows across status changes", std::to_string(changes));
  const auto kappa_changes =
      std::count_if(all.begin(), all.end(), [](const Case& c) { return c.name.find("kappa") != std::string::npos; });
  std::printf("%ld rows across status changes, %ld of them across kappa = 1e9\n", long(changes), long(kappa_changes));
  for (const std::string& target : targets) {
    const TargetLimit limit(target);
    ASSERT_EQ(simd::current_target(), target);
    Tally tally;
    for (const Case& c : all)
      for (FieldKernel kernel : {FieldKernel::Vector, FieldKernel::VectorMirrored})
        EXPECT_EQ(compare_with_reference(c, field_of(c, kernel), target, tally), 0) << target << ", " << c.name;
    // The cases reach every status the field gives.
    for (Status s : {Status::Ok, Status::Unreachable, Status::Singular, Status::OutOfLimits})
      EXPECT_GT(tally.by_status[int(s)], 200) << target << " " << to_string(s);
    EXPECT_LT(tally.cond_over_1e12, tally.by_status[int(Status::Ok)] / 20) << target;
    record(target, tally);
  }
}

// As on a machine with only the baseline instruction set (SSE2): the field
// as the application computes it (the default kernel) still agrees.
TEST(Pathos2FieldSimd, BaselineTargetAloneAgrees) {
  const std::string baseline = simd::available_targets().back();
  const TargetLimit limit("baseline");
  EXPECT_EQ(simd::current_target(), baseline);
  Tally tally;
  for (const Case& c : cases())
    EXPECT_EQ(compare_with_reference(c, *compute_field(c.model, c.request), baseline, tally), 0) << c.name;
  EXPECT_GT(tally.by_status[int(Status::Ok)], 1000);
  record(baseline + " alone", tally);
}

// On the axis of three-fold symmetry (x = y = 0, level, rz = 0 .. 60 deg
// in 6 deg steps, z over the reachable heights) the two horizontal singular
// values of each block coincide, where the closed form's trigonometric root
// alone is off by up to ~3e-9: a float's rounding in a few percent of the
// samples. Every target stores the reference's floats there, bit for bit.
TEST(Pathos2FieldSimd, AxisOfSymmetryMatchesTheReferenceBitForBit) {
  for (const std::string& target : simd::available_targets()) {
    const TargetLimit limit(target);
    long compared = 0, differing = 0;
    for (int deg = 0; deg <= 60; deg += 6) {
      Case c{"axis, rz " + std::to_string(deg) + " deg", Model{}, {}};
      c.request.rpy = Vector3d(0, 0, deg * kPi / 180);
      c.request.grid = Grid::box(Vector3d(-1, -1, 16), Vector3d(1, 1, 29), {1, 1, 128});  // x = y = 0 exactly
      const Field kernel = field_of(c, FieldKernel::Vector), reference = field_of(c, FieldKernel::Scalar);
      for (std::size_t i = 0; i < reference.cond.size(); ++i) {
        if (reference.status[i] != std::uint8_t(Status::Ok)) continue;
        ++compared;
        differing += kernel.cond[i] != reference.cond[i];
        differing += kernel.cond_orientation[i] != reference.cond_orientation[i];
      }
    }
    EXPECT_GT(compared, 800) << target;
    EXPECT_EQ(differing, 0) << target << ": of " << 2 * compared << " floats";
  }
}

TEST(Pathos2FieldSimd, KernelSwitch) {
  const Model m;
  Case c{"switch", m, {}};
  c.request.rpy = Vector3d(0, 0, kPi / 6);
  c.request.grid = Grid::box(Vector3d(-10, -10, 12.5), Vector3d(10, 10, 32.5), {11, 9, 7});
  const Field reference = field_of(c, FieldKernel::Scalar);
  const auto same = [](const Field& a, const Field& b) {
    return a.cond == b.cond && a.cond_orientation == b.cond_orientation && a.reach_margin == b.reach_margin &&
           a.residual == b.residual && a.status == b.status;
  };
  ::setenv("LINKSCAPE_FIELD_KERNEL", "scalar", 1);
  EXPECT_TRUE(same(*compute_field(m, c.request), reference));
  ::unsetenv("LINKSCAPE_FIELD_KERNEL");
  Tally tally;
  EXPECT_EQ(compare_with_reference(c, *compute_field(m, c.request), "default", tally), 0);
  EXPECT_TRUE(same(field_of(c, FieldKernel::Vector), field_of(c, FieldKernel::VectorMirrored)));
}

}  // namespace
}  // namespace linkscape::pathos2
