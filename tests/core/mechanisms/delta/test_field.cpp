// The Delta's vectorised field kernel (core/mechanisms/delta/field_simd.cpp)
// against the reference sample (sample_point: inverse, reach_margin and
// jacobian per point), on every SIMD target this CPU runs and once with only
// the baseline target, over random designs, actuator ranges, branches,
// tolerances and boxes that cross the workspace boundary, the z axis (where
// two singular values of J coincide) and rows that cross each status change
// in steps of 1e-12 of the device's size, and rows across the surface where
// the reach margin's geometric and actuator-range terms meet.
//
// What "agrees" means, sample by sample:
// - status, reachable, method_used and iterations are identical, and so is
//   every infinity (c(J) and residual);
// - the reach margin and the residual are within 1e-13 of the size
//   (size = La + Lb): the kernel takes sqrt(a^2 + b^2) for hypot and
//   Highway's arctangent for the actuator angles (just outside a leg's
//   serial singular band its angle, and with it the margin's range term,
//   can move by up to about 1e-10 rad in the reference as in the kernel;
//   the rows here do not come that near, and statuses that hang on it are
//   checked by RangeEndNearASerialSingularSurface);
// - c(J) is stored as the rounding of a value within kCondSlack of the
//   reference's double: 1e-12 relative, plus 64 ulps times c(J) (the
//   kernel's cos q_i, sin q_i are ratios instead of libm's cos and sin of the
//   angle, so J differs in its last bits, and a relative change e of J moves
//   c(J) by up to about 2 c(J) e), plus where two eigenvalues l_i > l_j of
//   J^T J nearly coincide 64 ulps times (l_i + l_j) / (l_i - l_j), capped at
//   1e-7 (the closed form's arccosine is flat there; the 12R kernel's test
//   explains it), plus 16 ulps times size / m where m is the smallest of the
//   legs' margins |m_i|: near a leg's serial singular surface (m_i = 0) its
//   angle depends on sqrt(m_i), so the last bits of m_i (an ulp of the size
//   in the kernel and in the reference alike, from hypot or sqrt) move J's
//   row i by about size / m_i ulps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/mechanism.h"
#include "core/mechanisms/delta/field.h"
#include "core/mechanisms/delta/mechanism.h"
#include "core/simd.h"
#include "tests/core/simd_targets.h"

namespace linkscape::delta {
namespace {

using Eigen::Vector3d;
using simd_test::bisect;
using simd_test::field_of;
using simd_test::kUlp;
using simd_test::row_through;
using simd_test::rounds_near;
using simd_test::rounds_within;
using simd_test::Tally;
using simd_test::TargetLimit;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

using Case = simd_test::FieldCase<Model, FieldRequest>;

Model random_model(std::mt19937_64& rng, int c) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Model m;
  m.R = 4 + 8 * unit(rng);
  m.r = c % 5 == 0 ? m.R : 6 * unit(rng);  // R = r: the legs' circles coincide
  m.La = 4 + 8 * unit(rng);
  m.Lb = m.La * (0.6 + 2 * unit(rng));
  const double width = 0.5 + 3.0 * unit(rng);
  for (auto& range : m.q_limits) {
    if (c % 4 == 1) {
      range = {-std::numbers::pi, std::numbers::pi};  // the full circle
    } else if (c % 4 == 3) {
      const double lo = -2.0 * unit(rng);  // the same width, centres apart
      range = {lo, lo + width};
    } else {
      range = {-2.0 * unit(rng), 2.0 * unit(rng)};
    }
  }
  if (c % 2 == 0) m.q_limits[2] = m.q_limits[1];  // the mirror in y holds with branches 0, 1, 6, 7
  return m;
}

// Rows of 61 samples 1e-12 size apart across the point where the reference's
// status changes between a and b (found by bisection), along the x axis.
void add_rows_across_status_changes(const std::string& name, const Model& m, const FieldRequest& r, Vector3d a,
                                    Vector3d b, std::vector<Case>& out) {
  // A change of status, or of c(J) between finite and infinite (J singular on a solved pose).
  const auto status = [&](const Vector3d& p) {
    const FieldSample s = sample_point(m, p, r);
    return 2 * int(s.status) + int(std::isinf(s.cond));
  };
  const int sa = status(a);
  if (sa == status(b)) return;
  const auto same_as_a = [&](const Vector3d& p) { return status(p) == sa; };
  bisect(a, b, same_as_a, 200, 1e-14 * m.size());
  Case c{name, m, r};
  c.request.grid = row_through(0.5 * (a + b), 0, 1e-12 * m.size(), 61);
  out.push_back(c);
  // On to the last bits, and a row a few ulps a step across it: where the
  // kernel's and the reference's roundings could decide differently.
  bisect(a, b, same_as_a, 80);
  Case fine = c;
  fine.name += ", ulp steps";
  fine.request.grid = row_through(0.5 * (a + b), 0, 4 * kUlp * std::max(std::abs(a.x()), 1e-3 * m.size()), 61);
  out.push_back(fine);
  // The same row and its mirror in y, two rows of one grid (y = -+y0 exactly,
  // with y0 rounded to 40 bits so that 3 y0 is exact): the mirrored kernel
  // computes the second from the first.
  const double y0 = std::ldexp(std::round(std::ldexp(std::abs(c.request.grid.point(0, 0, 0).y()), 40)), -40);
  if (y0 == 0.0) return;
  c.name += ", mirrored";
  c.request.grid.dims[1] = 2;
  c.request.grid.spacing.y() = 2.0 * y0;
  c.request.grid.origin.y() = -2.0 * y0;
  out.push_back(c);
}

// Rows of 61 samples across the surface where the reach margin's two terms
// meet (the legs' geometric margin and La times the smallest actuator range
// margin, found by bisection between a and b), in steps of 1e-5 and 1e-12 of
// the size: the kernel takes an arctangent only where the range term can be
// the smaller, decided by bounds on the angle.
void add_rows_across_margin_crossover(const std::string& name, const Model& m, const FieldRequest& r, Vector3d a,
                                      Vector3d b, std::vector<Case>& out) {
  const auto limits_smaller = [&](const Vector3d& p) {
    const ReachMargin margin = reach_margin(m, p, r.ik.branch);
    return margin.limits < margin.geometric;
  };
  const bool sa = limits_smaller(a);
  if (sa == limits_smaller(b)) return;
  bisect(a, b, [&](const Vector3d& p) { return limits_smaller(p) == sa; }, 200, 1e-14 * m.size());
  for (double step : {1e-5, 1e-12}) {
    Case c{name + " margin crossover, step " + std::to_string(step), m, r};
    c.request.grid = row_through(0.5 * (a + b), 0, step * m.size(), 61);
    out.push_back(c);
  }
}

// Rows across the type II singular surface of design m, where the sphere
// centres' circumradius reaches Lb (J singular on a solved pose): actuator
// angles in their ranges bisected between a pair whose forward kinematics
// is Ok and one where it is not, the platform there, and rows through it in
// random directions on the elbow branch of those angles.
void add_rows_across_type_two(const std::string& name, const Model& m, const FieldRequest& base, std::mt19937_64& rng,
                              std::vector<Case>& out) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto random_angles = [&] {
    Vector3d q;
    for (int i = 0; i < kLegCount; ++i) q(i) = m.q_limits[i].lo + (m.q_limits[i].hi - m.q_limits[i].lo) * unit(rng);
    return q;
  };
  int found = 0;
  for (int attempt = 0; attempt < 200 && found < 3; ++attempt) {
    Vector3d ok = random_angles(), other = random_angles();
    if (forward(m, ok).status != Status::Ok || forward(m, other).status == Status::Ok) continue;
    bisect(ok, other, [&](const Vector3d& q) { return forward(m, q).status == Status::Ok; }, 80);
    const Vector3d p = forward(m, ok).p_base_platform;
    FieldRequest r = base;
    r.ik.branch = branch_of(m, ok, p);
    const Vector3d dir = Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5).normalized();
    const std::size_t before = out.size();
    // p is at the edge of the thin layer where the circumradius is within
    // the singular tolerance of Lb: one side or the other crosses it.
    for (double side : {-1.0, 1.0})
      add_rows_across_status_changes(name + " type II " + std::to_string(attempt), m, r, p,
                                     p + side * 1e-4 * m.size() * dir, out);
    found += out.size() > before;
  }
}

std::vector<Case> cases() {
  std::vector<Case> out;
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int c = 0; c < 24; ++c) {
    const Model m = random_model(rng, c);
    FieldRequest r;
    r.ik.branch = c % kBranchCount;
    // 1e-3: looser than the Jacobian's closure check; 3e-17: under the
    // closure's rounding, so that most solved samples are NotConverged.
    r.ik.tolerance = c % 6 == 2 ? 1e-3 : c % 6 == 4 ? 3e-17 : 1e-10;
    const double s = m.size();
    // Boxes over the whole workspace, through the z axis (odd counts put a
    // column of samples on x = y = 0), and thin ones across the boundary.
    const int n = 15 + c % 3;
    const Vector3d centre = c % 3 == 2 ? Vector3d(0, 0, -0.5 * s) : Vector3d(0.3 * s * (unit(rng) - 0.5), 0, -0.5 * s);
    const Vector3d half = c % 3 == 2 ? Vector3d(1.2 * s, 1.2 * s, 1.2 * s) : Vector3d(0.7 * s, 0.7 * s, 0.7 * s);
    r.grid = Grid::box(centre - half, centre + half, {n, n, n});
    out.push_back({"design " + std::to_string(c), m, r});
    // Rows across the status changes on random segments through the box.
    for (int k = 0; k < 6; ++k) {
      const auto random = [&] { return Vector3d(2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1); };
      const Vector3d a = centre + half.cwiseProduct(random()), b = centre + half.cwiseProduct(random());
      add_rows_across_status_changes("design " + std::to_string(c) + " change " + std::to_string(k), m, r, a, b, out);
      add_rows_across_margin_crossover("design " + std::to_string(c) + " segment " + std::to_string(k), m, r, a, b, out);
    }
    if (c % 3 == 0) add_rows_across_type_two("design " + std::to_string(c), m, r, rng, out);
  }
  // The preset's design: its default box at a count with a tail in every row,
  // the z axis, and rows across leg 0's folded singular surface (d_max = Lb,
  // margin 0) in steps of 0.3 of the singular tolerance.
  const Model m;
  FieldRequest r;
  r.grid = Grid::box(Vector3d(-25, -25, -30), Vector3d(25, 25, 5), {37, 37, 37});
  out.push_back({"preset, box 37^3", m, r});
  r.grid = row_through(Vector3d(0, 0, -15), 2, 0.37, 81);
  out.push_back({"preset, z axis", m, r});
  // Along y through leg 0's motor axis (x = R - r, z = 0: its angle is 0 / 0),
  // and boxes far out (coordinates past 2^70, and within it), where the
  // kernel's products would leave double's range: the reference decides.
  r.grid = row_through(Vector3d(m.R - m.r, 0.0, 0.0), 1, 0.37, 81);
  out.push_back({"preset, leg 0's motor axis", m, r});
  r.grid = row_through(Vector3d(0.0, 1e76, -1e76), 0, 0.37, 41);  // near x = 0, far in y and z
  out.push_back({"preset, row far out in y and z", m, r});
  r.grid = row_through(Vector3d(0.0, 0.0, -10.0), 0, 1e158, 41);  // far out along x only
  out.push_back({"preset, row far out along x", m, r});
  for (double far : {1e20, 1e22, 1e160}) {
    r.grid = Grid::box(Vector3d(-far, -far, -far), Vector3d(far, far, far), {9, 9, 9});
    out.push_back({"preset, box at " + std::to_string(far), m, r});
  }
  // Ranges [-1, 1] (the same width, centre 0) on the plane z = 0, where every
  // leg that does not reach has the angle 0 or pi exactly: legs tie in
  // |q - centre| up to which of 0 and pi they are.
  {
    Model symmetric = m;
    symmetric.q_limits.fill({-1.0, 1.0});
    FieldRequest rz;
    rz.grid.dims = {41, 41, 1};
    rz.grid.spacing = Vector3d(1.25, 1.25, 1.0);
    rz.grid.origin = Vector3d(-25.625, -25.625, -0.5);  // z = 0 exactly
    out.push_back({"ranges [-1, 1], plane z = 0", symmetric, rz});
  }
  // The preset scaled far up and down: its default box has coordinates past
  // 2^70 and half-angle norms under 2^-300 at the extremes.
  for (double scale : {1e-60, 1e15, 1e30, 1e60, 1e76}) {
    Model scaled = m;
    scaled.R *= scale;
    scaled.r *= scale;
    scaled.La *= scale;
    scaled.Lb *= scale;
    FieldRequest rs;
    rs.grid = Grid::box(scale * Vector3d(-25, -25, -30), scale * Vector3d(25, 25, 5), {11, 11, 11});
    out.push_back({"preset scaled by " + std::to_string(scale), scaled, rs});
    // A row along x through its home position with x small: only y, z and the lengths are large.
    rs.grid = row_through(home_position(scaled), 0, 1e10, 41);
    out.push_back({"preset scaled by " + std::to_string(scale) + ", home row", scaled, rs});
  }
  const double tol = kSingularTolerance * m.size();
  for (int k = 0; k < 12; ++k) {
    const double a = -0.3 - 2.5 * k / 12.0, reach = m.Lb - m.La;
    r.grid = row_through(Vector3d((m.R - m.r) + reach * std::cos(a), 0.0, reach * std::sin(a)), 0, 0.3 * tol, 41);
    out.push_back({"preset, folded leg " + std::to_string(k), m, r});
  }
  // r = R and p = (0, 0, -La): every platform joint on its elbow's circle
  // (d_min = 0 for every leg), with Lb < La and full ranges, so that the
  // reach margin is Lb - d_min: d_min^2 must not come from a difference
  // of terms of size La^2 (its rounding would put d_min at about
  // sqrt(ulp) La).
  for (double La : {4.3, 5.9, 7.1, 9.7, 11.3})
    for (double ratio : {0.05, 0.1, 0.2}) {
      Model at_joints;
      at_joints.R = at_joints.r = 6.0;
      at_joints.La = La;
      at_joints.Lb = ratio * La;
      at_joints.q_limits.fill({-std::numbers::pi, std::numbers::pi});
      FieldRequest rj;
      for (int axis : {0, 1, 2})
        for (double step : {1e-7, 1e-13}) {
          rj.grid = row_through(Vector3d(0.0, 0.0, -La), axis, step * at_joints.size(), 41);
          out.push_back({"elbows at the joints, La " + std::to_string(La) + ", Lb / La " + std::to_string(ratio) +
                             ", axis " + std::to_string(axis) + ", step " + std::to_string(step),
                         at_joints, rj});
        }
    }
  return out;
}

// The c(J) slack at p (from the reference's J there).
double cond_slack(const Model& m, const Vector3d& p, const FieldRequest& r) {
  const IkResult ik = inverse(m, p, IkMethod::Closed, r.ik);
  const JacobianResult jac = jacobian(m, ik.q_actuated, p);
  const double coincident = simd_test::coincident_eigenvalue_allowance(jac.J_actuated_from_task);
  double margin = kInfinity;
  for (int i = 0; i < kLegCount; ++i) margin = std::min(margin, std::abs(leg_margin(m, i, p)));
  return 1e-12 + 64 * kUlp * jac.cond + 16 * kUlp * m.size() / margin + coincident;
}

// Compares f with sample_point at every sample; returns the number of
// failures (the first few are reported).
int compare_with_reference(const Case& c, const Field& f, const std::string& label, Tally& tally) {
  const Grid& g = c.request.grid;
  const double size = c.model.size();
  int failures = 0;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vector3d p = g.point(i, j, k);
        const std::size_t idx = g.index(i, j, k);
        const FieldSample want = sample_point(c.model, p, c.request);
        ++tally.samples;
        ++tally.by_status[want.status];
        bool ok = f.status[idx] == want.status && f.reachable[idx] == want.reachable &&
                  f.method_used[idx] == want.method_used && f.iterations[idx] == want.iterations;
        // want's floats are roundings themselves: the slack covers that too.
        ok = ok && rounds_within(f.reach_margin[idx], want.reach_margin, 1e-13 * size + std::abs(want.reach_margin) * 0x1p-24) &&
             rounds_within(f.residual[idx], want.residual, 1e-13 * size);
        if (ok && f.cond[idx] != want.cond) {
          ++tally.wide_cond;
          ok = rounds_near(f.cond[idx], want.cond, cond_slack(c.model, p, c.request) + 0x1p-24);
        }
        if (!ok && ++failures <= 5)
          ADD_FAILURE() << label << ", " << c.name << ": sample (" << i << ", " << j << ", " << k << ") at "
                        << p.transpose() << ": status " << int(f.status[idx]) << " vs " << int(want.status) << ", cond "
                        << f.cond[idx] << " vs " << want.cond << ", margin " << f.reach_margin[idx] << " vs "
                        << want.reach_margin << ", residual " << f.residual[idx] << " vs " << want.residual;
      }
  return failures;
}

TEST(DeltaField, EveryTargetAgreesWithTheReference) {
  const std::vector<std::string> targets = simd::available_targets();
  ASSERT_FALSE(targets.empty());
  const std::vector<Case> all = cases();
  const auto changes = std::count_if(all.begin(), all.end(), [](const Case& c) { return c.name.find("change") != std::string::npos; });
  EXPECT_GT(changes, 30);  // rows across status changes
  RecordProperty("rows across status changes", std::to_string(changes));
  const auto type_two = std::count_if(all.begin(), all.end(), [](const Case& c) { return c.name.find("type II") != std::string::npos; });
  EXPECT_GE(type_two, 6);  // rows across J's singular surface
  RecordProperty("rows across the type II surface", std::to_string(type_two));
  const auto crossover = std::count_if(all.begin(), all.end(), [](const Case& c) { return c.name.find("crossover") != std::string::npos; });
  EXPECT_GE(crossover, 30);  // rows where the margin's geometric and range terms meet
  RecordProperty("rows across the margin crossover", std::to_string(crossover));
  for (const std::string& target : targets) {
    const TargetLimit limit(target);
    ASSERT_EQ(simd::current_target(), target);
    Tally tally;
    int mirrored = 0;
    for (const Case& c : all) {
      EXPECT_EQ(compare_with_reference(c, field_of(c, FieldKernel::Vector), target, tally), 0) << target;
      // The default kernel, with the mirror in y where it holds.
      if (!mirror_holds(c.model, c.request)) continue;
      ++mirrored;
      EXPECT_EQ(compare_with_reference(c, field_of(c, FieldKernel::VectorMirrored), target + " mirrored", tally), 0) << target;
    }
    EXPECT_GE(mirrored, 8) << target;
    RecordProperty(target + " mirrored cases", std::to_string(mirrored));
    // The cases reach every status the closed IK gives, and c(J) mostly has
    // the reference's float.
    for (Status s : {Status::Ok, Status::Unreachable, Status::Singular, Status::OutOfLimits, Status::NotConverged})
      EXPECT_GT(tally.by_status[int(s)], 20) << target << " " << to_string(s);
    EXPECT_LT(tally.wide_cond, tally.samples / 20) << target;
    RecordProperty(target + " samples", std::to_string(tally.samples));
    RecordProperty(target + " c(J) floats not identical", std::to_string(tally.wide_cond));
  }
}

// The symmetry the mirrored kernel uses, on the reference alone: where legs 1
// and 2 have the same range and elbow, the sample at (x, -y, z) is the one at
// (x, y, z) -- the same status and the floats within the kernel's own
// tolerance -- at random points of random designs; and mirror_holds sees
// when it does not apply.
TEST(DeltaField, MirrorInYHoldsOnRandomPoints) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Tally tally;
  int compared = 0;
  for (int c = 0; c < 40; ++c) {
    const Model m = random_model(rng, 2 * c);  // even: legs 1 and 2 share their range
    FieldRequest r;
    r.ik.branch = std::array{0, 1, 6, 7}[c % 4];
    const double s = m.size();
    for (int k = 0; k < 400; ++k) {
      // Half in the box, half where random actuator angles in their ranges put the platform.
      Vector3d p(1.4 * s * (unit(rng) - 0.5), 1.4 * s * (unit(rng) - 0.5), -1.1 * s + 1.5 * s * unit(rng));
      if (k % 2) {
        Vector3d q;
        for (int i = 0; i < kLegCount; ++i) q(i) = m.q_limits[i].lo + (m.q_limits[i].hi - m.q_limits[i].lo) * unit(rng);
        const FkResult fk = forward(m, q);
        if (fk.status == Status::Ok) p = fk.p_base_platform;
      }
      const FieldSample a = sample_point(m, p, r), b = sample_point(m, Vector3d(p.x(), -p.y(), p.z()), r);
      ++compared;
      ++tally.by_status[a.status];
      EXPECT_EQ(a.status, b.status) << "design " << c << " at " << p.transpose();
      EXPECT_TRUE(rounds_within(b.reach_margin, a.reach_margin, 1e-13 * s + std::abs(a.reach_margin) * 0x1p-24));
      EXPECT_TRUE(rounds_within(b.residual, a.residual, 1e-13 * s));
      if (b.cond != a.cond) {
        EXPECT_TRUE(std::isfinite(a.cond) && rounds_near(b.cond, a.cond, cond_slack(m, p, r) + 0x1p-24))
            << b.cond << " vs " << a.cond;
      }
    }
  }
  EXPECT_GT(tally.by_status[int(Status::Ok)], compared / 20);
  EXPECT_GT(tally.by_status[int(Status::Unreachable)], compared / 20);
  // Where it does not hold, the mirrored kernel computes every row.
  Model m;
  FieldRequest r;
  r.grid = Grid::box(Vector3d(-25, -25, -30), Vector3d(25, 25, 5), {8, 8, 8});
  EXPECT_TRUE(mirror_holds(m, r));
  r.ik.branch = 2;  // leg 1 elbow out, leg 2 in
  EXPECT_FALSE(mirror_holds(m, r));
  r.ik.branch = 0;
  m.q_limits[2].hi += 0.1;
  EXPECT_FALSE(mirror_holds(m, r));
  m.q_limits[2] = m.q_limits[1];
  r.grid.origin.y() += 1.0;  // not symmetric in y
  EXPECT_FALSE(mirror_holds(m, r));
}

// As on a machine with only the baseline instruction set (SSE2): the field
// as the application computes it (the default kernel) still agrees.
TEST(DeltaField, BaselineTargetAloneAgrees) {
  const std::string baseline = simd::available_targets().back();
  const TargetLimit limit("baseline");
  EXPECT_EQ(simd::current_target(), baseline);
  Tally tally;
  for (const Case& c : cases()) EXPECT_EQ(compare_with_reference(c, *compute_field(c.model, c.request), baseline, tally), 0);
  EXPECT_GT(tally.by_status[int(Status::Ok)], 1000);
}

// Near a leg's serial singular surface, just outside the band the reference
// decides (leg margin 1.02-10 times 2e-12 size), a leg's angle depends on
// sqrt(A^2 + B^2 - C^2), so the kernel's angle and the reference's differ by
// up to about 1e-10 rad (ulps of C over that root, in both), more than the
// 1e-12 rad range hand-off band: with a range end that near the angle, the
// status (Ok against OutOfLimits) would differ from the reference's where the
// kernel did not widen the band by the angle's conditioning (without it, 520
// of about 2000 statuses differ).
TEST(DeltaField, RangeEndNearASerialSingularSurface) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int compared = 0, differ = 0;
  for (int c = 0; c < 40; ++c) {
    const Model design = random_model(rng, 4 * (c / 4) + 2);
    const double s = design.size(), band = 2e-12 * s;
    FieldRequest r;
    r.ik.branch = c % kBranchCount;
    for (int k = 0; k < 10; ++k) {
      // A point where leg 0's margin is a few times the band, on the solved side.
      Vector3d a(0.6 * s * (unit(rng) - 0.5), 0.6 * s * (unit(rng) - 0.5), -0.2 * s - 0.8 * s * unit(rng));
      const Vector3d dir = Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5).normalized();
      Vector3d b = a + 3 * s * dir;
      if (leg_margin(design, 0, a) <= 0 || leg_margin(design, 0, b) > 0) continue;
      const double target = band * std::array{1.02, 1.1, 1.5, 3.0, 10.0}[k % 5];
      bisect(a, b, [&](const Vector3d& p) { return leg_margin(design, 0, p) > target; }, 200);
      Case one{"range end near leg 0's serial singular surface", design, r};
      one.request.grid = row_through(a, 0, 1e-16 * s, 1);
      const Vector3d p = one.request.grid.point(0, 0, 0);
      const IkResult ik = inverse(design, p, IkMethod::Closed, r.ik);
      if (ik.status != Status::Ok && ik.status != Status::OutOfLimits) continue;
      // Leg 0's range ends delta from its angle (inside for delta > 0), the others full.
      for (double delta : {1.5e-12, -1.5e-12, 3e-12, -3e-12, 1e-11, -1e-11, 3e-11, -3e-11, 1e-10, -1e-10}) {
        const double q = ik.q_actuated(0);
        for (const Interval range : {Interval{q + delta - 1.0, q + delta}, Interval{q - delta, q - delta + 1.0}}) {
          one.model.q_limits = {range, Interval{-std::numbers::pi, std::numbers::pi}, Interval{-std::numbers::pi, std::numbers::pi}};
          const Field f = field_of(one, FieldKernel::Vector);
          ++compared;
          differ += f.status[0] != sample_point(one.model, p, one.request).status;
        }
      }
    }
  }
  EXPECT_GT(compared, 1000);
  EXPECT_EQ(differ, 0) << "of " << compared;
}

TEST(DeltaField, KernelSwitchAndTheMechanismInterface) {
  const Model m;
  Case c{"switch", m, {}};
  c.request.grid = Grid::box(Vector3d(-10, -10, -25), Vector3d(10, 10, -5), {11, 9, 7});
  const Field reference = field_of(c, FieldKernel::Scalar);
  const auto same = [](const Field& a, const Field& b) {
    return a.cond == b.cond && a.reach_margin == b.reach_margin && a.residual == b.residual && a.status == b.status;
  };
  ::setenv("LINKSCAPE_FIELD_KERNEL", "fastest", 1);
  EXPECT_THROW(compute_field(m, c.request), std::invalid_argument);
  ::setenv("LINKSCAPE_FIELD_KERNEL", "scalar", 1);
  EXPECT_TRUE(same(*compute_field(m, c.request), reference));
  ::unsetenv("LINKSCAPE_FIELD_KERNEL");
  Tally tally;
  EXPECT_EQ(compare_with_reference(c, *compute_field(m, c.request), "default", tally), 0);
  // What the window and the headless commands call: the default kernel.
  const auto mechanism = make_mechanism(m);
  const Field through_interface = *mechanism->compute_field(c.request.grid, mechanism->home_task(), {}, 0, {});
  EXPECT_TRUE(same(through_interface, *compute_field(m, c.request)));
  EXPECT_EQ(through_interface.measure_titles.size(), 1u);
  // Newton ignores the kernel: the reference per sample.
  c.request.method = IkMethod::Newton;
  EXPECT_TRUE(same(field_of(c, FieldKernel::VectorMirrored), field_of(c, FieldKernel::Scalar)));
}

}  // namespace
}  // namespace linkscape::delta
