#include "core/mechanisms/described/kinematics.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/mechanisms/described/chain.h"

namespace linkscape::described {

using namespace internal;  // its Eigen names too

namespace {
// How far p lies outside a leg's bounds: the shell `reach` about its base
// (distances in the plane where asked), and the bound about its first joint
// where given.
double outside_bounds(const Vector3d& base, const Vector3d& p, const Range& reach, const FirstJointReach* about,
                      bool in_plane) {
  Vector3d from_base = p - base;
  if (in_plane) from_base.z() = 0;
  const double distance = from_base.norm();
  const double outside = std::max(distance - reach.hi, reach.lo - distance);
  return about ? std::max(outside, about->outside(p)) : outside;
}
}  // namespace


// ---- Poses -------------------------------------------------------------------

PlatformPose Kinematics::pose(const VectorXd& x) const {
  PlatformPose p;
  pose_into(x, p);
  return p;
}

void Kinematics::pose_into(const VectorXd& x, PlatformPose& p) const {
  std::array<double, 6> c = model_.fixed;
  p.extras.setZero(Index(model_.extras.size()));
  for (std::size_t i = 0; i < model_.task.size(); ++i) {
    const TaskCoordinate& t = model_.task[i];
    if (t.platform_coordinate >= 0) c[std::size_t(t.platform_coordinate)] = x(Index(i));
    else p.extras(t.extra) = x(Index(i));
  }
  p.p = {c[0], c[1], c[2]};
  p.R = euler_zyx(c[3], c[4], c[5]);
  const Isometry3d platform = Eigen::Translation3d(p.p) * Isometry3d(p.R);
  p.bodies.clear();
  for (const Isometry3d& body : model_.platform_frames(p.extras)) p.bodies.push_back(platform * body);
}

Isometry3d Kinematics::anchor(int leg, const PlatformPose& pose) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  return pose.bodies[std::size_t(l.platform)] * l.anchor;
}

double Kinematics::wrap(double a) const {
  if (std::abs(a) < kPi) return a;  // as remainder() leaves it (most angles the closed forms give)
  a = std::remainder(a, 2 * kPi);
  return a <= -kPi ? a + 2 * kPi : a;
}

// ---- Branch rules ------------------------------------------------------------

std::vector<double> Kinematics::rule_scales(int leg, const LegState& state, const Isometry3d& anchor) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  const Chain c = walk(l, state);
  std::vector<double> out;
  for (const BranchRule& r : l.rules) {
    if (r.kind == BranchRule::Kind::Angle) out.push_back(std::sin(state.values(l.steps[std::size_t(r.steps[0])].variable)));
    else out.push_back(rule_value(r, c, anchor) / std::pow(model_.size, r.kind == BranchRule::Kind::Along ? 1 : 2));
  }
  return out;
}

std::vector<int> Kinematics::rule_signs(int leg, const LegState& state, const Isometry3d& anchor) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  const Chain c = walk(l, state);
  std::vector<int> signs;
  for (const BranchRule& r : l.rules) signs.push_back(rule_sign(r, l, c, state, anchor));
  return signs;
}

bool Kinematics::signs_match(int leg, const LegState& state, const Isometry3d& anchor, int branch) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  if (l.rules.empty()) return true;  // no chain to walk
  // Angle rules read the joint values alone: the chain is walked only for
  // the others, as far as the last step they read.
  thread_local Chain c;
  int through = -1;
  for (const BranchRule& r : l.rules)
    if (r.kind != BranchRule::Kind::Angle) through = std::max({through, r.steps[0], r.steps[1], r.steps[2]});
  if (through >= 0) walk_into(l, state, c, through);
  for (const BranchRule& r : l.rules) {
    if (rule_sign(r, l, c, state, anchor) * wanted_sign(r, branch) < 0) return false;
  }
  return true;
}

bool Kinematics::within_travel(int leg, const LegState& state) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  for (int a : l.actuators) {
    const Actuator& act = model_.actuators[std::size_t(a)];
    if (!act.limited) continue;
    const double v = state.values(l.steps[std::size_t(act.step)].variable);
    const double w = act.prismatic ? v : wrap(v);
    const bool inside = act.prismatic ? act.range.contains(v)
                                      : act.range.contains(w) || act.range.contains(w + 2 * kPi) ||
                                            act.range.contains(w - 2 * kPi);
    if (!inside) return false;
  }
  return true;
}

// ---- Leg inverse kinematics ----------------------------------------------------

const ClosedFormLeg* Kinematics::closed_form(int leg) const {
  const auto& c = closed_[std::size_t(leg)];
  return c ? &*c : nullptr;
}

bool Kinematics::solve_leg_closed(int leg, const Isometry3d& anchor, int branch, LegSolution& out, bool close) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  const ClosedFormLeg& form = *closed_[std::size_t(leg)];
  thread_local LegCandidates candidates;
  // Candidates judged on their joint values and centres; only the one kept
  // is closed. Those the branch's angle rules reject are not made at all.
  solve_closed(form, model_, l, anchor, candidates, true, branch);
  if (candidates.undecided) return false;
  // On the branch, within the travel first (as the numerical solver: a leg
  // that closes its anchor twice on one branch is ok if either is in travel),
  // else outside it (ok: inverse() says out-of-limits).
  // The first candidate on the branch (and within the travel, and within its
  // passive limits, where asked), or -1.
  const auto first_on_branch = [&](bool in_travel, bool in_limits) {
    for (int i = 0; i < candidates.count; ++i) {
      const LegState& s = candidates.states[std::size_t(i)];
      if ((!in_travel || within_travel(leg, s)) && signs_match(leg, s, anchor, branch) &&
          (!in_limits || leg_limits_hold(leg, s)))
        return i;
    }
    return -1;
  };
  // A rod ending in a universal joint closes each actuator value twice (the
  // rod half a turn about itself): the one its passive limits allow first.
  int kept = form.end_joints == 2 && has_joint_limits_ ? first_on_branch(true, true) : -1;
  if (kept < 0) kept = first_on_branch(true, false);
  if (kept < 0) kept = first_on_branch(false, false);
  // None on the branch: the state reported is the first of all solutions.
  if (kept < 0 && candidates.dropped) solve_closed(form, model_, l, anchor, candidates, true);
  out.residual = 0.0;
  out.iterations = 0;
  out.open_end = false;
  if (candidates.count == 0) {
    leave_unsolved(leg, Status::Unreachable, candidates.miss, out);
    return true;
  }
  // Closing only on another branch, the leg does not reach the anchor on
  // this one (decided: every solution is known); its miss stays 0, a lower
  // bound (the closed form does not give the distance to the branch's reach).
  out.status = kept >= 0 ? Status::Ok : Status::Unreachable;
  kept = std::max(kept, 0);
  out.state = candidates.states[std::size_t(kept)];
  out.open_end = candidates.open[std::size_t(kept)];
  out.end_frame = candidates.end_frames[std::size_t(kept)];
  if (close) close_end(leg, anchor, out);
  return true;
}

void Kinematics::leave_unsolved(int leg, Status status, double residual, LegSolution& out) const {
  out.state = spread_seeds_[std::size_t(leg)].front();
  out.status = status;
  out.residual = residual;
  out.iterations = 0;
  out.open_end = false;
}

void Kinematics::close_end(int leg, const Isometry3d& anchor, LegSolution& s) const {
  if (!s.open_end) return;
  close_open_end(*closed_[std::size_t(leg)], model_, model_.legs[std::size_t(leg)], anchor, s.state, s.end_frame);
  s.open_end = false;
}

const SampledReach& Kinematics::sampled_reach(int leg) const {
  std::call_once(sampled_->built[std::size_t(leg)], [&] {
    sampled_->legs[std::size_t(leg)] = linkscape::described::sample_reach(
        model_.legs[std::size_t(leg)], model_.actuators, model_.planar, spread_seeds_[std::size_t(leg)].front());
  });
  return sampled_->legs[std::size_t(leg)];
}

const TurnedReach& Kinematics::turned_reach(int leg) const {
  std::call_once(sampled_->turned_built[std::size_t(leg)], [&] {
    const Leg& l = model_.legs[std::size_t(leg)];
    const TurnedReach* like = nullptr;  // a copy's, sampled already
    for (int other = 0; other < leg && !like; ++other)
      if (same_from_first_joint(model_.legs[std::size_t(other)], l, model_.actuators)) like = &turned_reach(other);
    sampled_->turned[std::size_t(leg)] =
        sample_turned_reach(l, model_.actuators, model_.planar, spread_seeds_[std::size_t(leg)].front(), like);
  });
  return sampled_->turned[std::size_t(leg)];
}

double Kinematics::reach_outside(int leg, const Isometry3d& anchor, bool about_first_joint) const {
  return outside_bounds(model_.legs[std::size_t(leg)].base.translation(), anchor.translation(),
                        leg_reach_[std::size_t(leg)],
                        about_first_joint ? &leg_reach_about_first_[std::size_t(leg)] : nullptr, false);
}

double Kinematics::travel_outside(int leg, const Isometry3d& anchor, int branch, bool sampled) const {
  const double bounds = outside_bounds(model_.legs[std::size_t(leg)].base.translation(), anchor.translation(),
                                       leg_travel_reach_[std::size_t(leg)], &leg_travel_about_first_[std::size_t(leg)],
                                       model_.planar);
  return sampled ? std::max(bounds, sampled_outside(leg, anchor, branch)) : bounds;
}

double Kinematics::sampled_outside(int leg, const Isometry3d& anchor, int branch) const {
  const SampledReach& sampled = sampled_reach(leg);
  if (!sampled.built) return -kInf;
  const int combo = leg_combination(model_.legs[std::size_t(leg)], branch);
  return sampled.travel[std::size_t(combo)].outside(anchor.translation());
}

void Kinematics::solve_leg_on(int leg, const Isometry3d& anchor, int branch, double tolerance,
                              const LegState* extra_seed, LegSolver solver, LegSolution& out, bool close) const {
  // Outside a bound no seed can help: the miss is at least the distance
  // outside it (exactly that from the base's shell for a leg that can point
  // its stretched or folded chain at the anchor; from the first joint's for
  // a crank and a rod). Before the numerical solver, only beyond its
  // tolerance (within it, it accepts).
  const auto missed_by = [&](double outside, double cut) {
    if (!(outside > cut)) return false;
    leave_unsolved(leg, Status::Unreachable, outside, out);
    return true;
  };
  // A closed form decides exactly: before it, only the shell about the base
  // (as the SIMD lanes take it); before the numerical solver, every bound.
  const bool closed = solver == LegSolver::Fastest && closed_[std::size_t(leg)];
  const double numeric_cut = refusal_cut(tolerance);
  if ((closed || aided_) && missed_by(reach_outside(leg, anchor, !closed), closed ? 1e-9 * model_.size : numeric_cut))
    return;
  if (closed && solve_leg_closed(leg, anchor, branch, out, close)) return;
  if (closed && aided_ && missed_by(reach_outside(leg, anchor), numeric_cut)) return;
  // A leg of no known pattern: its reach about its first joint, sampled
  // finely (not a leg with a closed form, which `newton` alone solves
  // numerically: the reference, where the build would cost more than it saves).
  if (aided_ && !closed_[std::size_t(leg)] && missed_by(turned_reach(leg).outside(anchor.translation()), numeric_cut))
    return;
  out = solve_leg_numeric(leg, anchor, branch, tolerance, extra_seed);
}

PoseSolution Kinematics::inverse(const VectorXd& x, int branch, double tolerance, LegSolver solver) const {
  PoseSolution out;
  inverse_into(pose(x), branch, tolerance, solver, out);
  return out;
}

void Kinematics::inverse_into(const PlatformPose& p, int branch, double tolerance, LegSolver solver,
                              PoseSolution& out, bool close_every_leg) const {
  out.status = Status::Ok;
  out.failing_leg = -1;
  out.residual = 0.0;
  out.iterations = 0;
  out.q.setZero(Index(model_.actuators.size()));
  out.stops = Stops();
  out.stopped = false;
  out.legs.resize(model_.legs.size());
  auto rank = [](Status s) {
    switch (s) {
      case Status::Unreachable: return 4;
      case Status::NotConverged: return 3;
      case Status::Singular: return 2;
      case Status::OutOfLimits: return 1;
      default: return 0;
    }
  };
  // A leg that a reach bound rules out makes the pose unreachable: the legs
  // the numerical solver would take are then not solved (their misses,
  // which the reach margin takes the largest of, left out; where the bounds
  // are exact, as for a crank and a rod, they would close).
  const auto numeric = [&](std::size_t leg) { return solver == LegSolver::Numeric || !closed_[leg]; };
  const double cut = refusal_cut(tolerance);
  thread_local std::vector<double> outside;  // per numerically solved leg
  outside.assign(model_.legs.size(), -kInf);
  bool ruled_out = false;
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    if (numeric(leg) && aided_) outside[leg] = reach_outside(int(leg), anchor(int(leg), p));
    ruled_out = ruled_out || outside[leg] > cut;
  }
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    LegSolution& s = out.legs[leg];
    if (ruled_out && numeric(leg)) {
      if (outside[leg] > cut) leave_unsolved(int(leg), Status::Unreachable, outside[leg], s);
      else leave_unsolved(int(leg), Status::NotConverged, 0.0, s);  // not solved
    } else {
      solve_leg_on(int(leg), anchor(int(leg), p), branch, tolerance, nullptr, solver, s, close_every_leg);
    }
    out.iterations += s.iterations;
    out.residual = std::max(out.residual, s.residual);
    const Leg& l = model_.legs[leg];
    for (int a : l.actuators) {
      const Actuator& act = model_.actuators[std::size_t(a)];
      out.q(a) = reported(act, s.state.values(l.steps[std::size_t(act.step)].variable));
    }
    if (s.status == Status::Ok && !within_travel(int(leg), s.state)) s.status = Status::OutOfLimits;
    if (rank(s.status) > rank(out.status)) {
      out.status = s.status;
      out.failing_leg = int(leg);
    }
  }
  if (!close_every_leg && assembled(out))
    for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) close_end(int(leg), anchor(int(leg), p), out.legs[leg]);
  if ((has_joint_limits_ || has_capsules_) && assembled(out)) {
    out.stops = stops(p, out);
    if (out.status == Status::Ok && !out.stops.hold()) {
      out.status = Status::OutOfLimits;
      out.failing_leg = out.stops.leg_at_fault();
      out.stopped = true;
    }
  }
}

PoseSolution Kinematics::inverse_near(const VectorXd& x, const VectorXd& q, LegSolver solver) const {
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
      LegSolution s;
      solve_leg_on(int(leg), anchor(int(leg), p), device_branch(l, combo), 1e-10, nullptr, solver, s);
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
    out.q(l.actuators.front()) = best.state.values.size() ? reported(act, best.state.values(var)) : 0.0;
    out.legs.push_back(std::move(best));
  }
  return out;
}

// ---- Margins -------------------------------------------------------------------------

double Kinematics::reported(const Actuator& act, double v) const {
  if (act.prismatic) return v;
  if (!act.limited) return wrap(v);
  // The representative of the angle nearest the range's middle: within the
  // travel where the angle is (a five-bar's crank at 186 deg of 0..210 deg,
  // not -174 deg).
  const double mid = 0.5 * (act.range.lo + act.range.hi);
  return mid + wrap(v - mid);
}

double Kinematics::limits_margin(const VectorXd& q) const {
  double margin = kInf;
  for (std::size_t a = 0; a < model_.actuators.size(); ++a) {
    const Actuator& act = model_.actuators[a];
    if (!act.limited) continue;
    const double v = reported(act, q(Index(a)));
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
  // A passive joint's margin as an actuator's: the size times the angle.
  margin = std::min({margin, s.stops.joint_margin_deg * kPi / 180 * model_.size, s.stops.clearance});
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

}  // namespace linkscape::described
