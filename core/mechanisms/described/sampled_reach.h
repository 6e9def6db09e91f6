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
#include <limits>
#include <string>
#include <vector>

#include "core/mechanisms/described/closed_form.h"
#include "core/mechanisms/described/model.h"

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

}  // namespace linkscape::described
