#include "core/mechanisms/pathos2/methods.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace linkscape::pathos2_methods {
namespace {


using Eigen::Matrix3d;
using Eigen::Vector3d;
using LD = long double;
using V3L = Eigen::Matrix<LD, 3, 1>;
using M3L = Eigen::Matrix<LD, 3, 3>;
constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

template <class T>
T wrap(T a) {
  const T two_pi = T(2) * std::numbers::pi_v<T>;
  a = std::remainder(a, two_pi);
  return a <= -std::numbers::pi_v<T> ? a + two_pi : a;
}

// Eq. 3 and its derivative in T: a = Rz(t1)(s2 w, -l3 s3, l1 + c2 w), w = l2 + l3 c3.
template <class T>
void leg_chain(T l1, T l2, T l3, const Eigen::Matrix<T, 3, 1>& t, Eigen::Matrix<T, 3, 1>& a,
               Eigen::Matrix<T, 3, 3>* J) {
  using std::cos;
  using std::sin;
  const T c1 = cos(t(0)), s1 = sin(t(0)), c2 = cos(t(1)), s2 = sin(t(1)), c3 = cos(t(2)), s3 = sin(t(2));
  const T w = l2 + l3 * c3;
  const T bx = s2 * w, by = -l3 * s3, bz = l1 + c2 * w;
  a = Eigen::Matrix<T, 3, 1>(c1 * bx - s1 * by, s1 * bx + c1 * by, bz);
  if (!J) return;
  // d/dt2 of b = (c2 w, 0, -s2 w); d/dt3 = (-s2 l3 s3, -l3 c3, -c2 l3 s3).
  const T d2x = c2 * w, d2z = -s2 * w;
  const T d3x = -s2 * l3 * s3, d3y = -l3 * c3, d3z = -c2 * l3 * s3;
  *J << -s1 * bx - c1 * by, c1 * d2x, c1 * d3x - s1 * d3y,  //
      c1 * bx - s1 * by, s1 * d2x, s1 * d3x + c1 * d3y,     //
      T(0), d2z, d3z;
}

// (t1 + pi, -t2, -t3) places the links identically; keep c1x = s2 w >= 0.
template <class T>
void normalise(T l2, T l3, Eigen::Matrix<T, 3, 1>& t) {
  using std::cos;
  using std::sin;
  if (sin(t(1)) * (l2 + l3 * cos(t(2))) < T(0)) t = Eigen::Matrix<T, 3, 1>(t(0) + std::numbers::pi_v<T>, -t(1), -t(2));
  for (int k = 0; k < 3; ++k) t(k) = wrap(t(k));
}

// t1 of the closed form in T (the ActiveOnly path of pathos2::inverse).
template <class T>
bool leg_t1(T l1, T l2, T l3, const Eigen::Matrix<T, 3, 1>& a, int branch, T& t1) {
  using std::sqrt;
  const T dz = a.z() - l1;
  const T rxy2 = a.x() * a.x() + a.y() * a.y();
  const T c2z = (l2 * l2 - l3 * l3 + rxy2 + dz * dz) / (T(2) * l2);
  const T e = c2z - l2;
  const T y2 = l3 * l3 - e * e;
  if (y2 < T(0) || rxy2 <= T(0)) return false;
  const T c1y = (branch >= 0 ? T(1) : T(-1)) * sqrt(y2);
  const T x2 = rxy2 - y2;
  if (x2 < T(0)) return false;
  const T c1x = sqrt(x2);
  t1 = std::atan2((c1x * a.y() - c1y * a.x()) / rxy2, (c1x * a.x() + c1y * a.y()) / rxy2);
  return true;
}

template <class T>
Eigen::Matrix<T, 3, 3> rodrigues(const Eigen::Matrix<T, 3, 1>& w) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  const T angle = sqrt(w.squaredNorm());
  Eigen::Matrix<T, 3, 3> R = Eigen::Matrix<T, 3, 3>::Identity();
  if (angle == T(0)) return R;
  const Eigen::Matrix<T, 3, 1> k = w / angle;
  Eigen::Matrix<T, 3, 3> K;
  K << T(0), -k.z(), k.y(), k.z(), T(0), -k.x(), -k.y(), k.x(), T(0);
  return R + sin(angle) * K + (T(1) - cos(angle)) * K * K;
}

// Globular centre of leg i at a pose, in T (leg frame and world).
template <class T>
Eigen::Matrix<T, 3, 1> leg_target(const Geometry& g, int i, const Eigen::Matrix<T, 3, 1>& p,
                                  const Eigen::Matrix<T, 3, 3>& R, T h0, Eigen::Matrix<T, 3, 1>* world = nullptr) {
  Eigen::Matrix<T, 3, 1> r_E = g.p_E_attach_plate[i].cast<T>();
  r_E.z() += T(g.grip_side[i]) * h0;
  const Eigen::Matrix<T, 3, 1> pg = p + R * r_E;
  if (world) *world = pg;
  return g.R_world_B[i].cast<T>().transpose() * (pg - g.p_world_B[i].cast<T>());
}

template <class T>
Eigen::Matrix<T, 3, 3> frame_from(const Eigen::Matrix<T, 3, 1>& n, const Eigen::Matrix<T, 3, 1>& u) {
  const Eigen::Matrix<T, 3, 1> z = n.normalized();
  const Eigen::Matrix<T, 3, 1> x = (u - u.dot(z) * z).normalized();
  Eigen::Matrix<T, 3, 3> F;
  F.col(0) = x;
  F.col(1) = z.cross(x);
  F.col(2) = z;
  return F;
}


}  // namespace

// ---- Leg IK --------------------------------------------------------------------------

Matrix3d leg_jacobian(double l1, double l2, double l3, const Vector3d& t) {
  Vector3d a;
  Matrix3d J;
  leg_chain<double>(l1, l2, l3, t, a, &J);
  return J;
}

LegNewtonResult leg_inverse_newton(double l1, double l2, double l3, const Vector3d& a, int branch, const Vector3d& seed,
                                   const LegNewtonOptions& o) {
  if (!a.allFinite() || !seed.allFinite()) throw std::invalid_argument("leg_inverse_newton: target and seed must be finite");
  LegNewtonResult out;
  out.t = seed;
  const double tol = o.tolerance * (l1 + l2 + l3);
  Vector3d p;
  Matrix3d J;
  leg_chain<double>(l1, l2, l3, out.t, p, &J);
  Vector3d e = a - p;
  double res = e.norm();
  int it = 0;
  bool singular = false;
  for (; it < o.max_iterations && res > tol; ++it) {
    const Eigen::PartialPivLU<Matrix3d> lu(J);
    const Vector3d step = lu.solve(e);
    if (!step.allFinite() || !(std::abs(lu.determinant()) > 1e-14 * std::pow(l2 + l3, 3))) {
      singular = true;
      break;
    }
    double s = 1.0;
    bool improved = false;
    for (int h = 0; h < 30; ++h, s *= 0.5) {
      const Vector3d trial = out.t + s * step;
      Vector3d pt;
      leg_chain<double>(l1, l2, l3, trial, pt, nullptr);
      const double r = (a - pt).norm();
      if (r < res) {
        out.t = trial;
        res = r;
        improved = true;
        break;
      }
    }
    if (!improved) break;
    leg_chain<double>(l1, l2, l3, out.t, p, &J);
    e = a - p;
    res = e.norm();
  }
  normalise<double>(l2, l3, out.t);
  out.iterations = it;
  out.residual = res;
  const bool right_branch = (branch >= 0) == (-std::sin(out.t(2)) >= 0);
  if (res <= tol && right_branch) {
    // Like leg_inverse: Ok unless sin t2 or sin t3 vanishes to the closed form's tolerance.
    const double c1x = std::sin(out.t(1)) * (l2 + l3 * std::cos(out.t(2))), c1y = -l3 * std::sin(out.t(2));
    out.status = std::abs(c1x * c1y) <= 1e-10 * (l2 + l3) * (l2 + l3) ? Status::Singular : Status::Ok;
  } else {
    out.status = singular ? Status::Singular : Status::NotConverged;
  }
  return out;
}

LegReference reference_leg_inverse(double l1, double l2, double l3, const Vector3d& a, const Vector3d& seed) {
  if (!a.allFinite() || !seed.allFinite()) throw std::invalid_argument("reference_leg_inverse: non-finite input");
  const LD L1 = l1, L2 = l2, L3 = l3;
  const V3L target = a.cast<LD>();
  V3L t = seed.cast<LD>(), p;
  M3L J;
  leg_chain<LD>(L1, L2, L3, t, p, &J);
  V3L e = target - p;
  LD res = e.norm();
  const LD u = std::numeric_limits<LD>::epsilon() / 2;
  LegReference out;
  // The residual cannot fall below the rounding of the angles times |J| and
  // of the target; stop a little above it rather than backtrack in vain.
  auto floor_of = [&](const M3L& JJ) { return u * (L1 + L2 + L3 + LD(kPi) * JJ.norm()); };
  int it = 0;
  for (; it < 100 && res > LD(8) * floor_of(J); ++it) {
    const V3L step = J.partialPivLu().solve(e);
    if (!step.allFinite()) break;
    LD s = 1;
    bool improved = false;
    for (int h = 0; h < 60; ++h, s /= 2) {
      const V3L trial = t + s * step;
      V3L pt;
      leg_chain<LD>(L1, L2, L3, trial, pt, nullptr);
      const LD r = (target - pt).norm();
      if (r < res) {
        t = trial;
        res = r;
        improved = true;
        break;
      }
    }
    if (!improved) break;
    leg_chain<LD>(L1, L2, L3, t, p, &J);
    e = target - p;
    res = e.norm();
  }
  normalise<LD>(L2, L3, t);
  out.iterations = it;
  out.residual = res;
  out.converged = res <= LD(1000) * floor_of(J);
  for (int k = 0; k < 3; ++k) out.t[k] = t(k);
  return out;
}

double leg_joint_error(const Vector3d& t, const LegReference& r) {
  LD best = std::numeric_limits<LD>::infinity();
  for (int flip = 0; flip < 2; ++flip) {
    const LD q[3] = {LD(t(0)) + (flip ? std::numbers::pi_v<LD> : 0), flip ? -LD(t(1)) : LD(t(1)),
                     flip ? -LD(t(2)) : LD(t(2))};
    LD e = 0;
    for (int k = 0; k < 3; ++k) e = std::max(e, std::abs(wrap<LD>(q[k] - r.t[k])));
    best = std::min(best, e);
  }
  return double(best);
}

// ---- FK references ----------------------------------------------------------------------

PoseReference reference_nine_sensors(const Geometry& g, const pathos2::NineSensors& sensors) {
  const pathos2::Model& m = g.model;
  PoseReference out;
  auto globular = [&](int leg, const Vector3d& q) {
    V3L a;
    leg_chain<LD>(m.l1, m.l2, m.l3, q.cast<LD>(), a, nullptr);
    return V3L(g.p_world_B[leg].cast<LD>() + g.R_world_B[leg].cast<LD>() * a);
  };
  const V3L P3 = globular(0, sensors.leg1), P2 = globular(4, sensors.leg5), P1 = globular(5, sensors.leg6);
  const V3L in4 = g.p_E_attach_plate[3].cast<LD>(), in1 = g.p_E_attach_plate[0].cast<LD>(),
            in6 = g.p_E_attach_plate[5].cast<LD>(), in5 = g.p_E_attach_plate[4].cast<LD>();
  const LD side2 = (in4 - in6).squaredNorm();
  const LD chord_13 = (in1 - in6).head<2>().squaredNorm();
  const LD chord_34 = (in1 - in4).head<2>().squaredNorm();
  const LD h2 = (P1 - P3).squaredNorm() - chord_13;
  if (!(h2 > 0)) return out;
  const LD h = std::sqrt(h2);
  const LD r3_2 = h2 + chord_34;
  const V3L n1 = LD(2) * (P2 - P1), n2 = LD(2) * (P3 - P2);
  const LD b1 = P2.squaredNorm() - P1.squaredNorm();
  const LD b2 = side2 - r3_2 + P3.squaredNorm() - P2.squaredNorm();
  const V3L dir = n1.cross(n2);
  const LD dir2 = dir.squaredNorm();
  if (!(dir2 > 0)) return out;
  const V3L x0 = (b1 * n2.cross(dir) + b2 * dir.cross(n1)) / dir2;
  const V3L u = dir / std::sqrt(dir2);
  const V3L d0 = x0 - P1;
  const LD bq = d0.dot(u), cq = d0.squaredNorm() - side2;
  const LD sq = std::sqrt(std::max(bq * bq - cq, LD(0)));
  const V3L candidates[2] = {x0 + (-bq + sq) * u, x0 + (-bq - sq) * u};
  int pick = -1;
  LD best = 0;
  for (int c = 0; c < 2; ++c) {
    const LD score = (P1 - candidates[c]).cross(P2 - candidates[c]).dot(candidates[c] - P3);
    if (score > best) best = score, pick = c;
  }
  if (pick < 0) return out;
  const V3L P = candidates[pick];
  const V3L z_E = (P1 - P).cross(P2 - P).normalized();
  const LD h0 = h / 2;
  const V3L centroid_world = (P + P1 + P2) / LD(3);
  const V3L centroid_plate = (in4 + in5 + in6) / LD(3);
  const M3L F_world = frame_from<LD>(z_E, P - centroid_world);
  const M3L F_E = frame_from<LD>(V3L::UnitZ(), in4 - centroid_plate);
  out.R = F_world * F_E.transpose();
  out.p = centroid_world - out.R * (centroid_plate + V3L(0, 0, h0));
  const V3L P3_pose = out.p + out.R * (in1 + V3L(0, 0, -h0));
  out.residual = (P3_pose - P3).norm();
  out.converged = out.residual <= LD(1e-6) * LD(m.l2 + m.l3);
  return out;
}

PoseReference reference_forward(const Geometry& g, const Vector6d& q_active, double h0, const Pose& seed) {
  const pathos2::Model& m = g.model;
  PoseReference out;
  V3L p = seed.p_world_E.cast<LD>();
  M3L R = seed.R_world_E.cast<LD>();
  auto residual = [&](const V3L& pp, const M3L& RR, Eigen::Matrix<LD, 6, 1>& r) {
    for (int i = 0; i < pathos2::kLegCount; ++i) {
      const V3L a = leg_target<LD>(g, i, pp, RR, LD(h0));
      LD t1 = 0;
      if (!leg_t1<LD>(m.l1, m.l2, m.l3, a, m.branch[i], t1)) return false;
      r(i) = wrap<LD>(LD(q_active(i)) - t1);
    }
    return true;
  };
  Eigen::Matrix<LD, 6, 1> r;
  if (!residual(p, R, r)) return out;
  LD res = r.cwiseAbs().maxCoeff();
  int it = 0;
  for (; it < 30 && res > 1e-18L; ++it) {
    Pose pose;
    pose.p_world_E = p.cast<double>();
    pose.R_world_E = R.cast<double>();
    pose.h0 = h0;
    // Re-orthonormalise the rounded rotation for the double Jacobian.
    pose.R_world_E = Eigen::Quaterniond(pose.R_world_E).normalized().toRotationMatrix();
    const pathos2::PoseIkResult ik = pathos2::inverse(g, pose, pathos2::IkDetail::ActiveOnly);
    const pathos2::JacobianResult jr = pathos2::jacobian(g, pose, ik);
    if (!jr.J_twist_from_qdot.allFinite() || jr.status == Status::Singular) break;
    const Eigen::Matrix<LD, 6, 1> dx = jr.J_twist_from_qdot.cast<LD>() * r;
    LD s = 1;
    bool improved = false;
    for (int h = 0; h < 40; ++h, s /= 2) {
      const V3L pt = p + s * dx.head<3>();
      const M3L Rt = rodrigues<LD>(V3L(s * dx.tail<3>())) * R;
      Eigen::Matrix<LD, 6, 1> rt;
      if (residual(pt, Rt, rt) && rt.norm() < r.norm()) {
        p = pt, R = Rt, r = rt;
        improved = true;
        break;
      }
    }
    if (!improved) break;
    res = r.cwiseAbs().maxCoeff();
  }
  out.p = p;
  out.R = R;
  out.residual = res;
  out.iterations = it;
  out.converged = res <= 1e-16L;
  return out;
}

double pose_error(const Pose& pose, const PoseReference& r, double length_scale) {
  const LD dp = (pose.p_world_E.cast<LD>() - r.p).norm() / LD(length_scale);
  const M3L D = pose.R_world_E.cast<LD>().transpose() * r.R;
  // Small-angle-safe: |vee(D - D^T)| / 2 = sin(angle).
  const V3L v(D(2, 1) - D(1, 2), D(0, 2) - D(2, 0), D(1, 0) - D(0, 1));
  const LD s = v.norm() / 2, c = (D.trace() - 1) / 2;
  return double(std::max(dp, std::atan2(s, c)));
}

// ---- Jacobian and conditioning ---------------------------------------------------------

bool reference_jacobian(const Geometry& g, const Pose& pose, Matrix6d& J) {
  const pathos2::Model& m = g.model;
  const pathos2::PoseIkResult ik = pathos2::inverse(g, pose, pathos2::IkDetail::Full);
  if (ik.status != Status::Ok && ik.status != Status::OutOfLimits) return false;
  Eigen::Matrix<LD, 6, 6> M;
  const V3L p = pose.p_world_E.cast<LD>();
  const M3L R = pose.R_world_E.cast<LD>();
  for (int i = 0; i < pathos2::kLegCount; ++i) {
    V3L pg;
    const V3L a = leg_target<LD>(g, i, p, R, LD(pose.h0), &pg);
    const auto& leg = ik.legs[i];
    const LegReference ref = reference_leg_inverse(m.l1, m.l2, m.l3, a.cast<double>(), Vector3d(leg.t1, leg.t2, leg.t3));
    // The leg target in long double, not its rounding: polish once more against it.
    V3L t(ref.t[0], ref.t[1], ref.t[2]), at;
    M3L Jl;
    for (int k = 0; k < 3; ++k) {
      leg_chain<LD>(m.l1, m.l2, m.l3, t, at, &Jl);
      t += Jl.partialPivLu().solve(V3L(a - at));
    }
    leg_chain<LD>(m.l1, m.l2, m.l3, t, at, &Jl);
    const V3L grad = Jl.transpose().partialPivLu().solve(V3L::UnitX());
    if (!grad.allFinite()) return false;
    const V3L gw = g.R_world_B[i].cast<LD>() * grad;
    const V3L rho = pg - p;
    M.block<1, 3>(i, 0) = gw.transpose();
    M.block<1, 3>(i, 3) = rho.cross(gw).transpose();
  }
  const Eigen::PartialPivLU<Eigen::Matrix<LD, 6, 6>> lu(M);
  if (!(std::abs(lu.determinant()) > 0)) return false;
  J = lu.inverse().cast<double>();
  return J.allFinite();
}

bool jacobian_finite_difference(const Geometry& g, const Pose& pose, double step, bool central, Matrix6d& J) {
  auto q_of = [&](const Pose& p, Vector6d& q) {
    const pathos2::PoseIkResult ik = pathos2::inverse(g, p, pathos2::IkDetail::ActiveOnly);
    q = ik.q_active;
    return ik.status == Status::Ok || ik.status == Status::OutOfLimits;
  };
  Vector6d q0;
  if (!central && !q_of(pose, q0)) return false;
  Matrix6d M;
  for (int k = 0; k < 6; ++k) {
    Vector6d twist = Vector6d::Zero();
    twist(k) = step;
    Vector6d qp, qm;
    if (!q_of(step_pose(pose, twist), qp)) return false;
    if (central) {
      if (!q_of(step_pose(pose, -twist), qm)) return false;
    } else {
      qm = q0;
    }
    for (int i = 0; i < 6; ++i) M(i, k) = wrap(qp(i) - qm(i)) / (central ? 2 * step : step);
  }
  const Eigen::PartialPivLU<Matrix6d> lu(M);
  if (!(std::abs(lu.determinant()) > 0)) return false;
  J = lu.inverse();
  return J.allFinite();
}

std::array<double, 2> condition_numbers_svd(const Matrix6d& J) {
  std::array<double, 2> c{};
  for (int b = 0; b < 2; ++b) {
    const Eigen::Matrix<double, 3, 6> B = J.middleRows<3>(3 * b);
    const Vector3d s = Eigen::JacobiSVD<Eigen::Matrix<double, 3, 6>>(B).singularValues();
    c[b] = s(2) > 0 ? s(0) / s(2) : kInf;
  }
  return c;
}

std::array<double, 2> reference_condition_numbers(const Matrix6d& J) {
  std::array<double, 2> c{};
  for (int b = 0; b < 2; ++b) {
    const Eigen::Matrix<LD, 3, 6> B = J.middleRows<3>(3 * b).cast<LD>();
    const V3L s = Eigen::JacobiSVD<Eigen::Matrix<LD, 3, 6>>(B).singularValues();
    c[b] = s(2) > 0 ? double(s(0) / s(2)) : kInf;
  }
  return c;
}

}  // namespace linkscape::pathos2_methods
