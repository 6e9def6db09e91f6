// The per-leg geometry of the described devices' SIMD lanes (lanes.h):
// vectors per lane, a leg's candidate, the passive revolutes' stop margins,
// the crank-parallelogram's and three-revolute leg's closed forms and
// Jacobian rows, and the links' clearance. Included by lanes_simd.cpp after core/simd_field-inl.h; like
// every Highway "-inl.h" header it is compiled once per target (the include
// guard toggles with HWY_TARGET_TOGGLE).
#if defined(LINKSCAPE_DESCRIBED_LANES_LEGS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LINKSCAPE_DESCRIBED_LANES_LEGS_INL_H_
#undef LINKSCAPE_DESCRIBED_LANES_LEGS_INL_H_
#else
#define LINKSCAPE_DESCRIBED_LANES_LEGS_INL_H_
#endif

#include <hwy/highway.h>

#include <cmath>

#include "core/mechanisms/described/lanes.h"
#include "core/simd_field-inl.h"

HWY_BEFORE_NAMESPACE();
namespace linkscape::described::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using namespace linkscape::simd::HWY_NAMESPACE;  // D, V, M and the shared helpers

struct V3 {
  V x, y, z;
};
HWY_INLINE V3 Splat(D d, const Eigen::Vector3d& v) { return {hn::Set(d, v.x()), hn::Set(d, v.y()), hn::Set(d, v.z())}; }
HWY_INLINE V3 operator+(const V3& a, const V3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
HWY_INLINE V3 operator-(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
HWY_INLINE V3 operator*(V s, const V3& a) { return {s * a.x, s * a.y, s * a.z}; }
HWY_INLINE V Dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
HWY_INLINE V3 Cross(const V3& a, const V3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
HWY_INLINE V3 Select(M m, const V3& a, const V3& b) {
  return {hn::IfThenElse(m, a.x, b.x), hn::IfThenElse(m, a.y, b.y), hn::IfThenElse(m, a.z, b.z)};
}
HWY_INLINE V Get(const V3& a, int i) { return i == 0 ? a.x : i == 1 ? a.y : a.z; }
HWY_INLINE M None(D d) { return hn::FirstN(d, 0); }
// Fixed vector x turned about unit a by the angle of (c, s).
HWY_INLINE V3 Turn(D d, const Eigen::Vector3d& a, const Eigen::Vector3d& x, V c, V s) {
  const V3 along = hn::Set(d, a.dot(x)) * Splat(d, a);
  return hn::Set(d, 1.0) * along + c * (Splat(d, x) - along) + s * Splat(d, a.cross(x));
}
// The same of a vector per lane.
HWY_INLINE V3 Turn(D d, const Eigen::Vector3d& a, const V3& x, V c, V s) {
  const V3 axis = Splat(d, a), along = Dot(axis, x) * axis;
  return along + c * (x - along) + s * Cross(axis, x);
}
// Fixed matrix times a vector per lane.
HWY_INLINE V3 Times(D d, const Eigen::Matrix3d& m, const V3& x) {
  const auto row = [&](int i) {
    return hn::MulAdd(hn::Set(d, m(i, 0)), x.x, hn::MulAdd(hn::Set(d, m(i, 1)), x.y, hn::Set(d, m(i, 2)) * x.z));
  };
  return {row(0), row(1), row(2)};
}
HWY_INLINE V Clamp(V x, V lo, V hi) { return hn::Min(hi, hn::Max(lo, x)); }

// The widest of angles in [0, pi] given as (sin, cos) up to a common
// positive scale: arctangent is monotonic, so the margins of one size (the
// cones of one half angle, the travels of one half width) take one, of the
// widest.
struct Widest {
  V s, c;
};
HWY_INLINE void Widen(Widest& w, V s, V c) {
  const M wider = hn::MulSub(s, w.c, c * w.s) > hn::Zero(hn::DFromV<V>());
  w.s = hn::IfThenElse(wider, s, w.s);
  w.c = hn::IfThenElse(wider, c, w.c);
}

// A passive revolute's margin to its stop, degrees, from its angle's
// direction (c, s): Kinematics::stops' angle nearest the range's middle.
HWY_INLINE V StopMargin(D d, const LaneLeg::Stop& stop, V c, V s) {
  const V cm = hn::Set(d, stop.cos_mid), sm = hn::Set(d, stop.sin_mid);
  const V from_mid = Atan2(d, hn::MulSub(s, cm, c * sm), hn::MulAdd(c, cm, s * sm));
  const V angle = (hn::Set(d, stop.mid) + from_mid) * hn::Set(d, 180 / M_PI);
  return hn::Min(angle - hn::Set(d, stop.lo_deg), hn::Set(d, stop.hi_deg) - angle);
}

// The distance between segments [a0, a1] and [b0, b1] of nonzero length, as
// interference::closest_points takes it; `to_scalar` where they are nearly
// parallel (its s then rests on a vanishing denominator).
HWY_INLINE V SegmentDistance(D d, const V3& a0, const V3& a1, const V3& b0, const V3& b1, M& to_scalar) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const V3 d1 = a1 - a0, d2 = b1 - b0, r = a0 - b0;
  const V a = Dot(d1, d1), e = Dot(d2, d2), f = Dot(d2, r), c = Dot(d1, r), b = Dot(d1, d2);
  const V denom = a * e - b * b;
  to_scalar = hn::Or(to_scalar, denom <= hn::Set(d, 1e-12) * a * e);
  V s = hn::IfThenElse(denom > zero, Clamp((b * f - c * e) / denom, zero, one), zero);
  V t = (b * s + f) / e;
  const M below = t < zero, above = t > one;
  s = hn::IfThenElse(below, Clamp(hn::Neg(c) / a, zero, one), hn::IfThenElse(above, Clamp((b - c) / a, zero, one), s));
  t = Clamp(t, zero, one);
  const V3 gap = (a0 + s * d1) - (b0 + t * d2);
  return hn::Sqrt(Dot(gap, gap));
}

// One closed-form solution of a leg.
struct Candidate {
  V3 ball;     // the ball joint's centre
  V3 axis;     // the actuator's axis (an extensible leg's turns with the ball)
  V q;         // a slide's length
  V c, s;      // a crank's cos q, sin q
  V rc, rs;    // a limited crank's q - mid as a direction
  V sigma;     // an extensible leg's side: +-1
  // A parallelogram's: its joints' centres, cos, sin of the actuator's and
  // knee's turns together, and the passive joints' angles as directions
  // (cos, sin; indexed by LaneJoint).
  V3 knee, upper, lower;
  V cqk, sqk;
  V jc[kLaneJoints], js[kLaneJoints];
  M valid, match, inside;  // valid (a parallelogram's): the closed form gives this candidate
};

HWY_INLINE void Pick(M take, const Candidate& from, Candidate& to) {
  to.ball = Select(take, from.ball, to.ball);
  to.axis = Select(take, from.axis, to.axis);
  to.knee = Select(take, from.knee, to.knee);
  to.upper = Select(take, from.upper, to.upper);
  to.lower = Select(take, from.lower, to.lower);
  for (V Candidate::*v : {&Candidate::q, &Candidate::c, &Candidate::s, &Candidate::rc, &Candidate::rs, &Candidate::sigma,
                          &Candidate::cqk, &Candidate::sqk})
    to.*v = hn::IfThenElse(take, from.*v, to.*v);
  for (int j = 0; j < kLaneJoints; ++j) {
    to.jc[j] = hn::IfThenElse(take, from.jc[j], to.jc[j]);
    to.js[j] = hn::IfThenElse(take, from.js[j], to.js[j]);
  }
}

struct LegLanes {
  M unreachable, outside_travel, to_scalar;
  V residual;  // where unreachable
  Candidate at;
  V3 end, anchor;
};

// A crank-parallelogram's reach in closed form (closed_form.cpp's
// crank_parallelogram, in its actuator's frame): the end at height h along
// the motor axis and rho across it; `missed` and `miss` where the end is out
// of the leg's reach, `band` near the thresholds that decide it.
struct ParallelogramReach {
  V3 w, across;
  V h, rho;
};
HWY_NOINLINE ParallelogramReach ParallelogramMiss(D d, const LaneLeg& g, double size, const V3& end, M& missed, V& miss,
                                                M& band) {
  ParallelogramReach r;
  r.w = Times(d, g.frame.transpose(), end - Splat(d, g.actuator_centre));
  const V3 A = Splat(d, g.local_axis);
  const V along = Dot(A, r.w);
  r.h = along - hn::Set(d, g.height);
  r.across = r.w - along * A;
  r.rho = hn::Sqrt(Dot(r.across, r.across));
  const double r1 = g.thigh.norm();
  const V lo = hn::Abs(r.rho - hn::Set(d, r1)), hi = r.rho + hn::Set(d, r1), h2 = r.h * r.h;
  V best = hn::Inf(d);
  for (double centre : {g.bar, -g.bar}) {
    const V C = hn::Set(d, centre);
    const V near = Clamp(C, lo, hi) - C, far = hn::Max(hn::Abs(lo - C), hn::Abs(hi - C));
    const V nearest = hn::Sqrt(near * near + h2), farthest = hn::Sqrt(far * far + h2);
    best = hn::Min(best, hn::Max(nearest - hn::Set(d, g.side), hn::Set(d, g.side) - farthest));
  }
  missed = best > hn::Zero(d);
  miss = hn::Max(hn::Zero(d), best);
  band = hn::Or(hn::Abs(best) < hn::Set(d, 1e-9 * size), r.rho < hn::Set(d, 1e-9 * size));
  return r;
}

// Its four candidates in the scalar path's order (the upper joint's sign,
// then the elbow's), their joints' centres (base frame) and angles; `band`
// near the closed form's ties (a straight elbow or side, a vanishing reach).
HWY_NOINLINE void ParallelogramCandidates(D d, const LaneLeg& g, double size, const ParallelogramReach& r, Candidate (&c)[4],
                                        M& band) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const double r1 = g.thigh.norm();
  const V ch = Clamp(r.h / hn::Set(d, g.side), hn::Neg(one), one);
  const V sh = hn::Sqrt(hn::Max(zero, one - ch * ch));
  band = hn::Or(band, one - hn::Abs(ch) < hn::Set(d, 1e-6));
  const V cp = hn::Set(d, g.cos_phase), sp = hn::Set(d, g.sin_phase);
  const V ct = hn::Set(d, g.cos_thigh_phase), st = hn::Set(d, g.sin_thigh_phase);
  const V cl = hn::Set(d, g.cos_level), sl = hn::Set(d, g.sin_level);
  for (int u = 0; u < 2; ++u) {
    const V sign = hn::Set(d, u == 0 ? 1.0 : -1.0);
    const V x = hn::Set(d, g.bar) - hn::Set(d, g.side) * sign * sh;  // the parallelogram's reach along n
    const V ce = (r.rho * r.rho - hn::Set(d, r1 * r1) - x * x) / (hn::Set(d, 2 * r1) * x);
    band = hn::Or(band, hn::Or(hn::Abs(x) < hn::Set(d, 1e-9 * size), hn::Abs(hn::Abs(ce) - one) < hn::Set(d, 1e-6)));
    const M valid = hn::Abs(ce) <= hn::Set(d, 1 + 1e-9);
    const V cc = Clamp(ce, hn::Neg(one), one), se = hn::Sqrt(hn::Max(zero, one - cc * cc));
    const V cu = hn::MulSub(ch, cp, sign * sh * sp), su = hn::MulAdd(sign * sh, cp, ch * sp);
    for (int e = 0; e < 2; ++e) {
      Candidate& k = c[2 * u + e];
      const V s_elbow = e == 0 ? se : hn::Neg(se);
      const V ck = hn::MulAdd(cc, ct, s_elbow * st), sk = hn::MulSub(s_elbow, ct, cc * st);  // knee = elbow - thigh phase
      const V3 v = Splat(d, g.thigh) + x * Turn(d, g.local_axis, g.across, ck, sk);
      const V cq = Dot(v, r.across), sq = Dot(Splat(d, g.local_axis), Cross(v, r.across));
      const V inv = one / hn::Sqrt(cq * cq + sq * sq);
      k.c = cq * inv;
      k.s = sq * inv;
      k.cqk = hn::MulSub(k.c, ck, k.s * sk);
      k.sqk = hn::MulAdd(k.s, ck, k.c * sk);
      const V3 knee = Turn(d, g.local_axis, g.knee_rest, k.c, k.s);
      const V3 upper = knee + Turn(d, g.local_axis, g.to_upper, k.cqk, k.sqk);
      const V3 lower = upper + Turn(d, g.local_axis, Turn(d, g.upper_axis, g.side_link, cu, su), k.cqk, k.sqk);
      const V3 origin = Splat(d, g.actuator_centre);
      k.knee = origin + Times(d, g.frame, knee);
      k.upper = origin + Times(d, g.frame, upper);
      k.lower = origin + Times(d, g.frame, lower);
      k.ball = k.knee;
      k.axis = Splat(d, g.axis);
      k.q = zero;
      k.sigma = one;
      k.valid = valid;
      k.jc[int(LaneJoint::Ball)] = one;
      k.js[int(LaneJoint::Ball)] = zero;
      k.jc[int(LaneJoint::Knee)] = ck;
      k.js[int(LaneJoint::Knee)] = hn::Set(d, g.knee_sign) * sk;
      k.jc[int(LaneJoint::Upper)] = cu;
      k.js[int(LaneJoint::Upper)] = su;
      k.jc[int(LaneJoint::Lower)] = cu;
      k.js[int(LaneJoint::Lower)] = hn::Set(d, -g.lower_sign) * su;
      // grip = grip_sign (level - q - knee)
      k.jc[int(LaneJoint::Grip)] = hn::MulAdd(cl, k.cqk, sl * k.sqk);
      k.js[int(LaneJoint::Grip)] = hn::Set(d, g.grip_sign) * hn::MulSub(sl, k.cqk, cl * k.sqk);
    }
  }
}

// The angle turning p about unit a onto q (their parts across a) as a
// direction (cos, sin); `band` where either part nearly vanishes (relative
// to `scale2`, |p| |q|), the angle ill-defined.
HWY_INLINE void TurnDirection(D d, const Eigen::Vector3d& a, const V3& p, const V3& q, V scale2, V& c, V& s, M& band) {
  const V3 axis = Splat(d, a), pp = p - Dot(axis, p) * axis, qq = q - Dot(axis, q) * axis;
  const V x = Dot(pp, qq), y = Dot(axis, Cross(pp, qq)), n2 = x * x + y * y;
  band = hn::Or(band, n2 < hn::Set(d, 1e-12) * scale2 * scale2);
  const V inv = hn::Set(d, 1.0) / hn::Sqrt(n2);
  c = x * inv;
  s = y * inv;
}

// A three-revolute leg's reach (closed_form.cpp's three_revolute): the end's
// centre w from the second joint, in the actuator's frame (gl), its distance
// n; `missed` and `miss` where n is beyond [nearest, farthest], `band` near
// either or n near zero.
struct ThreeRevoluteReach {
  V3 gl;
  V n2, n;
};
HWY_NOINLINE ThreeRevoluteReach ThreeRevoluteMiss(D d, const LaneLeg& g, double size, const V3& w, M& missed, V& miss,
                                                M& band) {
  ThreeRevoluteReach r;
  const V tiny = hn::Set(d, 1e-9 * size);
  r.gl = Times(d, g.frame.transpose(), w - Splat(d, g.origin));
  r.n2 = Dot(r.gl, r.gl);
  r.n = hn::Sqrt(r.n2);
  const V nearest = hn::Set(d, g.nearest), farthest = hn::Set(d, g.farthest);
  missed = hn::Or(r.n < nearest, r.n > farthest);
  miss = hn::Max(nearest - r.n, r.n - farthest);
  band = hn::Or(hn::Or(hn::Abs(r.n - nearest) < tiny, hn::Abs(r.n - farthest) < tiny), r.n < tiny);
  return r;
}

// Its candidates in the scalar path's order: the third angle's two
// solutions (phi + half, phi - half), each with the two of Paden-Kahan's
// subproblem 2 for the actuator and second angle (+-sqrt(g2)); `band` near a
// third angle's double root, g2's zero (where the scalar path's count of
// candidates changes), or an angle ill-defined.
HWY_NOINLINE void ThreeRevoluteCandidates(D d, const LaneLeg& g, const ThreeRevoluteReach& r, const V3& w, Candidate (&c)[4],
                                        M& band) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0);
  const V3& gl = r.gl;
  const V n = r.n;
  const double R = std::hypot(g.harmonic_b, g.harmonic_c);
  const V cr = Clamp((hn::Set(d, 0.5) * r.n2 - hn::Set(d, g.harmonic_k0)) * hn::Set(d, 1 / R), hn::Neg(one), one);
  band = hn::Or(band, one - hn::Abs(cr) < hn::Set(d, 1e-9));
  const V sr = hn::Sqrt(hn::Max(zero, (one - cr) * (one + cr)));
  const V cphi = hn::Set(d, g.harmonic_b / R), sphi = hn::Set(d, g.harmonic_c / R);
  const Eigen::Vector3d &a1 = g.local_axis, &a2 = g.second_axis;
  const double c12 = a1.dot(a2), s12 = 1 - c12 * c12;
  const Eigen::Vector3d normal = a1.cross(a2);
  for (int k = 0; k < 2; ++k) {
    const V sign = hn::Set(d, k == 0 ? 1.0 : -1.0);
    const V c3 = cphi * cr - sign * sphi * sr, s3 = sphi * cr + sign * cphi * sr;
    const V3 p = Splat(d, g.second_link) + Turn(d, g.third_axis, g.third_link, c3, s3);
    const V p2 = Dot(p, p);
    const V3 q = (hn::Sqrt(p2) / n) * gl;
    // Paden-Kahan 2: z = alpha a1 + beta a2 +- sqrt(g2) a1 x a2.
    const V a2p = Dot(Splat(d, a2), p), a1q = Dot(Splat(d, a1), q);
    const V alpha = (hn::Set(d, c12) * a2p - a1q) * hn::Set(d, -1 / s12);
    const V beta = (hn::Set(d, c12) * a1q - a2p) * hn::Set(d, -1 / s12);
    const V g2 = (p2 - alpha * alpha - beta * beta - hn::Set(d, 2 * c12) * alpha * beta) * hn::Set(d, 1 / s12);
    band = hn::Or(band, hn::Abs(g2) < hn::Set(d, 1e-9) * p2);
    const V root = hn::Sqrt(hn::Max(zero, g2));
    for (int e = 0; e < 2; ++e) {
      Candidate& x = c[2 * k + e];
      const V3 z = alpha * Splat(d, a1) + beta * Splat(d, a2) + (e == 0 ? root : hn::Neg(root)) * Splat(d, normal);
      TurnDirection(d, a1, z, q, p2, x.c, x.s, band);
      TurnDirection(d, a2, p, z, p2, x.jc[int(LaneJoint::Second)], x.js[int(LaneJoint::Second)], band);
      x.jc[int(LaneJoint::Third)] = c3;
      x.js[int(LaneJoint::Third)] = s3;
      x.valid = g2 > zero;
      x.axis = Splat(d, g.axis);
      x.ball = w;
      x.q = zero;
      x.sigma = one;
    }
  }
}

// A three-revolute leg's force (Kinematics::jacobian's closed wrench):
// square to the velocities its second and third joints give the end's centre
// w, u2 x u3, in the base frame; `near` within 1e-6 of the scalar path's
// test of its passive joints losing a freedom.
HWY_NOINLINE V3 ThreeRevoluteForce(D d, const LaneLeg& g, const Candidate& a, const V3& w, M& near) {
  const V3 gl = Times(d, g.frame.transpose(), w - Splat(d, g.origin));  // w from the second joint
  const V c2 = a.jc[int(LaneJoint::Second)], s2 = a.js[int(LaneJoint::Second)];
  const V3 second = Turn(d, g.local_axis, g.second_axis, a.c, a.s);
  const V3 third = Turn(d, g.local_axis, Turn(d, g.second_axis, g.third_axis, c2, s2), a.c, a.s);
  const V3 link = Turn(d, g.local_axis, Turn(d, g.second_axis, g.second_link, c2, s2), a.c, a.s);
  const V3 u2 = Cross(second, gl), u3 = Cross(third, gl - link), f = Cross(u2, u3);
  near = hn::Or(near, Dot(f, f) < hn::Set(d, 1e-12) * Dot(u2, u2) * Dot(u3, u3));
  return Times(d, g.frame, f);
}

// A parallelogram leg's Jacobian row as Kinematics::jacobian builds it for a
// leg holding more than one wrench: the actuator's twist about the end, less
// its part in the span of the four passive twists (modified Gram-Schmidt),
// normalised; jq its length. `near` where the passive twists are within 1e-6
// of losing their rank (the product of Gram-Schmidt's pivots bounds
// sigma_min / sigma_max from below by it over |T|_F^4; the scalar path calls
// the leg singular below 1e-10).
// `couple`: the constraint couple the leg holds the platform by, square to
// its knee's and upper bar's axes.
template <int N>
HWY_NOINLINE void ParallelogramRow(D d, const LaneLeg& g, const std::vector<int>& coordinate, double size,
                                 const LegLanes& leg, V (&row)[N], V& jq, M& near, V3& couple) {
  const Candidate& a = leg.at;
  const V inv_size = hn::Set(d, 1 / size), zero = hn::Zero(d);
  const V3 axis = Splat(d, g.axis), upper = Turn(d, g.axis, Eigen::Vector3d(g.frame * g.upper_axis), a.cqk, a.sqk);
  couple = Cross(axis, upper);
  const auto twist = [&](const V3& w, const V3& centre, V (&t)[6]) {
    const V3 v = inv_size * Cross(w, leg.anchor - centre);
    t[0] = w.x, t[1] = w.y, t[2] = w.z, t[3] = v.x, t[4] = v.y, t[5] = v.z;
  };
  const auto dot = [](const V (&x)[6], const V (&y)[6]) {
    V sum = x[0] * y[0];
    for (int k = 1; k < 6; ++k) sum = hn::MulAdd(x[k], y[k], sum);
    return sum;
  };
  V t[4][6], actuator[6];
  twist(axis, a.knee, t[0]);
  twist(upper, a.upper, t[1]);
  twist(upper, a.lower, t[2]);
  twist(axis, leg.end, t[3]);
  twist(axis, Splat(d, g.actuator_centre), actuator);
  V frobenius2 = zero, pivots = hn::Set(d, 1.0);
  for (auto& x : t) frobenius2 = frobenius2 + dot(x, x);
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < i; ++j) {
      const V along = dot(t[i], t[j]);
      for (int k = 0; k < 6; ++k) t[i][k] = hn::NegMulAdd(along, t[j][k], t[i][k]);
    }
    const V n = hn::Sqrt(dot(t[i], t[i])), inv = hn::Set(d, 1.0) / n;
    pivots = pivots * n;
    for (int k = 0; k < 6; ++k) t[i][k] = t[i][k] * inv;
  }
  near = hn::Or(near, pivots < hn::Set(d, 1e-6) * frobenius2 * frobenius2);
  for (auto& x : t) {
    const V along = dot(actuator, x);
    for (int k = 0; k < 6; ++k) actuator[k] = hn::NegMulAdd(along, x[k], actuator[k]);
  }
  jq = hn::Sqrt(dot(actuator, actuator));
  const V scale = inv_size / jq;
  for (int j = 0; j < N; ++j) row[j] = actuator[3 + coordinate[std::size_t(j)]] * scale;
}

// A constraint singularity (Kinematics::jacobian's rank of the legs'
// constraint wrenches, here the parallelograms' couples): `near` where the
// `count` couples come within 1e-6 of losing their rank (the scalar path's
// test at 1e-10 lies within), so that the scalar path decides.
HWY_INLINE M CouplesNearRankLoss(D d, const V3* c, int count) {
  const V eps2 = hn::Set(d, 1e-12);
  if (count == 1) return Dot(c[0], c[0]) < eps2;
  if (count == 2) {
    const V3 k = Cross(c[0], c[1]);
    return Dot(k, k) < eps2 * Dot(c[0], c[0]) * Dot(c[1], c[1]);
  }
  if (count == 3) {
    const V det = Dot(c[0], Cross(c[1], c[2]));
    return det * det < eps2 * Dot(c[0], c[0]) * Dot(c[1], c[1]) * Dot(c[2], c[2]);
  }
  return None(d);
}

// The smallest gap between the capsules of the pairs the scalar path checks,
// at the chosen candidates; `near` where it is within 1e-9 of the size of
// zero (which pair sets it does not change it). Each capsule is placed once;
// a pair whose bounding spheres lie no nearer than the smallest gap so far,
// in every lane, is passed over, the pair that set it last time (`first`)
// taken first.
template <int N>
HWY_NOINLINE V Clearance(D d, const LaneDevice& dev, const V3& p, const LegLanes (&legs)[N], M& near, std::size_t& first) {
  V3 ends[kMaxLaneCapsules][2];
  for (std::size_t c = 0; c < dev.capsules.size(); ++c) {
    const LaneCapsule& k = dev.capsules[c];
    const LaneLeg& g = dev.legs[std::size_t(k.leg)];
    const Candidate& a = legs[k.leg].at;
    const Eigen::Vector3d* points[2] = {&k.a, &k.b};
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d& x = *points[i];
      V3& e = ends[c][i];
      switch (k.body) {
        case LaneBody::Fixed: e = Splat(d, x); break;
        case LaneBody::Platform: e = p + Splat(d, x); break;
        case LaneBody::Crank: e = Splat(d, g.actuator_centre) + Turn(d, g.axis, x, a.c, a.s); break;
        case LaneBody::Knee: e = a.knee + Turn(d, g.axis, x, a.cqk, a.sqk); break;
        case LaneBody::Ankle: e = a.lower + Turn(d, g.axis, x, a.cqk, a.sqk); break;
        case LaneBody::Shin: {
          const Eigen::Vector3d upper = g.frame * g.upper_axis;
          e = a.upper + Turn(d, g.axis, Turn(d, upper, x, a.jc[int(LaneJoint::Upper)], a.js[int(LaneJoint::Upper)]), a.cqk, a.sqk);
          break;
        }
      }
    }
  }
  V smallest = hn::Inf(d);
  const std::size_t pairs = dev.pairs.size();
  std::size_t setter = first;
  for (std::size_t step = 0; step < pairs; ++step) {
    const std::size_t i = (first + step) % pairs;
    const std::size_t c0 = std::size_t(dev.pairs[i][0]), c1 = std::size_t(dev.pairs[i][1]);
    const LaneCapsule &k0 = dev.capsules[c0], &k1 = dev.capsules[c1];
    const V3 between = hn::Set(d, 0.5) * ((ends[c0][0] + ends[c0][1]) - (ends[c1][0] + ends[c1][1]));
    const V bound = hn::Sqrt(Dot(between, between)) - hn::Set(d, k0.reach + k1.reach);
    if (hn::AllTrue(d, bound >= smallest)) continue;
    const V gap = SegmentDistance(d, ends[c0][0], ends[c0][1], ends[c1][0], ends[c1][1], near) -
                  hn::Set(d, k0.radius + k1.radius);
    if (!hn::AllFalse(d, gap < smallest)) setter = i;
    smallest = hn::Min(smallest, gap);
  }
  first = setter;
  near = hn::Or(near, hn::Abs(smallest) < hn::Set(d, 1e-9 * dev.size));
  return smallest;
}

}  // namespace linkscape::described::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // LINKSCAPE_DESCRIBED_LANES_LEGS_INL_H_
