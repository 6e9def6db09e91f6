// Closed-form inverse kinematics of the leg patterns parallel devices are
// built from, recognised from a leg's steps (docs/described-internals.md,
// "How each leg is solved"). A recognised leg yields every solution of its
// closure at once (up to four), each a full leg state; the caller keeps the
// one the branch rules and the travel select. Legs of no known pattern keep
// the numerical solver.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/mechanisms/described/model.h"

namespace linkscape::described {

// A leg's joint values: one per revolute/prismatic step (spherical steps'
// slots unused) and a rotation per spherical joint.
struct LegState {
  Eigen::VectorXd values;
  std::vector<Eigen::Matrix3d> spheres;
};

enum class LegPattern {
  Numeric,        // no known pattern: damped Gauss-Newton from seeds
  // The rod patterns end in a spherical joint, or after a universal ball in a
  // universal (RUU, PUU, UPU: end_joints).
  CrankRod,       // revolute actuator, crank, ball (spherical/universal), rod, spherical (Delta, 6-RUS)
  SlideRod,       // prismatic actuator, carriage, ball, rod, spherical (linear Delta)
  Extensible,     // ball, prismatic actuator, spherical (Gough-Stewart UPS/SPS)
  PlanarDyad,     // planar: revolute actuator, link, revolute, link, revolute (five-bar, 3-RRR)
  ThreeRevolute,  // revolute actuator whose axis holds the second joint, two revolutes, spherical (PATHOS-II)
  CrankParallelogram,  // revolute actuator, knee, parallelogram (two revolutes), revolute grip: the end kept level (Falcon)
};

// The pattern's name as a description names it ("crank-rod", ..., "numeric").
std::string pattern_name(LegPattern p);

// Whether the leg's step and the next are two passive revolutes of two
// joints as written, one right after the other (so at one point) with
// crossing axes: a universal joint, recognised as one.
bool meets_as_universal(const Leg& leg, std::size_t step);
// The pattern a description names; throws std::invalid_argument listing the names.
LegPattern pattern_of_name(const std::string& name);
// A leg's joints in order as the patterns read them, the actuated one
// starred, e.g. "revolute*, universal, spherical" (describe says it of a
// numeric leg, to set beside the patterns' sequences).
std::string joint_sequence(const Leg& leg);

// A leg's closed form: where its joints are in its chain and the design's
// constant vectors (leg base frame).
struct ClosedFormLeg {
  LegPattern pattern = LegPattern::Numeric;
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();  // base frame <- the actuator's frame
  int actuator_step = -1;
  Eigen::Vector3d actuator_axis = Eigen::Vector3d::UnitZ();  // local
  // The fixed transforms between the joints (identity where absent).
  Eigen::Isometry3d after_actuator = Eigen::Isometry3d::Identity();  // Extensible: ball -> slide
  Eigen::Isometry3d rod = Eigen::Isometry3d::Identity();   // ball -> last joint
  Eigen::Isometry3d tail = Eigen::Isometry3d::Identity();  // last joint -> end
  // The ball (spherical, universal or, planar, a revolute) after the actuator
  // (before it: Extensible).
  int ball_step = -1;
  int ball_joints = 0;  // 1: spherical or a planar revolute; 2: universal
  bool ball_read = false;  // a branch rule reads the ball's joints (a universal's two solutions both count)
  // ThreeRevolute: the second and third revolutes, the links after them.
  int second_step = -1, third_step = -1;
  Eigen::Vector3d second_link = Eigen::Vector3d::Zero(), third_link = Eigen::Vector3d::Zero();
  int end_step = -1;  // the last joint (spherical, universal; planar: revolute)
  // 2: the rod ends in a universal joint, as it starts in one (RUU, PUU,
  // UPU): the leg also holds the platform's orientation, and a candidate
  // whose end cannot take the anchor's orientation is no solution.
  int end_joints = 1;
  // A branch rule reads the last joint or a step after it: a candidate is
  // judged only once its last joint is closed.
  bool end_read = false;
  double offset = 0;  // Extensible: the fixed length along the slide
  // CrankParallelogram, in the actuator's frame (A its axis, B the
  // parallelogram's, n = A x B): the knee about +-A, the parallelogram's
  // joints about B (upper) and +-B (lower), the grip (end_step) about +-A.
  // Closed, the parallelogram keeps the knee bar's direction (lower = -upper)
  // and the grip undoes the crank's and knee's turns; the end then lies at
  // height + side cos(upper - phase) along A, and across A at the end of a
  // planar 2R: the thigh, then the parallelogram's reach along n turned by
  // the knee, bar - side sin(upper - phase).
  struct Parallelogram {
    int knee_step = -1, upper_step = -1, lower_step = -1;
    double knee_sign = 1, lower_sign = 1, grip_sign = 1;
    Eigen::Vector3d across = Eigen::Vector3d::UnitX();  // n
    Eigen::Vector3d thigh = Eigen::Vector3d::Zero();    // the first link's part across A
    double thigh_phase = 0;  // the angle from the thigh to n about A
    double height = 0, side = 0, phase = 0, bar = 0;
  } parallelogram;
};

// The leg's pattern, or nullopt (numeric). Only structure that the closed
// form solves exactly is recognised: a degenerate design (a crank of zero
// length, a rod of zero length) stays numeric.
std::optional<ClosedFormLeg> recognise(const Model& model, const Leg& leg);

// The sign of sin(angle), as an angle rule reads it: the angle's own sign
// within [-pi, pi] (where sin(pi), rounded, is still positive), else by sin.
inline int sine_sign(double angle) {
  const double v = std::abs(angle) <= 3.141592653589793 ? angle : std::sin(angle);
  return v > 0 ? 1 : v < 0 ? -1 : 0;
}

// The sign a branch rule asks for on a device branch.
inline int wanted_sign(const BranchRule& r, int branch) {
  return r.fixed_sign != 0 ? r.fixed_sign : ((branch >> r.free_index) & 1) ? -1 : 1;
}

// Every solution of the leg's closure for `anchor` (base frame), or the
// distance by which the anchor is out of the leg's reach.
struct LegCandidates {
  int count = 0;
  std::array<LegState, 4> states;
  double miss = 0;        // length unit, where count == 0
  bool undecided = false;  // a degenerate pose (the anchor on an axis): use the numerical solver
  // Per candidate, where its last joint is left open: the frame at that joint.
  std::array<Eigen::Isometry3d, 4> end_frames;
  std::array<bool, 4> open{};
  bool dropped = false;  // the branch's angle rules left out some (possible) solution
};
// With `leave_ends_open` (and no branch rule reading the last joint), each
// candidate's last joint is left for close_open_end: a caller that keeps
// one candidate closes only that one. With a branch >= 0, a three-revolute
// leg's solutions whose angles break an angle rule of that branch are left
// out (`dropped`).
void solve_closed(const ClosedFormLeg& form, const Model& model, const Leg& leg, const Eigen::Isometry3d& anchor,
                  LegCandidates& out, bool leave_ends_open = false, int branch = -1);
// Closes the last joint of a candidate that solve_closed left open (`frame`:
// its end_frames entry).
void close_open_end(const ClosedFormLeg& form, const Model& model, const Leg& leg, const Eigen::Isometry3d& anchor,
                    LegState& s, const Eigen::Isometry3d& frame);

}  // namespace linkscape::described
