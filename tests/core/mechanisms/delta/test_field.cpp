// The Delta's fast field kernel against the reference sample (inverse,
// reach_margin and jacobian per point): every array bit for bit, over random
// designs, actuator ranges, branches, tolerances and boxes that cross the
// workspace boundary, the leg singular surfaces and the z axis.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include "core/mechanism.h"
#include "core/mechanisms/delta/field.h"
#include "core/mechanisms/delta/mechanism.h"

namespace linkscape::delta {
namespace {

using Eigen::Vector3d;

template <class Array>
std::size_t bit_differences(const Array& a, const Array& b) {
  if (a.size() != b.size()) return std::max(a.size(), b.size());
  std::size_t differences = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differences += std::memcmp(&a[i], &b[i], sizeof a[i]) != 0;
  return differences;
}

void expect_same_field(const Field& fast, const Field& reference, const std::string& what) {
  EXPECT_EQ(bit_differences(fast.cond, reference.cond), 0u) << what;
  EXPECT_EQ(bit_differences(fast.reach_margin, reference.reach_margin), 0u) << what;
  EXPECT_EQ(bit_differences(fast.residual, reference.residual), 0u) << what;
  EXPECT_EQ(bit_differences(fast.reachable, reference.reachable), 0u) << what;
  EXPECT_EQ(bit_differences(fast.status, reference.status), 0u) << what;
  EXPECT_EQ(bit_differences(fast.iterations, reference.iterations), 0u) << what;
  EXPECT_EQ(bit_differences(fast.method_used, reference.method_used), 0u) << what;
}

Field field_of(const Model& m, FieldRequest r, FieldKernel kernel) {
  r.kernel = kernel;
  return *compute_field(m, r);
}

TEST(DeltaField, FastKernelEqualsTheReferenceBitForBit) {
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t samples = 0, ok = 0, singular = 0, unreachable = 0, out_of_limits = 0;
  for (int c = 0; c < 24; ++c) {
    Model m;
    m.R = 4 + 8 * unit(rng);
    m.r = c % 5 == 0 ? m.R : 6 * unit(rng);  // R = r: the legs' circles coincide
    m.La = 4 + 8 * unit(rng);
    m.Lb = m.La * (0.6 + 2 * unit(rng));
    for (auto& range : m.q_limits) {
      if (c % 4 == 1) range = {-std::numbers::pi, std::numbers::pi};  // the full circle
      else range = {-2.0 * unit(rng), 2.0 * unit(rng)};
    }
    FieldRequest r;
    r.ik.branch = c % kBranchCount;
    r.ik.tolerance = c % 6 == 2 ? 1e-3 : 1e-10;  // 1e-3: looser than the Jacobian's closure check
    const double s = m.size();
    // Boxes over the whole workspace, through the z axis (odd counts put a
    // column of samples on x = y = 0), and thin ones across the boundary.
    const int n = 15 + c % 3;
    const Vector3d centre = c % 3 == 2 ? Vector3d(0, 0, -0.5 * s) : Vector3d(0.3 * s * (unit(rng) - 0.5), 0, -0.5 * s);
    const Vector3d half = c % 3 == 2 ? Vector3d(1.2 * s, 1.2 * s, 1.2 * s) : Vector3d(0.7 * s, 0.7 * s, 0.7 * s);
    r.grid = Grid::box(centre - half, centre + half, {n, n, n});
    const Field fast = field_of(m, r, FieldKernel::VectorMirrored);
    expect_same_field(fast, field_of(m, r, FieldKernel::Scalar), "design " + std::to_string(c));
    samples += fast.status.size();
    for (std::uint8_t st : fast.status) {
      ok += st == std::uint8_t(Status::Ok);
      singular += st == std::uint8_t(Status::Singular);
      unreachable += st == std::uint8_t(Status::Unreachable);
      out_of_limits += st == std::uint8_t(Status::OutOfLimits);
    }
  }
  // The grids reach every status the closed IK gives.
  EXPECT_GT(ok, samples / 20);
  EXPECT_GT(unreachable, samples / 20);
  EXPECT_GT(out_of_limits, 0u);
  RecordProperty("samples", std::to_string(samples));
  RecordProperty("singular", std::to_string(singular));
}

// Samples exactly on a leg's singular surface (margin 0: status Singular,
// cond +inf) and within the singular tolerance of it, where the reference
// solves the leg a second time for the reach margin.
TEST(DeltaField, FastKernelEqualsTheReferenceOnTheSingularSurfaces) {
  const Model m;
  const FieldLegs legs = field_legs(m);
  const double tol = kSingularTolerance * m.size();
  std::size_t singular = 0, checked = 0;
  for (int k = 0; k < 400; ++k) {
    // Leg 0 folded (d_max = Lb: elbow and platform joint on one line
    // through the motor axis) along a direction in its plane, then nudged
    // by multiples of the tolerance.
    const double a = -0.3 - 2.5 * k / 400.0, reach = m.Lb - m.La;
    for (double nudge : {0.0, -0.5 * tol, -2 * tol, 0.5 * tol}) {
      const Vector3d p((m.R - m.r) + (reach + nudge) * std::cos(a), 0.0, (reach + nudge) * std::sin(a));
      FieldRequest r;
      const FieldSample ref = sample_point(m, p, r);
      const std::optional<FieldSample> fast = sample_closed(m, legs, p, 0, r.ik.tolerance);
      ASSERT_TRUE(fast.has_value());
      EXPECT_EQ(std::memcmp(&fast->cond, &ref.cond, sizeof ref.cond), 0) << k;
      EXPECT_EQ(std::memcmp(&fast->reach_margin, &ref.reach_margin, sizeof ref.reach_margin), 0) << k;
      EXPECT_EQ(std::memcmp(&fast->residual, &ref.residual, sizeof ref.residual), 0) << k;
      EXPECT_EQ(fast->status, ref.status) << k;
      EXPECT_EQ(fast->reachable, ref.reachable) << k;
      EXPECT_EQ(fast->method_used, ref.method_used) << k;
      singular += ref.status == std::uint8_t(Status::Singular);
      ++checked;
    }
  }
  EXPECT_GT(singular, checked / 10);
}

TEST(DeltaField, KernelSwitchAndTheMechanismInterface) {
  const Model m;
  FieldRequest r;
  r.grid = Grid::box(Vector3d(-10, -10, -25), Vector3d(10, 10, -5), {11, 9, 7});
  const Field reference = field_of(m, r, FieldKernel::Scalar);
  ::setenv("LINKSCAPE_FIELD_KERNEL", "fastest", 1);
  EXPECT_THROW(compute_field(m, r), std::invalid_argument);
  ::setenv("LINKSCAPE_FIELD_KERNEL", "scalar", 1);
  expect_same_field(*compute_field(m, r), reference, "scalar from the environment");
  ::unsetenv("LINKSCAPE_FIELD_KERNEL");
  expect_same_field(*compute_field(m, r), reference, "default");
  // What the window and the headless commands call.
  const auto mechanism = make_mechanism(m);
  const Field through_interface = *mechanism->compute_field(r.grid, mechanism->home_task(), {}, 0, {});
  expect_same_field(through_interface, reference, "mechanism interface");
  EXPECT_EQ(through_interface.measure_titles.size(), 1u);
  // Newton ignores the kernel: the reference per sample.
  r.method = IkMethod::Newton;
  expect_same_field(field_of(m, r, FieldKernel::VectorMirrored), field_of(m, r, FieldKernel::Scalar), "newton");
}

}  // namespace
}  // namespace linkscape::delta
