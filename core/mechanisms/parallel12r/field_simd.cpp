// The 12R planar kernel on rows of samples in SIMD vectors (Highway): the
// part between HWY_BEFORE_NAMESPACE and HWY_AFTER_NAMESPACE is compiled once
// per instruction set (foreach_target.h re-includes this file) and the best
// one the CPU has is chosen at run time (core/simd.h).
//
// Lane for lane it is planar::sample (field.cpp), operation for operation up
// to J, with the early returns replaced by masks, so the coordinates, the
// reach margin, the residual and J have the scalar path's bits. c(J) follows
// condition_number_fast with three differences: the arccosine and cosine are
// Highway's (a few ulps from libm), divisions by a common denominator are
// multiplications by its reciprocal, and J is not scaled by a power of two
// first (which changes no rounding while J's entries stay within 2^+-100 of
// 1). Lanes whose status could hang on those last bits -- within 1e-12 rad of
// a range limit (the arctangents are Highway's too) or 1e-6 relative of
// kMaxTrustedCondition -- and lanes with a non-finite coordinate or a J
// outside that range are recomputed by planar::sample, so the statuses are
// the scalar path's exactly.
//
// Built with -ffp-contract=off (core/CMakeLists.txt): a fused multiply-add
// rounds once where the scalar code rounds twice, which would move the grid
// coordinates and the reach margin off the scalar path's bits.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/mechanisms/parallel12r/field_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>
#include <hwy/contrib/math/math-inl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/mechanisms/parallel12r/planar_kernel.h"

HWY_BEFORE_NAMESPACE();
namespace linkscape::parallel12r::planar::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;
using V = hn::Vec<D>;
using M = hn::Mask<D>;

// atan2 from Atan and the quadrant: a few ulps (absolute), enough for range
// margins, which keep a band around zero for the scalar path.
HWY_INLINE V Atan2(D d, V y, V x) {
  const V zero = hn::Zero(d);
  const V at = hn::Atan(d, y / x);
  const V turned = at + hn::CopySign(hn::Set(d, std::numbers::pi), y);
  const V on_axis = hn::CopySign(hn::Set(d, std::numbers::pi / 2), y);
  return hn::IfThenElse(x == zero, on_axis, hn::IfThenElse(x < zero, turned, at));
}

// min over the three angles of the distances to their range ends (rad).
HWY_INLINE V AngleMargin(D d, const Model& m, V alpha, V beta, V gamma) {
  const auto to_range = [&](V q, const Interval& r) { return hn::Min(q - hn::Set(d, r.lo), hn::Set(d, r.hi) - q); };
  return hn::Min(to_range(alpha, m.alpha_limits), hn::Min(to_range(beta, m.beta_limits), to_range(gamma, m.gamma_limits)));
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
  const V angle = hn::Acos(d, r) * hn::Set(d, 1.0 / 3.0);
  const V largest = q + hn::Set(d, 2.0) * p * hn::Cos(d, angle);
  return hn::IfThenElse(p == hn::Zero(d), q, largest);
}

// condition_number_fast (core/conditioning.cpp) of J = [c0 c1 c2] given by
// columns, without the unit scale; +inf where det J is zero or not finite.
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

// The status codes of a vector of samples, as doubles (exact small integers).
HWY_INLINE V StatusCode(D d, Status s) { return hn::Set(d, double(s)); }
HWY_INLINE V Flag(D d, M m) { return hn::IfThenElseZero(m, hn::Set(d, 1.0)); }
HWY_INLINE M IsSet(D d, V flag) { return flag != hn::Zero(d); }
// Small whole numbers (0..255) held as doubles, as bytes.
HWY_INLINE hn::Vec<hn::Rebind<std::uint8_t, D>> ToBytes(D /*d*/, V v) {
  return hn::DemoteTo(hn::Rebind<std::uint8_t, D>(), hn::DemoteTo(hn::Rebind<std::int32_t, D>(), v));
}

// A row is computed in blocks of samples, each in passes: the geometry up to
// J, then c(J), then the stores into the Field. Each pass is short enough for
// the CPU to overlap the square roots and divisions of consecutive vectors,
// and a block's Jacobians and state (about 32 KiB) stay in the L1 cache
// between passes.
constexpr int kBlock = 256;

struct alignas(64) Block {  // structure of arrays, one entry per sample
  double J[9][kBlock];      // column by column
  double cond[kBlock], status[kBlock], reach_margin[kBlock], residual[kBlock];
  double wants_cond[kBlock], to_scalar[kBlock];  // flags: 1 or 0
};

// The row's samples in the model's units (coordinate `axis` as Grid::point
// computes it), their status without c(J), margins, residual and J.
void Geometry(const UnitModel& u, int branch, bool check_limits, const Grid& g, const detail::GridRow& row,
              int first, int count, Block& b) {
  const D d;
  const Model& m = u.unit;
  const double reach = m.reach(), tol = kSingularTolerance * reach;
  const V one = hn::Set(d, 1.0), zero = hn::Zero(d), inf = hn::Inf(d);
  const V to_unit = hn::Set(d, u.to_unit), from_unit = hn::Set(d, u.from_unit);
  const V vL1 = hn::Set(d, m.L1), vL2 = hn::Set(d, m.L2), vtol = hn::Set(d, tol);
  const V branch_sign = hn::Set(d, branch == 0 ? 1.0 : -1.0);
  const Eigen::Vector3d p0 = row.point(g, 0);
  const int axis = row.axis;
  const V origin = hn::Set(d, g.origin(axis)), spacing = hn::Set(d, g.spacing(axis));

  for (int t = 0; t < count; t += int(hn::Lanes(d))) {
    const V along = origin + (hn::Iota(d, double(row.start[axis] + first + t)) + hn::Set(d, 0.5)) * spacing;
    const V x = (axis == 0 ? along : hn::Set(d, p0.x())) * to_unit;
    const V y = (axis == 1 ? along : hn::Set(d, p0.y())) * to_unit;
    const V z = (axis == 2 ? along : hn::Set(d, p0.z())) * to_unit;

    const V rho2 = x * x + y * y, R2 = rho2 + z * z, R = hn::Sqrt(R2), rho = hn::Sqrt(rho2);
    const V margin = hn::Min(hn::Set(d, reach) - R, R - hn::Set(d, m.inner_reach()));
    const M unreachable = margin < hn::Neg(vtol);
    const M band = hn::Or(margin <= vtol, hn::Or(hn::Abs(y) <= vtol, rho <= vtol));
    const M solve = hn::Not(hn::Or(unreachable, band));
    M to_scalar = hn::Not(hn::And(hn::IsFinite(x), hn::And(hn::IsFinite(y), hn::IsFinite(z))));
    M within_limits = solve;
    V reach_margin = margin, residual = inf;
    V status = hn::IfThenElse(unreachable, StatusCode(d, Status::Unreachable), StatusCode(d, Status::Singular));
    if (!hn::AllFalse(d, solve)) {
      const V sign_y = hn::IfThenElse(y > zero, one, hn::Neg(one)), abs_y = hn::Abs(y);
      const V inv = one / (rho * R * abs_y), inv_rho = R * abs_y * inv, inv_R = rho * abs_y * inv;
      const V ca = abs_y * inv_rho, sa = hn::Neg(x) * sign_y * inv_rho, r = sign_y * rho, inv_ca = rho * (rho * R * inv);
      const V half_inv_R = hn::Set(d, 0.5) * inv_R;
      const V a = (R2 + vL1 * vL1 - vL2 * vL2) * half_inv_R;
      const V h = hn::Sqrt(hn::Max(zero, (vL1 + vL2 - R) * (vL2 - vL1 + R) * (R + vL1 - vL2) * (R + vL1 + vL2))) * half_inv_R;
      const V ur = r * inv_R, uz = z * inv_R;
      const V l1r = a * ur - branch_sign * h * uz, l1z = a * uz + branch_sign * h * ur;
      const V l2r = r - l1r, l2z = z - l1z;

      const V n1 = ca * ca * l1r * l1r + l1z * l1z, n2 = ca * ca * l2r * l2r + l2z * l2z;
      const V k1 = inv_ca * hn::Set(d, 1.0 / (m.L1 * m.L1)), k2 = inv_ca * hn::Set(d, 1.0 / (m.L2 * m.L2));
      const V k1n1 = k1 * n1, k2n2 = k2 * n2, nsa = hn::Neg(sa), nca = hn::Neg(ca);
      const V J[9] = {k1 * (hn::Neg(n1) * l1r) + k2 * (hn::Neg(n2) * l2r),
                      k1 * (nsa * ca * l1r * l1r * l1r) + k2 * (nsa * ca * l2r * l2r * l2r),
                      k1 * (nsa * l1z * l1r * l1r) + k2 * (nsa * l2z * l2r * l2r),
                      k1n1 * (sa * l1z),
                      k1n1 * (nca * l1z),
                      k1n1 * l1r,
                      k2n2 * (sa * l2z),
                      k2n2 * (nca * l2z),
                      k2n2 * l2r};
      for (int e = 0; e < 9; ++e) hn::Store(J[e], d, b.J[e] + t);
      // forward(q) - p as the scalar kernel computes it.
      const V w1x = nsa * l1r, w1y = ca * l1r, w2x = nsa * l2r, w2y = ca * l2r;
      const V d1 = (vL1 * vL1 - (l1r * l1r + l1z * l1z)) * hn::Set(d, 0.5 / (m.L1 * m.L1));
      const V d2 = (vL2 * vL2 - (l2r * l2r + l2z * l2z)) * hn::Set(d, 0.5 / (m.L2 * m.L2));
      const V ex = w1x + w2x - x + d1 * w1x + d2 * w2x, ey = w1y + w2y - y + d1 * w1y + d2 * w2y,
              ez = l1z + l2z - z + d1 * l1z + d2 * l2z;
      residual = hn::IfThenElse(solve, hn::Sqrt(ex * ex + ey * ey + ez * ez) * from_unit, inf);

      if (check_limits) {
        const V angle_margin = AngleMargin(d, m, Atan2(d, sa, ca), Atan2(d, l1z, ca * l1r), Atan2(d, l2z, ca * l2r));
        within_limits = hn::AndNot(angle_margin < zero, solve);
        const M near_limit = hn::Or(hn::Abs(angle_margin) <= hn::Set(d, 1e-12), hn::IsNaN(angle_margin));
        to_scalar = hn::Or(to_scalar, hn::And(solve, near_limit));
        reach_margin = hn::IfThenElse(solve, hn::Min(margin, angle_margin * hn::Set(d, reach)), margin);
      }
      status = hn::IfThenElse(solve, StatusCode(d, Status::OutOfLimits), status);
    }
    hn::Store(status, d, b.status + t);
    hn::Store(reach_margin * from_unit, d, b.reach_margin + t);
    hn::Store(residual, d, b.residual + t);
    hn::Store(Flag(d, within_limits), d, b.wants_cond + t);
    hn::Store(Flag(d, to_scalar), d, b.to_scalar + t);
  }
}

// c(J) where the geometry found a solution within the ranges, and the
// statuses that follow from it.
void Conditioning(int count, Block& b) {
  const D d;
  const V inf = hn::Inf(d), trusted = hn::Set(d, kMaxTrustedCondition);
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
    // J's largest entry, and whether all are finite (a NaN or inf makes the sum so).
    V largest = hn::Abs(c0[0]), sum = c0[0];
    for (const V* column : {c0, c1, c2})
      for (int e = 0; e < 3; ++e) {
        largest = hn::Max(largest, hn::Abs(column[e]));
        sum = sum + column[e];
      }
    const M unit_range =
        hn::And(hn::IsFinite(sum), hn::And(largest >= hn::Set(d, 0x1p-100), largest <= hn::Set(d, 0x1p100)));
    const V c = ConditionNumber(d, c0, c1, c2);
    const M ok = hn::And(wants_cond, c <= trusted);
    const V status = hn::IfThenElse(
        wants_cond, hn::IfThenElse(ok, StatusCode(d, Status::Ok), StatusCode(d, Status::Singular)), hn::Load(d, b.status + t));
    const M near_trust = hn::Abs(c - trusted) <= hn::Set(d, 1e-6 * kMaxTrustedCondition);
    const M to_scalar = hn::And(wants_cond, hn::Or(hn::Not(unit_range), near_trust));
    hn::Store(hn::IfThenElse(ok, c, inf), d, b.cond + t);
    hn::Store(status, d, b.status + t);
    hn::Store(hn::Or(hn::Load(d, b.to_scalar + t), Flag(d, to_scalar)), d, b.to_scalar + t);
  }
}

// Where a sample goes: at its own index, and with `mirror` also at its
// mirror image in the row (n - 1 - i), written from the same registers.
struct RowStore {
  const detail::FieldRowOut& out;
  bool mirror;
  int n;  // samples in the row

  void put(int i, const FieldSample& s) const {
    out.store(i, s);
    if (mirror) out.store(n - 1 - i, s);
  }
};

void SampleRow(const UnitModel& u, int branch, bool check_limits, const Grid& g, const detail::GridRow& row,
               int first, int count, bool mirror, const detail::FieldRowOut& out) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  const hn::Rebind<float, D> df;
  const hn::Rebind<std::uint8_t, D> du8;
  const hn::Rebind<std::uint16_t, D> du16;
  // The portable targets' DemoteTo saturates infinities to the largest float.
  constexpr bool kDemoteKeepsInfinity = HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128;
  const RowStore to{out, mirror, row.count};
  const int last = row.count - 1;
  Block b;
  for (int block = 0; block < count; block += kBlock) {
    const int n = std::min(kBlock, count - block), full = kDemoteKeepsInfinity ? n / lanes * lanes : 0;
    Geometry(u, branch, check_limits, g, row, first + block, n, b);
    Conditioning(n, b);
    const int i0 = first + block;
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
    // The byte arrays follow from the status: reachable where Ok, the planar
    // method where Ok or OutOfLimits, no iterations.
    const auto store_bytes = [&](V status, int i) {
      const V ok = hn::IfThenElseZero(status == StatusCode(d, Status::Ok), hn::Set(d, 1.0));
      const M solved = hn::Or(status == StatusCode(d, Status::Ok), status == StatusCode(d, Status::OutOfLimits));
      const V method = hn::IfThenElse(solved, hn::Set(d, double(IkMethod::Planar)), hn::Set(d, double(Field::kNoMethod)));
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
    for (int t = full; t < n; ++t)  // the last partial vector, one sample at a time
      to.put(i0 + t, to_field_sample({b.cond[t], b.reach_margin[t], b.residual[t], Status(int(b.status[t]))}));
    for (int t = 0; t < n; t += lanes) {
      if (hn::AllFalse(d, IsSet(d, hn::Load(d, b.to_scalar + t)))) continue;
      for (int l = t; l < std::min(n, t + lanes); ++l)
        if (b.to_scalar[l] != 0.0) to.put(i0 + l, to_field_sample(sample(u, row.point(g, i0 + l), branch, check_limits)));
    }
  }
}

}  // namespace linkscape::parallel12r::planar::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace linkscape::parallel12r::planar {

HWY_EXPORT(SampleRow);

void sample_row_vector(const UnitModel& u, int branch, bool check_limits, const Grid& g, const detail::GridRow& row,
                       int first, int count, bool mirror, const detail::FieldRowOut& out) {
  HWY_DYNAMIC_DISPATCH(SampleRow)(u, branch, check_limits, g, row, first, count, mirror, out);
}

}  // namespace linkscape::parallel12r::planar
#endif  // HWY_ONCE
