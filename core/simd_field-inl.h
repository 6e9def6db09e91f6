// The parts every vectorised field kernel shares (Highway): the arctangent,
// c(J) of a 3x3 Jacobian, status codes held as doubles, and a block of
// samples in structure-of-arrays form with its stores into a Field's row.
// Included by a kernel's source between its foreach_target.h and its own
// per-target code; like every Highway "-inl.h" header it is compiled once per
// target (the include guard toggles with HWY_TARGET_TOGGLE).
#if defined(LINKSCAPE_CORE_SIMD_FIELD_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LINKSCAPE_CORE_SIMD_FIELD_INL_H_
#undef LINKSCAPE_CORE_SIMD_FIELD_INL_H_
#else
#define LINKSCAPE_CORE_SIMD_FIELD_INL_H_
#endif

#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <optional>

#include "core/field.h"
#include "core/field_sampling.h"
#include "core/status.h"

HWY_BEFORE_NAMESPACE();
namespace linkscape::simd::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

// atan2 to a few ulps (absolute), enough for range margins, which keep a
// band around zero for the scalar path: Highway's arctangent polynomial on
// [0, 1] at min(|y|, |x|) / max(|y|, |x|) (one division, where hn::Atan(y /
// x) takes two), then the octant. Split in two so that a kernel can take
// the ratio num / den from a division it shares with other quotients.
struct AtanOctant {
  V num, den;  // the ratio's parts, 0 <= num <= den; 0 / 1 at the origin
  M steep, x_negative;
  V y;  // whose sign the angle takes
};

HWY_INLINE AtanOctant Octant(D d, V y, V x) {
  const V ax = hn::Abs(x), ay = hn::Abs(y), zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const M steep = ay > ax;
  // At the origin num / den = 0 / 1: the angle is std::atan2's, +-0 for x = +0, +-pi for x = -0.
  const M diagonal = ax == ay;
  const V num = hn::IfThenElse(diagonal, hn::IfThenElse(ax == zero, zero, one), hn::IfThenElse(steep, ax, ay));
  const V den = hn::IfThenElse(diagonal, one, hn::IfThenElse(steep, ay, ax));
  return {num, den, steep, hn::CopySign(one, x) < zero /* -0 included */, y};
}

HWY_INLINE V AngleOfOctant(D d, const AtanOctant& o, V ratio) {
  V a = hn::impl::AtanImpl<double>().AtanPoly(d, ratio);
  a = hn::IfThenElse(o.steep, hn::Set(d, std::numbers::pi / 2) - a, a);
  a = hn::IfThenElse(o.x_negative, hn::Set(d, std::numbers::pi) - a, a);
  return hn::CopySign(a, o.y);
}

HWY_INLINE V Atan2(D d, V y, V x) {
  const AtanOctant o = Octant(d, y, x);
  return AngleOfOctant(d, o, o.num / o.den);
}

// cos(acos(r) / 3) for r in [-1, 1], as largest_eigenvalue takes it with
// libm's acos and cos: a polynomial in s = sqrt((1 + r) / 2) = cos(acos(r) / 2),
// in which it is analytic on [0, 1] (an even function of acos(s), and acos^2
// is analytic at s = 1). The degree-17 Chebyshev interpolant (mpmath,
// chebyfit at 60 digits) is within 1.7e-16 of it, 5.2e-16 as evaluated here
// (tests/core/test_simd_math.cpp; libm's acos and cos in double: about
// 2.4e-16): one square root and 17 multiply-adds where Acos and Cos took two
// polynomials, a square root and a range reduction (docs/performance.md).
HWY_INLINE V CosOfAcosOver3(D d, V r) {
  const V s = hn::Sqrt(hn::Max(hn::Zero(d), (hn::Set(d, 1.0) + r) * hn::Set(d, 0.5)));
  // Estrin's scheme (Highway's): a shorter chain of dependent multiply-adds than Horner's.
  return hn::impl::Estrin(s,
                          hn::Set(d, 0.50000000000000022), hn::Set(d, 0.57735026918951615), hn::Set(d, -0.11111111109923312),
                          hn::Set(d, 0.053458357745060213), hn::Set(d, -0.032921798931632495), hn::Set(d, 0.022868132364985042),
                          hn::Set(d, -0.017069017920350656), hn::Set(d, 0.0133598231805251), hn::Set(d, -0.010788571334488309),
                          hn::Set(d, 0.0088335671721010024), hn::Set(d, -0.0071360307458022921), hn::Set(d, 0.0054524181946897302),
                          hn::Set(d, -0.0037299160736523518), hn::Set(d, 0.0021473896765229006), hn::Set(d, -0.00097221584090348477),
                          hn::Set(d, 0.00031848663505108793), hn::Set(d, -6.6323768258064474e-05), hn::Set(d, 6.5415558694125153e-06));
}

// largest_eigenvalue (core/conditioning.cpp) of the symmetric matrix with
// diagonal a00, a11, a22 and off-diagonal a01, a02, a12.
HWY_INLINE V LargestEigenvalue(D d, V a00, V a11, V a22, V a01, V a02, V a12) {
  const V q = (a00 + a11 + a22) * hn::Set(d, 1.0 / 3.0);
  const V off = a01 * a01 + a02 * a02 + a12 * a12;
  const V d0 = a00 - q, d1 = a11 - q, d2 = a22 - q;
  const V p = hn::Sqrt((d0 * d0 + d1 * d1 + d2 * d2 + hn::Set(d, 2.0) * off) * hn::Set(d, 1.0 / 6.0));
  // B = (A - q I) / p and its determinant, as Eigen evaluates a 3x3 one.
  const V inv_p = hn::Set(d, 1.0) / p;
  const V b00 = d0 * inv_p, b11 = d1 * inv_p, b22 = d2 * inv_p, b01 = a01 * inv_p, b02 = a02 * inv_p, b12 = a12 * inv_p;
  const V det = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
  const V r = hn::Min(hn::Max(det * hn::Set(d, 0.5), hn::Set(d, -1.0)), hn::Set(d, 1.0));
  const V largest = q + hn::Set(d, 2.0) * p * CosOfAcosOver3(d, r);
  return hn::IfThenElse(p == hn::Zero(d), q, largest);
}

// condition_number_fast (core/conditioning.cpp) of J = [c0 c1 c2] given by
// columns (or rows: c(J) = c(J^T)), without the unit scale; +inf where det J
// is zero or not finite.
HWY_INLINE V ConditionNumber(D d, const V* c0, const V* c1, const V* c2) {
  const auto cross = [](const V* a, const V* b, V* k) {
    k[0] = a[1] * b[2] - a[2] * b[1];
    k[1] = a[2] * b[0] - a[0] * b[2];
    k[2] = a[0] * b[1] - a[1] * b[0];
  };
  const auto dot = [](const V* a, const V* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  V k0[3], k1[3], k2[3];
  cross(c1, c2, k0);
  cross(c2, c0, k1);
  cross(c0, c1, k2);
  const V det = dot(c0, k0);
  const V l1 = LargestEigenvalue(d, dot(c0, c0), dot(c1, c1), dot(c2, c2), dot(c0, c1), dot(c0, c2), dot(c1, c2));
  // 1/l1 and 1/det^2 from one division.
  const V det2 = det * det, inv = hn::Set(d, 1.0) / (l1 * det2), inv_l1 = det2 * inv, inv_det2 = l1 * inv;
  const V product = det2 * inv_l1;                                         // lambda_2 lambda_3
  const V sum = (dot(k0, k0) + dot(k1, k1) + dot(k2, k2) - product) * inv_l1;  // lambda_2 + lambda_3
  const V l2 = hn::Set(d, 0.5) * (sum + hn::Sqrt(hn::Max(hn::Zero(d), sum * sum - hn::Set(d, 4.0) * product)));
  const V cond = hn::Sqrt(l1 * l2 * l1 * inv_det2);  // l1 l2 / product
  const M degenerate = hn::Or(det == hn::Zero(d), hn::Not(hn::IsFinite(det)));
  return hn::IfThenElse(degenerate, hn::Inf(d), cond);
}

// Whether every entry of the 3x3 matrix [c0 c1 c2] is finite and the largest
// is within 2^+-100 of 1: there the products ConditionNumber forms (up to the
// sixth power of the entries) neither overflow nor underflow, so leaving out
// condition_number_fast's power-of-two scaling changes no rounding.
HWY_INLINE M UnitRange(D d, const V* c0, const V* c1, const V* c2) {
  V largest = hn::Abs(c0[0]), sum = c0[0];  // a NaN or inf makes the sum so
  for (const V* column : {c0, c1, c2})
    for (int e = 0; e < 3; ++e) {
      largest = hn::Max(largest, hn::Abs(column[e]));
      sum = sum + column[e];
    }
  return hn::And(hn::IsFinite(sum), hn::And(largest >= hn::Set(d, 0x1p-100), largest <= hn::Set(d, 0x1p100)));
}

// Status codes and flags of a vector of samples, as doubles (exact small integers).
HWY_INLINE V StatusCode(D d, Status s) { return hn::Set(d, double(s)); }
HWY_INLINE V Flag(D d, M m) { return hn::IfThenElseZero(m, hn::Set(d, 1.0)); }
HWY_INLINE M IsSet(D d, V flag) { return flag != hn::Zero(d); }
// Small whole numbers (0..255) held as doubles, as bytes.
HWY_INLINE hn::Vec<hn::Rebind<std::uint8_t, D>> ToBytes(D /*d*/, V v) {
  return hn::DemoteTo(hn::Rebind<std::uint8_t, D>(), hn::DemoteTo(hn::Rebind<std::int32_t, D>(), v));
}

// A row is computed in blocks of samples, each in passes (the geometry up to
// J, then c(J), then the stores into the Field). Each pass is short enough
// for the CPU to overlap the square roots and divisions of consecutive
// vectors, and a block's Jacobians and state (about 32 KiB) stay in the L1
// cache between passes.
constexpr int kBlock = 256;

struct alignas(64) Block {  // structure of arrays, one entry per sample
  double J[9][kBlock];      // column by column
  double cond[kBlock], status[kBlock], reach_margin[kBlock], residual[kBlock];
  double cond_orientation[kBlock];  // a second measure, for kernels with one (FieldRowOut::cond_orientation)
  double wants_cond[kBlock], to_scalar[kBlock];  // flags: 1 or 0
};

// c(J) of the block's samples flagged wants_cond (+inf elsewhere). With
// `trusted`, those samples become Ok up to it and Singular beyond, with
// c(J) = +inf, and samples within 1e-6 relative of it go to the scalar
// kernel; without, their status stays. Samples whose J is outside UnitRange
// go to the scalar kernel too, unless the kernel vouches that every J it
// flags is within it (unit_range_known).
HWY_INLINE void BlockConditioning(int count, Block& b, std::optional<double> trusted_condition,
                                  bool unit_range_known = false) {
  const D d;
  const V inf = hn::Inf(d), trusted = hn::Set(d, trusted_condition.value_or(HUGE_VAL));
  for (int t = 0; t < count; t += int(hn::Lanes(d))) {
    const M wants_cond = IsSet(d, hn::Load(d, b.wants_cond + t));
    if (hn::AllFalse(d, wants_cond)) {
      hn::Store(inf, d, b.cond + t);
      continue;
    }
    V c0[3], c1[3], c2[3];
    for (int e = 0; e < 3; ++e) {
      c0[e] = hn::Load(d, b.J[e] + t);
      c1[e] = hn::Load(d, b.J[3 + e] + t);
      c2[e] = hn::Load(d, b.J[6 + e] + t);
    }
    const V c = ConditionNumber(d, c0, c1, c2);
    M to_scalar = unit_range_known ? hn::FirstN(d, 0) : hn::And(wants_cond, hn::Not(UnitRange(d, c0, c1, c2)));
    if (trusted_condition) {
      const M ok = hn::And(wants_cond, c <= trusted);
      const V status = hn::IfThenElse(wants_cond, hn::IfThenElse(ok, StatusCode(d, Status::Ok), StatusCode(d, Status::Singular)),
                                      hn::Load(d, b.status + t));
      const M near_trust = hn::Abs(c - trusted) <= hn::Set(d, 1e-6 * *trusted_condition);
      to_scalar = hn::Or(to_scalar, hn::And(wants_cond, near_trust));
      hn::Store(hn::IfThenElse(ok, c, inf), d, b.cond + t);
      hn::Store(status, d, b.status + t);
    } else {
      hn::Store(hn::IfThenElse(wants_cond, c, inf), d, b.cond + t);
    }
    hn::Store(hn::Or(hn::Load(d, b.to_scalar + t), Flag(d, to_scalar)), d, b.to_scalar + t);
  }
}

// How a kernel's statuses map to the Field's method_used: `method` where the
// IK solved the pose (Ok, and OutOfLimits where `solved_out_of_limits`),
// Field::kNoMethod elsewhere; reachable where Ok; no iterations.
struct MethodRule {
  double method = 0;
  bool solved_out_of_limits = false;

  M Solved(D d, V status) const {
    const M ok = status == StatusCode(d, Status::Ok);
    return solved_out_of_limits ? hn::Or(ok, status == StatusCode(d, Status::OutOfLimits)) : ok;
  }
  FieldSample Sample(const Block& b, int t) const {
    const Status status = Status(int(b.status[t]));
    const bool solved = status == Status::Ok || (solved_out_of_limits && status == Status::OutOfLimits);
    FieldSample s;
    s.cond = float(b.cond[t]);
    s.reach_margin = float(b.reach_margin[t]);
    s.residual = float(b.residual[t]);
    s.status = std::uint8_t(status);
    s.reachable = status == Status::Ok;
    s.method_used = solved ? std::uint8_t(method) : Field::kNoMethod;
    return s;
  }
};

// Copies `bytes` bytes with streaming stores where the destination allows
// (16-byte aligned parts): they write whole cache lines without reading them
// first.
HWY_INLINE void StreamBytes(const void* from, void* to, std::size_t bytes) {
  const hn::CappedTag<std::uint8_t, 16> d8;
  const std::size_t lanes = hn::Lanes(d8);
  const auto* source = static_cast<const std::uint8_t*>(from);
  auto* target = static_cast<std::uint8_t*>(to);
  const std::size_t head = std::min(bytes, (16 - reinterpret_cast<std::uintptr_t>(target) % 16) % 16);
  std::memcpy(target, source, head);
  std::size_t i = head;
  for (; i + lanes <= bytes; i += lanes) hn::Stream(hn::LoadU(d8, source + i), d8, target + i);
  std::memcpy(target + i, source + i, bytes - i);
}

// Copies samples [first, first + n) of one row's arrays into another's at
// the same places (a row that is another's mirror image), by streaming
// stores: the other row is usually far away in the Field, where ordinary
// stores first read every line they write. fill_field_rows fences them at
// the end of each chunk of rows.
HWY_INLINE void CopySamples(const detail::FieldRowOut& from, const detail::FieldRowOut& to, int first, int n) {
  const auto copy = [&](const auto* source, auto* target) { StreamBytes(source + first, target + first, sizeof(*source) * std::size_t(n)); };
  copy(from.cond, to.cond);
  copy(from.reach_margin, to.reach_margin);
  copy(from.residual, to.residual);
  copy(from.reachable, to.reachable);
  copy(from.status, to.status);
  copy(from.iterations, to.iterations);
  copy(from.method_used, to.method_used);
  if (from.cond_orientation) copy(from.cond_orientation, to.cond_orientation);
}

// Calls handed_off(t) for each of the block's samples [0, n) flagged to_scalar.
template <class HandedOff>
HWY_INLINE void ForEachHandedOff(const Block& b, int n, HandedOff&& handed_off) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  for (int t = 0; t < n; t += lanes) {
    if (hn::AllFalse(d, IsSet(d, hn::Load(d, b.to_scalar + t)))) continue;
    for (int l = t; l < std::min(n, t + lanes); ++l)
      if (b.to_scalar[l] != 0.0) handed_off(l);
  }
}

// Stores samples [0, n) of block b at i0.. of the row `out` (row_count
// samples), and with `mirror` also at their mirror images row_count - 1 - i,
// written from the same registers; b.cond_orientation only where `out` has
// that array. Samples flagged to_scalar are then replaced by
// scalar_sample(i) (the reference kernel at the row's sample i).
template <class ScalarSample>
HWY_INLINE void StoreBlock(const Block& b, int i0, int n, int row_count, bool mirror, const MethodRule& rule,
                           const detail::FieldRowOut& out, ScalarSample&& scalar_sample) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  const hn::Rebind<float, D> df;
  const hn::Rebind<std::uint8_t, D> du8;
  const hn::Rebind<std::uint16_t, D> du16;
  // The portable targets' DemoteTo saturates infinities to the largest float.
  constexpr bool kDemoteKeepsInfinity = HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128;
  const int full = kDemoteKeepsInfinity ? n / lanes * lanes : 0;
  const int last = row_count - 1;
  const auto put = [&](int i, const FieldSample& s) {
    out.store(i, s);
    if (mirror) out.store(last - i, s);
  };
  const auto store_floats = [&](const double* from, float* into) {
    for (int t = 0; t < full; t += lanes) {
      const auto v = hn::DemoteTo(df, hn::Load(d, from + t));
      hn::StoreU(v, df, into + i0 + t);
      if (mirror) hn::StoreU(hn::Reverse(df, v), df, into + last - (i0 + t + lanes - 1));
    }
  };
  store_floats(b.cond, out.cond);
  store_floats(b.reach_margin, out.reach_margin);
  store_floats(b.residual, out.residual);
  if (out.cond_orientation) store_floats(b.cond_orientation, out.cond_orientation);
  // The byte arrays follow from the status.
  const auto store_bytes = [&](V status, int i) {
    const V ok = hn::IfThenElseZero(status == StatusCode(d, Status::Ok), hn::Set(d, 1.0));
    const V method = hn::IfThenElse(rule.Solved(d, status), hn::Set(d, rule.method), hn::Set(d, double(Field::kNoMethod)));
    hn::StoreU(ToBytes(d, status), du8, out.status + i);
    hn::StoreU(ToBytes(d, ok), du8, out.reachable + i);
    hn::StoreU(ToBytes(d, method), du8, out.method_used + i);
    hn::StoreU(hn::Zero(du16), du16, out.iterations + i);
  };
  for (int t = 0; t < full; t += lanes) {
    const V status = hn::Load(d, b.status + t);
    store_bytes(status, i0 + t);
    if (mirror) store_bytes(hn::Reverse(d, status), last - (i0 + t + lanes - 1));
  }
  for (int t = full; t < n; ++t) {  // the last partial vector
    FieldSample sample = rule.Sample(b, t);
    if (out.cond_orientation) sample.cond_orientation = float(b.cond_orientation[t]);
    put(i0 + t, sample);
  }
  ForEachHandedOff(b, n, [&](int t) { put(i0 + t, scalar_sample(i0 + t)); });
}

}  // namespace linkscape::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // LINKSCAPE_CORE_SIMD_FIELD_INL_H_
