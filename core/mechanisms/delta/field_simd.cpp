// The Delta's closed-IK field kernel on rows of samples in SIMD vectors
// (Highway), compiled once per instruction set and chosen at run time
// (core/simd.h), as the 12R's (core/mechanisms/parallel12r/field_simd.cpp).
//
// Lane for lane it is the reference sample (sample_point: inverse, then
// reach_margin, then jacobian) with the early returns replaced by masks and
// no transcendental call where algebra does without one:
// - a leg's coordinates u, v are linear along a row: one multiply-add each;
// - hypot(a, b) is sqrt(a^2 + b^2): one rounding more, no scaling (the
//   lengths of a field are far from overflow; rows past 2^70 go to the
//   reference);
// - a leg's margin min(Lb - d_min, d_max - Lb) is taken only as the smallest
//   over the legs, from the largest d_min^2 and the smallest d_max^2 (two
//   square roots a sample instead of six); its tests against 0 and the
//   singular tolerance follow from the squares;
// - each leg's cos q and sin q are (A C - sigma B root, B C + sigma A root)
//   / (A^2 + B^2), from solve_leg's tan(q/2) without forming it (the three
//   legs' from one division), instead of cos and sin of 2 atan2(n, d); the
//   actuator ranges need no angle per leg: each leg's
//   excess over its range is a direction, the largest is found by comparing
//   directions (where the ranges share one width, by |q_i - centre_i|
//   alone), and its angle is taken (one vector arctangent a few ulps from
//   libm's where the reference takes three) only in vectors where La times
//   it can be smaller than the legs' margin (bounds by its sine and tangent
//   decide elsewhere);
// - a leg's quadratic is solved only where it reaches in some lane, and the
//   Jacobian only where some lane is Ok (the rest store no J);
// - the type II test compares the circumradius's square, without its root;
// - the closure error | |s_i| - Lb | is | |s_i|^2 - Lb^2 | / (2 Lb), and
//   |s_i|^2 - Lb^2 is the leg's closure C - A cos q - B sin q;
// - c(J) is condition_number_fast's closed form (core/simd_field-inl.h)
//   where the reference takes condition_number_closed_form;
// - where the model states ball-joint cones (stops.h), the six joints'
//   angles come from each leg's cos q and sin q and its coordinates
//   (ConeMargin), and only the largest per joint type is taken as an angle
//   (two arctangents a sample where cones_of_sample solves the legs again
//   and takes six).
// So J differs from the reference's in its last bits, and c(J) by about its
// own size times an ulp (a relative change of J moves c(J) by at most about
// twice c(J) times as much), more near a leg's serial singular surface and
// where two singular values nearly coincide
// (tests/core/mechanisms/delta/test_field.cpp states the tolerance).
// Every lane whose status could hang on those bits -- a leg margin within
// the singular tolerance and a band around it, an angle within 1e-12 rad of a
// range end (wider near a leg's serial singular surface, where the angle is
// ill-conditioned), a residual near the IK tolerance, a J^-1 row near zero, a
// circumcircle near the type II test, a cone's margin within its band of 0
// (below), a non-finite coordinate or a J far from unit scale -- is
// recomputed by the reference, so the statuses are the
// reference's exactly. The reach margin's range term La theta carries the
// same conditioning near such a surface, in the reference as here.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/mechanisms/delta/field_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "core/simd_field-inl.h"  // per target, like this file

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/mechanisms/delta/field.h"

HWY_BEFORE_NAMESPACE();
namespace linkscape::delta::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using namespace linkscape::simd::HWY_NAMESPACE;  // D, V, M, Block and the shared helpers

// Whether the angle of direction (c1, s1) is larger than that of (c2, s2),
// both taken in (-pi, pi] (atan2's): the upper half-plane's angles are the
// larger; within one half-plane the sign of the cross product decides.
HWY_INLINE M AngleGreater(D d, V c1, V s1, V c2, V s2) {
  const V zero = hn::Zero(d);
  const M upper1 = hn::Or(s1 > zero, hn::And(s1 == zero, c1 < zero));
  const M upper2 = hn::Or(s2 > zero, hn::And(s2 == zero, c2 < zero));
  const M halves_differ = hn::Xor(upper1, upper2);
  return hn::Or(hn::And(halves_differ, upper1), hn::AndNot(halves_differ, c2 * s1 - s2 * c1 > zero));
}

constexpr double kSmallestLa = 0x1p-50;

// The ball-joint sockets' axes (stops.cpp's Sockets), where the model states cones.
struct Cones {
  bool elbow = false, wrist = false;  // whether each joint type has a cone
  double elbow_cos = 0, elbow_sin = 0, wrist_cos = 0, wrist_sin = 0;
  explicit Cones(const Model& m)
      : elbow(m.elbow_cone < std::numbers::pi), wrist(m.wrist_cone < std::numbers::pi), elbow_cos(std::cos(m.elbow_axis)),
        elbow_sin(std::sin(m.elbow_axis)), wrist_cos(std::cos(m.wrist_axis)), wrist_sin(std::sin(m.wrist_axis)) {}
  bool any() const { return elbow || wrist; }
};

struct Setup {
  const Model& m;
  const FieldLegs& legs;
  int branch;
  double tolerance;  // the IK's, relative to size()
  Cones cones;
};

constexpr double kDegrees = 180.0 / std::numbers::pi;

// min over the six ball joints of (cone - angle), deg, as joint_stops
// (stops.cpp, angles_at), in each leg's frame (e radial, t, z up): the arm
// (cos q, 0, -sin q), the rod C - B = (u - La cos q, v, w + La sin q), the
// elbow's socket axis elbow_cos arm - elbow_sin normal = (cos(q + a), 0,
// -sin(q + a)), the wrist's (-wrist_cos, 0, -wrist_sin). A joint's angle is
// atan2(|axis x rod|, axis . rod); the margin needs per joint type only the
// largest, found by comparing the directions (axis . rod, |axis x rod|),
// whose angle alone is taken.
HWY_INLINE V ConeMargin(const Setup& s, V z, const V* u, const V* v, const V* qc, const V* qs, const V* inv_norm) {
  const D d;
  const Cones& k = s.cones;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), La = hn::Set(d, s.m.La);
  const V ec = hn::Set(d, k.elbow_cos), es = hn::Set(d, k.elbow_sin), wc = hn::Set(d, k.wrist_cos), ws = hn::Set(d, k.wrist_sin);
  const V wrist_norm2 = hn::Set(d, k.wrist_cos * k.wrist_cos + k.wrist_sin * k.wrist_sin);
  V elbow_dot = one, elbow_perp = zero, wrist_dot = one, wrist_perp = zero;  // angle 0
  // Whether direction (dot, perp) (perp >= 0) has the larger angle than the best so far; then it is.
  const auto keep_largest = [&](V dot, V perp, V& best_dot, V& best_perp) {
    const M larger = hn::MulSub(best_dot, perp, best_perp * dot) > zero;
    best_dot = hn::IfThenElse(larger, dot, best_dot);
    best_perp = hn::IfThenElse(larger, perp, best_perp);
  };
#pragma GCC unroll 3
  for (int i = 0; i < kLegCount; ++i) {
    const V cos_q = qc[i] * inv_norm[i], sin_q = qs[i] * inv_norm[i];
    const V re = hn::NegMulAdd(La, cos_q, u[i]), rz = hn::MulAdd(La, sin_q, z), rt2 = v[i] * v[i];
    // |a x rod|^2 = |a|^2 rt^2 + (az re - ax rz)^2 for a = (ax, 0, az).
    if (k.elbow) {
      const V ax = hn::MulSub(ec, cos_q, es * sin_q), az = hn::Neg(hn::MulAdd(ec, sin_q, es * cos_q));
      const V cross = hn::MulSub(az, re, ax * rz);
      keep_largest(hn::MulAdd(ax, re, az * rz), hn::Sqrt(hn::MulAdd(rt2, hn::MulAdd(ax, ax, az * az), cross * cross)),
                   elbow_dot, elbow_perp);
    }
    if (k.wrist) {
      const V cross = hn::MulSub(wc, rz, ws * re);
      keep_largest(hn::Neg(hn::MulAdd(wc, re, ws * rz)), hn::Sqrt(hn::MulAdd(rt2, wrist_norm2, cross * cross)), wrist_dot,
                   wrist_perp);
    }
  }
  V margin = hn::Inf(d);
  if (k.elbow) margin = (hn::Set(d, s.m.elbow_cone) - Atan2(d, elbow_perp, elbow_dot)) * hn::Set(d, kDegrees);
  if (k.wrist) margin = hn::Min(margin, (hn::Set(d, s.m.wrist_cone) - Atan2(d, wrist_perp, wrist_dot)) * hn::Set(d, kDegrees));
  return margin;
}

// The samples [first, first + count) of the row: statuses without c(J),
// reach margins, residuals, the rows of J = -diag(1 / Jq) S, and the flags;
// with kCones (the model states cones), their joint margins in `joint_deg`
// (a parameter of the template, so that the kernel without them is
// compiled as before: keeping the legs' coordinates costs it 5%).
template <bool kCones>
void Geometry(const Setup& s, const Grid& g, const detail::GridRow& row, int first, int count, Block& b,
              double* joint_deg) {
  const D d;
  const Model& m = s.m;
  const double size = m.size(), tol = kSingularTolerance * size;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), inf = hn::Inf(d);
  const V La = hn::Set(d, m.La), Lb = hn::Set(d, m.Lb);
  // Where the reference decides: a leg margin within tol + 1e-12 size of 0
  // (its singular tolerance and the band around it; d^2 - Lb^2 is about
  // 2 Lb (d - Lb) there), an angle within 1e-12 rad of a range end.
  const V zone_half_width = hn::Set(d, 2.0 * m.Lb * (tol + 1e-12 * size) * 1.01);
  // The closure error is rounding (1e-15 of the size) that differs from the
  // reference's: within 1e-13 of the size of the IK tolerance (or of the
  // Jacobian's closure check, 1e-6) the reference decides.
  const V residual_limit = hn::Set(d, (std::min(s.tolerance, 1e-6) - 1e-13) * size);
  const bool equal_widths = s.legs.cos_half_width[1] == s.legs.cos_half_width[0] &&
                            s.legs.cos_half_width[2] == s.legs.cos_half_width[0] &&
                            s.legs.sin_half_width[1] == s.legs.sin_half_width[0] &&
                            s.legs.sin_half_width[2] == s.legs.sin_half_width[0];
  const Eigen::Vector3d p0 = row.point(g, 0);
  const int axis = row.axis;
  const V origin = hn::Set(d, g.origin(axis)), spacing = hn::Set(d, g.spacing(axis));
  // leg_coordinates along the row: u = c x + sn y - (R - r) and v = -sn x + c y
  // are linear in the row's coordinate `along` (the one that varies), so
  // each is one multiply-add with per-row constants; w = z.
  double u_slope[kLegCount], u_offset[kLegCount], v_slope[kLegCount], v_offset[kLegCount];
  for (int i = 0; i < kLegCount; ++i) {
    const double c = s.legs.cos_phi[i], sn = s.legs.sin_phi[i];
    u_slope[i] = axis == 0 ? c : axis == 1 ? sn : 0.0;
    v_slope[i] = axis == 0 ? -sn : axis == 1 ? c : 0.0;
    u_offset[i] = (axis == 0 ? 0.0 : c * p0.x()) + (axis == 1 ? 0.0 : sn * p0.y()) - (m.R - m.r);
    v_offset[i] = (axis == 0 ? 0.0 : -sn * p0.x()) + (axis == 1 ? 0.0 : c * p0.y());
  }
  // A leg's half-angle norm is about its coordinates to the fourth power:
  // coordinates and lengths within 2^70 keep it under 2^300 (below, where
  // the three norms' product could leave double's range).
  const double kLargest = 0x1p70;
  const V tiny_rho2 = hn::Set(d, 0x1p-300 / (4.0 * m.La * m.La));
  // The range hand-off's bound on C + |p|^2 + R^2 + 2 Lb^2 is 3 C + extent
  // (below), from |p|^2 <= 2 (C - La^2 + Lb^2) + 2 (R - r)^2.
  const double extent = 2.0 * (m.Lb * m.Lb - m.La * m.La) + 2.0 * (m.R - m.r) * (m.R - m.r) + m.R * m.R + 2.0 * m.Lb * m.Lb;
  // La at least 2^-50 keeps J within UnitRange (SampleRow).
  const bool row_scaled = std::max({std::abs(p0.x()), std::abs(p0.y()), std::abs(p0.z()), m.R, m.La, m.Lb}) <= kLargest &&
                          m.La >= kSmallestLa;

  for (int t = 0; t < count; t += int(hn::Lanes(d))) {
    const V along = origin + (hn::Iota(d, double(row.start[axis] + first + t)) + hn::Set(d, 0.5)) * spacing;
    const V x = axis == 0 ? along : hn::Set(d, p0.x());
    const V y = axis == 1 ? along : hn::Set(d, p0.y());
    const V z = axis == 2 ? along : hn::Set(d, p0.z());
    // Not a number, infinite or too large: the reference decides.
    M to_scalar = hn::Not(hn::And(hn::Abs(along) <= hn::Set(d, kLargest), hn::Set(d, row_scaled ? 1.0 : 0.0) > zero));
    M unreachable = hn::FirstN(d, 0);
    // The largest d_min^2 and the smallest d_max^2 over the legs.
    V largest_X = zero, smallest_Y = inf;
    // Per leg: the direction (qc, qs) of its angle q (the angle of closest
    // approach where it does not reach) and whether it reaches.
    V qc[kLegCount], qs[kLegCount];
    // The smallest root and the largest C over the legs (for the range
    // hand-off below).
    V smallest_root = inf, largest_C = hn::Neg(inf);
    // Each leg's closure A cos q + B sin q = C; B = -2 La w, w = z for every leg.
    V A[kLegCount], C[kLegCount], norm[kLegCount];  // norm = A^2 + B^2
    V u[kLegCount], v[kLegCount];
    const V B = hn::Set(d, -2.0 * m.La) * z, w2 = z * z;
    M leg_unreachable[kLegCount];
#pragma GCC unroll 3
    for (int i = 0; i < kLegCount; ++i) {
      // leg_coordinates and leg_reach
      u[i] = hn::MulAdd(hn::Set(d, u_slope[i]), along, hn::Set(d, u_offset[i]));
      v[i] = hn::MulAdd(hn::Set(d, v_slope[i]), along, hn::Set(d, v_offset[i]));
      const V rho2 = hn::MulAdd(u[i], u[i], w2);
      A[i] = hn::Set(d, 2.0 * m.La) * u[i];
      C[i] = hn::MulAdd(v[i], v[i], rho2 + hn::Set(d, m.La * m.La - m.Lb * m.Lb));
      norm[i] = hn::Set(d, 4.0 * m.La * m.La) * rho2;
      // d_min^2 = (rho - La)^2 + v^2 and d_max^2 = (rho + La)^2 + v^2, rho from
      // S = 2 La rho = sqrt(A^2 + B^2). The leg's margin min(Lb - d_min,
      // d_max - Lb) is needed only as the smallest over the legs (below). Its
      // tests against 0 and +-tol follow from Lb^2 - d_min^2 = S - C and
      // d_max^2 - Lb^2 = S + C outside the singular zone |margin| <= tol +
      // band (where the smaller of the two, |S - |C||, is small), which goes
      // to the reference. (d_min^2 as Lb^2 + C - S would cancel: terms of
      // size La^2 whose difference can be about -Lb^2.)
      const V S = hn::Sqrt(norm[i]);
      const M zone = hn::Abs(S - hn::Abs(C[i])) <= zone_half_width;
      const V rho = S * hn::Set(d, 0.5 / m.La), v2 = v[i] * v[i];
      largest_X = hn::Max(largest_X, hn::MulAdd(rho - La, rho - La, v2));
      smallest_Y = hn::Min(smallest_Y, hn::MulAdd(rho + La, rho + La, v2));
      largest_C = hn::Max(largest_C, C[i]);
      // solve_leg. Its discriminant A^2 + B^2 - C^2 = (S - C)(S + C) without
      // S (whose square root it need not wait for), and from it whether the
      // leg reaches: outside the zone, which goes to the reference, its
      // rounding cannot change the sign.
      const V disc = hn::NegMulAdd(C[i], C[i], norm[i]);
      leg_unreachable[i] = disc < zero;
      // q's direction without its half-angle: A cos q + B sin q = C has
      // (cos q, sin q) (A^2 + B^2) = (A C - sigma B root, B C + sigma A root),
      // tan(q / 2) = (B + sigma root) / (C + A) being solve_leg's solution
      // (docs/mechanisms/delta.md derives it). Its rounding is a few ulps of the angle
      // wherever A^2 + B^2 is not tiny (below). Where the leg does not reach,
      // root = 0 leaves C (A, B): the angle of closest approach, turned by pi
      // where C < 0 (too near, d_max < Lb), as solve_leg's.
      if (hn::AllTrue(d, leg_unreachable[i])) {
        qc[i] = A[i] * C[i];
        qs[i] = B * C[i];
      } else {
        const V root = hn::Sqrt(hn::Max(zero, disc));
        smallest_root = hn::Min(smallest_root, root);
        const V sigma_root = (s.branch >> i) & 1 ? root : hn::Neg(root);
        qc[i] = hn::MulSub(A[i], C[i], B * sigma_root);
        qs[i] = hn::MulAdd(A[i], sigma_root, B * C[i]);
      }
      // A^2 + B^2 = 4 La^2 rho^2 under 2^-300 (a degenerate leg, 0 / 0): the
      // reference decides.
      to_scalar = hn::Or(to_scalar, hn::Or(rho2 < tiny_rho2, zone));
      unreachable = hn::Or(unreachable, leg_unreachable[i]);
    }
    // The actuator ranges without an arctangent per leg: range_margin(q) is
    // w - |q - centre| (q - centre wrapped into (-pi, pi], w the half width),
    // so each leg's excess delta_i = |q_i - centre_i| - w_i has the direction
    // of q_i's (qc, qs) rotated by -centre_i, folded to |.| and rotated by
    // -w_i. The largest excess is found by comparing directions.
    V excess_c = zero, excess_s = zero;
#pragma GCC unroll 3
    for (int i = 0; i < kLegCount; ++i) {
      const V cc = hn::Set(d, s.legs.cos_centre[i]), sc = hn::Set(d, s.legs.sin_centre[i]);
      const V rc = hn::MulAdd(qc[i], cc, qs[i] * sc), rs = hn::Abs(hn::MulSub(qs[i], cc, qc[i] * sc));  // q - centre, folded
      if (equal_widths) {
        // The same w for every leg: the largest |q_i - centre_i| (in [0, pi],
        // rs >= 0) has the largest excess; it alone is rotated below. Within
        // the upper half-plane the cross product decides, and on the real
        // axis (cross product 0) the direction of pi beats that of 0.
        const V cross = hn::MulSub(excess_c, rs, excess_s * rc);
        const M larger = i == 0 ? hn::Not(hn::FirstN(d, 0)) : hn::Or(cross > zero, hn::And(cross == zero, rc < excess_c));
        excess_c = hn::IfThenElse(larger, rc, excess_c);
        excess_s = hn::IfThenElse(larger, rs, excess_s);
        continue;
      }
      const V cw = hn::Set(d, s.legs.cos_half_width[i]), sw = hn::Set(d, s.legs.sin_half_width[i]);
      const V ec = hn::MulAdd(rc, cw, rs * sw), es = hn::MulSub(rs, cw, rc * sw);  // delta_i
      const M larger = i == 0 ? hn::Not(hn::FirstN(d, 0)) : AngleGreater(d, ec, es, excess_c, excess_s);
      excess_c = hn::IfThenElse(larger, ec, excess_c);
      excess_s = hn::IfThenElse(larger, es, excess_s);
    }
    if (equal_widths) {
      const V cw = hn::Set(d, s.legs.cos_half_width[0]), sw = hn::Set(d, s.legs.sin_half_width[0]);
      const V rc = excess_c, rs = excess_s;
      excess_c = hn::MulAdd(rc, cw, rs * sw);
      excess_s = hn::MulSub(rs, cw, rc * sw);
    }
    // Whether the largest excess is within 1e-12 rad of 0 (a range end) or of
    // +-pi (the sine of the direction's angle, bounded by |es| / (|ec| + |es|),
    // with room for rounding), or not a number: there the reference decides.
    // Elsewhere its sign is that of es (the sign of atan2(es, ec)), and the
    // other legs' excesses, smaller, decide neither the status nor the margin.
    const V excess_norm = hn::Abs(excess_c) + hn::Abs(excess_s);
    const V beyond_band = hn::NegMulAdd(hn::Set(d, 2e-12), excess_norm, hn::Abs(excess_s));
    to_scalar = hn::Or(to_scalar, hn::Not(beyond_band > zero));
    const M outside_range = excess_s > zero;
    // min over the legs of min(Lb - d_min, d_max - Lb), from the largest
    // d_min and the smallest d_max (sqrt is monotonic, so these are the bits
    // of the smallest of the six differences).
    const V geometric = hn::Min(Lb - hn::Sqrt(largest_X), hn::Sqrt(smallest_Y) - Lb);
    // The margin min(geometric, -La theta), theta the largest excess's angle,
    // needs theta only where theta > alpha = -geometric / La. theta <= alpha
    // for sure (so the margin is geometric) where theta <= 0 <= alpha; or
    // theta in [0, pi/2] and tan theta <= alpha; or theta in [-pi/2, 0] and
    // sin theta <= alpha; or theta in (-pi, -pi/2), below -1 <= alpha (the
    // legs' margin is at most La: d_max - d_min <= 2 La).
    const V alpha = geometric * hn::Set(d, -1.0 / m.La);
    const M right = excess_c >= zero, lower = excess_s <= zero;
    const M below_by_sine = hn::Or(alpha >= zero, excess_s * excess_s * (one - alpha * alpha) >= alpha * alpha * excess_c * excess_c);
    const M below_by_tangent = excess_s <= alpha * excess_c;
    const M below_alpha = hn::Or(hn::And(right, hn::Or(hn::And(lower, below_by_sine), hn::AndNot(lower, below_by_tangent))),
                                 hn::AndNot(right, lower));
    const M solved = hn::Not(unreachable);
    V status = StatusCode(d, Status::Unreachable);  // solved samples below
    V residual = inf;
    M wants_cond = hn::FirstN(d, 0);
    V joint = hn::NaN(d);  // the cones' margin, deg, on solved samples
    if (!hn::AllFalse(d, solved)) {
      // Near a leg's serial singular surface its angle is ill-conditioned: it
      // moves by about 1 / root per unit of C, so the rounding of C and of the
      // root's argument (some ulps of C + |p|^2 + R^2 + 2 Lb^2) moves it, in the
      // reference as here, by up to 16 u (that) / root, more than the band
      // above just outside the singular zone. Where every leg reaches, a
      // largest excess within that of 0 for the worst-conditioned leg goes to
      // the reference too (the smallest root and largest C over the legs bound
      // every leg's; |p|^2 <= 2 |p - a_i|^2 + 2 |a_i|^2 bounds |p|^2 by C:
      // C + |p|^2 + R^2 + 2 Lb^2 <= 3 C + extent).
      const V ill_scale = hn::MulAdd(hn::Set(d, 3.0), largest_C, hn::Set(d, extent));
      const M ill_conditioned = beyond_band * smallest_root <= hn::Set(d, 16 * 0x1p-53) * excess_norm * ill_scale;
      to_scalar = hn::Or(to_scalar, hn::And(solved, ill_conditioned));
      // cos q_i and sin q_i are (qc, qs) / norm_i, norm_i = A_i^2 + B^2, the
      // three 1 / norm_i from one division.
      const V norm01 = norm[0] * norm[1], inv_all = one / (norm01 * norm[2]);
      const V inv_norm[kLegCount] = {norm[1] * norm[2] * inv_all, norm[0] * norm[2] * inv_all, norm01 * inv_all};
      // The closure error | |s_i| - Lb | as | |s_i|^2 - Lb^2 | / (2 Lb), the same
      // to a relative 1e-15 where it is rounding, and |s_i|^2 - Lb^2 as the
      // leg's closure C - A cos q - B sin q in its own frame.
      V closure = zero;
      for (int i = 0; i < kLegCount; ++i)
        closure = hn::Max(closure, hn::Abs(hn::NegMulAdd(B, qs[i], hn::MulSub(C[i], norm[i], A[i] * qc[i]))) * inv_norm[i]);
      residual = hn::IfThenElse(solved, closure * hn::Set(d, 0.5 / m.Lb), inf);
      M beyond = outside_range;
      if constexpr (kCones) {
        joint = ConeMargin(s, z, u, v, qc, qs, inv_norm);
        // The band round 0 where the reference decides: the angles' rounding
        // here and there (the rod's components to some ulps of the size, the
        // arctangent to a few ulps: about 1e-15 size / Lb rad) with a margin
        // of a thousand, and near a leg's serial singular surface its angle's
        // error (16 u (that) / root, as above) times how much it turns a
        // joint's angle: the socket axis by as much, the rod by La / Lb of it,
        // twice over.
        const double band = 1e-12 * size / m.Lb * kDegrees, turn = 2 * 16 * 0x1p-53 * (1 + m.La / m.Lb) * kDegrees;
        const M clear = hn::Abs(joint) * smallest_root > hn::MulAdd(hn::Set(d, band), smallest_root, hn::Set(d, turn) * ill_scale);
        to_scalar = hn::Or(to_scalar, hn::AndNot(clear, solved));
        beyond = hn::Or(beyond, joint < zero);
        joint = hn::IfThenElse(solved, joint, hn::NaN(d));
      }
      status = hn::IfThenElse(
          solved, hn::IfThenElse(beyond, StatusCode(d, Status::OutOfLimits), StatusCode(d, Status::Ok)), status);
      // NotConverged (a residual over the IK tolerance) comes before the range test.
      const M near_closure = hn::Not(residual <= residual_limit);  // NaN included
      to_scalar = hn::Or(to_scalar, hn::And(solved, near_closure));
      const M ok = hn::AndNot(beyond, solved);
      if (!hn::AllFalse(d, ok)) {
        // The sphere centres c_i = B_i - r e_i, S's rows s_i = p - c_i and
        // Jq_i = -La s_i . dB_i/dq_i.
        V sx[kLegCount], sy[kLegCount], sz[kLegCount], cx[kLegCount], cy[kLegCount], cz[kLegCount], Jq[kLegCount];
        M serial = hn::FirstN(d, 0), near_serial = serial;
#pragma GCC unroll 3
        for (int i = 0; i < kLegCount; ++i) {
          const double c = s.legs.cos_phi[i], sn = s.legs.sin_phi[i];  // e_i = (c, sn, 0), A_i = R e_i
          const V cos_q = qc[i] * inv_norm[i], sin_q = qs[i] * inv_norm[i];
          const V arm = La * cos_q;
          cx[i] = hn::Set(d, m.R * c - m.r * c) + arm * hn::Set(d, c);  // A_i - r e_i + La cos q_i e_i
          cy[i] = hn::Set(d, m.R * sn - m.r * sn) + arm * hn::Set(d, sn);
          cz[i] = hn::Neg(La * sin_q);
          sx[i] = x - cx[i];
          sy[i] = y - cy[i];
          sz[i] = z - cz[i];
          Jq[i] = La * (sin_q * (sx[i] * hn::Set(d, c) + sy[i] * hn::Set(d, sn)) + cos_q * sz[i]);
          serial = hn::Or(serial, Jq[i] == zero);
          near_serial = hn::Or(near_serial, hn::Abs(Jq[i]) <= hn::Set(d, 1e-12 * m.La * m.Lb));
        }
        // The circumcircle of the centres (spheres_from_centres) and det S.
        const V ax = cx[0] - cx[2], ay = cy[0] - cy[2], az = cz[0] - cz[2];
        const V bx = cx[1] - cx[2], by = cy[1] - cy[2], bz = cz[1] - cz[2];
        const V nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
        const V n2 = nx * nx + ny * ny + nz * nz, a2 = ax * ax + ay * ay + az * az, b2 = bx * bx + by * by + bz * bz;
        const V abx = ax - bx, aby = ay - by, abz = az - bz;
        // The type II test Lb - circumradius <= tol and its band of 1e-9 size
        // on the circumradius's square a2 b2 |a - b|^2 / (4 n2), without its
        // division and square root.
        const V circumradius2_num = a2 * b2 * (abx * abx + aby * aby + abz * abz), circumradius2_den = hn::Set(d, 4.0) * n2;
        const auto circumradius_at_least = [&](double r) {
          return r <= 0.0 ? hn::Not(hn::IsNaN(circumradius2_num)) : circumradius2_num >= circumradius2_den * hn::Set(d, r * r);
        };
        const M type_two = circumradius_at_least(m.Lb - tol);
        const M near_type_two =
            hn::AndNot(circumradius_at_least(m.Lb - tol + 1e-9 * size), circumradius_at_least(m.Lb - tol - 1e-9 * size));
        const V flat = hn::Set(d, 1e-24) * a2 * b2;
        const M degenerate = hn::Not(n2 > flat);
        const V det = sx[0] * (sy[1] * sz[2] - sz[1] * sy[2]) - sy[0] * (sx[1] * sz[2] - sz[1] * sx[2]) +
                      sz[0] * (sx[1] * sy[2] - sy[1] * sx[2]);
        const M parallel = hn::Or(det == zero, hn::Or(degenerate, type_two));
        wants_cond = hn::AndNot(hn::Or(serial, parallel), ok);
        const M near_parallel = hn::Or(near_type_two,
                                       hn::Or(hn::Abs(n2 - flat) <= hn::Set(d, 1e-6) * flat,
                                              hn::Abs(det) <= hn::Set(d, 1e-12 * m.Lb * m.Lb * m.Lb)));
        // J^-1 is refused over the closure check.
        to_scalar = hn::Or(to_scalar, hn::And(ok, hn::Or(near_serial, near_parallel)));
        // J's rows -s_i / Jq_i, stored as its columns (c(J) = c(J^T)).
        // The three reciprocals -1 / Jq_i from one division (J outside 2^+-100
        // goes to the reference anyway).
        const V Jq01 = Jq[0] * Jq[1], minus_inv = hn::Neg(one) / (Jq01 * Jq[2]);
        const V scales[kLegCount] = {Jq[1] * Jq[2] * minus_inv, Jq[0] * Jq[2] * minus_inv, Jq01 * minus_inv};
        for (int i = 0; i < kLegCount; ++i) {
          const V scale = scales[i];
          hn::Store(sx[i] * scale, d, b.J[3 * i] + t);
          hn::Store(sy[i] * scale, d, b.J[3 * i + 1] + t);
          hn::Store(sz[i] * scale, d, b.J[3 * i + 2] + t);
        }
      }
    }
    V margin = geometric;
    if (!hn::AllTrue(d, below_alpha)) margin = hn::Min(geometric, La * hn::Neg(Atan2(d, excess_s, excess_c)));
    if constexpr (kCones) {
      // As cones_of_sample: at most the size times the cones' margin in rad.
      const V cone_reach = hn::Set(d, size) * joint * hn::Set(d, std::numbers::pi) / hn::Set(d, 180.0);
      margin = hn::IfThenElse(hn::IsNaN(joint), margin, hn::Min(margin, cone_reach));
      hn::Store(joint, d, joint_deg + t);
    }
    hn::Store(status, d, b.status + t);
    hn::Store(margin, d, b.reach_margin + t);
    hn::Store(residual, d, b.residual + t);
    hn::Store(Flag(d, wants_cond), d, b.wants_cond + t);
    hn::Store(Flag(d, to_scalar), d, b.to_scalar + t);
  }
}

void SampleRow(const Model& m, const FieldLegs& legs, const FieldRequest& request, const Grid& g,
               const detail::GridRow& row, const detail::FieldRowOut& out, const RowMirror* mirror, float* joint_margin) {
  const Setup setup{m, legs, request.ik.branch, request.ik.tolerance, Cones(m)};
  const MethodRule rule{0.0 /* IkMethod::Closed */, false};
  Block b;
  HWY_ALIGN double joint[kBlock];
  // The reference at a point of the row or of its mirror, cones included.
  const auto reference = [&](const detail::GridRow& at, int i) {
    const Eigen::Vector3d p = at.point(g, i);
    FieldSample sample = sample_point(m, p, request);
    if (joint_margin) joint_margin[at.index + std::size_t(i)] = cones_of_sample(m, p, request, sample);
    return sample;
  };
  for (int first = 0; first < row.count; first += kBlock) {
    const int n = std::min(kBlock, row.count - first);
    if (joint_margin)
      Geometry<true>(setup, g, row, first, n, b, joint);
    else
      Geometry<false>(setup, g, row, first, n, b, nullptr);
    // The joint margins are mirror-symmetric too: the six angles depend on
    // v only through v^2, and legs 1 and 2 swap.
    for (int t = 0; joint_margin && t < n; ++t) {
      joint_margin[row.index + std::size_t(first + t)] = float(joint[t]);
      if (mirror) joint_margin[mirror->row.index + std::size_t(first + t)] = float(joint[t]);
    }
    // J's rows are s_i / Jq_i with |s_i| = Lb (to the closure check) and
    // 1e-12 La Lb < |Jq_i| <= La |s_i| (nearer 0 goes to the reference), so
    // its largest entry is between 1 / (sqrt 3 La) and about 1e12 / La:
    // within UnitRange's 2^+-100 for La in [2^-50, 2^70] (Geometry sends
    // other designs to the reference).
    BlockConditioning(n, b, std::nullopt, true);
    StoreBlock(b, first, n, row.count, false, rule, out, [&](int i) { return reference(row, i); });
    // The mirror row takes the same values; the lanes the reference decides
    // are decided at the mirror row's own points.
    if (mirror) {
      CopySamples(out, mirror->out, first, n);
      ForEachHandedOff(b, n, [&](int t) {
        mirror->out.store(first + t, reference(mirror->row, first + t));
      });
    }
  }
}

}  // namespace linkscape::delta::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace linkscape::delta {

HWY_EXPORT(SampleRow);

void sample_row_vector(const Model& m, const FieldLegs& legs, const FieldRequest& request, const Grid& g,
                       const detail::GridRow& row, const detail::FieldRowOut& out, const RowMirror* mirror,
                       float* joint_margin) {
  HWY_DYNAMIC_DISPATCH(SampleRow)(m, legs, request, g, row, out, mirror, joint_margin);
}

}  // namespace linkscape::delta
#endif  // HWY_ONCE
