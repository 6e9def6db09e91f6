// The closest points of two segments (core/interference.h) against brute
// force: a fine sampling of both segments refined by ternary search on
// each (the distance is convex along either segment).
#include <gtest/gtest.h>

#include <random>

#include "core/interference.h"

using namespace linkscape::interference;
using Eigen::Vector3d;

namespace {

// min over s of (min over t of |a(s) - b(t)|), both by ternary search after a coarse scan.
double brute_force(const Vector3d& a0, const Vector3d& a1, const Vector3d& b0, const Vector3d& b1) {
  auto to_b = [&](const Vector3d& p) {
    auto f = [&](double t) { return (p - (b0 + t * (b1 - b0))).norm(); };
    double lo = 0, hi = 1;
    for (int i = 0; i < 100; ++i) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      (f(m1) < f(m2) ? hi : lo) = (f(m1) < f(m2) ? m2 : m1);
    }
    return f(0.5 * (lo + hi));
  };
  auto g = [&](double s) { return to_b(a0 + s * (a1 - a0)); };
  double lo = 0, hi = 1;
  for (int i = 0; i < 100; ++i) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (g(m1) < g(m2)) hi = m2;
    else lo = m1;
  }
  return std::min({g(0.5 * (lo + hi)), g(0), g(1)});
}

}  // namespace

TEST(Interference, SegmentDistanceMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  auto point = [&] { return Vector3d(u(rng), u(rng), u(rng)); };
  double worst = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Vector3d a0 = point(), a1 = point(), b0 = point(), b1 = point();
    // Special cases among the random ones: parallel, collinear, a point, crossing.
    switch (trial % 5) {
      case 1: b1 = b0 + 0.7 * (a1 - a0); break;
      case 2: b0 = a0 + 1.5 * (a1 - a0), b1 = a0 + 2.5 * (a1 - a0); break;
      case 3: b1 = b0; break;
      case 4: b0 = 0.5 * (a0 + a1) - 0.3 * (b1 - b0); break;
      default: break;
    }
    const SegmentPair p = closest_points(a0, a1, b0, b1);
    const double expected = brute_force(a0, a1, b0, b1);
    worst = std::max(worst, std::abs(p.distance - expected));
    ASSERT_NEAR(p.distance, expected, 1e-9) << "trial " << trial;
    // The points lie on their segments and are as far apart as stated.
    EXPECT_NEAR((p.on_a - p.on_b).norm(), p.distance, 1e-15);
    EXPECT_NEAR((p.on_a - a0).norm() + (a1 - p.on_a).norm(), (a1 - a0).norm(), 1e-12);
    EXPECT_NEAR((p.on_b - b0).norm() + (b1 - p.on_b).norm(), (b1 - b0).norm(), 1e-12);
  }
  std::printf("segment distance: worst difference from brute force %.2e over 2000 pairs\n", worst);
}

TEST(Interference, CapsuleClearance) {
  // Two rods of radius 1 crossing 5 apart: a gap of 3; moved to 1.5 apart they overlap by 0.5.
  const Capsule a{{-10, 0, 0}, {10, 0, 0}, 1.0};
  Capsule b{{0, -10, 5}, {0, 10, 5}, 1.0};
  EXPECT_DOUBLE_EQ(clearance(a, b), 3.0);
  b.a.z() = b.b.z() = 1.5;
  EXPECT_DOUBLE_EQ(clearance(a, b), -0.5);
  // End to end along one line: the gap between the caps.
  const Capsule c{{12, 0, 0}, {20, 0, 0}, 0.5};
  EXPECT_DOUBLE_EQ(clearance(a, c), 0.5);
}
