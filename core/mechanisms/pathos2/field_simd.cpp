// PATHOS-II's field kernel on rows of samples in SIMD vectors (Highway),
// compiled once per instruction set and chosen at run time (core/simd.h), as
// the Delta's (core/mechanisms/delta/field_simd.cpp).
//
// Lane for lane it is the per-point fast path (sample_oriented: the Field IK,
// then jacobian) with the early returns replaced by masks:
// - the legs' IK (leg_core and inverse_with) operation for operation with
//   the reference's roundings: the globular centre in the leg frame as
//   Eigen's 3x3 product sums it, Eq. 14's roots, t1's cosine and sine and
//   the other cosines and sines by the same divisions (by reciprocals where
//   no status depends on them), the cone's cos t5 summed in Eigen's order.
//   So every leg's status -- Unreachable on kRootSlack, Singular on
//   kLegSingularTolerance, OutOfLimits on the limits' cosines -- and so the
//   pose's (its most severe leg's) has the reference's bits;
// - the reach margin as the fast path takes it (sqrt for hypot, c1y from
//   the IK) with Highway's arctangent (a few ulps from libm's) for the
//   angles of the limit margins; the residual from the legs' cosines;
// - M (rows g_i, rho_i x g_i, translation columns times the power of two
//   near l2 + l3), its LU with partial pivoting per lane (the pivot rows
//   swapped by masks), the inverse J from six solves, kappa = |M|_1 |J|_1,
//   Singular beyond kMaxJacobianCondition;
// - cond(Jp) and cond(Jo): modified Gram-Schmidt of the two 3x6 blocks of J,
//   then the lower-triangular closed form of core/conditioning.h (the
//   largest eigenvalues with CosOfAcosOver3, core/simd_field-inl.h), with
//   products by reciprocals for some divisions.
// J differs from the reference's in its last bits: the reference's cond(Jp)
// and cond(Jo) are themselves accurate to about 4 u kappa (u = 2^-53), and
// this kernel's too, so the two agree to 1e-12 relative plus 16 u kappa,
// plus where two singular values of a block come close 64 u (s_i^2 + s_j^2) /
// (s_i^2 - s_j^2), capped at 1e-7 (tests/core/mechanisms/pathos2/test_field_simd.cpp):
// the trigonometric root taken here loses up to ~sqrt(u) as they meet,
// where the reference deflates (pathos2.cpp), so the lanes with a close pair
// (kClosePair) go to the reference.
// Every lane whose status could hang on last bits -- kappa within a factor 2
// of kMaxJacobianCondition or not finite, a non-finite M or one with its
// largest entry outside 2^+-100, a non-finite coordinate, and a leg whose
// reach margin the fast path takes from hypot -- goes to sample_oriented,
// so the statuses are the reference's exactly; so does every Ok lane with
// a close pair of singular values in a block.
//
// Built with -ffp-contract=off (core/CMakeLists.txt): a fused multiply-add
// would round once where the reference rounds twice.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/mechanisms/pathos2/field_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "core/simd_field-inl.h"  // per target, like this file

#include <algorithm>
#include <cmath>

#include "core/mechanisms/pathos2/field.h"

HWY_BEFORE_NAMESPACE();
namespace linkscape::pathos2::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using namespace linkscape::simd::HWY_NAMESPACE;  // D, V, M, Block and the shared helpers

// Two squared singular values closer than this (relative) make a close
// pair: the trigonometric root's relative error is ~3 u / gap, 1e-12 at a
// gap of 3e-4, so this margin keeps the kernel's cond within ~1e-12 of the
// reference's elsewhere.
constexpr double kClosePair = 1e-3;

// condition_number_lower_triangular (core/conditioning.cpp) of L = [a 0 0;
// b c 0; d e f]; +inf where det L is zero or not finite. `close` marks the
// lanes where two of L's singular values form a close pair: there the
// trigonometric root loses up to ~sqrt(u), where the reference deflates.
HWY_INLINE V LowerTriangularCondition(D d, V a, V b, V c, V dd, V e, V f, M& close) {
  const V det = a * c * f;
  const V a2 = a * a, f2 = f * f;
  const V k02 = b * e - c * dd;
  const V s_max = LargestEigenvalue(d, a2, b * b + c * c, dd * dd + e * e + f2, a * b, a * dd, b * dd + c * e);
  const V t_max = LargestEigenvalue(d, c * c * f2, b * b * f2 + a2 * f2, k02 * k02 + a2 * e * e + a2 * c * c,
                                    hn::Neg(b) * c * f2, c * f * k02, hn::Neg(b) * f * k02 - a2 * e * f);
  const V cond = hn::Sqrt(s_max * t_max) / hn::Abs(det);
  const M degenerate = hn::Or(det == hn::Zero(d), hn::Not(hn::IsFinite(det)));
  // s_max = s1^2, t_max = (s1 s2)^2, det^2 / t_max = s3^2: s2^2 > (1 - k) s1^2
  // or s3^2 > (1 - k) s2^2, without divisions.
  const V keep = hn::Set(d, 1.0 - kClosePair);
  close = hn::Or(keep * s_max * s_max < t_max, keep * t_max * t_max < det * det * s_max);
  return hn::IfThenElse(degenerate, hn::Inf(d), cond);
}

// three_column_condition_number (pathos2.cpp) of the 6x3 matrix with
// columns b0, b1, b2: modified Gram-Schmidt to the triangle, then its
// closed form (`close` as there).
HWY_INLINE V ThreeColumnCondition(D d, const V* b0, const V* b1, const V* b2, M& close) {
  const V one = hn::Set(d, 1.0);
  // Summed from the first entry on, as the reference's loops do.
  const auto dot = [](const V* u, const V* v) {
    V sum = u[0] * v[0];
    for (int k = 1; k < 6; ++k) sum = sum + u[k] * v[k];
    return sum;
  };
  // v /= |v|, returning |v|.
  const auto normalise = [&](V* v) {
    const V r = hn::Sqrt(dot(v, v)), inv = one / r;
    for (int k = 0; k < 6; ++k) v[k] = v[k] * inv;
    return r;
  };
  // v -= r q, returning r = q . v.
  const auto remove_along = [&](V* v, const V* q) {
    const V r = dot(q, v);
    for (int k = 0; k < 6; ++k) v[k] = v[k] - r * q[k];
    return r;
  };
  V q0[6], q1[6], v2[6];
  std::copy_n(b0, 6, q0);
  std::copy_n(b1, 6, q1);
  std::copy_n(b2, 6, v2);
  const V r00 = normalise(q0);
  const V r01 = remove_along(q1, q0);
  const V r11 = normalise(q1);
  const V r02 = remove_along(v2, q0);
  const V r12 = remove_along(v2, q1);
  const V r22 = dot(v2, v2);
  // r00 or r11 zero (a rank-deficient block) makes det zero or NaN: +inf.
  return LowerTriangularCondition(d, r00, r01, r11, r02, r12, hn::Sqrt(r22), close);
}

// The samples [first, first + count) of the row into b (status, reach
// margin, residual, cond = cond(Jp), cond_orientation = cond(Jo), to_scalar).
void Samples(const Model& m, const FieldSetup& fs, const Grid& g, const detail::GridRow& row, int first, int count,
             Block& b) {
  const D d;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), inf = hn::Inf(d);
  const double scale2 = (m.l2 + m.l3) * (m.l2 + m.l3);
  const V l1 = hn::Set(d, m.l1), l2 = hn::Set(d, m.l2), l3 = hn::Set(d, m.l3);
  const V c2z_offset = hn::Set(d, m.l2 * m.l2 - m.l3 * m.l3), two_l2 = hn::Set(d, 2.0 * m.l2);
  const V l3_squared = hn::Set(d, m.l3 * m.l3);
  const V root_slack = hn::Set(d, -kRootSlack * scale2), leg_singular = hn::Set(d, kLegSingularTolerance * scale2);
  const V reach = hn::Set(d, m.l2 + m.l3), inner = hn::Set(d, std::abs(m.l2 - m.l3));
  const V cos_cone = hn::Set(d, fs.cos_cone), cos_t2 = hn::Set(d, fs.cos_t2), cos_t3 = hn::Set(d, fs.cos_t3);
  const V inv_l3 = hn::Set(d, 1.0 / m.l3);
  const bool any_limit = fs.check_cone || fs.check_t2 || fs.check_t3;
  const V s_unit = hn::Set(d, fs.length_scale);
  const Eigen::Vector3d p0 = row.point(g, 0);
  const int axis = row.axis;
  const V origin = hn::Set(d, g.origin(axis)), spacing = hn::Set(d, g.spacing(axis));
  const V ok_code = StatusCode(d, Status::Ok);

  for (int t = 0; t < count; t += int(hn::Lanes(d))) {
    const V along = origin + (hn::Iota(d, double(row.start[axis] + first + t)) + hn::Set(d, 0.5)) * spacing;
    const V x = axis == 0 ? along : hn::Set(d, p0.x());
    const V y = axis == 1 ? along : hn::Set(d, p0.y());
    const V z = axis == 2 ? along : hn::Set(d, p0.z());
    M to_scalar = hn::Not(hn::And(hn::IsFinite(x), hn::And(hn::IsFinite(y), hn::IsFinite(z))));
    V status = ok_code;
    V margin = inf, closure = zero;
    // What the Jacobian needs of each leg.
    V ax[kLegCount], ay[kLegCount], az[kLegCount], c1v[kLegCount], s1v[kLegCount], c2v[kLegCount], s2v[kLegCount];
#pragma GCC unroll 6
    for (int i = 0; i < kLegCount; ++i) {
      const FieldSetup::Leg& leg = fs.legs[i];
      const auto R = [&](int r, int c) { return hn::Set(d, leg.R[3 * r + c]); };
      // inverse_with: p_glob = p + offset, a = R^T (p_glob - p_B), each
      // coordinate summed left to right as Eigen's product does.
      const V dx = (x + hn::Set(d, leg.offset[0])) - hn::Set(d, leg.p_B[0]);
      const V dy = (y + hn::Set(d, leg.offset[1])) - hn::Set(d, leg.p_B[1]);
      const V dz = (z + hn::Set(d, leg.offset[2])) - hn::Set(d, leg.p_B[2]);
      const V a_x = (R(0, 0) * dx + R(1, 0) * dy) + R(2, 0) * dz;
      const V a_y = (R(0, 1) * dx + R(1, 1) * dy) + R(2, 1) * dz;
      const V a_z = (R(0, 2) * dx + R(1, 2) * dy) + R(2, 2) * dz;
      // leg_core
      const V dzl = a_z - l1;
      const V rxy2 = a_x * a_x + a_y * a_y;
      const V rho2 = rxy2 + dzl * dzl;
      const V w = (c2z_offset + rho2) / two_l2;  // c2z
      const V e = w - l2;
      const V y2 = l3_squared - e * e;
      const M unreachable_y = y2 < root_slack;
      const V y2c = hn::Max(y2, zero);
      const V c1y = hn::Set(d, leg.branch_sign) * hn::Sqrt(y2c);
      // leg_reach_margin_from_ik; out of its range the fast path takes hypot: the scalar sample.
      to_scalar = hn::Or(to_scalar, hn::Not(hn::And(rho2 <= hn::Set(d, 1e300), rxy2 >= hn::Set(d, 1e-290))));
      const V rho = hn::Sqrt(rho2);
      const V shell = hn::Min(reach - rho, rho - inner);
      const V c1y_kept = hn::IfThenElse(unreachable_y, zero, c1y);  // 0 where c2z's root failed
      margin = hn::Min(margin, hn::Min(shell, hn::Sqrt(rxy2) - hn::Abs(c1y_kept)));
      // Where an earlier leg made every lane Unreachable and no limit margin
      // is asked for, nothing else of this leg shows.
      ax[i] = a_x, ay[i] = a_y, az[i] = a_z;
      if (!any_limit && hn::AllTrue(d, status == StatusCode(d, Status::Unreachable))) {
        c1v[i] = c2v[i] = one, s1v[i] = s2v[i] = zero;
        continue;
      }
      const V x2 = rxy2 - y2c;
      const M unreachable = hn::Or(unreachable_y, x2 < root_slack);
      const V c1x = hn::Sqrt(hn::Max(x2, zero));
      const M off_axis = rxy2 > zero;
      V c1, s1;
      if (fs.check_cone) {  // cos t5 decides a status: the reference's divisions
        c1 = (c1x * a_x + c1y * a_y) / rxy2;
        s1 = (c1x * a_y - c1y * a_x) / rxy2;
      } else {
        const V inv = one / rxy2;
        c1 = (c1x * a_x + c1y * a_y) * inv;
        s1 = (c1x * a_y - c1y * a_x) * inv;
      }
      c1 = hn::IfThenElse(off_axis, c1, one);
      s1 = hn::IfThenElse(off_axis, s1, zero);
      const M singular = hn::AndNot(unreachable, hn::Abs(c1x * c1y) <= leg_singular);
      // inverse_with's cosines and sines; c2 and c3 against the limits'
      // cosines (default limits too: a cosine may round below -1).
      const M w_nonzero = w != zero;
      const V c2 = hn::IfThenElse(w_nonzero, dzl / w, zero);
      const V s2 = hn::IfThenElse(w_nonzero, fs.check_cone ? c1x / w : c1x * (one / w), one);
      const V c3 = (w - l2) / l3;
      const V s3 = fs.check_cone ? hn::Neg(c1y) / l3 : hn::Neg(c1y) * inv_l3;
      M out_of_limits = hn::Or(c2 < cos_t2, c3 < cos_t3);
      V limit_margin = inf;
      if (any_limit) {
        if (fs.check_cone) {
          // The z column of R_world_B R_B_end, rows 0 and 1 summed left to
          // right and row 2 right to left as Eigen's 3x3 product does.
          const V e0 = c1 * s2 * c3 + s1 * s3, e1 = s1 * s2 * c3 - c1 * s3, e2 = c2 * c3;
          const V w0 = (R(0, 0) * e0 + R(0, 1) * e1) + R(0, 2) * e2;
          const V w1 = (R(1, 0) * e0 + R(1, 1) * e1) + R(1, 2) * e2;
          const V w2 = R(2, 0) * e0 + (R(2, 1) * e1 + R(2, 2) * e2);
          const V cos_t5 = (w0 * hn::Set(d, leg.z_A[0]) + w1 * hn::Set(d, leg.z_A[1])) + w2 * hn::Set(d, leg.z_A[2]);
          out_of_limits = hn::Or(out_of_limits, cos_t5 < cos_cone);
          // t5 for its margin: B(0, 2) and B(1, 2) from A's z axis in the leg frame.
          const V zx = hn::Set(d, leg.z_A_in_B[0]), zy = hn::Set(d, leg.z_A_in_B[1]), zz = hn::Set(d, leg.z_A_in_B[2]);
          const V b02 = c1 * c2 * zx + s1 * c2 * zy - s2 * zz;
          const V b12 = (c1 * s2 * s3 - s1 * c3) * zx + (s1 * s2 * s3 + c1 * c3) * zy + c2 * s3 * zz;
          const V t5 = Atan2(d, hn::Sqrt(b02 * b02 + b12 * b12), cos_t5);
          limit_margin = (hn::Set(d, m.cone_limit) - t5) * l3;
        }
        if (fs.check_t2) {
          const V t2 = Atan2(d, w * c1x, w * dzl);
          limit_margin = hn::Min(limit_margin, (hn::Set(d, m.t2_limit) - hn::Abs(t2)) * reach);
        }
        if (fs.check_t3) {
          const V t3 = Atan2(d, hn::Neg(c1y), w - l2);
          limit_margin = hn::Min(limit_margin, (hn::Set(d, m.t3_limit) - hn::Abs(t3)) * l3);
        }
      }
      // The pose's status: its most severe leg's (inverse_with).
      const M leg_ok = hn::Not(hn::Or(unreachable, singular));
      out_of_limits = hn::And(leg_ok, out_of_limits);
      const V unreachable_code = StatusCode(d, Status::Unreachable), singular_code = StatusCode(d, Status::Singular);
      status = hn::IfThenElse(unreachable, unreachable_code,
                              hn::IfThenElse(hn::And(singular, status != unreachable_code), singular_code,
                                             hn::IfThenElse(hn::And(out_of_limits, status == ok_code),
                                                            StatusCode(d, Status::OutOfLimits), status)));
      if (any_limit) margin = hn::Min(margin, hn::IfThenElse(unreachable, inf, limit_margin));
      // The unreachable legs keep LegSolution's cosines and sines (1 and 0).
      c1v[i] = hn::IfThenElse(unreachable, one, c1);
      s1v[i] = hn::IfThenElse(unreachable, zero, s1);
      c2v[i] = hn::IfThenElse(unreachable, one, c2);
      s2v[i] = hn::IfThenElse(unreachable, zero, s2);
      const V c3k = hn::IfThenElse(unreachable, one, c3), s3k = hn::IfThenElse(unreachable, zero, s3);
      // leg_end: the closure error of the solved angles.
      const V ly = hn::Set(d, -m.l3) * s3k, lz = l2 + l3 * c3k;
      const V x1 = s2v[i] * lz, z1 = l1 + c2v[i] * lz;
      const V ex = c1v[i] * x1 - s1v[i] * ly - a_x, ey = s1v[i] * x1 + c1v[i] * ly - a_y, ez = z1 - a_z;
      closure = hn::Max(closure, hn::Sqrt(ex * ex + ey * ey + ez * ez));
    }
    const M solved = hn::Or(status == ok_code, status == StatusCode(d, Status::OutOfLimits));
    const V residual = hn::IfThenElse(solved, closure, inf);
    V cond_p = inf, cond_orientation = inf;
    const M ok = status == ok_code;
    if (!hn::AllFalse(d, ok)) {
      // jacobian: row i of M_unit = [g_i s, rho_i x g_i] (g_i = dt1_i/dp).
      V Mu[kLegCount][6];
#pragma GCC unroll 6
      for (int i = 0; i < kLegCount; ++i) {
        const FieldSetup::Leg& leg = fs.legs[i];
        const auto R = [&](int r, int c) { return hn::Set(d, leg.R[3 * r + c]); };
        const V c1 = c1v[i], s1 = s1v[i], c2 = c2v[i], s2 = s2v[i];
        const V dzl = az[i] - l1;
        // col1 = z x a, col2 = axis2 x (a - l1 z), col3 = axis3 x (a - p3).
        const V k1x = hn::Neg(ay[i]), k1y = ax[i];
        const V k2x = c1 * dzl, k2y = s1 * dzl, k2z = hn::Neg(s1 * ay[i] + c1 * ax[i]);
        const V a3x = c1 * c2, a3y = s1 * c2, a3z = hn::Neg(s2);
        const V ex = ax[i] - l2 * (c1 * s2), ey = ay[i] - l2 * (s1 * s2), ez = dzl - l2 * c2;
        const V k3x = a3y * ez - a3z * ey, k3y = a3z * ex - a3x * ez, k3z = a3x * ey - a3y * ex;
        const V nx = k2y * k3z - k2z * k3y, ny = k2z * k3x - k2x * k3z, nz = k2x * k3y - k2y * k3x;
        const V inv_det = one / (k1x * nx + k1y * ny);
        const V gx = nx * inv_det, gy = ny * inv_det, gz = nz * inv_det;
        const V Gx = (R(0, 0) * gx + R(0, 1) * gy) + R(0, 2) * gz;
        const V Gy = (R(1, 0) * gx + R(1, 1) * gy) + R(1, 2) * gz;
        const V Gz = (R(2, 0) * gx + R(2, 1) * gy) + R(2, 2) * gz;
        const V rx = (x + hn::Set(d, leg.offset[0])) - x, ry = (y + hn::Set(d, leg.offset[1])) - y,
                rz = (z + hn::Set(d, leg.offset[2])) - z;
        Mu[i][0] = Gx * s_unit, Mu[i][1] = Gy * s_unit, Mu[i][2] = Gz * s_unit;
        Mu[i][3] = ry * Gz - rz * Gy, Mu[i][4] = rz * Gx - rx * Gz, Mu[i][5] = rx * Gy - ry * Gx;
      }
      // A = M_unit^T (the reference factors it): A[r][c] = Mu[c][r]. Its
      // 1-norm (the largest column sum of |A|) and finiteness and range.
      V A[6][6];
      V norm_A = zero, largest = zero, sum = zero;
      for (int r = 0; r < 6; ++r) {
        V row_sum = zero;
        for (int c = 0; c < 6; ++c) {
          A[r][c] = Mu[c][r];
          row_sum = row_sum + hn::Abs(A[r][c]);
          largest = hn::Max(largest, hn::Abs(A[r][c]));
          sum = sum + A[r][c];
        }
        norm_A = hn::Max(norm_A, row_sum);
      }
      const M scaled = hn::And(hn::IsFinite(sum), hn::And(largest >= hn::Set(d, 0x1p-100), largest <= hn::Set(d, 0x1p100)));
      // LU with partial pivoting, row by row as Eigen's unblocked one:
      // perm[k] is the row of A now at k.
      V perm[6], inv_pivot[6];
      for (int r = 0; r < 6; ++r) perm[r] = hn::Set(d, double(r));
      for (int k = 0; k < 6; ++k) {
        V best = hn::Abs(A[k][k]), pivot = hn::Set(d, double(k));
        for (int r = k + 1; r < 6; ++r) {
          const M bigger = hn::Abs(A[r][k]) > best;
          best = hn::IfThenElse(bigger, hn::Abs(A[r][k]), best);
          pivot = hn::IfThenElse(bigger, hn::Set(d, double(r)), pivot);
        }
        for (int r = k + 1; r < 6; ++r) {
          const M swap = pivot == hn::Set(d, double(r));
          if (hn::AllFalse(d, swap)) continue;
          for (int c = 0; c < 6; ++c) {
            const V top = A[k][c];
            A[k][c] = hn::IfThenElse(swap, A[r][c], top);
            A[r][c] = hn::IfThenElse(swap, top, A[r][c]);
          }
          const V top = perm[k];
          perm[k] = hn::IfThenElse(swap, perm[r], top);
          perm[r] = hn::IfThenElse(swap, top, perm[r]);
        }
        inv_pivot[k] = one / A[k][k];
        for (int r = k + 1; r < 6; ++r) {
          A[r][k] = A[r][k] * inv_pivot[k];
          for (int c = k + 1; c < 6; ++c) A[r][c] = A[r][c] - A[r][k] * A[k][c];
        }
      }
      // X = A^-1 column by column: P A = L U, so A x = e_c is L U x = P e_c.
      V X[6][6];  // X[r][c]
      for (int c = 0; c < 6; ++c) {
        const V target = hn::Set(d, double(c));
        V yv[6];
        for (int r = 0; r < 6; ++r) {
          V v = hn::IfThenElseZero(perm[r] == target, one);
          for (int j = 0; j < r; ++j) v = v - A[r][j] * yv[j];
          yv[r] = v;
        }
        for (int r = 5; r >= 0; --r) {
          V v = yv[r];
          for (int j = r + 1; j < 6; ++j) v = v - A[r][j] * X[j][c];
          X[r][c] = v * inv_pivot[r];
        }
      }
      // kappa = |M_unit|_1 |M_unit^-1|_1 = |A|_inf-like sums as the reference: the
      // largest row sums of |A| and |X|.
      // (Max may drop a NaN: X's finiteness from the sum of its entries.)
      V norm_X = zero, sum_X = zero;
      for (int r = 0; r < 6; ++r) {
        V row_sum = zero;
        for (int c = 0; c < 6; ++c) {
          row_sum = row_sum + hn::Abs(X[r][c]);
          sum_X = sum_X + X[r][c];
        }
        norm_X = hn::Max(norm_X, row_sum);
      }
      const V kappa = hn::IfThenElse(hn::IsFinite(sum_X), norm_A * norm_X, hn::NaN(d));
      const V max_condition = hn::Set(d, kMaxJacobianCondition);
      const M trusted = kappa <= max_condition;
      const M near_max = hn::And(kappa >= hn::Set(d, 0.5 * kMaxJacobianCondition),
                                 kappa <= hn::Set(d, 2.0 * kMaxJacobianCondition));
      const M doubtful = hn::Or(hn::Not(scaled), hn::Or(near_max, hn::Not(hn::IsFinite(kappa))));
      to_scalar = hn::Or(to_scalar, hn::And(ok, doubtful));
      status = hn::IfThenElse(hn::AndNot(trusted, ok), StatusCode(d, Status::Singular), status);
      const M wants = hn::And(ok, trusted);
      if (!hn::AllFalse(d, wants)) {
        // The columns of X are the rows of J_unit: 0-2 give Jp, 3-5 Jo.
        V col[6][6];
        for (int c = 0; c < 6; ++c)
          for (int r = 0; r < 6; ++r) col[c][r] = X[r][c];
        M close_p, close_o;
        cond_p = hn::IfThenElse(wants, ThreeColumnCondition(d, col[0], col[1], col[2], close_p), inf);
        cond_orientation = hn::IfThenElse(wants, ThreeColumnCondition(d, col[3], col[4], col[5], close_o), inf);
        to_scalar = hn::Or(to_scalar, hn::And(wants, hn::Or(close_p, close_o)));
      }
    }
    hn::Store(status, d, b.status + t);
    hn::Store(margin, d, b.reach_margin + t);
    hn::Store(residual, d, b.residual + t);
    hn::Store(cond_p, d, b.cond + t);
    hn::Store(cond_orientation, d, b.cond_orientation + t);
    hn::Store(Flag(d, to_scalar), d, b.to_scalar + t);
  }
}

void SampleRow(const Geometry& g, const FieldSetup& setup, const Pose& oriented, const GlobularOffsets& offsets,
               const Grid& grid, const detail::GridRow& row, const detail::FieldRowOut& out) {
  const MethodRule rule{double(Field::kNoMethod), false};  // closed form: no method recorded
  Block b;
  for (int first = 0; first < row.count; first += kBlock) {
    const int n = std::min(kBlock, row.count - first);
    Samples(g.model, setup, grid, row, first, n, b);
    StoreBlock(b, first, n, row.count, false, rule, out,
               [&](int i) { return sample_oriented(g, oriented, offsets, row.point(grid, i)); });
  }
}

}  // namespace linkscape::pathos2::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace linkscape::pathos2 {

HWY_EXPORT(SampleRow);

void sample_row_vector(const Geometry& g, const FieldSetup& setup, const Pose& oriented,
                       const GlobularOffsets& offsets, const Grid& grid, const detail::GridRow& row,
                       const detail::FieldRowOut& out) {
  HWY_DYNAMIC_DISPATCH(SampleRow)(g, setup, oriented, offsets, grid, row, out);
}

}  // namespace linkscape::pathos2
#endif  // HWY_ONCE
