// PATHOS-II's forward kinematics (core/mechanisms/pathos2/pathos2.h): from
// the nine sensors in closed form, and numerically from the six actuators.
#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/mechanisms/pathos2/checks.h"
#include "core/mechanisms/pathos2/pathos2.h"

namespace linkscape::pathos2 {

using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();
using checks::require_pose;
using checks::require_positive;
using checks::wrap_angle;

// ---- Forward kinematics ------------------------------------------------------

NineSensors sensors_of(const PoseIkResult& ik) {
  NineSensors s;
  s.leg1 = Vector3d(ik.legs[0].t1, ik.legs[0].t2, ik.legs[0].t3);
  s.leg5 = Vector3d(ik.legs[4].t1, ik.legs[4].t2, ik.legs[4].t3);
  s.leg6 = Vector3d(ik.legs[5].t1, ik.legs[5].t2, ik.legs[5].t3);
  return s;
}

namespace {

Vector3d globular_world(const Geometry& g, int leg, const Vector3d& q) {
  const Model& m = g.model;
  return g.p_world_B[leg] + g.R_world_B[leg] * leg_forward(m.l1, m.l2, m.l3, q.x(), q.y(), q.z());
}

// Orthonormal frame with z along n and x along the part of u normal to n.
Matrix3d frame_from(const Vector3d& n, const Vector3d& u) {
  const Vector3d z = n.normalized();
  const Vector3d x = (u - u.dot(z) * z).normalized();
  Matrix3d F;
  F.col(0) = x;
  F.col(1) = z.cross(x);
  F.col(2) = z;
  return F;
}

}  // namespace

FkResult forward_nine_sensors(const Geometry& g, const NineSensors& sensors) {
  if (!sensors.leg1.allFinite() || !sensors.leg5.allFinite() || !sensors.leg6.allFinite())
    throw std::invalid_argument("pathos2: sensor angles must be finite");
  const Model& m = g.model;
  FkResult out;
  out.status = Status::Unreachable;
  if (!(m.lp > 0.0)) {
    out.status = Status::Singular;  // all globular centres of a plate coincide
    return out;
  }
  // Globular centres from the sensed legs (Eq. 2). Paper names (Fig. 5):
  // P3 = leg 1 (lower plate), P2 = leg 5, P1 = leg 6 (upper plate), P = leg 4.
  const Vector3d P3 = globular_world(g, 0, sensors.leg1);
  const Vector3d P2 = globular_world(g, 4, sensors.leg5);
  const Vector3d P1 = globular_world(g, 5, sensors.leg6);
  // In-plate offsets (E frame, without the grip term) fix every distance the
  // paper writes with r = lp: |P - P1| = |P - P2| = sqrt(3) lp, and the
  // horizontal offset of P from P3 (0 for plate_phase = 0).
  const Vector3d& in4 = g.p_E_attach_plate[3];
  const Vector3d& in1 = g.p_E_attach_plate[0];
  const Vector3d& in6 = g.p_E_attach_plate[5];
  const double side2 = (in4 - in6).squaredNorm();            // 3 lp^2
  const double chord_13 = (in1 - in6).head<2>().squaredNorm();  // horizontal |P3 P1|^2
  const double chord_34 = (in1 - in4).head<2>().squaredNorm();  // horizontal |P3 P|^2
  // Eq. 19 with h = 2 h0: |P1 - P3|^2 = h^2 + (horizontal chord)^2.
  const double h2 = (P1 - P3).squaredNorm() - chord_13;
  if (!(h2 > 0.0)) return out;
  const double h = std::sqrt(h2);
  const double r3_2 = h2 + chord_34;  // |P - P3|^2
  // Eq. 20 has rank 2 (its rows sum to zero). Keep rows 1 and 2 (the planes
  // |P - P1| = |P - P2| and |P - P2|^2 - |P - P3|^2 = 3 r^2 - h^2) and add
  // the sphere |P - P1|^2 = 3 r^2: a line meets a sphere in two roots.
  const Vector3d n1 = 2.0 * (P2 - P1), n2 = 2.0 * (P3 - P2);
  const double b1 = P2.squaredNorm() - P1.squaredNorm();
  const double b2 = side2 - r3_2 + P3.squaredNorm() - P2.squaredNorm();
  const Vector3d dir = n1.cross(n2);
  const double dir2 = dir.squaredNorm();
  if (!(dir2 > 1e-24 * n1.squaredNorm() * n2.squaredNorm())) {
    out.status = Status::Singular;  // P1, P2, P3 collinear
    return out;
  }
  // Point of the line: x0 = (b1 (n2 x dir) + b2 (dir x n1)) / |dir|^2.
  const Vector3d x0 = (b1 * n2.cross(dir) + b2 * dir.cross(n1)) / dir2;
  const Vector3d u = dir / std::sqrt(dir2);
  const Vector3d d0 = x0 - P1;
  const double bq = d0.dot(u), cq = d0.squaredNorm() - side2;
  const double disc = bq * bq - cq;
  if (disc < -1e-12 * side2) return out;
  const double sq = std::sqrt(std::max(disc, 0.0));
  // Handedness: legs 4, 6, 5 run counter-clockwise about z_E on the upper
  // plate, and the lower plate (P3) lies on the -z_E side.
  const Vector3d candidates[2] = {x0 + (-bq + sq) * u, x0 + (-bq - sq) * u};
  int pick = -1;
  double best = 0.0;
  for (int c = 0; c < 2; ++c) {
    const Vector3d& P = candidates[c];
    const Vector3d normal = (P1 - P).cross(P2 - P);
    const double score = normal.dot(P - P3);
    if (score > best) best = score, pick = c;
  }
  if (pick < 0) return out;
  const Vector3d P = candidates[pick];
  const Vector3d z_E = (P1 - P).cross(P2 - P).normalized();
  const double h0 = h / 2.0;
  // Upper plate: its globular centres are in-plate offsets + h0 z_E; match
  // the plate triangle's centroid and the direction to leg 4.
  const Vector3d centroid_world = (P + P1 + P2) / 3.0;
  const Vector3d centroid_plate = (in4 + g.p_E_attach_plate[4] + in6) / 3.0;
  const Matrix3d F_world = frame_from(z_E, P - centroid_world);
  const Matrix3d F_E = frame_from(Vector3d::UnitZ(), in4 - centroid_plate);
  out.pose.R_world_E = F_world * F_E.transpose();
  out.pose.h0 = h0;
  out.pose.p_world_E =
      centroid_world - out.pose.R_world_E * (centroid_plate + Vector3d(0.0, 0.0, h0));
  // Residual: the lower point the pose predicts against the measured one.
  const Vector3d P3_pose =
      out.pose.p_world_E + out.pose.R_world_E * (in1 + Vector3d(0.0, 0.0, -h0));
  out.residual = (P3_pose - P3).norm();
  out.status = out.residual <= 1e-6 * (m.l2 + m.l3) ? Status::Ok : Status::Unreachable;
  return out;
}

FkResult forward_nine_sensors(const Model& model, const NineSensors& sensors) {
  return forward_nine_sensors(make_geometry(model), sensors);
}

namespace {

double max_wrapped_error(const Vector6d& target, const Vector6d& q, Vector6d& r) {
  double worst = 0.0;
  for (int i = 0; i < kLegCount; ++i) {
    r[i] = wrap_angle(target[i] - q[i]);
    worst = std::max(worst, std::abs(r[i]));
  }
  return worst;
}


}  // namespace

Pose step_pose(const Pose& pose, const Vector6d& twist) {
  Pose next = pose;
  next.p_world_E += twist.head<3>();
  const Vector3d w = twist.tail<3>();
  const double angle = w.norm();
  if (angle > 0.0) next.R_world_E = Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() * pose.R_world_E;
  return next;
}

FkResult forward_numeric(const Geometry& g, const Vector6d& q_active, double h0, const Pose& seed,
                         const FkOptions& options) {
  if (!q_active.allFinite()) throw std::invalid_argument("pathos2: q_active must be finite");
  require_positive(h0, "grip h0");
  require_pose(seed);
  if (options.max_iterations < 0 || !(options.tolerance > 0.0) || !(options.damping >= 0.0) ||
      !(options.max_step_cm > 0.0) || !(options.max_step_rad > 0.0))
    throw std::invalid_argument(
        "pathos2: FK options need max_iterations >= 0, tolerance > 0, damping >= 0, max steps > 0");
  FkResult out;
  out.status = Status::NotConverged;
  Pose pose = seed;
  pose.h0 = h0;
  out.pose = pose;
  PoseIkResult ik = inverse(g, pose, IkDetail::ActiveOnly);
  if (ik.status == Status::Unreachable || ik.status == Status::Singular) {
    out.residual = kInf;
    return out;  // the seed itself is not an assembly of this model
  }
  // The targets in [-pi, pi] once, so every error below is a difference of
  // small angles: at 8e4 rad a difference would round by 7e-12 rad, several
  // times the tolerance (found by the eval fuzzer).
  Vector6d target;
  for (int i = 0; i < kLegCount; ++i) target[i] = wrap_angle(q_active[i]);
  Vector6d r;
  double err = max_wrapped_error(target, ik.q_active, r);
  out.residual = err;
  const double length_scale = std::ldexp(1.0, std::ilogb(g.model.l2 + g.model.l3));
  for (int it = 0; it < options.max_iterations && err > options.tolerance; ++it) {
    const JacobianResult jr = jacobian(g, pose, ik);
    // qdot = M twist. In the twist (translation / s, rotation), s a power of
    // two near l2 + l3, M_unit = M diag(s I, I) is dimensionless: the damping
    // then means the same for every design size and scale.
    Matrix6d M = jr.J_qdot_from_twist;
    if (!M.allFinite()) break;
    M.leftCols<3>() *= length_scale;
    // Levenberg-Marquardt step (M^T M + lambda I) dx = M^T r, lambda relative
    // to |M|^2. Far from the answer the damping keeps the steps on this
    // assembly; within 1e-6 rad of it (steps of ~1e-6 cond(M), no other
    // assembly in reach) it fades with the residual, so the last steps are
    // Newton's and converge quadratically. A fixed lambda there shrank the
    // error by only lambda / (sigma_min^2 + lambda) per step: 40 iterations
    // where cond(M) ~ 1e3 (found by fuzzing). Fading it from larger
    // residuals let 1 % of the harness's seeds jump to a twin assembly.
    constexpr double kNewtonResidual = 1e-6;
    const double lambda = options.damping * M.squaredNorm() / 6.0 * std::min(1.0, r.norm() / kNewtonResidual);
    const Matrix6d A = M.transpose() * M + lambda * Matrix6d::Identity();
    Vector6d dx = A.ldlt().solve(M.transpose() * r);
    dx.head<3>() *= length_scale;
    if (!dx.allFinite()) break;
    // Trust region: a tracking solver must not jump to another assembly.
    const double scale = std::min({1.0, options.max_step_cm / std::max(dx.head<3>().norm(), 1e-300),
                                   options.max_step_rad / std::max(dx.tail<3>().norm(), 1e-300)});
    dx *= scale;
    bool accepted = false;
    for (int halving = 0; halving < 12; ++halving) {
      const Pose trial = step_pose(pose, dx);
      const PoseIkResult trial_ik = inverse(g, trial, IkDetail::ActiveOnly);
      if (trial_ik.status != Status::Unreachable && trial_ik.status != Status::Singular) {
        Vector6d trial_r;
        const double trial_err = max_wrapped_error(target, trial_ik.q_active, trial_r);
        if (trial_r.norm() < r.norm()) {
          pose = trial, ik = trial_ik, r = trial_r, err = trial_err;
          accepted = true;
          break;
        }
      }
      dx *= 0.5;
    }
    out.iterations = it + 1;
    if (!accepted) break;  // stalled: report, do not guess
  }
  // Re-orthonormalise against drift from many small rotations.
  const Eigen::Quaterniond qn(pose.R_world_E);
  pose.R_world_E = qn.normalized().toRotationMatrix();
  out.pose = pose;
  out.residual = err;
  out.status = err <= options.tolerance ? Status::Ok : Status::NotConverged;
  return out;
}

FkResult forward_numeric(const Model& model, const Vector6d& q_active, double h0, const Pose& seed,
                         const FkOptions& options) {
  return forward_numeric(make_geometry(model), q_active, h0, seed, options);
}

}  // namespace linkscape::pathos2
