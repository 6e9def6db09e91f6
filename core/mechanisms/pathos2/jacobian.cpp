// PATHOS-II's Jacobian and its condition numbers (core/mechanisms/pathos2/pathos2.h).
#include <Eigen/LU>
#include <cmath>
#include <limits>

#include "core/conditioning.h"
#include "core/mechanisms/pathos2/pathos2.h"

namespace linkscape::pathos2 {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

// ---- Jacobian -------------------------------------------------------------------

namespace {

// c of a 6x3 matrix B (the transpose of a block of J) whose entries are
// within ~1e+-70 of 1. B = Q R with Q's columns orthonormal, by modified
// Gram-Schmidt: the triangle R is backward stable (exactly the factor of a
// matrix within a few u |B| of B) and has B's singular values; its closed
// form (conditioning.h) keeps the relative error ~u c. (Forming B^T B would square c,
// and a threshold on its determinant cannot tell rank deficiency from
// rounding.)
template <class Columns>
double three_column_condition_number(const Eigen::MatrixBase<Columns>& B) {
  // Plain loops: Eigen's 6-vector updates were not inlined here.
  double q0[6], q1[6], v2[6];
  double r00 = 0.0;
  for (int k = 0; k < 6; ++k) q0[k] = B(k, 0), r00 += q0[k] * q0[k];
  r00 = std::sqrt(r00);
  if (r00 == 0.0) return kInf;
  double r01 = 0.0, r02 = 0.0;
  for (int k = 0; k < 6; ++k) {
    q0[k] /= r00;
    r01 += q0[k] * B(k, 1);
  }
  double r11 = 0.0;
  for (int k = 0; k < 6; ++k) q1[k] = B(k, 1) - r01 * q0[k], r11 += q1[k] * q1[k];
  r11 = std::sqrt(r11);
  if (r11 == 0.0) return kInf;
  for (int k = 0; k < 6; ++k) q1[k] /= r11, r02 += q0[k] * B(k, 2);
  double r12 = 0.0;
  for (int k = 0; k < 6; ++k) v2[k] = B(k, 2) - r02 * q0[k], r12 += q1[k] * v2[k];
  double r22 = 0.0;
  for (int k = 0; k < 6; ++k) v2[k] -= r12 * q1[k], r22 += v2[k] * v2[k];
  Matrix3d L;  // R^T
  L << r00, 0.0, 0.0, r01, r11, 0.0, r02, r12, std::sqrt(r22);
  return condition_number_lower_triangular(L);
}

}  // namespace

double block_condition_number(const Eigen::Matrix<double, 3, 6>& block) {
  // Scaled by a power of two (exact) so the largest entry is in [1, 2).
  const double largest = block.cwiseAbs().maxCoeff();
  if (!(largest > 0.0) || !std::isfinite(largest)) return kInf;
  const Eigen::Matrix<double, 6, 3> unit = block.transpose() * std::ldexp(1.0, -std::ilogb(largest));
  return three_column_condition_number(unit);
}

JacobianResult jacobian(const Geometry& g, const Pose& pose, const PoseIkResult& ik) {
  JacobianResult out;
  out.cond_p = out.cond_o = kInf;
  if (ik.status != Status::Ok && ik.status != Status::OutOfLimits) {
    out.status = ik.status;
    return out;
  }
  const Model& m = g.model;
  Matrix6d& M = out.J_qdot_from_twist;
  for (int i = 0; i < kLegCount; ++i) {
    const LegSolution& leg = ik.legs[i];
    const Vector3d& a = leg.p_B_globular;
    // Columns of the leg Jacobian da/dt (leg frame): about R1 (z through the
    // origin), R2 (through l1 z) and R3 (through the elbow). dt1/da is the
    // first row of its inverse: (c2 x c3) / det.
    const double c1 = leg.cos_t1, s1 = leg.sin_t1, c2 = leg.cos_t2, s2 = leg.sin_t2;
    const Vector3d axis1 = Vector3d::UnitZ();
    const Vector3d axis2(-s1, c1, 0.0);
    const Vector3d axis3(c1 * c2, s1 * c2, -s2);
    const Vector3d p2(0.0, 0.0, m.l1);
    const Vector3d p3 = p2 + m.l2 * Vector3d(c1 * s2, s1 * s2, c2);
    const Vector3d col1 = axis1.cross(a), col2 = axis2.cross(a - p2), col3 = axis3.cross(a - p3);
    const Vector3d n = col2.cross(col3);
    const double det = col1.dot(n);
    const Vector3d grad_world = g.R_world_B[i] * (n / det);
    const Vector3d rho = ik.p_world_globular[i] - pose.p_world_E;
    M.block<1, 3>(i, 0) = grad_world.transpose();
    M.block<1, 3>(i, 3) = rho.cross(grad_world).transpose();
  }
  if (!M.allFinite()) {
    out.status = Status::Singular;
    return out;
  }
  // M's translation columns scale like 1 / length, its rotation columns not
  // at all. With the translation columns multiplied by a power of two near
  // l2 + l3 (exact), M_unit = M diag(s I, I) is dimensionless and the tests
  // below do not depend on the model's scale; J = diag(s I, I) M_unit^-1.
  const double s = std::ldexp(1.0, std::ilogb(m.l2 + m.l3));
  // Transposed: column c of (M_unit^T)^-1 is row c of J_unit, so the rows of
  // J_unit the condition numbers need come out contiguous.
  Matrix6d Mt_unit = M.transpose();
  Mt_unit.topRows<3>() *= s;
  const Eigen::PartialPivLU<Matrix6d> lu(Mt_unit);
  // Column by column: Eigen's matrix right-hand side takes its blocked
  // (GEMM) path, several times slower at 6x6 than six vector solves.
  Matrix6d Jt_unit;
  for (int c = 0; c < kLegCount; ++c) Jt_unit.col(c) = lu.solve(Vector6d::Unit(c));
  // Condition number of M_unit in the 1-norm, exact from M_unit and its
  // inverse: J's relative error is about u times it.
  const double kappa =
      Mt_unit.cwiseAbs().rowwise().sum().maxCoeff() * Jt_unit.cwiseAbs().rowwise().sum().maxCoeff();
  if (!(kappa <= kMaxJacobianCondition)) {
    out.status = Status::Singular;
    return out;
  }
  out.J_twist_from_qdot = Jt_unit.transpose();
  out.J_twist_from_qdot.topRows<3>() *= s;
  // J_unit is dimensionless and, with kappa bounded, of moderate size.
  out.cond_p = three_column_condition_number(Jt_unit.leftCols<3>());
  out.cond_o = three_column_condition_number(Jt_unit.rightCols<3>());
  out.status = ik.status;
  return out;
}

JacobianResult jacobian(const Model& model, const Pose& pose) {
  const Geometry g = make_geometry(model);
  return jacobian(g, pose, inverse(g, pose));
}

}  // namespace linkscape::pathos2
