// A leg's reach from its joints sampled on a grid: a bound that follows the
// chain's shape, where the shells of reach.h know only its lengths.
//
// Every assembly's joint values lie within half a step of a sample's, and a
// freedom moved by at most half a step moves the end by at most that times
// its lever (a revolute's or a ball's: the longest the links after it
// reach; a slide's: one). So every assembly's end lies within a margin (the
// sum of those) of some sample's end, and an anchor farther than that from
// every sample's end cannot be reached. With the actuators within their
// travel, per combination of the leg's branch rules: the numerical solver's
// search for an assembly within the travel (kinematics.cpp) is left out
// where no sample on the branch comes near.
//
// Built for a leg whose end point moves with at most three freedoms (the
// joints after its last link only turn it): revolutes, slides with a
// travel, and a ball joint as the last of them (its link's direction; its
// spin moves nothing sampled).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/mechanisms/described/closed_form.h"
#include "core/mechanisms/described/model.h"
#include "core/range.h"

namespace linkscape::described {

// A lower bound on the distance from a point to a set of points, each
// standing for a ball of radius `margin`: their ends on a voxel grid, with
// the Euclidean distance transform of the voxels that hold one. In a planar
// device's plane where asked (z ignored).
class BallSetDistance {
 public:
  BallSetDistance() = default;
  // At most `voxels` voxels (0: a default that suits a leg's reach within
  // its travel) over the points' box grown by `pad` of its extent each way
  // (beyond the box the bound is looser).
  BallSetDistance(const std::vector<Eigen::Vector3d>& points, double margin, bool in_plane, double voxels = 0,
                  double pad = 0);
  // How far p lies outside every ball (a lower bound; > 0: outside them
  // all); +inf for an empty set.
  double outside(const Eigen::Vector3d& p) const;
  double margin() const { return margin_; }
  double slack() const { return slack_; }  // what the voxels add to the margin, at most

 private:
  Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), hi_ = Eigen::Vector3d::Zero();  // the points' box
  double voxel_ = 1, slack_ = 0, margin_ = 0;
  std::array<int, 3> n_{0, 0, 0};
  std::vector<float> distance_;  // per voxel: to the nearest voxel that holds a point (length unit)
  bool in_plane_ = false;
};

struct SampledReach {
  bool built = false;
  std::string why_not;  // where not built: what moves the end that a grid cannot sample
  int joints = 0;       // the joints that move the end point (a ball one)
  int samples = 0;
  // Per combination of the leg's free rules (leg_combination): the
  // assemblies with the actuators within their travel on that branch. A
  // sample next to where a rule changes sign counts on both branches.
  std::vector<BallSetDistance> travel;
};

// Samples the leg within its travel (its state `seed` for the joints that
// only turn the end).
SampledReach sample_reach(const Leg& leg, const std::vector<Actuator>& actuators, bool planar, const LegState& seed);

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
  double seed_value = 0, margin = 0, cell = 1;
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
