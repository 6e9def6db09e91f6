// The 12R planar kernel on rows of samples in SIMD vectors (Highway): the
// part between HWY_BEFORE_NAMESPACE and HWY_AFTER_NAMESPACE is compiled once
// per instruction set (foreach_target.h re-includes this file) and the best
// one the CPU has is chosen at run time (core/simd.h).
//
// Lane for lane it is planar::sample (field.cpp), operation for operation up
// to J, with the early returns replaced by masks, so the coordinates, the
// reach margin, the residual and J have the scalar path's bits. c(J) follows
// condition_number_fast with three differences: cos(acos(r) / 3) is a
// polynomial within 2.2e-16 of libm's (CosOfAcosOver3 in
// core/simd_field-inl.h), divisions by a common denominator are
// multiplications by its reciprocal, and J is not scaled by a power of two
// first (which changes no rounding while J's entries stay within 2^+-100 of
// 1). Lanes whose status could hang on those last bits -- within 1e-12 rad of
// a range limit (the arctangents are vector ones too) or 1e-6 relative of
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

#include "core/simd_field-inl.h"  // per target, like this file

#include <algorithm>

#include "core/mechanisms/parallel12r/planar_kernel.h"

HWY_BEFORE_NAMESPACE();
namespace linkscape::parallel12r::planar::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using namespace linkscape::simd::HWY_NAMESPACE;  // D, V, M, Block and the shared helpers

// min over the three angles of the distances to their range ends (rad).
HWY_INLINE V AngleMargin(D d, const Model& m, V alpha, V beta, V gamma) {
  const auto to_range = [&](V q, const Interval& r) { return hn::Min(q - hn::Set(d, r.lo), hn::Set(d, r.hi) - q); };
  return hn::Min(to_range(alpha, m.alpha_limits), hn::Min(to_range(beta, m.beta_limits), to_range(gamma, m.gamma_limits)));
}

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

void SampleRow(const UnitModel& u, int branch, bool check_limits, const Grid& g, const detail::GridRow& row,
               int first, int count, bool mirror, const detail::FieldRowOut& out) {
  const MethodRule rule{double(IkMethod::Planar), true};
  Block b;
  for (int block = 0; block < count; block += kBlock) {
    const int n = std::min(kBlock, count - block);
    Geometry(u, branch, check_limits, g, row, first + block, n, b);
    BlockConditioning(n, b, kMaxTrustedCondition);
    StoreBlock(b, first + block, n, row.count, mirror, rule, out,
               [&](int i) { return to_field_sample(sample(u, row.point(g, i), branch, check_limits)); });
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
