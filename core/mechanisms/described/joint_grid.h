// The grid over a leg's joints that the sampled reaches share
// (sampled_reach.h, turned_reach.h): which joints move its end and over
// what, how many samples each takes for a proved margin, the frames they
// move, their ends and branch signs at every sample, and which branch
// combinations each sample stands for.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "core/mechanisms/described/closed_form.h"  // LegState
#include "core/mechanisms/described/model.h"

namespace linkscape::described::joint_grid {

// One freedom (a dimension of the grid) over [lo, hi] in `count` steps
// (their centres): a revolute's angle, a slide's travel, or a ball joint's
// direction for the link after it (polar angle from the link's direction
// as written, then azimuth; its spin about the link moves nothing sampled).
// `wraps`: a full turn, whose ends are neighbours.
struct Freedom {
  enum class Kind { Turn, Slide, Polar, Azimuth };
  Kind kind = Kind::Turn;
  int step = 0;
  double lever = 0;  // how far a unit of it moves the end, at most
  double lo = 0, hi = 0;
  bool wraps = false;
  int count = 1;
  double half_step() const { return 0.5 * (hi - lo) / count; }
  double value(int i) const { return lo + (i + 0.5) * (hi - lo) / count; }
};

// Counts per dimension for about `budget` samples, each one's half step
// times its lever alike; returns the margin (the sum of those).
double allot(std::vector<Freedom>& freedoms, double budget);

// An orthonormal basis whose first column is the unit u.
Eigen::Matrix3d basis_along(const Eigen::Vector3d& u);

// The leg as the frames its sampled joints move: the frame after motion m
// is frame m times lead[m] times its motion; every step's frame (before
// it) is one of those times a fixed offset. The joints it does not sample
// keep the seed's values.
struct Frames {
  std::vector<Eigen::Isometry3d> lead;    // per motion (a revolute, a slide, a ball)
  std::vector<int> frame_of_step;         // per step: the frame it follows (0: the base's, m + 1: motion m's)
  std::vector<Eigen::Isometry3d> offset;  // per step: from that frame to the step
  Eigen::Isometry3d tail = Eigen::Isometry3d::Identity();  // from the last frame to the end
};

Frames frames_of(const Leg& leg, const std::vector<Freedom>& freedoms, const LegState& seed);

// The end's point and every rule's sign at each sample, the last dimension
// fastest; each frame recomputed only where a motion before it moved.
struct Samples {
  std::vector<Eigen::Vector3d> ends;
  std::vector<std::int8_t> signs;  // per sample, per rule
};

Samples walk_samples(const Leg& leg, const std::vector<Freedom>& freedoms, const Frames& f);

// The joints that move a leg's end point, as the freedoms a grid samples:
// up to its last link or slide (the joints after it only turn the end),
// each revolute over its actuator's travel (where `within_travel` and it has
// one) or a full turn, a slide over its actuator's travel, a ball joint (the
// last of them) over every direction of its link. None, and why not, where
// they cannot be sampled so.
struct EndFreedoms {
  std::vector<Freedom> freedoms;
  int last = -1;  // the last step that moves the end
  int ball = -1;  // the ball joint's step
  std::string why_not;
};

EndFreedoms end_freedoms(const Leg& leg, const std::vector<Actuator>& actuators, bool planar, bool within_travel);

// Per sample, the combinations of the leg's free rules (at most six) it
// stands for: bit c set for combination c. From its signs, where it tells
// them; a sample next to where a rule's sign changes stands for both signs.
// `turned_about`: the samples leave the first joint as the seed has it (the
// turned reach), and a rule along a direction not that joint's axis changes
// as it turns (a triple of the leg's centres and axes turns with them).
std::vector<std::uint64_t> combinations_of(const Leg& leg, const std::vector<Freedom>& freedoms, const Samples& samples,
                                           int last, int ball, const Eigen::Vector3d* turned_about);

}  // namespace linkscape::described::joint_grid
