// A leg's reach about a first joint that turns, sampled in the two
// coordinates that turn leaves as they are (sampled_reach.h samples all
// three): the numerical solver's refusal of an anchor near the reach's
// edge, and of its travel search, for a leg of no known pattern.
#pragma once

#include <Eigen/Core>
#include <cstdint>
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

  // Within the travel of an actuator that drives the first joint (where no
  // other joint that moves the end has a travel), per combination of the
  // leg's free rules: on a grid of (distance, height), the azimuths about
  // the axis (in 64 bins, from `zero`) that the samples within the margin
  // of each cell take with the joint at `seed_value`. A joint value q turns
  // a sample at azimuth psi to psi + q - seed_value: where no sample near
  // the anchor's cell has an azimuth that a value within the travel turns
  // onto the anchor's (widened by the angle the margin subtends), no
  // assembly within the travel on that combination reaches it.
  bool binned = false;
  // Azimuths from `zero` towards `onwards` (units square to the axis and to
  // each other), the way the joint turns an end.
  Eigen::Vector3d zero = Eigen::Vector3d::UnitX(), onwards = Eigen::Vector3d::UnitY();
  Range travel;
  double seed_value = 0, cell = 1;
  Eigen::Vector2d grid_lo = Eigen::Vector2d::Zero();
  int columns = 0, rows = 0;
  std::vector<std::vector<std::uint64_t>> azimuths;  // per combination, per cell (row-major)
  // True where the bins prove that no assembly within the travel on
  // combination `combo` reaches p (false where not binned).
  bool rules_out_within_travel(const Eigen::Vector3d& p, int combo) const;
};

// `like`: one built for a leg with the same chain from its first joint on,
// the same branch rules and the same joints after it held within a travel
// (a copy of this one: same_from_first_joint), taken about this leg's first
// joint and within its travel rather than sampled again.
TurnedReach sample_turned_reach(const Leg& leg, const std::vector<Actuator>& actuators, bool planar,
                                const LegState& seed, const TurnedReach* like = nullptr);
bool same_from_first_joint(const Leg& a, const Leg& b, const std::vector<Actuator>& actuators);

}  // namespace linkscape::described
