// Kinematics of a described mechanism, all numerical: per-leg inverse
// kinematics by damped Gauss-Newton on the leg's closure, forward kinematics
// by Gauss-Newton on every loop closure at once, the Jacobian by reciprocal
// screws, conditioning, reach margin and mobility
// (docs/described-mechanisms.md, "What Linkscape computes from it").
//
// Closure of a leg: the frame at the end of its chain equals its anchor frame.
// The error is e = [rotation vector of R_anchor R_end^T; (p_anchor - p_end) / size]
// (dimensionless; planar devices keep the rows of rz, x, y). Joint twists are
// taken about the anchor point, so a leg's equations do not depend on where
// the base frame's origin is.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/interference.h"
#include "core/mechanisms/described/closed_form.h"
#include "core/mechanisms/described/model.h"
#include "core/mechanisms/described/reach.h"
#include "core/mechanisms/described/sampled_reach.h"
#include "core/mechanisms/described/turned_reach.h"
#include "core/range.h"
#include "core/status.h"

namespace linkscape::described {

// The platform's pose for a task vector (the model's task order).
struct PlatformPose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::VectorXd extras;
  std::vector<Eigen::Isometry3d> bodies;  // base <- platform body
};

struct LegSolution {
  LegState state;
  Status status = Status::Unreachable;
  double residual = 0.0;  // length unit
  int iterations = 0;
  // The state's last joint left open (inverse_into where the pose does not
  // assemble): the frame at that joint, from which it closes.
  bool open_end = false;
  Eigen::Isometry3d end_frame = Eigen::Isometry3d::Identity();
};

// What bounds an assembly beyond its actuators' travel: its passive joints'
// limits and its links' interference (limits.cpp). +inf where the device
// states none.
struct Stops {
  double joint_margin_deg = std::numeric_limits<double>::infinity();  // the nearest passive joint to its limit; < 0 beyond
  int joint_leg = -1, joint_limit = -1;  // that joint: the leg, the index in its limits
  double clearance = std::numeric_limits<double>::infinity();  // the smallest gap between two links (length unit); < 0: they overlap
  std::array<int, 4> pair{-1, -1, -1, -1};  // that pair: leg and capsule of each
  bool hold() const { return joint_margin_deg >= 0 && clearance >= 0; }
  int leg_at_fault() const { return joint_margin_deg < 0 ? joint_leg : clearance < 0 ? pair[0] : -1; }
};

struct PoseSolution {
  std::vector<LegSolution> legs;
  Status status = Status::Ok;
  int failing_leg = -1;
  double residual = 0.0;  // largest leg residual
  int iterations = 0;     // summed over the legs
  Eigen::VectorXd q;      // actuators as reported (Kinematics::reported)
  Stops stops;            // where every leg assembles and the device states limits or links
  bool stopped = false;   // out-of-limits by a passive joint or two links rather than an actuator
};

// Every leg closes (ok, or ok but outside its actuator's travel).
bool assembled(const PoseSolution& s);

// A condition of Jx beyond this is singular (type II).
inline constexpr double kSingularCondition = 1e12;

struct JacobianParts {
  Eigen::MatrixXd Jx, Jq, J;  // J = -Jx^-1 Jq (driven task rows x actuators), physical units
  std::vector<double> serial_margin;  // per leg: size * |Jq_ii| for the unit wrench (length)
  // Of the dimensionless Jx (+inf if singular): 2-norm by an SVD (solver
  // Numeric), else the LU's 1-norm estimate.
  double jx_condition = 0.0;
  Status status = Status::Ok;  // Singular at a type I, type II or constraint singularity
  int singular_leg = -1;       // type I: the leg
  // The rank of the constraint wrenches the legs transmit besides their
  // actuation wrenches (a universal joint's couple, a parallelogram's), and
  // whether it fell below its rank at home: the platform gains a freedom
  // that the legs held there (a 3-UPU's legs' couples in one plane).
  int constraint_rank = 0;
  bool constraint_singular = false;
};

struct ForwardSolution {
  Status status = Status::NotConverged;
  Eigen::VectorXd x;  // task (model order)
  std::vector<LegState> legs;
  double residual = 0.0;
  int iterations = 0;
};

struct Mobility {
  int gruebler = 0;      // Gruebler-Kutzbach count of the joint graph
  int fixed = 0;         // platform coordinates held by the description
  int idle = 0;          // idle freedoms at home (rank of the passive joints' null space)
  int closure_rank = 0;  // numerical mobility of the closure at home (held extras)
  int freedoms = 0;      // device freedoms: closure_rank - idle (+ extras)
  // The held platform coordinates that the legs as written leave free ("rx",
  // ...): with the actuators locked the platform could still move so.
  std::vector<std::string> held_by_description_alone;
};

// How legs are solved: in closed form where a leg's pattern is recognised
// (the numerical solver elsewhere), or all numerically (the reference).
enum class LegSolver { Fastest, Numeric };

class Kinematics {
 public:
  // Solves home on every branch; throws std::invalid_argument naming the leg
  // that does not reach or the mobility that does not match.
  explicit Kinematics(Model model);

  const Model& model() const { return model_; }
  const Mobility& mobility() const { return mobility_; }
  int branches() const { return 1 << model_.free_rules; }

  PlatformPose pose(const Eigen::VectorXd& x) const;
  void pose_into(const Eigen::VectorXd& x, PlatformPose& out) const;
  // The leg's anchor frame in the base frame at this pose.
  Eigen::Isometry3d anchor(int leg, const PlatformPose& pose) const;

  // The largest closure error of the legs that close in `s` (length unit):
  // a closed form's, which inverse() leaves at 0, evaluated in double.
  double closure_residual(const Eigen::VectorXd& x, const PoseSolution& s) const;
  // Every leg on `branch` (bits of the free rules). Seeds: the thread's last
  // solution, the leg at home on the branch, spread seeds.
  PoseSolution inverse(const Eigen::VectorXd& x, int branch, double tolerance,
                       LegSolver solver = LegSolver::Fastest) const;
  // The same at a pose, into `out` (its storage reused: a field's samples
  // allocate nothing once the thread's first has run). Without
  // `close_every_leg`, where the pose does not assemble, a closed-form leg's
  // last joint may be left open (LegSolution::open_end): the states of such
  // a pose serve nothing but their actuators.
  void inverse_into(const PlatformPose& pose, int branch, double tolerance, LegSolver solver, PoseSolution& out,
                    bool close_every_leg = true) const;
  // Each leg on the solution whose actuator is nearest q (q, x consistent).
  PoseSolution inverse_near(const Eigen::VectorXd& x, const Eigen::VectorXd& q,
                            LegSolver solver = LegSolver::Fastest) const;

  // The leg's closed form (nullptr: solved numerically) and the bounds of the
  // distance from its base to its anchor (outside them it cannot close).
  const ClosedFormLeg* closed_form(int leg) const;
  // How many legs have a closed form (the others are solved numerically).
  int closed_form_count() const {
    return int(std::count_if(closed_.begin(), closed_.end(), [](const auto& f) { return f.has_value(); }));
  }
  const Range& reach(int leg) const { return leg_reach_[std::size_t(leg)]; }
  // The bound about its first joint, which the numerical solver takes first.
  const FirstJointReach& reach_about_first_joint(int leg) const { return leg_reach_about_first_[std::size_t(leg)]; }
  // How far the anchor lies outside the leg's reach bounds (> 0: it cannot
  // close): from its base, and about its first joint unless told not to.
  double reach_outside(int leg, const Eigen::Isometry3d& anchor, bool about_first_joint = true) const;
  // The leg's joints sampled on a grid within their travel (sampled_reach.h):
  // built at its first use, once per design.
  const SampledReach& sampled_reach(int leg) const;
  // The rest of the leg sampled about a first joint that turns, whatever
  // the travel (turned_reach.h): built at the numerical solver's first
  // use of the leg, once per design.
  const TurnedReach& turned_reach(int leg) const;
  // The same bounds with the leg's actuators held within their travel, and
  // (unless told not to) its sampled reach on the device branch `branch`
  // (> 0: no assembly of the leg within its travel on that branch reaches
  // the anchor).
  double travel_outside(int leg, const Eigen::Isometry3d& anchor, int branch, bool sampled = true) const;
  // The rank of the leg's passive joints' twists at home: one less than the
  // closure's rows where the leg transmits one wrench (its closed wrench serves).
  int passive_rank(int leg) const { return passive_rank_[std::size_t(leg)]; }
  // Where the leg's branch rules do not tell its assemblies at home apart; empty where they do.
  std::string branch_warning(int leg) const {
    return std::size_t(leg) < branch_warnings_.size() ? branch_warnings_[std::size_t(leg)] : std::string();
  }
  // At a solved pose (its legs' states).
  // Solver Fastest: each recognised leg's reciprocal wrench in closed form.
  JacobianParts jacobian(const Eigen::VectorXd& x, const PoseSolution& solved,
                         LegSolver solver = LegSolver::Fastest) const;
  // The same at the pose `solved` was solved at, into `out` (storage reused).
  void jacobian_into(const PlatformPose& pose, const PoseSolution& solved, LegSolver solver, JacobianParts& out) const;
  ForwardSolution forward(const Eigen::VectorXd& q, const Eigen::VectorXd& seed, double tolerance,
                          int max_iterations) const;

  // Reach margin on a branch (length unit), see the format page.
  double reach_margin(const Eigen::VectorXd& x, int branch) const;
  // The same of a solved pose: `parts` (its Jacobian) where it assembles, else null.
  double reach_margin(const PoseSolution& s, const JacobianParts* parts) const;
  double limits_margin(const Eigen::VectorXd& q) const;

  // Whether the device states passive-joint limits, link capsules.
  bool has_joint_limits() const { return has_joint_limits_; }
  bool has_capsules() const { return has_capsules_; }
  // The passive joints' and the links' margins of an assembly (its legs' states).
  Stops stops(const PlatformPose& pose, const std::vector<LegState>& legs) const;
  Stops stops(const PlatformPose& pose, const PoseSolution& solved) const;
  // Why stops do not hold, naming the leg and joint or the two links:
  // "leg 2 ball joint elbow2 at 38.2 deg beyond its 35.0 deg cone"; "" where they hold.
  std::string stop_reason(const Stops& s, const std::vector<LegState>& legs) const;
  // Each link's capsule at an assembly (base frame), leg by leg, for drawing and tests.
  std::vector<std::vector<interference::Capsule>> capsules(const PlatformPose& pose,
                                                           const std::vector<LegState>& legs) const;

  // The frames of a leg's steps (base frame), for drawing.
  struct LegDrawing {
    std::vector<Eigen::Isometry3d> frames;  // per step: the frame after it
  };
  LegDrawing draw_leg(int leg, const LegState& state) const;

  double wrap(double angle) const;
  // An actuator's value as reported: a revolute's angle in (-pi, pi], or,
  // where its travel is limited, within a turn centred on the travel.
  double reported(const Actuator& act, double value) const;

 private:
  struct LegSolveResult;
  // forward() from the seed in one Gauss-Newton run; forward() follows the
  // actuators' path where this stalls.
  ForwardSolution forward_from(const Eigen::VectorXd& q, const Eigen::VectorXd& seed, double tolerance,
                               int max_iterations) const;
  // Damped Gauss-Newton on one leg; stops when an iteration gains less than
  // `crawl` (relative) away from a solution. The variable `held` (>= 0)
  // stays where the state has it.
  LegSolveResult solve_leg(int leg, const Eigen::Isometry3d& anchor, LegState state, int max_iterations,
                           double crawl, int held = -1) const;
  // How far the anchor lies outside the leg's sampled reach on `branch`
  // (-inf where it has none).
  double sampled_outside(int leg, const Eigen::Isometry3d& anchor, int branch) const;
  // Beyond how far outside a bound the numerical solver's legs are refused:
  // its tolerance (at least 1e-9), times the size.
  double refusal_cut(double tolerance) const { return std::max(1e-9, tolerance) * model_.size; }
  // Into `out` (its state's storage reused).
  void solve_leg_on(int leg, const Eigen::Isometry3d& anchor, int branch, double tolerance,
                    const LegState* extra_seed, LegSolver solver, LegSolution& out, bool close = true) const;
  // The leg at home on combination `combo`, its first joint turned about (or
  // slid along) its axis so that the home end comes nearest the anchor (a
  // spherical one: by the least turn that points the end at it): a seed that
  // depends on the anchor alone. False where the turn is not defined (the
  // anchor or the end on the axis, or at the centre).
  bool home_toward(int leg, int combo, const Eigen::Isometry3d& anchor, LegState& out) const;
  // Whether two states of a leg are one assembly (every joint's centre
  // within 0.01 of the size).
  bool same_assembly(int leg, const LegState& a, const LegState& b) const;
  // Where the seeds closed the leg only outside its travel or off the branch:
  // the actuator swept over its travel (the passive joints following it),
  // released where the closure error is least. An assembly found on the
  // branch within the travel goes to `out`; false where none is. Its
  // iterations are added to `iterations`.
  bool search_travel(int leg, const Eigen::Isometry3d& anchor, int branch, double tolerance,
                     const std::vector<const LegState*>& starts, LegSolution& out, int& iterations) const;
  // The numerical solver from seeds (after the reach bounds).
  LegSolution solve_leg_numeric(int leg, const Eigen::Isometry3d& anchor, int branch, double tolerance,
                                const LegState* extra_seed) const;
  // The closed form's solution on the branch into `out`; false where it cannot decide.
  // Its last joint left open (out.open_end) unless `close`.
  bool solve_leg_closed(int leg, const Eigen::Isometry3d& anchor, int branch, LegSolution& out, bool close) const;
  // A leg decided without a solution (its state the first spread seed).
  void leave_unsolved(int leg, Status status, double residual, LegSolution& out) const;
  // Closes the leg's last joint where solve_leg_closed left it open.
  void close_end(int leg, const Eigen::Isometry3d& anchor, LegSolution& s) const;
  bool signs_match(int leg, const LegState& state, const Eigen::Isometry3d& anchor, int branch) const;
  // Whether the leg's actuator lies within its travel (a revolute one: some turn of it).
  bool within_travel(int leg, const LegState& state) const;
  // Whether the leg's own passive-joint limits hold at `state` (true where it
  // states none or they are switched off).
  bool leg_limits_hold(int leg, const LegState& state) const;
  std::vector<int> rule_signs(int leg, const LegState& state, const Eigen::Isometry3d& anchor) const;
  // Each rule's value over the size (a triple over its square, an angle's
  // sine): how far the state is from the rule's zero.
  std::vector<double> rule_scales(int leg, const LegState& state, const Eigen::Isometry3d& anchor) const;
  std::string unseparated(int leg, const LegCandidates& c, const Eigen::Isometry3d& anchor) const;

  Model model_;
  Mobility mobility_;
  std::uint64_t id_ = 0;
  // Per leg, per combination of its free rules' signs: the leg at home.
  std::vector<std::vector<std::optional<LegState>>> home_states_;
  std::vector<std::vector<LegState>> spread_seeds_;
  // Per leg: its reach bounds with its actuators within their travel.
  std::vector<Range> leg_travel_reach_;
  std::vector<FirstJointReach> leg_travel_about_first_;
  // Per leg, per combination: the end's centre at home; per leg: its first
  // joint (home_toward).
  std::vector<std::vector<Eigen::Vector3d>> home_ends_;
  std::vector<FirstJoint> first_joints_;
  // Per leg: the shortest (lo) and longest (hi) distance from its base to
  // its end, and its reach about its first joint (reach.h).
  std::vector<Range> leg_reach_;
  std::vector<FirstJointReach> leg_reach_about_first_;
  // Per leg: its sampled reach, built at its first use, and the iterations
  // the numerical solver's searches of its travel have taken (shared by
  // copies: they depend on the model alone).
  struct SampledReaches {
    std::vector<std::once_flag> built, turned_built;
    std::vector<SampledReach> legs;
    std::vector<TurnedReach> turned;
    std::vector<std::atomic<int>> search_iterations;
    explicit SampledReaches(std::size_t n)
        : built(n), turned_built(n), legs(n), turned(n), search_iterations(n) {}
  };
  std::shared_ptr<SampledReaches> sampled_;
  // Per leg: the rank of its passive joints' twists at home (6 less the
  // wrenches the leg transmits: the actuation wrench and any constraint ones).
  std::vector<int> passive_rank_;
  int constraint_rank_ = 0;  // JacobianParts::constraint_rank at home
  // Per closed-form leg (empty for the others): where its branch rules do not
  // tell its assemblies at home apart (Kinematics::unseparated).
  std::vector<std::string> branch_warnings_;
  std::vector<std::optional<ClosedFormLeg>> closed_;
  bool has_joint_limits_ = false, has_capsules_ = false;
  // The numerical solver's aids: its reach bounds' refusals and its row
  // seeding (the thread's last solution). Off (LINKSCAPE_NUMERIC_AIDS=off
  // when the device is built), the solver decides every leg from its fixed
  // seeds alone: the reference their speed-up is measured against, with the
  // same verdicts.
  bool aided_ = true;
};

}  // namespace linkscape::described
