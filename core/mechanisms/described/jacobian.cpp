// The Jacobian of a described mechanism by reciprocal screws: each leg's
// actuation wrench, J = -Jx^-1 Jq, its condition numbers and singular sets
// (docs/described-mechanisms.md, "What Linkscape computes from it").
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/kinematics.h"

namespace linkscape::described {

using namespace internal;  // its Eigen names too

// ---- The Jacobian by reciprocal screws ----------------------------------------------

namespace internal {
namespace {
template <int Rows, int Cols>
double fixed_condition(const MatrixXd& M) {
  const Eigen::JacobiSVD<Eigen::Matrix<double, Rows, Cols>> svd(M);
  const auto& s = svd.singularValues();
  return s(s.size() - 1) > 0 ? s(0) / s(s.size() - 1) : kInf;
}
}  // namespace

double condition_number(const MatrixXd& M) {
  if (M.rows() == 2 && M.cols() == 2) return fixed_condition<2, 2>(M);
  if (M.rows() == 3 && M.cols() == 3) return fixed_condition<3, 3>(M);
  if (M.rows() == 3 && M.cols() == 6) return fixed_condition<3, 6>(M);
  if (M.rows() == 6 && M.cols() == 6) return fixed_condition<6, 6>(M);
  return fixed_condition<Eigen::Dynamic, Eigen::Dynamic>(M);
}

PlatformColumns platform_columns(const Model& m, const PlatformPose& pose, const Vector3d& r) {
  const bool all_rotations = m.free[3] && m.free[4] && m.free[5];
  // The Euler angles, for the rates (not needed where all three rotations are free).
  const Vector3d e = all_rotations ? Vector3d::Zero() : euler_of(pose.R);
  PlatformColumns cols(6, m.driven());
  int col = 0;
  for (const TaskCoordinate& t : m.task) {
    if (t.extra >= 0) continue;
    Vector6d tw;
    const int c = t.platform_coordinate;
    if (c < 3) {
      tw << Vector3d::Zero(), Vector3d::Unit(c) / m.size;
    } else {
      Vector3d w = Vector3d::Unit(c - 3);
      if (!all_rotations) {
        const Matrix3d Rz = Eigen::AngleAxisd(e[2], Vector3d::UnitZ()).toRotationMatrix();
        const Matrix3d Ry = Eigen::AngleAxisd(e[1], Vector3d::UnitY()).toRotationMatrix();
        w = c == 3 ? Vector3d(Rz * Ry * Vector3d::UnitX()) : c == 4 ? Vector3d(Rz * Vector3d::UnitY()) : Vector3d::UnitZ();
      }
      tw << w, w.cross(r - pose.p) / m.size;
    }
    cols.col(col++) = tw;
  }
  return cols;
}
}  // namespace internal

namespace {
// The wrench reciprocal to a recognised leg's passive joints, in closed form:
// a force through the centre of its last (spherical) joint w, along the rod
// (crank-rod, slide-rod, extensible, planar dyad) or square to the linear
// velocities the second and third revolutes give w (three revolutes), as
// closure rows about r, of unit norm. False where the passive joints lose a
// freedom (the leg is singular).
bool closed_wrench(const ClosedFormLeg& form, const Leg& l, const Chain& c, const Vector3d& r, double size, bool planar,
                   Rows& W) {
  const Vector3d w = c.step_centre[std::size_t(form.end_step)];
  Vector3d f;
  if (form.pattern == LegPattern::ThreeRevolute) {
    const int v2 = l.steps[std::size_t(form.second_step)].variable, v3 = l.steps[std::size_t(form.third_step)].variable;
    const Vector3d u2 = c.axis[std::size_t(v2)].cross(w - c.centre[std::size_t(v2)]);
    const Vector3d u3 = c.axis[std::size_t(v3)].cross(w - c.centre[std::size_t(v3)]);
    f = u2.cross(u3);
    if (!(f.norm() > 1e-10 * u2.norm() * u3.norm())) return false;
  } else {
    f = w - c.step_centre[std::size_t(form.ball_step)];
    if (!(f.norm() > 1e-12 * size)) return false;
    if (form.ball_joints == 2) {  // a universal: its two axes must move the rod's end two ways
      const int v1 = l.steps[std::size_t(form.ball_step)].variable;
      const Vector3d n = f.normalized();
      if (!(c.axis[std::size_t(v1)].cross(n).cross(c.axis[std::size_t(v1 + 1)].cross(n)).norm() > 1e-10)) return false;
    }
  }
  Vector6d full;
  full << (w - r).cross(f), f * size;
  W = rows_of(full, planar);
  W.normalize();
  return true;
}
}  // namespace

JacobianParts Kinematics::jacobian(const VectorXd& x, const PoseSolution& solved, LegSolver solver) const {
  JacobianParts out;
  jacobian_into(pose(x), solved, solver, out);
  return out;
}

void Kinematics::jacobian_into(const PlatformPose& p, const PoseSolution& solved, LegSolver solver,
                               JacobianParts& out) const {
  const int n = model_.driven();
  const int a_count = int(model_.actuators.size());
  out.Jx.setZero(a_count, n);
  out.Jq.setZero(a_count, a_count);
  out.serial_margin.assign(model_.legs.size(), kInf);
  out.status = Status::Ok;
  out.singular_leg = -1;
  out.constraint_rank = 0;  // (`out` is often a thread's scratch, reused from the last sample)
  out.constraint_singular = false;
  const int m = model_.planar ? 3 : 6;
  thread_local Chain c;
  // The legs' constraint wrenches side by side (at most m per leg).
  using Constraints = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, Eigen::Dynamic>;
  thread_local Constraints constraints;
  constraints.resize(m, m * Index(model_.legs.size()));
  int constraint_columns = 0;
  Rows w(m);
  int row = 0;
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    const Leg& l = model_.legs[leg];
    walk_into(l, solved.legs[leg].state, c);
    const Vector3d r = c.end.translation();
    const int actuator = l.actuators.front();
    const int act_var = l.steps[std::size_t(model_.actuators[std::size_t(actuator)].step)].variable;
    // The closed wrench is the one force of a leg that transmits one wrench
    // (not one that also holds the platform's orientation).
    const ClosedFormLeg* form =
        solver == LegSolver::Fastest && passive_rank_[leg] == m - 1 ? closed_form(int(leg)) : nullptr;
    bool passive_singular = false;
    if (form) {
      passive_singular = !closed_wrench(*form, l, c, r, model_.size, model_.planar, w);
    } else {
      // At most six rows and a leg's variables: on the stack.
      using Passive = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, kMaxLegVariables>;
      using Reciprocal = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
      Passive passive(m, l.variables - 1);
      for (int v = 0, col = 0; v < l.variables; ++v)
        if (v != act_var) passive.col(col++) = rows_of(twist(c, v, r, model_.size), model_.planar);
      // The wrenches reciprocal to every passive twist: the orthogonal
      // complement of their span, as many as the passive twists leave free at
      // home (one for a leg of five passive freedoms; more where the leg also
      // holds the platform's orientation, as a Falcon's revolute legs do): the
      // last columns of Q in a column-pivoted QR (a third of an SVD's cost,
      // the same subspace). Of them, the actuation wrench is the one the
      // actuator works against; the others are constraint wrenches,
      // reciprocal to the actuator too.
      const Eigen::ColPivHouseholderQR<Passive> qr(passive);
      // A vanishing pivot beyond the leg's idle freedoms: the passive joints
      // lose a freedom, the leg is singular.
      const int expected_rank = passive_rank_[leg];
      const auto R = qr.matrixQR().diagonal().cwiseAbs();
      int rank = 0;
      for (Index i = 0; i < R.size(); ++i) rank += R(i) > 1e-10 * R(0);
      const Reciprocal Q = qr.householderQ();
      const Reciprocal reciprocal = Q.rightCols(m - expected_rank);
      const Rows actuation = reciprocal.transpose() * rows_of(twist(c, act_var, r, model_.size), model_.planar);
      if (actuation.norm() > 0) w = reciprocal * actuation.normalized();
      else w = reciprocal.col(reciprocal.cols() - 1);
      passive_singular = rank < expected_rank;
      if (reciprocal.cols() > 1 && actuation.norm() > 0) {
        // The wrenches that do no work on any of the leg's joints: its
        // reciprocal ones with the actuation wrench's share taken out.
        const Rows a = actuation.normalized();
        constraints.middleCols(constraint_columns, reciprocal.cols()) = reciprocal - w * a.transpose();
        constraint_columns += int(reciprocal.cols());
      }
    }
    const PlatformColumns cols = platform_columns(model_, p, r);
    for (Index j = 0; j < cols.cols(); ++j) out.Jx(row, j) = w.dot(rows_of(cols.col(j), model_.planar));
    const double jq = w.dot(rows_of(twist(c, act_var, r, model_.size), model_.planar));
    out.Jq(row, actuator) = jq;
    const bool prismatic = model_.actuators[std::size_t(actuator)].prismatic;
    out.serial_margin[leg] = model_.size * std::abs(jq) * (prismatic ? model_.size : 1.0);
    if (passive_singular || std::abs(jq) <= 1e-12) {
      if (out.status == Status::Ok) out.singular_leg = int(leg);
      out.status = Status::Singular;
      out.serial_margin[leg] = passive_singular ? 0.0 : out.serial_margin[leg];
    }
    ++row;
  }
  if (constraint_columns > 0) {
    const Eigen::ColPivHouseholderQR<Constraints> qr(constraints.leftCols(constraint_columns));
    const auto R = qr.matrixQR().diagonal().cwiseAbs();
    for (Index i = 0; i < R.size(); ++i) out.constraint_rank += R(i) > 1e-10 * R(0);
    if (out.constraint_rank < constraint_rank_) {
      out.constraint_singular = true;
      out.status = Status::Singular;
    }
  }
  thread_local Eigen::PartialPivLU<MatrixXd> lu;
  lu.compute(out.Jx);
  // The closed forms take the LU's estimate (1-norm, within a small factor of
  // the 2-norm's): an SVD of Jx would cost more than the rest of the sample.
  out.jx_condition = solver == LegSolver::Fastest ? 1 / lu.rcond() : condition_number(out.Jx);
  if (!(out.jx_condition <= kSingularCondition)) out.status = Status::Singular;
  out.J = lu.solve(out.Jq);
}

}  // namespace linkscape::described
