// Forward kinematics of a described mechanism, and its construction: each
// leg solved at home on every branch, the mobility checked.
#include <Eigen/LU>
#include <Eigen/QR>
#include <atomic>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/closed_form.h"
#include "core/mechanisms/described/kinematics.h"

namespace linkscape::described {

using namespace internal;  // its Eigen names too

namespace {
std::atomic<std::uint64_t> next_id{1};

// How well an ok forward answer knows the pose, a fraction of the size: as
// IK's default tolerance.
constexpr double kPoseAccuracy = 1e-10;

// |(J^+)_pose| |e| (Frobenius over the first `pose` unknowns), the pose's
// first-order error for a closure error of norm `e`. The pseudo-inverse by a
// rank-revealing (complete orthogonal) decomposition: the null directions of
// passive joints alone (a rod spinning about itself), zero to rounding, are
// dropped rather than divided by.
double pose_error_bound(const MatrixXd& J, int pose, double e) {
  if (e == 0.0) return 0.0;
  const Eigen::CompleteOrthogonalDecomposition<MatrixXd> cod(J);
  return e * cod.pseudoInverse().topRows(pose).norm();
}
}  // namespace

// ---- Forward kinematics -------------------------------------------------------------

ForwardSolution Kinematics::forward(const VectorXd& q, const VectorXd& seed, double tolerance,
                                    int max_iterations) const {
  ForwardSolution out = forward_from(q, seed, tolerance, max_iterations);
  const auto answers = [](const ForwardSolution& f) { return f.status == Status::Ok || f.status == Status::Singular; };
  if (answers(out)) return out;
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
    int iterations = 0, k = 1;
    // A step on the way that pins its pose less well than an answer must
    // (singular) still seeds the next; only the last step is the answer.
    for (; k <= pieces; ++k) {
      step = forward_from(k == pieces ? q : VectorXd(start.q + path * (double(k) / pieces)), step.x, tolerance,
                          max_iterations);
      iterations += step.iterations;
      if (!answers(step)) break;
    }
    if (k > pieces && answers(step)) {
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
  // The closure's derivative in the unknowns at the current pose and chains.
  auto closure_jacobian = [&] {
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
    return J;
  };
  for (; it < max_iterations && norm > 1e-15; ++it) {
    const MatrixXd J = closure_jacobian();
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
  // A small closure error pins the pose only where the closure is well
  // conditioned in it: at a type II singularity a residual of 1e-15 leaves
  // the pose 1e-7 of the size off. Where the first-order pose error,
  // |(J^+)_pose| |e|, exceeds what an ok IK answer promises (1e-10 of the
  // size), the pose is not known: singular. Null directions of the legs'
  // passive joints alone (a parallelogram's) have no pose part.
  if (out.status == Status::Ok && pose_error_bound(closure_jacobian(), n, norm) > std::max(tolerance, kPoseAccuracy))
    out.status = Status::Singular;
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

// ---- Construction: home on every branch, mobility ---------------------------------------------

Kinematics::Kinematics(Model model) : model_(std::move(model)), id_(next_id++) {
  has_joint_limits_ = model_.has_joint_limits();
  has_capsules_ = model_.has_capsules();
  const char* aids = std::getenv("LINKSCAPE_NUMERIC_AIDS");
  aided_ = !(aids && std::string(aids) == "off");
  sampled_ = std::make_shared<SampledReaches>(model_.legs.size());
  // Each leg's reach bounds (reach.h). About the first joint only for a
  // spatial device: a planar one closes x and y, not z.
  for (const Leg& l : model_.legs) {
    leg_reach_.push_back(chain_reach(l));
    leg_reach_about_first_.push_back(model_.planar ? FirstJointReach{} : first_joint_reach(l));
    leg_travel_reach_.push_back(chain_reach(l, 0, &model_.actuators, model_.planar));
    leg_travel_about_first_.push_back(first_joint_reach(l, &model_.actuators, model_.planar));
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
    first_joints_.push_back(first_joint(l));
    home_ends_.emplace_back(home_states_[leg].size(), Vector3d::Zero());
    for (std::size_t combo = 0; combo < home_states_[leg].size(); ++combo)
      if (home_states_[leg][combo]) home_ends_[leg][combo] = walk(l, *home_states_[leg][combo]).end.translation();
    std::ostringstream msg;
    if (!home_states_[leg][0]) {
      msg << "description.legs \"" << l.name << "\": the leg does not reach its anchor at home";
      if (best < kInf && best > 1e-10 * model_.size) msg << " (misses by " << best << " " << model_.length_unit << ")";
      else msg << " on branch 0 (every branch rule positive or as its sign says)";
      throw std::invalid_argument(msg.str());
    }
  }

  // Closed forms: each recognised leg must reproduce its home solution (a
  // safeguard: a leg whose closed form would not close stays numerical).
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    const Leg& l = model_.legs[leg];
    std::optional<ClosedFormLeg> form = recognise(model_, l);
    std::string warning;
    if (form) {
      LegCandidates c;
      solve_closed(*form, model_, l, anchor(int(leg), home), c);
      bool closes = c.count > 0;
      for (int i = 0; i < c.count; ++i)
        closes = closes && rows_of(closure_error(walk(l, c.states[std::size_t(i)]), anchor(int(leg), home), model_.size),
                                   model_.planar)
                                   .norm() <= 1e-9;
      if (!closes) form.reset();
      if (form) warning = unseparated(int(leg), c, anchor(int(leg), home));
    }
    branch_warnings_.push_back(warning);
    const std::string found = pattern_name(form ? form->pattern : LegPattern::Numeric);
    std::optional<LegPattern> named;
    try {
      if (!l.pattern.empty()) named = pattern_of_name(l.pattern);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("description.legs \"" + l.name + "\": pattern: " + e.what());
    }
    if (named && pattern_name(*named) != found)
      throw std::invalid_argument("description.legs \"" + l.name + "\": pattern: the description names \"" + l.pattern +
                                  "\" but the leg is solved as \"" + found + "\"");
    closed_.push_back(form);
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
    std::vector<Vector3d> ends;  // each leg's end at home
    for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
      const Leg& l = model_.legs[leg];
      const Chain c = walk(l, *home_states_[leg][0]);
      const Vector3d r = c.end.translation();
      ends.push_back(r);
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
    // Each held coordinate released on its own: where the closure's rank
    // does not grow with its column, the legs do not hold it.
    static const char* const kNames[6] = {"x", "y", "z", "rx", "ry", "rz"};
    for (int coordinate = 0; coordinate < 6; ++coordinate) {
      if (model_.free[std::size_t(coordinate)] || (model_.planar && coordinate >= 2 && coordinate <= 4)) continue;
      MatrixXd released(C.rows(), C.cols() + 1);
      released << C, MatrixXd::Zero(C.rows(), 1);
      for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
        Vector6d twist;
        if (coordinate < 3) twist << Vector3d::Zero(), Vector3d::Unit(coordinate) / model_.size;
        else twist << Vector3d::Unit(coordinate - 3), Vector3d::Unit(coordinate - 3).cross(ends[leg] - home.p) / model_.size;
        released.block(Index(leg) * m, C.cols(), m, 1) = -rows_of(twist, model_.planar);
      }
      Eigen::FullPivLU<MatrixXd> with(released);
      with.setThreshold(1e-9);
      if (with.rank() == lu.rank()) mobility_.held_by_description_alone.push_back(kNames[coordinate]);
    }
  }
  mobility_.freedoms = mobility_.closure_rank - mobility_.idle;
  if (mobility_.freedoms != int(model_.actuators.size())) {
    std::ostringstream msg;
    msg << "description: the mechanism has " << mobility_.freedoms << " freedom(s) at home (closure "
        << mobility_.closure_rank << ", idle " << mobility_.idle << ") but " << model_.actuators.size()
        << " actuator(s); each freedom of the task needs one actuator (Gruebler-Kutzbach count "
        << mobility_.gruebler << ", " << mobility_.fixed << " platform coordinate(s) held by the description)";
    // A link written with no length joins two joints at one point (a
    // parameter set to 0), or with none beside the device's size (another
    // one absurdly long): the likely cause, named.
    for (const Leg& l : model_.legs)
      for (std::size_t i = 1; i + 1 < l.steps.size(); ++i) {
        const Step& st = l.steps[i];
        const double length = st.transform.translation().norm();
        if (st.kind != Step::Kind::Fixed || !st.transform.linear().isIdentity(0) || length > 1e-12 * model_.size)
          continue;
        msg << "; leg \"" << l.name << "\" has a link of ";
        if (length == 0) msg << "no length";
        else msg << length << " " << model_.length_unit << ", nothing beside the device's size of " << model_.size << " " << model_.length_unit;
        msg << " after joint " << l.steps[i - 1].joint;
        break;
      }
    throw std::invalid_argument(msg.str());
  }
  if (model_.driven() != int(model_.actuators.size())) {
    std::ostringstream msg;
    msg << "description.task: " << model_.driven() << " driven coordinate(s) but " << model_.actuators.size()
        << " actuator(s)";
    throw std::invalid_argument(msg.str());
  }
  // The count can hold where the actuators hold nothing: a crank of zero
  // length turns without moving its rod. At a singular home the device does
  // not do what its actuators say (whether or not the assembly found there
  // keeps a joint within its limits: the rod spins with the idle crank).
  const PoseSolution at_home = inverse(model_.home, 0, 1e-10);
  if (at_home.status == Status::Ok || at_home.status == Status::OutOfLimits) {
    const JacobianParts parts = jacobian(model_.home, at_home);
    constraint_rank_ = parts.constraint_rank;  // the rank every pose's constraint wrenches keep
    if (parts.status == Status::Singular) {
      std::ostringstream msg;
      msg << "description: the device is singular at home: ";
      if (parts.singular_leg >= 0)
        msg << "leg \"" << model_.legs[std::size_t(parts.singular_leg)].name
            << "\"'s actuator does not move its anchor there (type I; a crank or a slide of no length?)";
      else
        msg << "its actuators do not hold the platform there (type II: Jx singular)";
      msg << "; move home or change the design";
      throw std::invalid_argument(msg.str());
    }
  }
  // A rule that is 0 at home chooses nothing there (a direction normal to
  // a planar device's plane, a triple that names one joint twice, a leg
  // folded at home): its branches would be one assembly.
  const PlatformPose home_pose = pose(model_.home);
  for (std::size_t leg = 0; leg < model_.legs.size(); ++leg) {
    const Leg& l = model_.legs[leg];
    const std::vector<double> scales = rule_scales(int(leg), *home_states_[leg][0], anchor(int(leg), home_pose));
    for (std::size_t r = 0; r < scales.size(); ++r)
      if (std::abs(scales[r]) <= 1e-9)
        throw std::invalid_argument("description.legs \"" + l.name + "\": branch rule " + std::to_string(r + 1) +
                                    " is 0 at home, so it does not tell the assemblies apart there (a direction "
                                    "normal to a planar device's plane, a triple naming one joint twice, or a leg "
                                    "folded or stretched at home?)");
  }
}

bool Kinematics::home_toward(int leg, int combo, const Isometry3d& anchor, LegState& out) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  const std::optional<LegState>& home = home_states_[std::size_t(leg)][std::size_t(combo)];
  if (!home) return false;
  const FirstJoint& joint = first_joints_[std::size_t(leg)];
  if (joint.step == l.steps.size()) return false;
  const Step* first = &l.steps[joint.step];
  const Isometry3d& T = joint.frame;
  const Vector3d to_end = home_ends_[std::size_t(leg)][std::size_t(combo)] - T.translation();
  const Vector3d to_anchor = anchor.translation() - T.translation();
  if (first->kind == Kind::Spherical) {  // the least turn taking the end's direction to the anchor's
    if (to_end.norm() < 1e-9 * model_.size || to_anchor.norm() < 1e-9 * model_.size) return false;
    const Matrix3d turn = Eigen::Quaterniond::FromTwoVectors(to_end, to_anchor).toRotationMatrix();
    out = *home;
    out.spheres.front() = T.linear().transpose() * turn * T.linear() * out.spheres.front();
    return true;
  }
  const Vector3d a = T.linear() * first->axis;
  double move = 0;
  if (first->kind == Kind::Prismatic) {
    move = a.dot(to_anchor - to_end);
  } else {
    const Vector3d e = to_end - a * a.dot(to_end), t = to_anchor - a * a.dot(to_anchor);
    if (e.norm() < 1e-9 * model_.size || t.norm() < 1e-9 * model_.size) return false;
    move = std::atan2(a.dot(e.cross(t)), e.dot(t));
  }
  out = *home;
  out.values(first->variable) += move;
  return true;
}

// Two of a leg's closed-form solutions at home with different actuator
// values within its travel and the same sign for every branch rule: the
// rules choose nothing between them (the first is taken). Empty where they do.
std::string Kinematics::unseparated(int leg, const LegCandidates& c, const Isometry3d& at) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  const Actuator& a = model_.actuators[std::size_t(l.actuators.front())];
  const int v = l.steps[std::size_t(a.step)].variable;
  const double scale = a.prismatic ? model_.size : 1.0;
  for (int i = 0; i < c.count; ++i)
    for (int j = i + 1; j < c.count; ++j) {
      const double qi = c.states[std::size_t(i)].values(v), qj = c.states[std::size_t(j)].values(v);
      // The travel chooses where it holds one of them only (a slide's negative length).
      const bool both_in_travel = !a.limited || (a.range.contains(qi) && a.range.contains(qj));
      if (!both_in_travel || std::abs(qi - qj) <= 1e-6 * scale ||
          rule_signs(leg, c.states[std::size_t(i)], at) != rule_signs(leg, c.states[std::size_t(j)], at))
        continue;
      std::ostringstream msg;
      const double shown = a.prismatic ? 1.0 : 180 / M_PI;
      msg << (l.rules.empty() ? "no branch rule tells apart" : "its branch rules give the same signs to")
          << " two of its assemblies at home (" << a.name << " = " << qi * shown << " and " << qj * shown
          << (a.prismatic ? " " + model_.length_unit : " deg") << "): the first is taken";
      return msg.str();
    }
  return "";
}

double Kinematics::closure_residual(const VectorXd& x, const PoseSolution& s) const {
  const PlatformPose p = pose(x);
  double worst = 0.0;
  for (std::size_t leg = 0; leg < model_.legs.size() && leg < s.legs.size(); ++leg) {
    const LegSolution& l = s.legs[leg];
    if ((l.status != Status::Ok && l.status != Status::OutOfLimits) || l.open_end) continue;
    const Chain c = walk(model_.legs[leg], l.state);
    const double e = rows_of(closure_error(c, anchor(int(leg), p), model_.size), model_.planar).norm();
    worst = std::max(worst, e * model_.size);
  }
  return worst;
}

}  // namespace linkscape::described
