// Point legs', crank-parallelograms' and three-revolute legs' closed forms and the measures in
// SIMD lanes (lanes.h), compiled once per instruction set and chosen at run
// time (core/simd.h); the per-leg geometry is lanes_legs-inl.h's.
//
// Lane for lane it is the scalar closed path (Kinematics::inverse with the
// closed forms, stops, jacobian, reach_margin) with the early returns
// replaced by masks: each leg's reach bounds, its closed form's candidates (a
// crank's cos q, sin q from A cos q + B sin q = C without an angle; a slide's
// quadratic; an extensible leg's distance; a parallelogram's four, its
// upper joint's and elbow's signs; a three-revolute leg's four, its third
// angle's and Paden-Kahan's signs), the branch rules' signs on the actuator,
// ball, end, anchor and a parallelogram's joints (and the sine of a
// parallelogram's or three-revolute leg's joint's angle), the travel, the ball joints' cones, the
// passive revolutes' stops (their angles as directions from the joints'
// points), the links' clearance (capsule segments from the joints' points,
// segment-segment distance as interference::closest_points takes it), the
// Jacobian row (the force along the rod, or square to a three-revolute
// leg's second and third joints' velocities; a parallelogram's actuator twist
// off its passive twists), J = -Jx^-1 Jq (Jx^-1 by cofactors for 2x2 and
// 3x3, by Gauss-Jordan with partial pivoting for 6x6), the serial and travel margins, and the measures: c(J) of a 2x2
// or 3x3 J in closed form (core/simd_field-inl.h's for 3x3), cond(Jp) and
// cond(Jo) of a 6x6 J as c(R) of the QR factor (modified Gram-Schmidt) of
// their 3x6 rows, no general SVD. A planar dyad is a crank in the plane. A
// lane decides only clearly away from every threshold the scalar path
// decides at: reach bounds within 1e-9 of the size of their cut, a closed
// form within 1e-9 of its discriminant's zero or a degenerate pose (a
// parallelogram: its miss within 1e-9 of the size of zero, its side or elbow
// within 1e-6 of straight; a three-revolute leg's: its reach's ends, its
// third angle's double root, Paden-Kahan's discriminant's zero, an
// ill-defined angle, its passive joints losing a freedom), a rule's value within 1e-9 size^k of 0, an
// actuator within 1e-9 of a travel end, a cone or a revolute stop within
// 1e-7 deg of its limit, two capsules within 1e-9 of the size of touching
// or nearly parallel, a rod or a Jq entry within 1e-6 of zero, a universal
// joint within 1e-6 of gimbal lock, a parallelogram's passive twists within
// 1e-6 of losing their rank, Jx's 1-norm condition number over 1e8 (the
// scalar path's type II test is the LU's estimate over 1e12, at most this),
// a Jacobian far from unit scale, two of its singular values within about
// 1e-4 of each other (where the closed-form c(J) is inexact): those lanes are
// the scalar closed path's.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/mechanisms/described/lanes_simd.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h
#include <hwy/highway.h>

#include "core/simd_field-inl.h"  // per target, like this file
#include "core/mechanisms/described/lanes_legs-inl.h"  // likewise
#include "core/mechanisms/described/lanes_matrix-inl.h"  // likewise

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/mechanisms/described/lanes.h"
#include "core/simd.h"

HWY_BEFORE_NAMESPACE();
namespace linkscape::described::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using namespace linkscape::simd::HWY_NAMESPACE;  // D, V, M, Block and the shared helpers

HWY_INLINE V3 PointOf(LanePoint p, const LaneLeg& g, const Candidate& c, const V3& end, const V3& anchor, D d) {
  switch (p) {
    case LanePoint::Actuator:  // a slide's start: along the leg from its ball
      return g.pattern == LegPattern::Extensible ? c.ball + hn::Set(d, g.slide_start) * c.axis : Splat(d, g.actuator_centre);
    case LanePoint::Ball: return c.ball;
    case LanePoint::End: return end;
    case LanePoint::Knee: return c.knee;
    case LanePoint::Upper: return c.upper;
    case LanePoint::Lower: return c.lower;
    case LanePoint::Anchor: break;
  }
  return anchor;
}

// The candidate's rules (unless they pick the branch's candidate:
// branch_candidate) and travel; bands near their thresholds go to `to_scalar`.
HWY_INLINE void Decide(D d, const LaneLeg& g, double size, const V3& end, const V3& anchor, Candidate& c, M& to_scalar) {
  const V zero = hn::Zero(d);
  c.match = hn::Not(None(d));
  const std::size_t rules = g.branch_candidate >= 0 ? 0 : g.rules.size();
  for (std::size_t k = 0; k < rules; ++k) {
    const LaneLeg::Rule& r = g.rules[k];
    if (r.angle) {  // sin of the joint's angle
      const V v = c.js[int(r.joint)];
      c.match = hn::And(c.match, hn::Not(v * hn::Set(d, r.wanted) < zero));
      to_scalar = hn::Or(to_scalar, hn::Abs(v) < hn::Set(d, 1e-9));
      continue;
    }
    const V3 a = PointOf(r.points[0], g, c, end, anchor, d), b = PointOf(r.points[1], g, c, end, anchor, d);
    V v;
    if (r.triple) v = Dot(Cross(b - a, PointOf(r.points[2], g, c, end, anchor, d) - b), r.fixed_axis ? Splat(d, r.axis) : c.axis);
    else v = Dot(b - a, Splat(d, r.direction));
    c.match = hn::And(c.match, hn::Not(v * hn::Set(d, r.wanted) < zero));
    to_scalar = hn::Or(to_scalar, hn::Abs(v) < hn::Set(d, 1e-9 * (r.triple ? size * size : size)));
  }
  if (!g.limited) {
    c.inside = hn::Not(None(d));
  } else if (g.prismatic) {
    c.inside = hn::And(c.q >= hn::Set(d, g.lo), c.q <= hn::Set(d, g.hi));
    const V band = hn::Set(d, 1e-9 * size);
    to_scalar = hn::Or(to_scalar, hn::Or(hn::Abs(c.q - hn::Set(d, g.lo)) < band, hn::Abs(c.q - hn::Set(d, g.hi)) < band));
  } else {
    // theta = q - mid as a direction (rc, rs); |theta| <= w (the half width)
    // where sin(|theta| - w) = |rs| cos w - rc sin w <= 0, without an angle.
    const V cm = hn::Set(d, g.cos_mid), sm = hn::Set(d, g.sin_mid);
    c.rc = hn::MulAdd(c.c, cm, c.s * sm);
    c.rs = hn::MulSub(c.s, cm, c.c * sm);
    const V excess = hn::MulSub(hn::Abs(c.rs), hn::Set(d, g.cos_half_width), c.rc * hn::Set(d, g.sin_half_width));
    c.inside = excess <= zero;
    const V band = hn::Set(d, 1e-9);
    // Near a travel end, or theta near +-pi (where the wrap picks the representative).
    to_scalar = hn::Or(to_scalar, hn::Or(hn::Abs(excess) < band, hn::And(hn::Abs(c.rs) < band, c.rc < zero)));
  }
}

// A leg's distances on one grid row, p = p0 + t e (e the row's axis, p0 its
// point at t = 0): the anchor's from the reach bounds' centre and a crank's
// end from its circle's centre are p + a fixed vector f, so |p + f|^2 = (t +
// f_e)^2 + |f_perp|^2 (f_e, f_perp: (p0 + f)'s parts along and across e) and a
// component along a fixed direction is linear in t: a multiply-add or two
// each where a dot product of three took five operations. Rounded as the
// dot product was: t + f_e to about an ulp of the size, so the square to
// about eps size |p + f| (a sum of squares: no cancellation near the centre).
struct RowLeg {
  double base_along = 0, base_across2 = 0;  // |anchor - leg_base|^2 = (t + along)^2 + across2
  double end_along = 0, end_across2 = 0;    // |end - origin|^2 + rho^2 = (t + along)^2 + across2
  double u_slope = 0, u_offset = 0, v_slope = 0, v_offset = 0;  // (end - origin) . u, . v
};
HWY_INLINE RowLeg RowLegOf(const LaneLeg& g, const Eigen::Vector3d& p0, int axis) {
  RowLeg r;
  Eigen::Vector3d from_base = p0 + g.anchor_offset - g.leg_base, from_origin = p0 + g.end_offset - g.origin;
  r.u_offset = g.u.dot(from_origin);
  r.v_offset = g.v.dot(from_origin);
  r.u_slope = g.u(axis);
  r.v_slope = g.v(axis);
  r.base_along = std::exchange(from_base(axis), 0.0);
  r.base_across2 = from_base.squaredNorm();
  r.end_along = std::exchange(from_origin(axis), 0.0);
  r.end_across2 = from_origin.squaredNorm() + g.rho * g.rho;
  return r;
}

// Leg `g` at platform positions p: its candidates, the one the branch and
// travel choose, or why it is unreachable (the square roots taken only
// where some lane needs them). Lanes `decided` (unreachable by an earlier
// leg, their margin that leg's residual, < 0) need only this leg's residual
// where it misses: where it closes there they count as closing.
HWY_INLINE void SolveLeg(D d, const LaneLeg& g, const RowLeg& row, double size, const V3& p, V along, M decided,
                         LegLanes& out) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const V3 anchor = p + Splat(d, g.anchor_offset);
  out.anchor = anchor;
  out.end = p + Splat(d, g.end_offset);
  const V3& w = out.end;
  // The reach bounds, as solve_leg_on takes them first: outside = max(|a -
  // base| - hi, lo - |a - base|) > 1e-9 size, decided on the squares away
  // from the band (0.5e-9, 2e-9] size, which goes to the scalar path.
  const V from_base = along + hn::Set(d, row.base_along);
  const V distance2 = hn::MulAdd(from_base, from_base, hn::Set(d, row.base_across2));
  const double hi = g.reach.hi, lo = g.reach.lo;
  const M bound = hn::Or(distance2 > hn::Set(d, g.far_out2), distance2 < hn::Set(d, g.near_out2));
  const M kept = hn::And(distance2 <= hn::Set(d, g.far_in2), distance2 >= hn::Set(d, g.near_in2));
  out.to_scalar = hn::Not(hn::Or(bound, kept));
  V outside = zero;
  if (!hn::AllFalse(d, bound)) {
    const V distance = hn::Sqrt(distance2);
    outside = hn::Max(distance - hn::Set(d, hi), hn::Set(d, lo) - distance);
  }
  out.unreachable = hn::Not(None(d));
  out.outside_travel = None(d);
  out.residual = outside;
  if (hn::AllTrue(d, bound)) return;
  M band = None(d);  // the closed form's, rules' and travel's: where the closed form decides
  M missed = None(d);
  M closed_band = None(d);  // a parallelogram's candidates', a branch candidate's: where the leg closes
  V miss = zero;
  Candidate c[4];  // a point leg's two, a parallelogram's and three-revolute leg's four
  const bool four = g.parallelogram || g.three;
  const bool single = g.branch_candidate >= 0;  // a crank whose rule picks one candidate
  // Where no undecided lane's leg closes, its candidates are not needed (the residual is).
  const auto none_closes = [&] {
    const M closes = hn::AndNot(hn::Or(bound, missed), hn::Not(None(d)));
    if (!hn::AllFalse(d, hn::AndNot(decided, closes))) return false;
    out.unreachable = hn::Not(closes);
    out.to_scalar = hn::Or(out.to_scalar, hn::AndNot(bound, band));
    out.residual = hn::IfThenElse(bound, outside, miss);
    return true;
  };
  if (g.parallelogram) {
    const ParallelogramReach reach = ParallelogramMiss(d, g, size, w, missed, miss, band);
    if (none_closes()) return;
    ParallelogramCandidates(d, g, size, reach, c, closed_band);
    // Within reach but no candidate (rounding): the scalar path's.
    M any = None(d);
    for (const Candidate& k : c) any = hn::Or(any, k.valid);
    closed_band = hn::Or(closed_band, hn::Not(any));
  } else if (g.three) {
    const ThreeRevoluteReach reach = ThreeRevoluteMiss(d, g, size, w, missed, miss, band);
    if (none_closes()) return;
    // Where no candidate is valid the leg closes on no branch (unreachable, miss 0).
    ThreeRevoluteCandidates(d, g, reach, w, c, closed_band);
  } else if (g.pattern == LegPattern::CrankRod) {
    const V du = hn::MulAdd(hn::Set(d, row.u_slope), along, hn::Set(d, row.u_offset));
    const V dw = hn::MulAdd(hn::Set(d, row.v_slope), along, hn::Set(d, row.v_offset));
    const V from_origin = along + hn::Set(d, row.end_along);
    const V R = hn::Sqrt(du * du + dw * dw), dd = hn::MulAdd(from_origin, from_origin, hn::Set(d, row.end_across2));
    const V two_rho_R = hn::Set(d, 2 * g.rho) * R, L = hn::Set(d, g.rod);
    // L < nearest = sqrt(dd - 2 rho R) or L > farthest = sqrt(dd + 2 rho R),
    // on the squares; |L - nearest| < 1e-9 size implies |L^2 - nearest^2| <
    // 1e-9 size (2 L + 1e-9 size) (the band, likewise for farthest).
    const V near2 = dd - two_rho_R, far2 = dd + two_rho_R, L2 = hn::Set(d, g.rod * g.rod);
    missed = hn::Or(L2 < near2, L2 > far2);
    const V tiny2 = hn::Set(d, 1e-9 * size * (2 * g.rod + 1e-9 * size));
    band = hn::Or(hn::Or(hn::Abs(L2 - near2) < tiny2, hn::Abs(L2 - far2) < tiny2), R < hn::Set(d, 1e-9 * size));
    if (!hn::AllFalse(d, missed)) {
      const V nearest = hn::Sqrt(hn::Max(zero, near2)), farthest = hn::Sqrt(far2);
      miss = hn::Max(nearest - L, L - farthest);
    }
    if (none_closes()) return;
    const V inv_R = one / R;
    const V cr = hn::Min(one, hn::Max(hn::Neg(one), (dd - L * L) * hn::Set(d, 0.5 / g.rho) * inv_R));
    const V sr = hn::Sqrt(hn::Max(zero, (one - cr) * (one + cr)));
    const V cphi = du * inv_R, sphi = dw * inv_R;
    // The branch's candidate alone where the rule reads the closed form's
    // sign (lanes.cpp's branch_candidate): its triple is -sign rho R sin(alpha).
    if (single) closed_band = hn::Set(d, g.rho) * R * sr < hn::Set(d, 1e-9 * size * size);
    for (int k = 0; k < (single ? 1 : 2); ++k) {
      const V sign = hn::Set(d, (single ? g.branch_candidate : k) == 0 ? 1.0 : -1.0);
      c[k].c = cphi * cr - sign * sphi * sr;
      c[k].s = sphi * cr + sign * cphi * sr;
      c[k].ball = Splat(d, g.origin) + hn::Set(d, g.rho) * (c[k].c * Splat(d, g.u) + c[k].s * Splat(d, g.v));
      c[k].axis = Splat(d, g.axis);
      c[k].q = zero;
      c[k].sigma = one;
    }
  } else if (g.pattern == LegPattern::SlideRod) {
    const V3 gap = Splat(d, g.origin) - w;
    const V b = Dot(Splat(d, g.axis), gap), h2 = Dot(gap, gap) - b * b, L2 = hn::Set(d, g.rod * g.rod);
    missed = h2 > L2;
    if (!hn::AllFalse(d, missed)) miss = hn::Sqrt(hn::Max(zero, h2)) - hn::Set(d, g.rod);
    band = hn::Abs(h2 - L2) < hn::Set(d, 1e-9 * size * size);
    if (none_closes()) return;
    const V root = hn::Sqrt(hn::Max(zero, L2 - h2));
    for (int k = 0; k < 2; ++k) {
      c[k].q = hn::Neg(b) + (k == 0 ? root : hn::Neg(root));
      c[k].ball = Splat(d, g.origin) + c[k].q * Splat(d, g.axis);
      c[k].axis = Splat(d, g.axis);
      c[k].c = c[k].s = zero;
      c[k].sigma = one;
    }
  } else {  // extensible
    const V3 dv = w - Splat(d, g.origin);
    const V n = hn::Sqrt(Dot(dv, dv));
    band = n < hn::Set(d, 1e-9 * size);
    if (none_closes()) return;
    const V inv_n = one / n;
    for (int k = 0; k < 2; ++k) {
      c[k].sigma = hn::Set(d, k == 0 ? 1.0 : -1.0);
      c[k].q = c[k].sigma * n - hn::Set(d, g.offset);
      c[k].ball = Splat(d, g.origin);
      c[k].axis = (c[k].sigma * inv_n) * dv;
      c[k].c = c[k].s = zero;
    }
  }
  M decided_band = closed_band;
  if (!four) {
    for (int k = 0; k < (single ? 1 : 2); ++k) {
      c[k].rc = c[k].rs = zero;
      Decide(d, g, size, w, anchor, c[k], decided_band);
    }
  } else {
    for (Candidate& x : c) {
      x.rc = x.rs = zero;
      M candidate_band = None(d);
      Decide(d, g, size, w, anchor, x, candidate_band);
      decided_band = hn::Or(decided_band, hn::And(x.valid, candidate_band));
    }
  }
  const M closes = hn::AndNot(bound, hn::Not(missed));
  // Bands count only where they could decide: the closed form's where the
  // bounds let it run, the rules' and travel's where it closes.
  out.to_scalar = hn::Or(out.to_scalar, hn::AndNot(bound, hn::Or(band, hn::And(closes, decided_band))));
  // As the scalar path: the first candidate on the branch within the travel,
  // else the first on the branch.
  Candidate& a = out.at;
  M within = None(d), on_branch = None(d);
  if (!four) {  // one or two candidates, the fields a point leg has
    M take1 = None(d);
    if (single) {  // on the branch wherever the lane decides
      within = c[0].inside;
      on_branch = hn::Not(None(d));
    } else {
      const M within0 = hn::And(c[0].match, c[0].inside), within1 = hn::And(c[1].match, c[1].inside);
      take1 = hn::AndNot(within0, hn::Or(within1, hn::AndNot(c[0].match, c[1].match)));
      within = hn::Or(within0, within1);
      on_branch = hn::Or(c[0].match, c[1].match);
    }
    const Candidate& second = single ? c[0] : c[1];
    a.ball = Select(take1, second.ball, c[0].ball);
    a.axis = Select(take1, second.axis, c[0].axis);
    a.q = hn::IfThenElse(take1, second.q, c[0].q);
    a.c = hn::IfThenElse(take1, second.c, c[0].c);
    a.s = hn::IfThenElse(take1, second.s, c[0].s);
    a.rc = hn::IfThenElse(take1, second.rc, c[0].rc);
    a.rs = hn::IfThenElse(take1, second.rs, c[0].rs);
    a.sigma = hn::IfThenElse(take1, second.sigma, c[0].sigma);
  } else {
    a = c[0];
    for (int k = 0; k < 4; ++k) {
      const M take = hn::AndNot(within, hn::And(hn::And(c[k].valid, c[k].match), c[k].inside));
      Pick(take, c[k], a);
      within = hn::Or(within, take);
    }
    for (int k = 0; k < 4; ++k) {
      const M matched = hn::And(c[k].valid, c[k].match);
      Pick(hn::AndNot(hn::Or(within, on_branch), matched), c[k], a);
      on_branch = hn::Or(on_branch, matched);
    }
  }
  out.unreachable = hn::Or(bound, hn::Or(missed, hn::Not(on_branch)));
  out.outside_travel = hn::AndNot(within, hn::Not(out.unreachable));
  out.residual = hn::IfThenElse(bound, outside, hn::IfThenElse(missed, miss, zero));
}

struct Extras {  // per block sample, beside simd::Block
  double joint_margin[kBlock], clearance[kBlock];
};

template <int N>
void Geometry(const LaneDevice& dev, const Grid& g, const detail::GridRow& row, int first, int count, Block& b,
              Extras& e) {
  const D d;
  const double size = dev.size;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0), inf = hn::Inf(d);
  const Eigen::Vector3d p0 = row.point(g, 0);
  const int axis = row.axis;
  const V origin = hn::Set(d, g.origin(axis)), spacing = hn::Set(d, g.spacing(axis));
  constexpr double kDeg = 180 / M_PI;
  std::size_t closest_pair = 0;  // the pair that set the last clearance: likely the next one's
  // The row's point at along = 0 (a planar device's z is its plane's) and each leg's distances on the row.
  Eigen::Vector3d start = p0;
  if (dev.planar) start.z() = 0;
  const bool moves = !(dev.planar && axis == 2);
  if (moves) start(axis) = 0;
  RowLeg row_legs[N];
  for (int i = 0; i < N; ++i) row_legs[i] = RowLegOf(dev.legs[std::size_t(i)], start, axis);
  for (int t = 0; t < count; t += int(hn::Lanes(d))) {
    // Grid::point's coordinates, bit for bit.
    const V along = origin + (hn::Iota(d, double(row.start[axis] + first + t)) + hn::Set(d, 0.5)) * spacing;
    const V3 p{axis == 0 ? along : hn::Set(d, p0.x()), axis == 1 ? along : hn::Set(d, p0.y()),
               dev.planar ? zero : axis == 2 ? along : hn::Set(d, p0.z())};
    M to_scalar = None(d), unreachable = None(d), outside_travel = None(d);
    V unreachable_margin = inf;
    LegLanes legs[N];
    for (int i = 0; i < N; ++i) {
      SolveLeg(d, dev.legs[std::size_t(i)], row_legs[i], size, p, moves ? along : zero, unreachable, legs[i]);
      to_scalar = hn::Or(to_scalar, legs[i].to_scalar);
      unreachable = hn::Or(unreachable, legs[i].unreachable);
      outside_travel = hn::Or(outside_travel, legs[i].outside_travel);
      unreachable_margin = hn::Min(unreachable_margin, hn::IfThenElse(legs[i].unreachable, hn::Neg(legs[i].residual), inf));
    }
    const M assembled = hn::Not(unreachable);
    V status = hn::IfThenElse(unreachable, StatusCode(d, Status::Unreachable),
                              hn::IfThenElse(outside_travel, StatusCode(d, Status::OutOfLimits), StatusCode(d, Status::Ok)));
    V margin = unreachable_margin, joint_margin = hn::NaN(d), clearance = hn::NaN(d);
    V cond = inf, cond_orientation = inf;
    if (!hn::AllFalse(d, assembled)) {
      M near = None(d);  // a threshold the scalar path decides at, where the device assembles
      V Jx[N][N], jq[N];
      V serial = inf, travel = inf, cones = inf;
      V3 couples[N];
      int parallelograms = 0;
      Widest widest_cone[kMaxLaneSizes], widest_travel[kMaxLaneSizes];
      for (std::size_t k = 0; k < kMaxLaneSizes; ++k) widest_cone[k] = widest_travel[k] = {zero, one};
      // A revolute travel's margin, or its angle kept for its width's.
      const auto travel_of = [&](const LaneLeg& g, const Candidate& a) {
        if (g.width >= 0) Widen(widest_travel[g.width], hn::Abs(a.rs), a.rc);
        else travel = hn::Min(travel, (hn::Set(d, g.half_width) - Atan2(d, hn::Abs(a.rs), a.rc)) * hn::Set(d, size));
      };
      for (int i = 0; i < N; ++i) {
        const LaneLeg& g = dev.legs[std::size_t(i)];
        const Candidate& a = legs[i].at;
        for (const LaneLeg::Stop& stop : g.stops) {
          V c = a.jc[int(stop.joint)], s = a.js[int(stop.joint)];
          if (stop.joint == LaneJoint::Ball) {  // a planar elbow: from the crank's rod at q = 0 to the rod
            const V3 link = Turn(d, g.axis, g.ball_link, a.c, a.s), rod = legs[i].end - a.ball;
            c = Dot(link, rod);
            s = Dot(Splat(d, g.ball_normal), Cross(link, rod));
          }
          cones = hn::Min(cones, StopMargin(d, stop, c, s));
        }
        if (g.parallelogram) {
          // Its constraint couple: square to its knee's axis and its upper bar's.
          ParallelogramRow<N>(d, g, dev.coordinate, size, legs[i], Jx[i], jq[i], near, couples[parallelograms++]);
          near = hn::Or(near, jq[i] < hn::Set(d, 1e-6));
          serial = hn::Min(serial, jq[i] * hn::Set(d, size));
          if (g.limited) travel_of(g, a);
          continue;
        }
        const V3 f = g.three ? ThreeRevoluteForce(d, g, a, legs[i].end, near) : legs[i].end - a.ball;
        if (!g.three) {
          const V f_norm = hn::Sqrt(Dot(f, f)), inv_f = one / f_norm;
          near = hn::Or(near, f_norm < hn::Set(d, 1e-6 * size));
          const V3 pointing = (a.sigma * inv_f) * f;  // where the ball points its link
          if (g.universal) {
            const V3 first_axis = g.pattern == LegPattern::CrankRod ? Turn(d, g.axis, g.universal_axis, a.c, a.s)
                                                                     : Splat(d, g.universal_axis);
            const V3 k = Cross(first_axis, pointing);
            near = hn::Or(near, Dot(k, k) < hn::Set(d, 1e-12));
          }
          for (const LaneLeg::Cone& cone : g.cones) {
            const V3 rod = hn::Set(d, cone.along) * pointing;
            V3 socket = rod, link = Splat(d, cone.fixed);
            if (cone.at_ball) {
              socket = g.pattern == LegPattern::CrankRod ? Turn(d, g.axis, cone.fixed, a.c, a.s) : Splat(d, cone.fixed);
              link = rod;
            }
            const V3 k = Cross(socket, link);
            const V sine = hn::Sqrt(Dot(k, k)), cosine = Dot(socket, link);
            if (cone.size >= 0) Widen(widest_cone[cone.size], sine, cosine);
            else cones = hn::Min(cones, hn::Set(d, cone.half_angle_deg) - Atan2(d, sine, cosine) * hn::Set(d, kDeg));
          }
        }
        // The force along the rod through the end's centre, as closure rows
        // [(w - r) x f; f size] of unit norm; Jx's row and Jq's entry.
        const V3 moment = Cross(Splat(d, g.end_offset - g.anchor_offset), f);
        const V inv_N = one / hn::Sqrt(Dot(moment, moment) + hn::Set(d, size * size) * Dot(f, f));
        const V3 turning = Cross(Splat(d, g.end_offset), f);
        for (int j = 0; j < N; ++j) {
          const int c = dev.coordinate[std::size_t(j)];
          Jx[i][j] = (c < 3 ? Get(f, c) : Get(turning, c - 3)) * inv_N;
        }
        if (g.pattern == LegPattern::CrankRod || g.three)
          jq[i] = Dot(a.axis, Cross(legs[i].end - Splat(d, g.actuator_centre), f)) * inv_N;
        else
          jq[i] = Dot(a.axis, f) * inv_N;
        near = hn::Or(near, hn::Abs(jq[i]) < hn::Set(d, 1e-6));
        serial = hn::Min(serial, hn::Abs(jq[i]) * hn::Set(d, g.prismatic ? size * size : size));
        if (g.limited && g.prismatic) travel = hn::Min(travel, hn::Min(a.q - hn::Set(d, g.lo), hn::Set(d, g.hi) - a.q));
        else if (g.limited) travel_of(g, a);
      }
      near = hn::Or(near, CouplesNearRankLoss(d, couples, parallelograms));
      for (std::size_t k = 0; k < dev.cone_sizes.size(); ++k)
        cones = hn::Min(cones, hn::Set(d, dev.cone_sizes[k]) - Atan2(d, widest_cone[k].s, widest_cone[k].c) * hn::Set(d, kDeg));
      for (std::size_t k = 0; k < dev.travel_widths.size(); ++k)
        travel = hn::Min(travel, (hn::Set(d, dev.travel_widths[k]) - Atan2(d, widest_travel[k].s, widest_travel[k].c)) *
                                     hn::Set(d, size));
      // Near a stop: only the smallest margin decides (the status, the joint margin).
      if (dev.cones) near = hn::Or(near, hn::Abs(cones) < hn::Set(d, 1e-7));
      if (dev.cones) {
        joint_margin = hn::IfThenElse(assembled, cones, joint_margin);
        status = hn::IfThenElse(hn::And(assembled, cones < zero), StatusCode(d, Status::OutOfLimits), status);
      }
      if (!dev.capsules.empty()) {
        const V gap = Clearance<N>(d, dev, p, legs, near, closest_pair);
        clearance = hn::IfThenElse(assembled, gap, clearance);
        status = hn::IfThenElse(hn::And(assembled, gap < zero), StatusCode(d, Status::OutOfLimits), status);
      }
      V inv[N][N];
      const V norm = NormOne(d, Jx);
      Invert(d, Jx, inv);
      const V kappa = norm * NormOne(d, inv);
      near = hn::Or(near, hn::Not(kappa < hn::Set(d, 1e8)));
      V J[N][N];  // -Jx^-1 Jq
      for (int r = 0; r < N; ++r)
        for (int c = 0; c < N; ++c) J[r][c] = hn::Neg(inv[r][c] * jq[c]);
      const M ok = status == StatusCode(d, Status::Ok);
      if (!hn::AllFalse(d, ok)) {
        if constexpr (N == 2) {
          // sigma_1^2 = (|J|_F^2 + sqrt((|J|_F^2 - 2 det)(|J|_F^2 + 2 det))) / 2, c(J) = sigma_1^2 / |det|,
          // both factors as sums of squares (no cancellation).
          const V a = J[0][0], b2 = J[0][1], c2 = J[1][0], e = J[1][1];
          const V det = a * e - b2 * c2;
          const V minus = (a - e) * (a - e) + (b2 + c2) * (b2 + c2), plus = (a + e) * (a + e) + (b2 - c2) * (b2 - c2);
          const V largest = hn::Set(d, 0.5) * (hn::Set(d, 0.5) * (minus + plus) + hn::Sqrt(minus * plus));
          const V c = largest / hn::Abs(det);
          near = hn::Or(near, hn::And(ok, hn::Not(hn::And(hn::IsFinite(c), det != zero))));
          cond = hn::IfThenElse(ok, c, inf);
        } else if constexpr (N == 3) {
          V c0[3] = {J[0][0], J[1][0], J[2][0]}, c1[3] = {J[0][1], J[1][1], J[2][1]}, c2[3] = {J[0][2], J[1][2], J[2][2]};
          near = hn::Or(near, hn::And(ok, hn::Or(hn::Not(UnitRange(d, c0, c1, c2)), NearDoubleEigenvalue(d, c0, c1, c2))));
          cond = hn::IfThenElse(ok, ConditionNumber(d, c0, c1, c2), inf);
        } else {
          V rows[2][3][N];
          int counts[2] = {0, 0};
          for (int r = 0; r < N; ++r) {
            const int part = dev.coordinate[std::size_t(r)] < 3 ? 0 : 1;
            for (int c = 0; c < N; ++c) rows[part][counts[part]][c] = J[r][c];
            ++counts[part];
          }
          M scale = None(d);
          cond = hn::IfThenElse(ok, RowsCondition(d, rows[0], scale), inf);
          cond_orientation = hn::IfThenElse(ok, RowsCondition(d, rows[1], scale), inf);
          near = hn::Or(near, hn::And(ok, scale));
        }
      }
      to_scalar = hn::Or(to_scalar, hn::And(assembled, near));
      const V joints = dev.cones ? cones * hn::Set(d, M_PI / 180 * size) : inf;
      const V gaps = dev.capsules.empty() ? inf : clearance;
      margin = hn::IfThenElse(assembled, hn::Min(hn::Min(serial, travel), hn::Min(joints, gaps)), margin);
    }
    hn::Store(status, d, b.status + t);
    hn::Store(margin, d, b.reach_margin + t);
    hn::Store(hn::IfThenElse(assembled, zero, inf), d, b.residual + t);
    hn::Store(cond, d, b.cond + t);
    hn::Store(cond_orientation, d, b.cond_orientation + t);
    hn::Store(joint_margin, d, e.joint_margin + t);
    hn::Store(clearance, d, e.clearance + t);
    hn::Store(Flag(d, to_scalar), d, b.to_scalar + t);
  }
}

void SampleRowLanes(const LaneDevice& dev, const Grid& g, const detail::GridRow& row, const detail::FieldRowOut& out,
                    const LaneStopsOut& stops, std::uint8_t method, const LaneFallback& fallback, LaneValues* values,
                    const LaneMirror* mirror) {
  const MethodRule rule{double(method), false};
  Block b;
  Extras e;
  if (values)
    for (auto* v : {&values->cond, &values->cond_orientation, &values->reach_margin, &values->joint_margin, &values->clearance})
      v->assign(std::size_t(row.count), std::numeric_limits<double>::quiet_NaN());
  for (int first = 0; first < row.count; first += kBlock) {
    const int n = std::min(kBlock, row.count - first);
    if (dev.legs.size() == 2) Geometry<2>(dev, g, row, first, n, b, e);
    else if (dev.legs.size() == 3) Geometry<3>(dev, g, row, first, n, b, e);
    else Geometry<6>(dev, g, row, first, n, b, e);
    const auto store_stops = [&](const LaneStopsOut& into) {
      if (into.joint_margin)
        for (int t = 0; t < n; ++t) into.joint_margin[first + t] = float(e.joint_margin[t]);
      if (into.clearance)
        for (int t = 0; t < n; ++t) into.clearance[first + t] = float(e.clearance[t]);
    };
    store_stops(stops);
    if (values)
      for (int t = 0; t < n; ++t) {
        if (b.to_scalar[t] != 0.0) continue;
        const std::size_t i = std::size_t(first + t);
        values->cond[i] = b.cond[t];
        values->cond_orientation[i] = b.cond_orientation[t];
        values->reach_margin[i] = b.reach_margin[t];
        values->joint_margin[i] = e.joint_margin[t];
        values->clearance[i] = e.clearance[t];
      }
    const auto scalar = [&](const LaneFallback& path, const LaneStopsOut& into, int i) {
      double jm = 0, gap = 0;
      const FieldSample s = path(i, jm, gap);
      if (into.joint_margin) into.joint_margin[i] = float(jm);
      if (into.clearance) into.clearance[i] = float(gap);
      return s;
    };
    StoreBlock(b, first, n, row.count, false, rule, out, [&](int i) { return scalar(fallback, stops, i); });
    // The mirror row takes the lanes' values (the joint margins and the
    // clearance too: the partner legs' cones and links reflect); the lanes
    // the scalar path decides are decided at the mirror row's own points.
    if (mirror) {
      CopySamples(out, mirror->out, first, n);
      store_stops(mirror->stops);
      ForEachHandedOff(b, n, [&](int t) {
        mirror->out.store(first + t, scalar(mirror->fallback, mirror->stops, first + t));
      });
    }
  }
}

}  // namespace linkscape::described::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace linkscape::described {

HWY_EXPORT(SampleRowLanes);

void sample_row_lanes(const LaneDevice& device, const Grid& grid, const detail::GridRow& row,
                      const detail::FieldRowOut& out, const LaneStopsOut& stops, std::uint8_t method,
                      const LaneFallback& fallback, LaneValues* values, const LaneMirror* mirror) {
  HWY_DYNAMIC_DISPATCH(SampleRowLanes)(device, grid, row, out, stops, method, fallback, values, mirror);
}

}  // namespace linkscape::described
#endif  // HWY_ONCE
