// Internal to the described solver (kinematics.cpp, forward.cpp,
// closed_form.cpp): a leg's chain walked at a state, its twists and closure
// error, and the damped Gauss-Newton step both solvers take.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/mechanisms/described/kinematics.h"

namespace linkscape::described::internal {

using Eigen::Index;
using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Kind = Step::Kind;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInf = std::numeric_limits<double>::infinity();


// The rows a device's closure keeps: spatial all six, planar (rz, x, y).
inline constexpr int kPlanarRows[3] = {2, 3, 4};

inline Matrix3d rotation_of(const Vector3d& v) {
  const double angle = v.norm();
  if (angle == 0) return Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
}

inline Vector3d rotation_vector(const Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

inline Matrix3d euler_zyx(double rx, double ry, double rz) {
  return (Eigen::AngleAxisd(rz, Vector3d::UnitZ()) * Eigen::AngleAxisd(ry, Vector3d::UnitY()) *
          Eigen::AngleAxisd(rx, Vector3d::UnitX()))
      .toRotationMatrix();
}

inline Vector3d euler_of(const Matrix3d& R) {
  const double ry = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  return {std::atan2(R(2, 1), R(2, 2)), ry, std::atan2(R(1, 0), R(0, 0))};
}

// A leg's chain at one state: the end frame and, per variable, the twist's
// axis and centre (base frame).
struct Chain {
  Isometry3d end = Isometry3d::Identity();
  std::vector<Vector3d> axis, centre;  // per variable
  std::vector<bool> sliding;           // per variable: prismatic
  std::vector<Vector3d> step_centre, step_axis;  // per step, for branch rules and drawing
  std::vector<Isometry3d> step_frame;            // per step: the frame after it
};

// Fills `c` (its vectors keep their capacity: no allocation in a solver's
// loop). With `through` >= 0, only the steps up to that one are walked: the
// centres and axes of steps 0..through (the rest of `c` left stale).
inline void walk_into(const Leg& leg, const LegState& s, Chain& c, int through = -1) {
  c.axis.resize(std::size_t(leg.variables));
  c.centre.resize(std::size_t(leg.variables));
  c.sliding.assign(std::size_t(leg.variables), false);
  c.step_centre.clear();
  c.step_axis.clear();
  c.step_frame.clear();
  Isometry3d T = leg.base;
  int sphere = 0;
  for (const Step& step : leg.steps) {
    const Vector3d here = T.translation();
    c.step_centre.push_back(here);
    c.step_axis.push_back(T.linear() * step.axis);
    if (int(c.step_centre.size()) > through && through >= 0) return;
    switch (step.kind) {
      case Kind::Fixed:
        T = T * step.transform;
        break;
      case Kind::Revolute: {
        c.axis[std::size_t(step.variable)] = T.linear() * step.axis;
        c.centre[std::size_t(step.variable)] = here;
        T.linear() = T.linear() * Eigen::AngleAxisd(s.values(step.variable), step.axis).toRotationMatrix();
        break;
      }
      case Kind::Prismatic: {
        const Vector3d a = T.linear() * step.axis;
        c.axis[std::size_t(step.variable)] = a;
        c.centre[std::size_t(step.variable)] = here;
        c.sliding[std::size_t(step.variable)] = true;
        T.translation() += a * s.values(step.variable);
        break;
      }
      case Kind::Spherical: {
        T.linear() = T.linear() * s.spheres[std::size_t(sphere++)];
        for (int k = 0; k < 3; ++k) {
          c.axis[std::size_t(step.variable + k)] = T.linear().col(k);
          c.centre[std::size_t(step.variable + k)] = here;
        }
        break;
      }
    }
    c.step_frame.push_back(T);
  }
  c.end = T;
}

inline Chain walk(const Leg& leg, const LegState& s) {
  Chain c;
  walk_into(leg, s, c);
  return c;
}

// The twist of variable v about point r: [axis; axis x (r - centre)] (or
// [0; axis] for a slide), position rows divided by size.
inline Vector6d twist(const Chain& c, int v, const Vector3d& r, double size) {
  Vector6d t;
  const Vector3d& a = c.axis[std::size_t(v)];
  if (c.sliding[std::size_t(v)]) t << Vector3d::Zero(), a / size;
  else t << a, a.cross(r - c.centre[std::size_t(v)]) / size;
  return t;
}

inline Vector6d closure_error(const Chain& c, const Isometry3d& anchor, double size) {
  Vector6d e;
  e << rotation_vector(anchor.linear() * c.end.linear().transpose()),
      (anchor.translation() - c.end.translation()) / size;
  return e;
}

// Keeps the rows the device closes (planar: rz, x, y).
// Closure rows: at most six, kept on the stack; a leg's columns (its joint
// variables, as many as the file gives) on the heap.
using Rows = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
using LegMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, Eigen::Dynamic>;

inline Rows rows_of(const Vector6d& v, bool planar) {
  if (!planar) return v;
  Rows out(3);
  for (int i = 0; i < 3; ++i) out(i) = v(kPlanarRows[i]);
  return out;
}

template <class Vector>
void apply(const Leg& leg, LegState& s, const Vector& delta, int offset = 0) {
  int sphere = 0;
  for (const Step& step : leg.steps) {
    if (step.kind == Kind::Revolute || step.kind == Kind::Prismatic) s.values(step.variable) += delta(offset + step.variable);
    if (step.kind == Kind::Spherical) {
      Matrix3d& R = s.spheres[std::size_t(sphere++)];
      R = R * rotation_of(delta.template segment<3>(offset + step.variable));
      // Re-orthonormalise now and then would be needed only over thousands of steps.
    }
  }
}

// A damped Gauss-Newton step for J d = e (J m x n): d = J^T (J J^T + mu I)^-1 e,
// the least-norm step, damped by mu = |e|^2 (Levenberg-Marquardt in the
// Yamashita-Fukushima form: quadratic convergence where a solution exists,
// also at singular ones). A leg's IK caps mu: at a least-squares minimum off
// the target (an unreachable pose) light damping converges to the minimum,
// whose distance is the reach margin outside.
template <class Jacobian, class Error>
auto damped_step(const Jacobian& J, const Error& e, double cap = kInf) {
  using Square = Eigen::Matrix<double, Jacobian::RowsAtCompileTime, Jacobian::RowsAtCompileTime, 0,
                               Jacobian::MaxRowsAtCompileTime, Jacobian::MaxRowsAtCompileTime>;
  using Step = Eigen::Matrix<double, Jacobian::ColsAtCompileTime, 1, 0, Jacobian::MaxColsAtCompileTime, 1>;
  Square A = J * J.transpose();
  const double mu = std::min(e.squaredNorm(), cap) + 1e-30;
  A.diagonal().array() += mu;
  Step d = J.transpose() * A.ldlt().solve(e);
  return d;
}

// Limits a step to half a radian in any angle and half the device's size in
// any length (`lengths` marks the length variables).
template <class Vector>
void limit_step(Vector& d, const std::vector<bool>& lengths, double size) {
  double ratio = 0;
  for (Index i = 0; i < d.size(); ++i)
    ratio = std::max(ratio, std::abs(d(i)) / (lengths[std::size_t(i)] ? 0.5 * size : 0.5));
  if (ratio > 1) d /= ratio;
}

inline double golden(int i, int j) {
  const double v = std::fmod(0.6180339887498949 * (i + 1) + 0.4142135623730951 * (j + 1) * (i + 3), 1.0);
  return 2 * v - 1;
}

// The combination index of a leg's own free rules for a device branch.
inline int leg_combination(const Leg& l, int branch) {
  int combo = 0, bit = 0;
  for (const BranchRule& r : l.rules)
    if (r.free_index >= 0) combo |= ((branch >> r.free_index) & 1) << bit++;
  return combo;
}
inline int device_branch(const Leg& l, int combo) {
  int branch = 0, bit = 0;
  for (const BranchRule& r : l.rules)
    if (r.free_index >= 0) branch |= ((combo >> bit++) & 1) << r.free_index;
  return branch;
}
inline int free_rules_of(const Leg& l) {
  int n = 0;
  for (const BranchRule& r : l.rules) n += r.free_index >= 0;
  return n;
}

// A triple or along rule's value (length^2 or length) from the centres and
// axes of the steps it reads (centre(-2): the anchor's).
template <class Centre, class Axis>
double rule_value_from(const BranchRule& r, Centre&& centre, Axis&& axis) {
  if (r.kind == BranchRule::Kind::Along) return (centre(r.steps[1]) - centre(r.steps[0])).dot(r.direction);
  const Vector3d a = centre(r.steps[0]), b = centre(r.steps[1]);
  return (b - a).cross(centre(r.steps[2]) - b).dot(axis(r.steps[0]));
}

// The same at a walked chain.
inline double rule_value(const BranchRule& r, const Chain& c, const Isometry3d& anchor) {
  return rule_value_from(
      r, [&](int step) -> Vector3d { return step == -2 ? anchor.translation() : c.step_centre[std::size_t(step)]; },
      [&](int step) -> Vector3d { return c.step_axis[std::size_t(step)]; });
}

// The sign of one rule at a walked chain.
inline int rule_sign(const BranchRule& r, const Leg& l, const Chain& c, const LegState& state, const Isometry3d& anchor) {
  if (r.kind == BranchRule::Kind::Angle) return sine_sign(state.values(l.steps[std::size_t(r.steps[0])].variable));
  const double v = rule_value(r, c, anchor);
  return v > 0 ? 1 : v < 0 ? -1 : 0;
}

// The platform's twists about r for each driven coordinate (translation:
// [0; e]; rotation: [w; w x (r - p)], w the angular velocity of a unit rate:
// the base axes where all three rotations are free, else the Euler rates).
using PlatformColumns = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;  // at most six driven coordinates
PlatformColumns platform_columns(const Model& m, const PlatformPose& pose, const Vector3d& r);

// sigma_max / sigma_min (+inf where singular), by a fixed-size SVD for the
// shapes devices have (no allocation): 2x2, 3x3, 3x6, 6x6.
double condition_number(const MatrixXd& M);

// The chain variable of a leg's (first) actuator.
inline int actuator_variable(const Model& m, const Leg& l) {
  return l.steps[std::size_t(m.actuators[std::size_t(l.actuators.front())].step)].variable;
}

}  // namespace linkscape::described::internal

namespace linkscape::described {

struct Kinematics::LegSolveResult {
  LegState state;
  double error = internal::kInf;  // |e|, dimensionless
  int iterations = 0;
  // At a least-squares minimum: the gradient J^T e vanishes against |J| |e|
  // (a pose the leg cannot reach from here), rather than merely slow.
  bool stationary = false;
};

}  // namespace linkscape::described
