// A described device's field in SIMD lanes (docs/described-mechanisms.md,
// "Fields in SIMD lanes"): for spatial devices whose legs are all point
// legs (crank-rod, slide-rod, extensible) and planar ones of dyads. In a field the platform's rotation
// is fixed, so each leg's platform joint centre is p plus a fixed vector and
// its closed form is a scalar equation in its actuator: the kernel
// (lanes_simd.cpp, Highway, chosen at run time) solves it for 4-8 poses at
// once with the leg's two candidates, branch rules, travel, cones, Jacobian
// row, serial margin and the measures. A lane decides only where it is
// clearly away from every threshold the scalar closed path decides at; every
// other lane is that path's (DescribedMechanism::sample), so the statuses are
// its exactly.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/field.h"
#include "core/field_sampling.h"
#include "core/mechanisms/described/kinematics.h"

namespace linkscape::described {

// Why the lanes cannot serve this device ("" where they can): extras, link
// capsules, a leg of another pattern, a rule, limit or task the kernel does
// not express.
std::string lanes_refusal(const Kinematics& kin);

// Where a rule's or Jacobian's point is, per candidate.
enum class LanePoint { Actuator, Ball, End, Anchor };

// One point leg's constants in the base frame for one field (the platform's
// rotation fixed). Offsets are from the platform position p.
struct LaneLeg {
  LegPattern pattern = LegPattern::CrankRod;
  Eigen::Vector3d anchor_offset, end_offset;  // anchor point and end joint centre: p + offset
  Eigen::Vector3d leg_base;                   // the reach bounds' centre
  Range reach;
  // Crank: its circle's centre `origin`, axis, radius rho and plane (u, v);
  // slide: the ball at q = 0 (`origin`) and the slide's axis; extensible:
  // `origin` the ball's centre.
  Eigen::Vector3d actuator_centre, origin, axis, u, v;
  double rho = 0, rod = 0, offset = 0;
  bool prismatic = false, limited = false;
  double lo = 0, hi = 0, mid = 0, half_width = 0;  // the travel (revolute: mid +- half_width)
  double cos_mid = 1, sin_mid = 0, cos_half_width = 1, sin_half_width = 0;
  bool universal = false;
  Eigen::Vector3d universal_axis;  // its first axis (a crank's at q = 0)
  struct Rule {
    bool triple = true;  // else along
    LanePoint points[3] = {LanePoint::Actuator, LanePoint::Actuator, LanePoint::Actuator};
    Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
    bool fixed_axis = false;  // a triple's axis: `axis`, else the candidate's actuator axis
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    double wanted = 1;  // the branch's sign
  };
  std::vector<Rule> rules;
  struct Cone {
    bool at_ball = true;
    // At the ball: the socket (a crank's at q = 0), the link along +-the
    // rod; at the end: the socket along +-the rod, the link fixed.
    Eigen::Vector3d fixed;
    double along = 1;  // the rod-aligned axis's sign
    double half_angle_deg = 0;
  };
  std::vector<Cone> cones;
};

struct LaneDevice {
  std::vector<LaneLeg> legs;
  std::vector<int> coordinate;  // per Jacobian row (task order): platform coordinate 0..5
  double size = 1;
  int branch = 0;
  bool planar = false;  // z is the plane's, whatever the grid's
  bool cones = false;   // joint margins stored
};

// The device's lane constants for a field at the fixed task `fixed` (model
// order; its x, y, z unused) on `branch`; nullopt where lanes_refusal says why.
std::optional<LaneDevice> lane_device(const Kinematics& kin, const Eigen::VectorXd& fixed, int branch);

// The scalar closed path at a row's sample t (its joint margin, degrees, NaN
// where it does not assemble).
using LaneFallback = std::function<FieldSample(int t, double& joint_margin_deg)>;

// The lanes' own values in double before the Field's floats, per row sample
// (NaN where the scalar path decided): for tests that compare them finer
// than a float.
struct LaneValues {
  std::vector<double> cond, cond_orientation, reach_margin;
};

// One grid row in lanes with the CPU's best instruction set (core/simd.h);
// `joint_margin` the row's joint-margin array (null: none). Samples the lanes
// serve take method code `method`; the others are `fallback`'s. With
// `values`, also their doubles.
void sample_row_lanes(const LaneDevice& device, const Grid& grid, const detail::GridRow& row,
                      const detail::FieldRowOut& out, float* joint_margin, std::uint8_t method,
                      const LaneFallback& fallback, LaneValues* values = nullptr);

}  // namespace linkscape::described
