// Small matrices in SIMD lanes for the described devices' lanes (lanes.h):
// Jx's inverse (cofactors for 2x2 and 3x3, Gauss-Jordan for 6x6), its
// 1-norm, and the condition number of three rows by their QR factor, with
// the tests that send a lane to the scalar path. Included by lanes_simd.cpp
// after core/simd_field-inl.h; like every Highway "-inl.h" header it is
// compiled once per target (the include guard toggles with HWY_TARGET_TOGGLE).
#if defined(LINKSCAPE_DESCRIBED_LANES_MATRIX_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LINKSCAPE_DESCRIBED_LANES_MATRIX_INL_H_
#undef LINKSCAPE_DESCRIBED_LANES_MATRIX_INL_H_
#else
#define LINKSCAPE_DESCRIBED_LANES_MATRIX_INL_H_
#endif

#include <hwy/highway.h>

#include "core/simd_field-inl.h"

HWY_BEFORE_NAMESPACE();
namespace linkscape::described::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using namespace linkscape::simd::HWY_NAMESPACE;  // D, V, M, UnitRange, ConditionNumber

// Gauss-Jordan with partial pivoting (each column's largest entry by
// compare-and-swap): inv = a^-1 (6x6).
template <int N>
HWY_INLINE void Invert(D d, V (&a)[N][N], V (&inv)[N][N]) {
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) inv[i][j] = hn::Set(d, i == j ? 1.0 : 0.0);
  for (int k = 0; k < N; ++k) {
    for (int i = k + 1; i < N; ++i) {
      const M swap = hn::Abs(a[i][k]) > hn::Abs(a[k][k]);
      for (int j = 0; j < N; ++j) {
        const V ak = a[k][j], ik = inv[k][j];
        a[k][j] = hn::IfThenElse(swap, a[i][j], ak);
        a[i][j] = hn::IfThenElse(swap, ak, a[i][j]);
        inv[k][j] = hn::IfThenElse(swap, inv[i][j], ik);
        inv[i][j] = hn::IfThenElse(swap, ik, inv[i][j]);
      }
    }
    const V scale = hn::Set(d, 1.0) / a[k][k];
    for (int j = 0; j < N; ++j) {
      a[k][j] = a[k][j] * scale;
      inv[k][j] = inv[k][j] * scale;
    }
    for (int i = 0; i < N; ++i) {
      if (i == k) continue;
      const V factor = a[i][k];
      for (int j = 0; j < N; ++j) {
        a[i][j] = hn::NegMulAdd(factor, a[k][j], a[i][j]);
        inv[i][j] = hn::NegMulAdd(factor, inv[k][j], inv[i][j]);
      }
    }
  }
}

// 2x2 and 3x3 inverses by cofactors (no pivoting: Jx is well conditioned
// where the lanes keep it, kappa_1 < 1e8; the scalar path's LU agrees to
// about kappa_1 u there as Gauss-Jordan's did).
HWY_INLINE void Invert(D d, V (&a)[2][2], V (&inv)[2][2]) {
  const V scale = hn::Set(d, 1.0) / (a[0][0] * a[1][1] - a[0][1] * a[1][0]);
  inv[0][0] = a[1][1] * scale;
  inv[0][1] = hn::Neg(a[0][1]) * scale;
  inv[1][0] = hn::Neg(a[1][0]) * scale;
  inv[1][1] = a[0][0] * scale;
}
HWY_INLINE void Invert(D d, V (&a)[3][3], V (&inv)[3][3]) {
  const V c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1], c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2],
          c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
  const V scale = hn::Set(d, 1.0) / (a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02);
  inv[0][0] = c00 * scale;
  inv[1][0] = c01 * scale;
  inv[2][0] = c02 * scale;
  inv[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * scale;
  inv[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * scale;
  inv[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * scale;
  inv[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * scale;
  inv[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * scale;
  inv[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * scale;
}

template <int N>
HWY_INLINE V NormOne(D d, const V (&a)[N][N]) {
  V largest = hn::Zero(d);
  for (int j = 0; j < N; ++j) {
    V sum = hn::Abs(a[0][j]);
    for (int i = 1; i < N; ++i) sum = sum + hn::Abs(a[i][j]);
    largest = hn::Max(largest, sum);
  }
  return largest;
}

// Whether two eigenvalues of M^T M, M = [c0 c1 c2], lie within about 1e-4
// of their spread of each other: there ConditionNumber's quadratic for the two
// smaller ones keeps only about the square root of the rounding (1e-8), so
// such lanes go to the scalar path. The test: the discriminant of the
// characteristic polynomial of B = M^T M - q I (q the eigenvalues' mean),
// the product of the squared differences of the eigenvalues, against p^6
// (p^2 their variance over two).
HWY_INLINE M NearDoubleEigenvalue(D d, const V* c0, const V* c1, const V* c2) {
  const auto dot = [](const V* a, const V* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  const V g00 = dot(c0, c0), g11 = dot(c1, c1), g22 = dot(c2, c2), g01 = dot(c0, c1), g02 = dot(c0, c2), g12 = dot(c1, c2);
  const V q = (g00 + g11 + g22) * hn::Set(d, 1.0 / 3.0);
  const V b0 = g00 - q, b1 = g11 - q, b2 = g22 - q;
  const V off = g01 * g01 + g02 * g02 + g12 * g12;
  const V p2 = (b0 * b0 + b1 * b1 + b2 * b2 + hn::Set(d, 2.0) * off) * hn::Set(d, 1.0 / 6.0);
  const V minors = b0 * b1 + b0 * b2 + b1 * b2 - off;
  const V det = b0 * (b1 * b2 - g12 * g12) - g01 * (g01 * b2 - g12 * g02) + g02 * (g01 * g12 - b1 * g02);
  const V discriminant = hn::Neg(hn::Set(d, 4.0) * minors * minors * minors) - hn::Set(d, 27.0) * det * det;
  return hn::Not(discriminant >= hn::Set(d, 1e-6) * p2 * p2 * p2);
}

// c(M) of the 3 x n matrix with rows r0, r1, r2 as c(R), R its transpose's
// QR factor by modified Gram-Schmidt; `to_scalar` where R is far from unit scale.
template <int N>
HWY_INLINE V RowsCondition(D d, V (&r)[3][N], M& to_scalar) {
  const auto dot = [&](int a, int b) {
    V s = r[a][0] * r[b][0];
    for (int j = 1; j < N; ++j) s = hn::MulAdd(r[a][j], r[b][j], s);
    return s;
  };
  const V zero = hn::Zero(d);
  V c0[3] = {zero, zero, zero}, c1[3] = {zero, zero, zero}, c2[3] = {zero, zero, zero};
  c0[0] = hn::Sqrt(dot(0, 0));
  V inv = hn::Set(d, 1.0) / c0[0];
  for (int j = 0; j < N; ++j) r[0][j] = r[0][j] * inv;
  c1[0] = dot(0, 1);
  c2[0] = dot(0, 2);
  for (int j = 0; j < N; ++j) {
    r[1][j] = hn::NegMulAdd(c1[0], r[0][j], r[1][j]);
    r[2][j] = hn::NegMulAdd(c2[0], r[0][j], r[2][j]);
  }
  c1[1] = hn::Sqrt(dot(1, 1));
  inv = hn::Set(d, 1.0) / c1[1];
  for (int j = 0; j < N; ++j) r[1][j] = r[1][j] * inv;
  c2[1] = dot(1, 2);
  for (int j = 0; j < N; ++j) r[2][j] = hn::NegMulAdd(c2[1], r[1][j], r[2][j]);
  c2[2] = hn::Sqrt(dot(2, 2));
  to_scalar = hn::Or(to_scalar, hn::Or(hn::Not(UnitRange(d, c0, c1, c2)), NearDoubleEigenvalue(d, c0, c1, c2)));
  return ConditionNumber(d, c0, c1, c2);
}

}  // namespace linkscape::described::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // LINKSCAPE_DESCRIBED_LANES_MATRIX_INL_H_
