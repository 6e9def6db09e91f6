// A leg's reach about a first joint that turns, sampled in the two
// coordinates that turn leaves as they are (sampled_reach.h samples all
// three): for a leg of no known pattern, the numerical solver's first seed,
// its refusal of an anchor near the reach's edge, and of its travel search.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "core/mechanisms/described/model.h"
#include "core/mechanisms/described/sampled_reach.h"
#include "core/range.h"

namespace linkscape::described {

// A leg whose first joint turns (a revolute): the ends of the rest of its
// chain at every value of their joints, whatever the travel, as distance
// from that joint's axis and height along it, which its turn leaves as they
// are. Every assembly's end, at any turn, lies within the margin of one of
// them in those two coordinates: an anchor farther from all of them cannot
// be reached. Two coordinates where a grid over the whole chain needs three,
// so the margin is a few times finer: it refuses anchors near the reach's
// edge that the shells of reach.h admit, where every seed of the numerical
// solver would crawl to a least-squares minimum off the anchor.
struct TurnedReach {
  bool built = false;
  std::string why_not;  // where not built
  int samples = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), axis = Eigen::Vector3d::UnitZ();  // the first joint's
  bool in_plane = false;  // a planar device's: the distance from the axis alone
  BallSetDistance rest;   // the ends as (distance from the axis, height along it, 0)
  // How far an end at p lies outside (a lower bound on the miss; > 0: no
  // assembly reaches p); -inf where not built.
  double outside(const Eigen::Vector3d& p) const;

  // Azimuths about the axis from `zero` towards `onwards` (units square to
  // the axis and to each other), the way the joint turns an end: a joint
  // value q turns a sample at azimuth psi (taken with the joint at
  // `seed_value`) to psi + q - seed_value.
  Eigen::Vector3d zero = Eigen::Vector3d::UnitX(), onwards = Eigen::Vector3d::UnitY();
  bool limited = false;  // the first joint's actuator has a travel (`travel`)
  Range travel;
  double seed_value = 0;
  // The grid of cells over the samples' (distance, height), row-major.
  double cell = 1;
  Eigen::Vector2d grid_lo = Eigen::Vector2d::Zero();
  int columns = 0, rows = 0;

  // The samples by their cell, with their azimuths and the combinations of
  // the leg's free rules (at most six) they stand for: shared by copies;
  // null where not built.
  struct Nearest;
  std::shared_ptr<const Nearest> nearest;
  // What the samples on combination `combo` within a few cells of p tell:
  struct Nearby {
    // Whether one within the margin of p turns onto p's azimuth within the
    // travel widened by the angle the margin subtends (false: no assembly
    // within the travel on that combination reaches p); true without a travel.
    bool within_travel = true;
    // `seed` set: the leg at the nearest such sample, or else at the nearest
    // of all, turned onto p's azimuth. Where p is reached, its end lies
    // within the margin of p (its turn within the widened travel where an
    // assembly within the travel reaches p), and the numerical solver
    // converges from it in a few steps.
    bool seeded = false;
  };
  Nearby nearby(const Eigen::Vector3d& p, int combo, LegState& seed) const;
  // A lower bound on the miss, a few times closer than outside() near the
  // reach's edge, where every joint after the first is a revolute or a
  // slide: each sample's box of joint values maps into its first-order image
  // (a zonogon in distance and height) grown by a bound on the second-order
  // rest, which is small where the margin is first-order. At most `cut`
  // (stopping at the first box that may come within it) where it cannot
  // prove more; -inf where there is no such refinement.
  double outside_finely(const Eigen::Vector3d& p, double cut) const;
};

// `like`: one built for a leg with the same chain from its first joint on,
// the same branch rules and the same joints after it held within a travel
// (a copy of this one: same_from_first_joint), taken about this leg's first
// joint and within its travel rather than sampled again.
TurnedReach sample_turned_reach(const Leg& leg, const std::vector<Actuator>& actuators, bool planar,
                                const LegState& seed, const TurnedReach* like = nullptr);
bool same_from_first_joint(const Leg& a, const Leg& b, const std::vector<Actuator>& actuators);

}  // namespace linkscape::described
