#include "core/mechanisms/described/kinematics.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace linkscape::described {
namespace {

using Eigen::Index;
using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Kind = Step::Kind;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::atomic<std::uint64_t> next_id{1};

// The rows a device's closure keeps: spatial all six, planar (rz, x, y).
constexpr int kPlanarRows[3] = {2, 3, 4};

Matrix3d rotation_of(const Vector3d& v) {
  const double angle = v.norm();
  if (angle == 0) return Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
}

Vector3d rotation_vector(const Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

Matrix3d euler_zyx(double rx, double ry, double rz) {
  return (Eigen::AngleAxisd(rz, Vector3d::UnitZ()) * Eigen::AngleAxisd(ry, Vector3d::UnitY()) *
          Eigen::AngleAxisd(rx, Vector3d::UnitX()))
      .toRotationMatrix();
}

Vector3d euler_of(const Matrix3d& R) {
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

// Fills `c` (its vectors keep their capacity: no allocation in a solver's loop).
void walk_into(const Leg& leg, const LegState& s, Chain& c) {
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

Chain walk(const Leg& leg, const LegState& s) {
  Chain c;
  walk_into(leg, s, c);
  return c;
}

// The twist of variable v about point r: [axis; axis x (r - centre)] (or
// [0; axis] for a slide), position rows divided by size.
Vector6d twist(const Chain& c, int v, const Vector3d& r, double size) {
  Vector6d t;
  const Vector3d& a = c.axis[std::size_t(v)];
  if (c.sliding[std::size_t(v)]) t << Vector3d::Zero(), a / size;
  else t << a, a.cross(r - c.centre[std::size_t(v)]) / size;
  return t;
}

Vector6d closure_error(const Chain& c, const Isometry3d& anchor, double size) {
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

Rows rows_of(const Vector6d& v, bool planar) {
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

double golden(int i, int j) {
  const double v = std::fmod(0.6180339887498949 * (i + 1) + 0.4142135623730951 * (j + 1) * (i + 3), 1.0);
  return 2 * v - 1;
}

struct ThreadSeeds {
  std::uint64_t id = 0;
  std::vector<std::vector<std::optional<LegState>>> legs;  // per leg, per combination
};
thread_local ThreadSeeds thread_seeds;

}  // namespace

struct Kinematics::LegSolveResult {
  LegState state;
  double error = kInf;  // |e|, dimensionless
  int iterations = 0;
  // At a least-squares minimum: the gradient J^T e vanishes against |J| |e|
  // (a pose the leg cannot reach from here), rather than merely slow.
  bool stationary = false;
};

// ---- Poses -------------------------------------------------------------------

PlatformPose Kinematics::pose(const VectorXd& x) const {
  PlatformPose p;
  std::array<double, 6> c = model_.fixed;
  p.extras = VectorXd::Zero(Index(model_.extras.size()));
  for (std::size_t i = 0; i < model_.task.size(); ++i) {
    const TaskCoordinate& t = model_.task[i];
    if (t.platform_coordinate >= 0) c[std::size_t(t.platform_coordinate)] = x(Index(i));
    else p.extras(t.extra) = x(Index(i));
  }
  p.p = {c[0], c[1], c[2]};
  p.R = euler_zyx(c[3], c[4], c[5]);
  const Isometry3d platform = Eigen::Translation3d(p.p) * Isometry3d(p.R);
  for (const Isometry3d& body : model_.platform_frames(p.extras)) p.bodies.push_back(platform * body);
  return p;
}

Isometry3d Kinematics::anchor(int leg, const PlatformPose& pose) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  return pose.bodies[std::size_t(l.platform)] * l.anchor;
}

double Kinematics::wrap(double a) const {
  a = std::remainder(a, 2 * kPi);
  return a <= -kPi ? a + 2 * kPi : a;
}

// ---- Branch rules ------------------------------------------------------------

std::vector<int> Kinematics::rule_signs(int leg, const LegState& state, const Isometry3d& anchor) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  const Chain c = walk(l, state);
  std::vector<int> signs;
  for (const BranchRule& r : l.rules) {
    double v = 0;
    if (r.kind == BranchRule::Kind::Angle) {
      v = std::sin(state.values(l.steps[std::size_t(r.steps[0])].variable));
    } else {
      const Vector3d a = c.step_centre[std::size_t(r.steps[0])], b = c.step_centre[std::size_t(r.steps[1])];
      const Vector3d cc = r.steps[2] == -2 ? anchor.translation() : c.step_centre[std::size_t(r.steps[2])];
      v = (b - a).cross(cc - b).dot(c.step_axis[std::size_t(r.steps[0])]);
    }
    signs.push_back(v > 0 ? 1 : v < 0 ? -1 : 0);
  }
  return signs;
}

bool Kinematics::signs_match(int leg, const LegState& state, const Isometry3d& anchor, int branch) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  if (l.rules.empty()) return true;  // no chain to walk
  const std::vector<int> signs = rule_signs(leg, state, anchor);
  for (std::size_t i = 0; i < l.rules.size(); ++i) {
    const BranchRule& r = l.rules[i];
    const int wanted = r.fixed_sign != 0 ? r.fixed_sign : ((branch >> r.free_index) & 1) ? -1 : 1;
    if (signs[i] * wanted < 0) return false;
  }
  return true;
}

bool Kinematics::within_travel(int leg, const LegState& state) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  for (int a : l.actuators) {
    const Actuator& act = model_.actuators[std::size_t(a)];
    if (!act.limited) continue;
    const double v = state.values(l.steps[std::size_t(act.step)].variable);
    const bool inside = act.prismatic ? act.range.contains(v)
                                      : act.range.contains(wrap(v)) || act.range.contains(wrap(v) + 2 * kPi) ||
                                            act.range.contains(wrap(v) - 2 * kPi);
    if (!inside) return false;
  }
  return true;
}

namespace {
// The combination index of a leg's own free rules for a device branch.
int leg_combination(const Leg& l, int branch) {
  int combo = 0, bit = 0;
  for (const BranchRule& r : l.rules)
    if (r.free_index >= 0) combo |= ((branch >> r.free_index) & 1) << bit++;
  return combo;
}
int device_branch(const Leg& l, int combo) {
  int branch = 0, bit = 0;
  for (const BranchRule& r : l.rules)
    if (r.free_index >= 0) branch |= ((combo >> bit++) & 1) << r.free_index;
  return branch;
}
int free_rules_of(const Leg& l) {
  int n = 0;
  for (const BranchRule& r : l.rules) n += r.free_index >= 0;
  return n;
}
}  // namespace

// ---- Leg inverse kinematics ----------------------------------------------------

Kinematics::LegSolveResult Kinematics::solve_leg(int leg, const Isometry3d& anchor, LegState s, int max_iterations,
                                                 double crawl) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  const double size = model_.size;
  // Scratch chains and states reused across iterations (no allocation in the loop).
  thread_local Chain c, tc;
  thread_local LegState trial;
  LegSolveResult out;
  walk_into(l, s, c);
  Rows e = rows_of(closure_error(c, anchor, size), model_.planar);
  double norm = e.norm();
  LegMatrix J(e.size(), l.variables);
  int it = 0;
  for (; it < max_iterations && norm > 1e-15; ++it) {
    for (int v = 0; v < l.variables; ++v) J.col(v) = rows_of(twist(c, v, c.end.translation(), size), model_.planar);
    auto d = damped_step(J, e, 1e-6);
    limit_step(d, c.sliding, size);
    bool accepted = false;
    for (int halving = 0; halving < 30 && !accepted; ++halving, d *= 0.5) {
      trial = s;
      apply(l, trial, d);
      walk_into(l, trial, tc);
      const Rows te = rows_of(closure_error(tc, anchor, size), model_.planar);
      if (te.norm() < norm) {
        accepted = true;
        // At the rounding floor, or crawling towards a least-squares minimum
        // off the target (an unreachable pose): either way, done.
        const bool floor = te.norm() > 0.5 * norm && norm < 1e-11;
        const bool crawling = te.norm() > (1 - crawl) * norm && norm > 1e-9;
        std::swap(s, trial);
        std::swap(c, tc);
        e = te;
        norm = te.norm();
        if (floor || crawling) it = max_iterations;
      }
    }
    if (!accepted) break;  // no decrease along the step: a least-squares minimum
  }
  for (int v = 0; v < l.variables; ++v) J.col(v) = rows_of(twist(c, v, c.end.translation(), size), model_.planar);
  const VectorXd gradient = MatrixXd(J).transpose() * VectorXd(e);
  out.stationary = gradient.norm() <= 1e-6 * J.norm() * norm;
  out.state = std::move(s);
  out.error = norm;
  out.iterations = std::min(it, max_iterations);
  return out;
}

LegSolution Kinematics::solve_leg_on(int leg, const Isometry3d& anchor, int branch, double tolerance,
                                     const LegState* extra_seed) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  const int combo = leg_combination(l, branch);
  ThreadSeeds& tls = thread_seeds;
  if (tls.id != id_) {
    tls.id = id_;
    tls.legs.assign(model_.legs.size(), {});
    for (std::size_t i = 0; i < model_.legs.size(); ++i)
      tls.legs[i].assign(std::size_t(1) << free_rules_of(model_.legs[i]), std::nullopt);
  }
  // Fast seeds first: the thread's last solution on this branch (a field's
  // neighbouring sample) and the caller's. Where they do not serve, fixed
  // seeds decide, so that an unreachable pose's miss distance does not depend
  // on what the thread solved before.
  std::vector<const LegState*> fast, fixed;
  if (tls.legs[std::size_t(leg)][std::size_t(combo)]) fast.push_back(&*tls.legs[std::size_t(leg)][std::size_t(combo)]);
  if (extra_seed) fast.push_back(extra_seed);
  // The leg at home on this branch first, then at home on its other branches.
  const auto& homes = home_states_[std::size_t(leg)];
  if (homes[std::size_t(combo)]) fixed.push_back(&*homes[std::size_t(combo)]);
  for (std::size_t other = 0; other < homes.size(); ++other)
    if (homes[other] && other != std::size_t(combo)) fixed.push_back(&*homes[other]);
  for (const LegState& s : spread_seeds_[std::size_t(leg)]) fixed.push_back(&s);

  LegSolution best;
  best.residual = kInf;
  // Beyond the leg's longest reach (its links end to end), or nearer than
  // its shortest, no seed can help: the miss is at least the distance
  // outside that shell, exactly that for a leg that can point its stretched
  // (or folded) chain at the anchor.
  const double distance = (anchor.translation() - l.base.translation()).norm();
  const Range& reach = leg_reach_[std::size_t(leg)];
  const double outside = std::max(distance - reach.hi, reach.lo - distance);
  if (outside > 1e-9 * model_.size) {
    best.state = spread_seeds_[std::size_t(leg)].front();
    best.residual = outside;
    best.status = Status::Unreachable;
    return best;
  }
  bool found_other_branch = false;
  // A solution on the branch whose actuator is outside its travel: the answer
  // only if the first fixed seed (the leg at home on the branch) does not
  // lead to one within it. (A leg may close the same
  // anchor twice on one branch, e.g. a prismatic leg at +d and, its universal
  // joint turned over, at -d; which one a seed finds must not decide the
  // status.)
  std::optional<LegSolution> outside_travel;
  int stationary_misses = 0;
  int iterations = 0;
  for (const auto* seeds : {&fast, &fixed}) {
    for (std::size_t i = 0; i < seeds->size(); ++i) {
      if (outside_travel && seeds == &fixed && i >= 1) break;
      // Towards a least-squares minimum only while it gains 0.1 % per step:
      // enough for the verdict and for the miss distance near the boundary,
      // where the residual is small and Gauss-Newton converges fast.
      LegSolveResult r = solve_leg(leg, anchor, *(*seeds)[i], 40, 1e-3);
      iterations += r.iterations;
      const double residual = r.error * model_.size;
      if (residual <= tolerance * model_.size) {
        if (signs_match(leg, r.state, anchor, branch)) {
          LegSolution solved;
          solved.state = std::move(r.state);
          solved.status = Status::Ok;
          solved.residual = residual;
          solved.iterations = iterations;
          if (!within_travel(leg, solved.state)) {
            if (!outside_travel) outside_travel = std::move(solved);
            continue;
          }
          tls.legs[std::size_t(leg)][std::size_t(combo)] = solved.state;
          return solved;
        }
        // Keep it only as a state to report (never empty), not as the answer.
        if (!found_other_branch && best.residual == kInf) best.state = r.state;
        found_other_branch = true;
        continue;
      }
      if (seeds == &fast) continue;
      if (residual < best.residual) {
        best.state = std::move(r.state);
        best.residual = residual;
      }
      // Two fixed seeds that both end at a least-squares minimum off the
      // target (not merely slow): the leg cannot reach it (more seeds would
      // repeat the verdict).
      if (r.stationary && ++stationary_misses >= 2 && !found_other_branch) break;
    }
  }
  if (outside_travel) {
    outside_travel->iterations = iterations;
    return *outside_travel;
  }
  if (found_other_branch) best.residual = 0.0;  // the leg reaches the anchor, on another branch
  if (best.state.values.size() == 0) best.state = spread_seeds_[std::size_t(leg)].front();
  best.status = found_other_branch ? Status::NotConverged : Status::Unreachable;
  best.iterations = iterations;
  return best;
}

PoseSolution Kinematics::inverse(const VectorXd& x, int branch, double tolerance) const {
  const PlatformPose p = pose(x);
  PoseSolution out;
  out.q = VectorXd::Zero(Index(model_.actuators.size()));
  auto rank = [](Status s) {
    switch (s) {
      case Status::Unreachable: return 4;
      case Status::NotConverged: return 3;
      case Status::Singular: return 2;
      case Status::OutOfLimits: return 1;
      default: return 0;
    }
  };
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    LegSolution s = solve_leg_on(int(leg), anchor(int(leg), p), branch, tolerance, nullptr);
    out.iterations += s.iterations;
    out.residual = std::max(out.residual, s.residual);
    const Leg& l = model_.legs[leg];
    for (int a : l.actuators) {
      const Actuator& act = model_.actuators[std::size_t(a)];
      const double v = s.state.values(l.steps[std::size_t(act.step)].variable);
      out.q(a) = act.prismatic ? v : wrap(v);
    }
    if (s.status == Status::Ok && !within_travel(int(leg), s.state)) s.status = Status::OutOfLimits;
    if (rank(s.status) > rank(out.status)) {
      out.status = s.status;
      out.failing_leg = int(leg);
    }
    out.legs.push_back(std::move(s));
  }
  return out;
}

PoseSolution Kinematics::inverse_near(const VectorXd& x, const VectorXd& q) const {
  const PlatformPose p = pose(x);
  PoseSolution out;
  out.q = VectorXd::Zero(Index(model_.actuators.size()));
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    const Leg& l = model_.legs[leg];
    const Actuator& act = model_.actuators[std::size_t(l.actuators.front())];
    const int var = l.steps[std::size_t(act.step)].variable;
    LegSolution best;
    double best_distance = kInf;
    for (int combo = 0; combo < (1 << free_rules_of(l)); ++combo) {
      LegSolution s = solve_leg_on(int(leg), anchor(int(leg), p), device_branch(l, combo), 1e-10, nullptr);
      if (s.status != Status::Ok) continue;
      const double v = s.state.values(var);
      const double distance = act.prismatic ? std::abs(v - q(l.actuators.front()))
                                            : std::abs(wrap(v - q(l.actuators.front())));
      if (distance < best_distance) {
        best_distance = distance;
        best = std::move(s);
      }
    }
    if (best.status != Status::Ok && out.status == Status::Ok) {
      out.status = Status::Unreachable;
      out.failing_leg = int(leg);
    }
    out.residual = std::max(out.residual, best.residual);
    out.q(l.actuators.front()) = act.prismatic ? best.state.values.size() ? best.state.values(var) : 0.0
                                               : best.state.values.size() ? wrap(best.state.values(var)) : 0.0;
    out.legs.push_back(std::move(best));
  }
  return out;
}

// ---- The Jacobian by reciprocal screws ----------------------------------------------

namespace {
// The platform's twists about r for each driven coordinate (translation:
// [0; e]; rotation: [w; w x (r - p)], w the angular velocity of a unit rate:
// the base axes where all three rotations are free, else the Euler rates).
MatrixXd platform_columns(const Model& m, const PlatformPose& pose, const Vector3d& r) {
  const bool all_rotations = m.free[3] && m.free[4] && m.free[5];
  // The Euler angles, for the rates (not needed where all three rotations are free).
  const Vector3d e = all_rotations ? Vector3d::Zero() : euler_of(pose.R);
  MatrixXd cols(6, m.driven());
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
}  // namespace

JacobianParts Kinematics::jacobian(const VectorXd& x, const PoseSolution& solved) const {
  const PlatformPose p = pose(x);
  const int n = model_.driven();
  const int a_count = int(model_.actuators.size());
  JacobianParts out;
  out.Jx = MatrixXd::Zero(a_count, n);
  out.Jq = MatrixXd::Zero(a_count, a_count);
  out.serial_margin.assign(model_.legs.size(), kInf);
  int row = 0;
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    const Leg& l = model_.legs[leg];
    const Chain c = walk(l, solved.legs[leg].state);
    const Vector3d r = c.end.translation();
    const int actuator = l.actuators.front();
    const int act_var = l.steps[std::size_t(model_.actuators[std::size_t(actuator)].step)].variable;
    const int m = model_.planar ? 3 : 6;
    MatrixXd passive(m, l.variables - 1);
    for (int v = 0, col = 0; v < l.variables; ++v)
      if (v != act_var) passive.col(col++) = rows_of(twist(c, v, r, model_.size), model_.planar);
    // The wrenches reciprocal to every passive twist: the last left singular
    // vectors, as many as the passive twists leave free at home (one for a leg
    // of five passive freedoms; more where the leg also holds the platform's
    // orientation, as a Falcon's revolute legs do). Of them, the actuation
    // wrench is the one the actuator works against; the others are
    // constraint wrenches, reciprocal to the actuator too.
    Eigen::JacobiSVD<MatrixXd> svd(passive, Eigen::ComputeFullU);
    const auto& sv = svd.singularValues();
    // A vanishing singular value beyond the leg's idle freedoms: the passive
    // joints lose a freedom, the leg is singular.
    const int expected_rank = passive_rank_[leg];
    int rank = 0;
    for (Index i = 0; i < sv.size(); ++i) rank += sv(i) > 1e-10 * sv(0);
    const MatrixXd reciprocal = svd.matrixU().rightCols(m - expected_rank);
    const VectorXd actuation = reciprocal.transpose() * rows_of(twist(c, act_var, r, model_.size), model_.planar);
    const VectorXd w = actuation.norm() > 0 ? VectorXd(reciprocal * actuation.normalized())
                                            : VectorXd(reciprocal.col(reciprocal.cols() - 1));
    const VectorXd platform = [&] {
      const MatrixXd cols = platform_columns(model_, p, r);
      MatrixXd kept(m, cols.cols());
      for (Index j = 0; j < cols.cols(); ++j) kept.col(j) = rows_of(cols.col(j), model_.planar);
      return VectorXd(w.transpose() * kept);
    }();
    out.Jx.row(row) = platform.transpose();
    const double jq = w.dot(rows_of(twist(c, act_var, r, model_.size), model_.planar));
    out.Jq(row, actuator) = jq;
    const bool prismatic = model_.actuators[std::size_t(actuator)].prismatic;
    out.serial_margin[leg] = model_.size * std::abs(jq) * (prismatic ? model_.size : 1.0);
    if (rank < expected_rank || std::abs(jq) <= 1e-12) {
      if (out.status == Status::Ok) out.singular_leg = int(leg);
      out.status = Status::Singular;
      out.serial_margin[leg] = rank < expected_rank ? 0.0 : out.serial_margin[leg];
    }
    ++row;
  }
  Eigen::JacobiSVD<MatrixXd> svd(out.Jx);
  const auto& sv = svd.singularValues();
  out.jx_condition = sv(sv.size() - 1) > 0 ? sv(0) / sv(sv.size() - 1) : kInf;
  if (!(out.jx_condition <= 1e12)) out.status = Status::Singular;
  out.J = out.Jx.partialPivLu().solve(out.Jq);
  return out;
}

// ---- Forward kinematics -------------------------------------------------------------

ForwardSolution Kinematics::forward(const VectorXd& q, const VectorXd& seed, double tolerance,
                                    int max_iterations) const {
  ForwardSolution out = forward_from(q, seed, tolerance, max_iterations);
  if (out.status == Status::Ok) return out;
  // Far from the seed, Gauss-Newton can stall where the closure's rank drops
  // on the way (a parallelogram leg's redundant orientation rows): follow the
  // actuators from the seed's to q in equal steps, each solved from the last,
  // which keeps the assembly mode nearest the seed.
  const PoseSolution start = inverse_near(seed, q);
  if (!assembled(start)) return out;
  VectorXd path = q - start.q;
  for (std::size_t a = 0; a < model_.actuators.size(); ++a)
    if (!model_.actuators[a].prismatic) path(Index(a)) = wrap(path(Index(a)));
  for (int pieces = 4; pieces <= 64; pieces *= 4) {
    ForwardSolution step;
    step.x = seed;
    int iterations = 0;
    for (int k = 1; k <= pieces; ++k) {
      step = forward_from(k == pieces ? q : VectorXd(start.q + path * (double(k) / pieces)), step.x, tolerance,
                          max_iterations);
      iterations += step.iterations;
      if (step.status != Status::Ok) break;
    }
    if (step.status == Status::Ok) {
      step.iterations = iterations;
      return step;
    }
  }
  return out;
}

ForwardSolution Kinematics::forward_from(const VectorXd& q, const VectorXd& seed, double tolerance,
                                         int max_iterations) const {
  ForwardSolution out;
  out.x = seed;
  const int n = model_.driven();
  const bool all_rotations = model_.free[3] && model_.free[4] && model_.free[5];
  // Leg states at the seed: each leg's solution with its actuator nearest q,
  // its actuator then set to q.
  PoseSolution start = inverse_near(seed, q);
  std::vector<LegState> legs;
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    const Leg& l = model_.legs[leg];
    LegState s = start.legs[leg].status == Status::Ok ? start.legs[leg].state : *home_states_[leg][0];
    const int a = l.actuators.front();
    const int var = l.steps[std::size_t(model_.actuators[std::size_t(a)].step)].variable;
    s.values(var) = model_.actuators[std::size_t(a)].prismatic ? q(a) : s.values(var) + wrap(q(a) - s.values(var));
    legs.push_back(std::move(s));
  }
  // Unknowns: the driven coordinates, then every leg's passive variables.
  std::vector<int> offset;
  int unknowns = n;
  for (const Leg& l : model_.legs) {
    offset.push_back(unknowns);
    unknowns += l.variables - 1;
  }
  const int m = model_.planar ? 3 : 6;
  const int rows = m * int(model_.legs.size());
  std::vector<bool> length_unknowns;  // translations and slides, for the step limit
  for (const TaskCoordinate& t : model_.task)
    if (t.extra < 0) length_unknowns.push_back(t.platform_coordinate < 3);
  for (const Leg& l : model_.legs) {
    const int act_var = l.steps[std::size_t(model_.actuators[std::size_t(l.actuators.front())].step)].variable;
    for (const Step& step : l.steps) {
      if (step.kind == Kind::Fixed || step.variable == act_var) continue;
      for (int k = 0; k < (step.kind == Kind::Spherical ? 3 : 1); ++k) length_unknowns.push_back(step.kind == Kind::Prismatic);
    }
  }
  VectorXd x = seed;
  // The closure errors at (xx, ls), with the pose and the legs' chains they
  // came from (kept for the next Jacobian).
  auto errors = [&](const VectorXd& xx, const std::vector<LegState>& ls, PlatformPose& p, std::vector<Chain>& chains) {
    p = pose(xx);
    chains.resize(model_.legs.size());
    VectorXd e(rows);
    for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
      walk_into(model_.legs[leg], ls[leg], chains[leg]);
      e.segment(Index(leg) * m, m) = rows_of(closure_error(chains[leg], anchor(int(leg), p), model_.size), model_.planar);
    }
    return e;
  };
  // `R`: the rotation of pose(xx), which the caller already has.
  auto step_pose = [&](const VectorXd& xx, const Matrix3d& R, const VectorXd& d) {
    VectorXd nx = xx;
    int col = 0;
    Vector3d dw = Vector3d::Zero();
    std::vector<int> rot_index(3, -1);
    for (std::size_t i = 0; i < model_.task.size(); ++i) {
      const TaskCoordinate& t = model_.task[i];
      if (t.extra >= 0) continue;
      if (t.platform_coordinate < 3 || !all_rotations) nx(Index(i)) += d(col);
      else {
        dw(t.platform_coordinate - 3) = d(col);
        rot_index[std::size_t(t.platform_coordinate - 3)] = int(i);
      }
      ++col;
    }
    if (all_rotations) {
      const Vector3d e = euler_of(rotation_of(dw) * R);
      for (int k = 0; k < 3; ++k) nx(rot_index[std::size_t(k)]) = e(k);
    }
    return nx;
  };
  // pose(x) and the legs' chains: updated with x and legs, never recomputed.
  PlatformPose p;
  std::vector<Chain> chains;
  VectorXd e = errors(x, legs, p, chains);
  double norm = e.norm();
  int it = 0;
  for (; it < max_iterations && norm > 1e-15; ++it) {
    MatrixXd J = MatrixXd::Zero(rows, unknowns);
    for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
      const Leg& l = model_.legs[leg];
      const Chain& c = chains[leg];
      const Vector3d r = c.end.translation();
      const MatrixXd cols = platform_columns(model_, p, r);
      for (Index j = 0; j < cols.cols(); ++j)
        J.block(Index(leg) * m, j, m, 1) = -rows_of(cols.col(j), model_.planar);
      const int act_var = l.steps[std::size_t(model_.actuators[std::size_t(l.actuators.front())].step)].variable;
      for (int v = 0, col = 0; v < l.variables; ++v)
        if (v != act_var)
          J.block(Index(leg) * m, offset[leg] + col++, m, 1) = rows_of(twist(c, v, r, model_.size), model_.planar);
    }
    VectorXd d = damped_step(J, e);
    limit_step(d, length_unknowns, model_.size);
    bool accepted = false;
    for (int halving = 0; halving < 30 && !accepted; ++halving, d *= 0.5) {
      const VectorXd tx = step_pose(x, p.R, d);
      std::vector<LegState> tl = legs;
      for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
        const Leg& l = model_.legs[leg];
        const int act_var = l.steps[std::size_t(model_.actuators[std::size_t(l.actuators.front())].step)].variable;
        VectorXd full = VectorXd::Zero(l.variables);
        for (int v = 0, col = 0; v < l.variables; ++v)
          if (v != act_var) full(v) = d(offset[leg] + col++);
        apply(l, tl[leg], full);
      }
      PlatformPose tp;
      std::vector<Chain> tchains;
      const VectorXd te = errors(tx, tl, tp, tchains);
      if (te.norm() < norm) {
        accepted = true;
        const bool floor = te.norm() > 0.5 * norm && norm < 1e-11;
        x = tx;
        legs = std::move(tl);
        p = std::move(tp);
        chains = std::move(tchains);
        e = te;
        norm = te.norm();
        if (floor) it = max_iterations;
      }
    }
    if (!accepted) break;
  }
  out.x = x;
  out.legs = std::move(legs);
  out.residual = norm * model_.size;
  out.iterations = std::min(it, max_iterations);
  out.status = norm <= tolerance ? Status::Ok : Status::NotConverged;
  // An assembly whose legs break the design's own branch rules (a "sign" in
  // the description) is not this device: report it as not converged.
  if (out.status == Status::Ok) {
    for (std::size_t leg = 0; leg < model_.legs.size() && out.status == Status::Ok; ++leg) {
      const Leg& l = model_.legs[leg];
      const std::vector<int> signs = rule_signs(int(leg), out.legs[leg], anchor(int(leg), p));
      for (std::size_t r = 0; r < l.rules.size(); ++r)
        if (l.rules[r].fixed_sign != 0 && signs[r] * l.rules[r].fixed_sign < 0) out.status = Status::NotConverged;
    }
  }
  return out;
}

// ---- Margins -------------------------------------------------------------------------

double Kinematics::limits_margin(const VectorXd& q) const {
  double margin = kInf;
  for (std::size_t a = 0; a < model_.actuators.size(); ++a) {
    const Actuator& act = model_.actuators[a];
    if (!act.limited) continue;
    double v = q(Index(a));
    if (!act.prismatic) {
      // The representative of the angle nearest the range's middle.
      const double mid = 0.5 * (act.range.lo + act.range.hi);
      v = mid + wrap(v - mid);
    }
    const double d = std::min(v - act.range.lo, act.range.hi - v);
    margin = std::min(margin, act.prismatic ? d : d * model_.size);
  }
  return margin;
}

bool assembled(const PoseSolution& s) {
  for (const LegSolution& l : s.legs)
    if (l.status != Status::Ok && l.status != Status::OutOfLimits) return false;
  return true;
}

double Kinematics::reach_margin(const PoseSolution& s, const JacobianParts* parts) const {
  double margin = kInf;
  for (const LegSolution& l : s.legs)
    if (l.status != Status::Ok && l.status != Status::OutOfLimits) margin = std::min(margin, -l.residual);
  if (!parts) return margin;
  for (double m : parts->serial_margin) margin = std::min(margin, m);
  return std::min(margin, limits_margin(s.q));
}

double Kinematics::reach_margin(const VectorXd& x, int branch) const {
  const PoseSolution s = inverse(x, branch, 1e-10);
  if (!assembled(s)) return reach_margin(s, nullptr);
  const JacobianParts parts = jacobian(x, s);
  return reach_margin(s, &parts);
}

// ---- Drawing ---------------------------------------------------------------------------

Kinematics::LegDrawing Kinematics::draw_leg(int leg, const LegState& state) const {
  const Chain c = walk(model_.legs[std::size_t(leg)], state);
  return {c.step_frame};
}

// ---- Construction: home on every branch, mobility ---------------------------------------------

Kinematics::Kinematics(Model model) : model_(std::move(model)), id_(next_id++) {
  // Each leg's longest and shortest reach from its base: the chain's end is
  // the base plus its fixed translations, each turned by the joints before
  // it, so by the triangle inequality its distance lies between the longest
  // translation less all the others and their sum, whatever the joints do.
  // Unbounded with a slide (IK solves without the travel, which makes
  // out-of-limits).
  for (const Leg& l : model_.legs) {
    double sum = 0, longest = 0;
    bool slides = false;
    for (const Step& step : l.steps) {
      const double length = step.kind == Kind::Fixed ? step.transform.translation().norm() : 0.0;
      sum += length;
      longest = std::max(longest, length);
      slides = slides || step.kind == Kind::Prismatic;
    }
    leg_reach_.push_back(slides ? Range{0.0, kInf} : Range{std::max(0.0, 2 * longest - sum), sum});
  }
  // Spread seeds: the chain as written, then joint values spread over a turn.
  for (const Leg& l : model_.legs) {
    std::vector<LegState> seeds;
    for (int j = 0; j < 12; ++j) {
      LegState s;
      s.values = VectorXd::Zero(l.variables);
      for (const Step& step : l.steps) {
        if (step.kind == Kind::Revolute) s.values(step.variable) = j == 0 ? 0.0 : kPi * golden(j, step.variable);
        if (step.kind == Kind::Prismatic) {
          const bool actuated = step.actuator >= 0;
          const Range r = actuated ? model_.actuators[std::size_t(step.actuator)].range : Range{0, 0};
          s.values(step.variable) = actuated ? 0.5 * (r.lo + r.hi) + 0.25 * (r.hi - r.lo) * golden(j, 0) : 0.0;
        }
        if (step.kind == Kind::Spherical)
          s.spheres.push_back(j == 0 ? Matrix3d::Identity()
                                     : rotation_of(kPi * Vector3d(golden(j, step.variable), golden(j, step.variable + 1),
                                                                   golden(j, step.variable + 2)) /
                                                   std::sqrt(3.0)));
      }
      seeds.push_back(std::move(s));
    }
    spread_seeds_.push_back(std::move(seeds));
  }
  // Home on every combination of each leg's free rules.
  const PlatformPose home = pose(model_.home);
  home_states_.resize(model_.legs.size());
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    const Leg& l = model_.legs[leg];
    home_states_[leg].assign(std::size_t(1) << free_rules_of(l), std::nullopt);
    const Isometry3d a = anchor(int(leg), home);
    double best = kInf;
    for (const LegState& seed : spread_seeds_[leg]) {
      LegSolveResult r = solve_leg(int(leg), a, seed, 100, 1e-9);
      best = std::min(best, r.error * model_.size);
      if (r.error * model_.size > 1e-10 * model_.size) continue;
      for (int combo = 0; combo < int(home_states_[leg].size()); ++combo)
        if (!home_states_[leg][std::size_t(combo)] && signs_match(int(leg), r.state, a, device_branch(l, combo)))
          home_states_[leg][std::size_t(combo)] = r.state;
    }
    std::ostringstream msg;
    if (!home_states_[leg][0]) {
      msg << "description.legs \"" << l.name << "\": the leg does not reach its anchor at home";
      if (best < kInf && best > 1e-10 * model_.size) msg << " (misses by " << best << " " << model_.length_unit << ")";
      else msg << " on branch 0 (every branch rule positive or as its sign says)";
      throw std::invalid_argument(msg.str());
    }
  }

  // Mobility: the joint graph against the closure's rank at home.
  const int lambda = model_.planar ? 3 : 6;
  int bodies = 1 + int(model_.platform_names.size()), joints = int(model_.platform_names.size()) - 1, freedom = int(model_.extras.size());
  for (const Leg& l : model_.legs) {
    std::set<std::string> names;
    for (const Step& s : l.steps)
      if (s.kind != Kind::Fixed) names.insert(s.joint);
    joints += int(names.size());
    bodies += int(names.size()) - 1;
    freedom += l.variables;
  }
  mobility_.gruebler = lambda * (bodies - 1 - joints) + freedom;
  int free_coordinates = 0;
  for (int c = 0; c < 6; ++c) free_coordinates += model_.free[std::size_t(c)] && (!model_.planar || c == 0 || c == 1 || c == 5);
  mobility_.fixed = lambda - free_coordinates;
  {
    const int m = model_.planar ? 3 : 6;
    int columns = model_.driven();
    for (const Leg& l : model_.legs) columns += l.variables;
    MatrixXd C = MatrixXd::Zero(m * Index(model_.legs.size()), columns);
    int col = model_.driven();
    for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
      const Leg& l = model_.legs[leg];
      const Chain c = walk(l, *home_states_[leg][0]);
      const Vector3d r = c.end.translation();
      const MatrixXd pc = platform_columns(model_, home, r);
      for (Index j = 0; j < pc.cols(); ++j) C.block(Index(leg) * m, j, m, 1) = -rows_of(pc.col(j), model_.planar);
      MatrixXd passive(m, l.variables);
      for (int v = 0; v < l.variables; ++v) {
        passive.col(v) = rows_of(twist(c, v, r, model_.size), model_.planar);
        C.block(Index(leg) * m, col++, m, 1) = passive.col(v);
      }
      const int act_var = l.steps[std::size_t(model_.actuators[std::size_t(l.actuators.front())].step)].variable;
      MatrixXd without(m, l.variables - 1);
      for (int v = 0, k = 0; v < l.variables; ++v)
        if (v != act_var) without.col(k++) = passive.col(v);
      Eigen::FullPivLU<MatrixXd> lu(without);
      lu.setThreshold(1e-9);
      mobility_.idle += int(without.cols()) - int(lu.rank());
      passive_rank_.push_back(int(lu.rank()));
    }
    Eigen::FullPivLU<MatrixXd> lu(C);
    lu.setThreshold(1e-9);
    mobility_.closure_rank = columns - int(lu.rank());
  }
  mobility_.freedoms = mobility_.closure_rank - mobility_.idle;
  if (mobility_.freedoms != int(model_.actuators.size())) {
    std::ostringstream msg;
    msg << "description: the mechanism has " << mobility_.freedoms << " freedom(s) at home (closure "
        << mobility_.closure_rank << ", idle " << mobility_.idle << ") but " << model_.actuators.size()
        << " actuator(s); each freedom of the task needs one actuator (Gruebler-Kutzbach count "
        << mobility_.gruebler << ", " << mobility_.fixed << " platform coordinate(s) held by the description)";
    throw std::invalid_argument(msg.str());
  }
  if (model_.driven() != int(model_.actuators.size())) {
    std::ostringstream msg;
    msg << "description.task: " << model_.driven() << " driven coordinate(s) but " << model_.actuators.size()
        << " actuator(s)";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace linkscape::described
