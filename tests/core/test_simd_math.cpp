// The vector functions of core/simd_field-inl.h against long-double libm on
// every SIMD target this CPU runs: cos(acos(r) / 3), from which the field
// kernels take the largest eigenvalue of J^T J, and atan2, from which they
// take the angles they check against actuator ranges. Compiled once per
// target, like the kernels (foreach_target.h re-includes this file).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/test_simd_math.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "core/simd_field-inl.h"  // per target, like this file

HWY_BEFORE_NAMESPACE();
namespace linkscape::simd_math_test::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
namespace kernel = linkscape::simd::HWY_NAMESPACE;

// out[i] = f(in[i]) for n a multiple of the lane count.
void CosOfAcosOver3(const double* r, double* out, std::size_t n) {
  const kernel::D d;
  for (std::size_t i = 0; i < n; i += hn::Lanes(d)) hn::StoreU(kernel::CosOfAcosOver3(d, hn::LoadU(d, r + i)), d, out + i);
}

void Atan2(const double* y, const double* x, double* out, std::size_t n) {
  const kernel::D d;
  for (std::size_t i = 0; i < n; i += hn::Lanes(d))
    hn::StoreU(kernel::Atan2(d, hn::LoadU(d, y + i), hn::LoadU(d, x + i)), d, out + i);
}

}  // namespace linkscape::simd_math_test::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "tests/core/simd_targets.h"

namespace linkscape::simd_math_test {
namespace {

HWY_EXPORT(CosOfAcosOver3);
HWY_EXPORT(Atan2);

std::string format(double v) {
  std::ostringstream out;
  out << std::setprecision(3) << v;
  return out.str();
}

// A multiple of every target's lane count.
constexpr std::size_t kPad = 16;
std::size_t padded(std::size_t n) { return (n + kPad - 1) / kPad * kPad; }

TEST(SimdMath, CosOfAcosOver3IsWithinTwoUlpsOnEveryTarget) {
  // A uniform grid over [-1, 1], and r within 1e-6 .. 1e-16 of both ends
  // (where acos is steep: r = -1 is l1 = l2, r = 1 is l2 = l3).
  std::vector<double> r;
  for (int k = 0; k <= 200000; ++k) r.push_back(-1.0 + k / 100000.0);
  for (double e = 1e-6; e > 1e-17; e /= 3) r.insert(r.end(), {-1.0 + e, 1.0 - e});
  r.resize(padded(r.size()), 0.0);
  std::vector<double> out(r.size());
  for (const std::string& target : simd::available_targets()) {
    const simd_test::TargetLimit limit(target);
    HWY_DYNAMIC_DISPATCH(CosOfAcosOver3)(r.data(), out.data(), r.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const long double want = std::cos(std::acos(static_cast<long double>(r[i])) / 3);
      worst = std::max(worst, double(std::abs(out[i] - want)));
    }
    // The result is in [0.5, 1], whose ulp is 2^-53 below 1: six of them
    // (the polynomial is within 1.7e-16; Estrin's scheme adds roundings,
    // 5.1e-16 measured; libm's acos and cos in double are about 2.4e-16 off).
    EXPECT_LE(worst, 6 * 0x1p-53) << target;
    RecordProperty(target + " worst absolute error", format(worst));
  }
}

TEST(SimdMath, Atan2IsWithinFourUlpsOfPiOnEveryTargetAndKeepsTheSignedZeros) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), exponent(-30, 30);
  std::vector<double> y, x;
  for (int k = 0; k < 200000; ++k) {
    y.push_back(unit(rng) * std::pow(10.0, exponent(rng)));
    x.push_back(k % 7 == 0 ? y.back() * (k % 2 ? 1 : -1) : unit(rng) * std::pow(10.0, exponent(rng)));
  }
  // The axes and the origin with both signs of zero, as std::atan2 takes them.
  for (double a : {0.0, -0.0, 1.0, -1.0})
    for (double b : {0.0, -0.0, 1.0, -1.0}) y.push_back(a), x.push_back(b);
  const std::size_t n = y.size();
  y.resize(padded(n), 1.0);
  x.resize(padded(n), 1.0);
  std::vector<double> out(y.size());
  for (const std::string& target : simd::available_targets()) {
    const simd_test::TargetLimit limit(target);
    HWY_DYNAMIC_DISPATCH(Atan2)(y.data(), x.data(), out.data(), y.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const long double want = std::atan2(static_cast<long double>(y[i]), static_cast<long double>(x[i]));
      worst = std::max(worst, double(std::abs(out[i] - want)));
      if (y[i] == 0.0 || x[i] == 0.0) {
        EXPECT_EQ(std::signbit(out[i]), std::signbit(std::atan2(y[i], x[i]))) << target << ": atan2(" << y[i] << ", " << x[i] << ")";
        EXPECT_EQ(out[i], std::atan2(y[i], x[i])) << target << ": atan2(" << y[i] << ", " << x[i] << ")";
      }
    }
    EXPECT_LE(worst, 4 * 0x1p-51) << target;  // four ulps of pi
    RecordProperty(target + " worst absolute error", format(worst));
  }
}

}  // namespace
}  // namespace linkscape::simd_math_test
#endif  // HWY_ONCE
