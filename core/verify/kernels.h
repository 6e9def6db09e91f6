// The inverse kinematics and Jacobian of the certifiable devices, written
// once for every number type: double and long double (points), Interval
// (a point's enclosure) and Dual (a box's enclosure with its gradient).
// Only +, -, *, / and sqrt appear, each correctly rounded, so an interval
// evaluation encloses the exact value at every point of its box.
//
// The 12R: the planar closed form of the device's field kernel
// (core/mechanisms/parallel12r/field.cpp). The Delta: each leg's elbow as
// the intersection of two circles in the leg's plane. Both give a matrix
// whose condition number is c(J): the 12R J = dD/dq itself, the Delta
// J^-1 = dq/dp (c(J^-1) = c(J)), which stays bounded at type II singularities.
#pragma once

#include <array>
#include <cmath>

#include "core/verify/interval.h"

namespace linkscape::verify {

template <typename T>
using Matrix3 = std::array<std::array<T, 3>, 3>;

// Why a kernel gives no matrix for a point (or for some point of a box).
enum class KernelFailure {
  None,
  Unreachable,  // out of reach (or, for a box, possibly out of reach)
  Singular,     // on (or, for a box, possibly on) a set where J is undefined
};

template <typename T>
struct KernelResult {
  KernelFailure failure = KernelFailure::None;
  Matrix3<T> M{};                  // J (12R) or J^-1 (Delta), when failure is None
  std::array<T, 3> cos_q{}, sin_q{};  // the actuator angles, for range checks
};

// ---- The 12R --------------------------------------------------------------------
// Endpoint (x, y, z) in the model's length unit; branch 0 or 1 as the device's.
template <typename T>
KernelResult<T> kernel_12r(double L1_, double L2_, int branch, const T& x, const T& y, const T& z) {
  using std::sqrt;
  KernelResult<T> out;
  const T L1(L1_), L2(L2_);
  // The actuator plane y = 0 is singular (cos alpha = 0); a box must lie on one side.
  const bool y_positive = certainly_positive(y);
  if (!y_positive && !certainly_negative(y)) {
    out.failure = KernelFailure::Singular;
    return out;
  }
  const T sign_y(y_positive ? 1.0 : -1.0);
  const T abs_y = sign_y * y;
  const T rho2 = sqr(x) + sqr(y), R2 = rho2 + sqr(z);
  const T rho = sqrt(rho2), R = sqrt(R2);
  // Reach: inside the outer sphere L1 + L2 and outside the inner |L1 - L2|.
  const T outer = (L1 + L2) - R;
  const T f2 = R + (L2 - L1), f3 = R + (L1 - L2);
  if (!certainly_positive(outer) || !certainly_positive(f2) || !certainly_positive(f3)) {
    const bool out_of_reach = certainly_negative(outer) || certainly_negative(f2) || certainly_negative(f3);
    out.failure = out_of_reach ? KernelFailure::Unreachable : KernelFailure::Singular;
    return out;
  }
  const T ca = abs_y / rho, sa = -(x * sign_y) / rho, r = sign_y * rho;
  const T a = (R2 + (sqr(L1) - sqr(L2))) / (T(2.0) * R);
  const T h = sqrt(outer * f2 * f3 * ((R + L1) + L2)) / (T(2.0) * R);
  const T ur = r / R, uz = z / R, s(branch == 0 ? 1.0 : -1.0);
  const T l1r = a * ur - s * h * uz, l1z = a * uz + s * h * ur;
  const T l2r = r - l1r, l2z = z - l1z;
  const T n1 = sqr(ca) * sqr(l1r) + sqr(l1z), n2 = sqr(ca) * sqr(l2r) + sqr(l2z);
  const T k1 = T(1.0) / (ca * sqr(L1)), k2 = T(1.0) / (ca * sqr(L2));
  // The field kernel's J (its header derives it from Eqs. 11-13).
  out.M[0][0] = k1 * (-(n1 * l1r)) + k2 * (-(n2 * l2r));
  out.M[1][0] = k1 * (-(sa * ca * l1r * sqr(l1r))) + k2 * (-(sa * ca * l2r * sqr(l2r)));
  out.M[2][0] = k1 * (-(sa * l1z * sqr(l1r))) + k2 * (-(sa * l2z * sqr(l2r)));
  out.M[0][1] = k1 * n1 * (sa * l1z);
  out.M[1][1] = k1 * n1 * (-(ca * l1z));
  out.M[2][1] = k1 * n1 * l1r;
  out.M[0][2] = k2 * n2 * (sa * l2z);
  out.M[1][2] = k2 * n2 * (-(ca * l2z));
  out.M[2][2] = k2 * n2 * l2r;
  // alpha = atan2(sa, ca); beta, gamma = atan2(l_iz, ca l_ir) (not normalised).
  out.cos_q = {ca, ca * l1r, ca * l2r};
  out.sin_q = {sa, l1z, l2z};
  return out;
}

// ---- The Delta --------------------------------------------------------------------
struct DeltaGeometry {
  double R = 0, r = 0, La = 0, Lb = 0;
  int branch = 0;  // bit i set: leg i elbow in
};

// Leg i's radial unit e_i = (cos phi_i, sin phi_i, 0) at phi_i = 0, 120, 240 deg, exactly.
template <typename T>
void delta_leg_direction(int leg, T& c, T& s) {
  using std::sqrt;
  if (leg == 0) {
    c = T(1.0), s = T(0.0);
    return;
  }
  const T half_root3 = sqrt(T(3.0)) / T(2.0);
  c = T(-0.5);
  s = leg == 1 ? half_root3 : -half_root3;
}

// Platform centre (x, y, z), in the model's length unit.
template <typename T>
KernelResult<T> kernel_delta(const DeltaGeometry& g, const T& x, const T& y, const T& z) {
  using std::sqrt;
  KernelResult<T> out;
  const T La(g.La), Lb(g.Lb), offset = T(g.R) - T(g.r);
  for (int i = 0; i < 3; ++i) {
    T c, s;
    delta_leg_direction(i, c, s);
    // The platform joint seen from the motor, in the leg's frame (e_i, t_i, z).
    const T px = x - offset * c, py = y - offset * s;
    const T u = c * px + s * py, v = c * py - s * px, w = z;
    // In the leg's plane the elbow E is on the circle of radius La about the
    // motor and on the circle of radius sqrt(Lb^2 - v^2) about (u, w).
    const T rb2 = (Lb - v) * (Lb + v), D2 = sqr(u) + sqr(w);
    if (!certainly_positive(rb2) || !certainly_positive(D2)) {
      out.failure = certainly_negative(rb2) ? KernelFailure::Unreachable : KernelFailure::Singular;
      return out;
    }
    const T D = sqrt(D2);
    const T a = (sqr(La) - rb2 + D2) / (T(2.0) * D);
    const T h2 = (La - a) * (La + a);
    if (!certainly_positive(h2)) {
      out.failure = certainly_negative(h2) ? KernelFailure::Unreachable : KernelFailure::Singular;
      return out;
    }
    const T h = sqrt(h2);
    // Elbow out (sigma = +1) puts dF_i/dq_i = -sigma h D < 0, as the device defines it.
    const T sigma((g.branch >> i) & 1 ? -1.0 : 1.0);
    const T Ee = (a * u - sigma * h * w) / D, Ez = (a * w + sigma * h * u) / D;
    // J^-1 row i = -s_i / (dF_i/dq_i) = sigma s_i / (h D), s_i = C_i - B_i.
    const T scale = sigma / (h * D);
    const T se = u - Ee, sz = w - Ez;
    out.M[i][0] = scale * (se * c - v * s);
    out.M[i][1] = scale * (se * s + v * c);
    out.M[i][2] = scale * sz;
    // Elbow B_i = A_i + La (cos q e_i - sin q z): (cos q, sin q) ~ (Ee, -Ez).
    out.cos_q[i] = Ee;
    out.sin_q[i] = -Ez;
  }
  return out;
}

}  // namespace linkscape::verify
