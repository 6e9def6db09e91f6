// Outward-rounded interval arithmetic and first-order interval derivatives,
// the enclosures certified task checks rest on (docs/task-volumes.md,
// "Certified verdicts").
//
// Every operation computes its bounds in round-to-nearest and widens each
// outward by at least the rounding error: +, -, *, / and sqrt are correctly
// rounded in IEEE 754 (error at most half an ulp, <= 2^-53 |x| for a normal
// result), so moving each bound by 2^-52 |x| plus the smallest subnormal
// keeps the exact result inside. No rounding-mode switch, so the compiler's
// ordinary optimisations stay sound as long as it does not contract a * b + c
// into one fused operation (verify's sources build with -ffp-contract=off).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace linkscape::verify {

inline constexpr double kTiny = std::numeric_limits<double>::denorm_min();
inline constexpr double kInf = std::numeric_limits<double>::infinity();

// A double at or below (above) the exact value of which x is the correctly
// rounded result.
// An overflow (+-inf) bounds a finite result that exceeds the largest double.
inline double down(double x) {
  return x == kInf ? std::numeric_limits<double>::max() : x - (std::abs(x) * 0x1p-52 + kTiny);
}
inline double up(double x) {
  return x == -kInf ? -std::numeric_limits<double>::max() : x + (std::abs(x) * 0x1p-52 + kTiny);
}

struct Interval {
  double lo = 0, hi = 0;
  Interval() = default;
  Interval(double v) : lo(v), hi(v) {}  // NOLINT: a double is a point interval
  Interval(double l, double h) : lo(l), hi(h) {}
  double mid() const { return 0.5 * lo + 0.5 * hi; }
  double rad() const { return up(std::max(up(hi - mid()), up(mid() - lo))); }
  double mag() const { return std::max(std::abs(lo), std::abs(hi)); }
  bool contains(double v) const { return lo <= v && v <= hi; }
  static Interval entire() { return {-kInf, kInf}; }
};

inline Interval operator+(Interval a, Interval b) { return {down(a.lo + b.lo), up(a.hi + b.hi)}; }
inline Interval operator-(Interval a, Interval b) { return {down(a.lo - b.hi), up(a.hi - b.lo)}; }
inline Interval operator-(Interval a) { return {-a.hi, -a.lo}; }
inline Interval operator*(Interval a, Interval b) {
  if (a.lo == a.hi && a.lo > 0) {  // scaling by a positive point: two products
    return {down(a.lo * b.lo), up(a.lo * b.hi)};
  }
  const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  double lo = p[0], hi = p[0];
  for (double v : p) {
    // 0 * inf is NaN: the product of 0 with anything finite is 0, and an
    // unbounded factor makes the interval unbounded anyway.
    if (std::isnan(v)) return Interval::entire();
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  return {down(lo), up(hi)};
}
// Division by an interval holding 0 has no bounded enclosure.
inline Interval operator/(Interval a, Interval b) {
  if (b.lo <= 0 && b.hi >= 0) return Interval::entire();
  const double p[4] = {a.lo / b.lo, a.lo / b.hi, a.hi / b.lo, a.hi / b.hi};
  double lo = p[0], hi = p[0];
  for (double v : p) {
    if (std::isnan(v)) return Interval::entire();
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  return {down(lo), up(hi)};
}
inline Interval& operator+=(Interval& a, Interval b) { return a = a + b; }
inline Interval& operator-=(Interval& a, Interval b) { return a = a - b; }
inline Interval& operator*=(Interval& a, Interval b) { return a = a * b; }

// x^2 without the dependency of x * x: [0, ...] where x holds 0.
inline Interval sqr(Interval a) {
  if (a.lo >= 0) return {down(a.lo * a.lo), up(a.hi * a.hi)};
  if (a.hi <= 0) return {down(a.hi * a.hi), up(a.lo * a.lo)};
  return {0.0, up(std::max(a.lo * a.lo, a.hi * a.hi))};
}
// sqrt of the non-negative part (callers check positivity first where it matters).
inline Interval sqrt(Interval a) {
  return {a.lo > 0 ? std::max(0.0, down(std::sqrt(a.lo))) : 0.0, a.hi > 0 ? up(std::sqrt(a.hi)) : 0.0};
}
inline Interval hull(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)}; }
// The intersection of two enclosures of one quantity (both hold it, so it is not empty).
inline Interval intersect(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::min(a.hi, b.hi)}; }

// Sign tests a kernel asks before a square root or a division: true only
// when every value of the enclosure has that sign.
inline bool certainly_positive(double v) { return v > 0; }
inline bool certainly_positive(Interval a) { return a.lo > 0; }
inline bool certainly_negative(double v) { return v < 0; }
inline bool certainly_negative(Interval a) { return a.hi < 0; }

// ---- First-order interval derivatives --------------------------------------------
// A value over a box of (x, y, z) and the enclosure of its gradient there:
// f(p) lies in f(m) + grad(box) . (p - m) for p and m in the box (mean
// value theorem), much tighter than the value's own enclosure on small boxes.
struct Dual {
  Interval v;
  Interval d[3];
  Dual() = default;
  Dual(double c) : v(c) {}   // NOLINT: a constant
  Dual(Interval c) : v(c) {}  // NOLINT: a constant
  static Dual variable(Interval value, int axis) {
    Dual r(value);
    r.d[axis] = Interval(1.0);
    return r;
  }
};

inline Dual operator+(const Dual& a, const Dual& b) {
  Dual r(a.v + b.v);
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] + b.d[k];
  return r;
}
inline Dual operator-(const Dual& a, const Dual& b) {
  Dual r(a.v - b.v);
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] - b.d[k];
  return r;
}
inline Dual operator-(const Dual& a) {
  Dual r(-a.v);
  for (int k = 0; k < 3; ++k) r.d[k] = -a.d[k];
  return r;
}
inline Dual operator*(const Dual& a, const Dual& b) {
  Dual r(a.v * b.v);
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
  return r;
}
inline Dual operator/(const Dual& a, const Dual& b) {
  Dual r(a.v / b.v);
  // (a / b)' = (a' - (a / b) b') / b
  for (int k = 0; k < 3; ++k) r.d[k] = (a.d[k] - r.v * b.d[k]) / b.v;
  return r;
}
inline Dual& operator+=(Dual& a, const Dual& b) { return a = a + b; }
inline Dual& operator-=(Dual& a, const Dual& b) { return a = a - b; }
inline Dual& operator*=(Dual& a, const Dual& b) { return a = a * b; }
inline Dual sqr(const Dual& a) {
  Dual r(sqr(a.v));
  for (int k = 0; k < 3; ++k) r.d[k] = Interval(2.0) * a.v * a.d[k];
  return r;
}
// Callers check the argument is positive (the derivative 1 / (2 sqrt) is unbounded at 0).
inline Dual sqrt(const Dual& a) {
  Dual r(sqrt(a.v));
  const Interval twice = Interval(2.0) * r.v;
  for (int k = 0; k < 3; ++k) r.d[k] = a.d[k] / twice;
  return r;
}
inline bool certainly_positive(const Dual& a) { return a.v.lo > 0; }
inline bool certainly_negative(const Dual& a) { return a.v.hi < 0; }

// Point arithmetic needs sqr for the kernels written once for every type.
inline double sqr(double a) { return a * a; }
inline long double sqr(long double a) { return a * a; }

}  // namespace linkscape::verify
