// The interval arithmetic certified checks rest on: every operation's
// enclosure holds the exact result (long double stands in for it: 11 more
// bits than double), and the derivative enclosures hold the gradient.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/verify/interval.h"

namespace linkscape::verify {
namespace {

using LD = long double;

bool holds(const Interval& i, LD exact) { return LD(i.lo) <= exact && exact <= LD(i.hi); }

// Doubles over many binades and both signs, plus the awkward ones.
double random_double(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  std::uniform_int_distribution<int> exponent(-60, 60), sign(0, 1);
  return (sign(rng) ? -1 : 1) * std::ldexp(mantissa(rng), exponent(rng));
}

TEST(Interval, ARoundedSumIsWidenedToHoldTheExactOne) {
  // 0.1 + 0.2 rounds to 0.30000000000000004, above the exact sum of the two
  // doubles: an enclosure without widening would miss it.
  const LD exact = LD(0.1) + LD(0.2);
  EXPECT_GT(LD(0.1 + 0.2), exact);
  EXPECT_TRUE(holds(Interval(0.1) + Interval(0.2), exact));
}

TEST(Interval, EveryOperationHoldsTheExactResult) {
  std::mt19937_64 rng(29);
  for (int n = 0; n < 200000; ++n) {
    const double a = random_double(rng), b = random_double(rng);
    const Interval A(a), B(b);
    ASSERT_TRUE(holds(A + B, LD(a) + LD(b))) << a << " + " << b;
    ASSERT_TRUE(holds(A - B, LD(a) - LD(b))) << a << " - " << b;
    ASSERT_TRUE(holds(A * B, LD(a) * LD(b))) << a << " * " << b;
    ASSERT_TRUE(holds(A / B, LD(a) / LD(b))) << a << " / " << b;
    ASSERT_TRUE(holds(sqr(A), LD(a) * LD(a))) << a;
    ASSERT_TRUE(holds(sqrt(Interval(std::abs(a))), std::sqrt(LD(std::abs(a))))) << a;
  }
}

TEST(Interval, WideningMovesAtLeastOneUlpEverywhere) {
  std::mt19937_64 rng(7);
  std::vector<double> values = {0.0, -0.0, std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
                                1.0, 2.0, 0.5, std::numeric_limits<double>::max()};
  for (int n = 0; n < 100000; ++n) values.push_back(random_double(rng));
  for (double x : values)
    for (double v : {x, -x}) {
      EXPECT_LE(down(v), std::nextafter(v, -kInf)) << v;
      EXPECT_GE(up(v), std::nextafter(v, kInf)) << v;
    }
  // An overflow stands for a finite value beyond the largest double.
  EXPECT_EQ(down(kInf), std::numeric_limits<double>::max());
  EXPECT_EQ(up(-kInf), -std::numeric_limits<double>::max());
}

TEST(Interval, RangesOfWideIntervalsHoldEveryPointResult) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3, 3), t(0, 1);
  for (int n = 0; n < 20000; ++n) {
    const double a0 = u(rng), a1 = a0 + t(rng), b0 = u(rng), b1 = b0 + t(rng);
    const Interval A(a0, a1), B(b0, b1);
    const LD a = a0 + (a1 - a0) * t(rng), b = b0 + (b1 - b0) * t(rng);
    ASSERT_TRUE(holds(A * B, a * b));
    ASSERT_TRUE(holds(sqr(A), a * a));
    if (B.lo > 0 || B.hi < 0) ASSERT_TRUE(holds(A / B, a / b));
  }
  // Zero times an unbounded interval: unbounded, not NaN.
  const Interval z = Interval(0.0) * Interval::entire();
  EXPECT_EQ(z.lo, -kInf);
  EXPECT_EQ(z.hi, kInf);
  // Division by an interval holding zero is unbounded, never a wrong finite answer.
  const Interval q = Interval(1.0) / Interval(-1.0, 1.0);
  EXPECT_EQ(q.lo, -kInf);
  EXPECT_EQ(q.hi, kInf);
}

// f(x, y, z) = sqrt(x^2 + y z) / (x + z): value and gradient over a box hold
// the exact ones at its points (gradient against central differences).
TEST(Dual, TheBoxEnclosureHoldsValuesAndGradients) {
  auto f = [](const auto& x, const auto& y, const auto& z) {
    using std::sqrt;
    return sqrt(sqr(x) + y * z) / (x + z);
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(1, 2), w(0.001, 0.3), t(0, 1);
  for (int n = 0; n < 2000; ++n) {
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) lo[k] = u(rng), hi[k] = lo[k] + w(rng);
    const Dual v = f(Dual::variable({lo[0], hi[0]}, 0), Dual::variable({lo[1], hi[1]}, 1), Dual::variable({lo[2], hi[2]}, 2));
    for (int s = 0; s < 10; ++s) {
      LD p[3];
      for (int k = 0; k < 3; ++k) p[k] = lo[k] + (hi[k] - lo[k]) * t(rng);
      ASSERT_TRUE(holds(v.v, f(p[0], p[1], p[2])));
      for (int k = 0; k < 3; ++k) {
        LD a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]};
        const LD h = 1e-7L;
        a[k] += h, b[k] -= h;
        const LD derivative = (f(a[0], a[1], a[2]) - f(b[0], b[1], b[2])) / (2 * h);
        // Central differences are accurate to ~h^2: allow that much outside.
        ASSERT_GE(derivative, LD(v.d[k].lo) - 1e-9L);
        ASSERT_LE(derivative, LD(v.d[k].hi) + 1e-9L);
      }
    }
  }
}

}  // namespace
}  // namespace linkscape::verify
