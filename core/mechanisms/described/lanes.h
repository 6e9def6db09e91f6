// A described device's field in SIMD lanes (docs/described-internals.md,
// "Fields in SIMD lanes"): for spatial devices whose legs are all point
// legs (crank-rod, slide-rod, extensible) or crank-parallelograms, and planar
// ones of dyads, and three-revolute legs. In a field the platform's rotation
// and the extras (they move only the platform bodies' frames) are fixed, so
// each leg's platform joint centre is p plus a fixed vector and its closed
// form is a scalar equation in its actuator (a parallelogram's and a
// three-revolute leg's, two): the kernel
// (lanes_simd.cpp, Highway, chosen at run time) solves it for 4-8 poses at
// once with the leg's candidates, branch rules, travel, cones, revolute
// stops, link capsules, Jacobian row, serial margin and the measures. A lane decides only where it is
// clearly away from every threshold the scalar closed path decides at; every
// other lane is that path's (DescribedMechanism::sample), so the statuses are
// its exactly. A device that is its own mirror image in y (LaneDevice::mirror_y)
// computes half the rows of a grid symmetric in y, each stored also at its
// mirror row.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/field.h"
#include "core/field_sampling.h"
#include "core/mechanisms/described/kinematics.h"

namespace linkscape::described {

// Why the lanes cannot serve this device ("" where they can): a leg of
// another pattern, a rule, limit, capsule or task the kernel does not express.
std::string lanes_refusal(const Kinematics& kin);

// Where a rule's or Jacobian's point is, per candidate (a parallelogram's
// joints: knee, upper, lower).
enum class LanePoint { Actuator, Ball, End, Anchor, Knee, Upper, Lower };

// The passive revolute a stop or angle rule reads, its angle known per
// candidate (Second, Third: a three-revolute leg's).
enum class LaneJoint { Ball, Knee, Upper, Lower, Grip, Second, Third };
inline constexpr int kLaneJoints = 7;

// The body a link capsule rides on: its points turn with the actuator
// (Crank), with the actuator and knee (Knee, and a parallelogram's lower bar:
// Ankle), with those and the upper joint (Shin), or stay: Fixed (base frame),
// Platform (p + a fixed vector).
enum class LaneBody { Fixed, Platform, Crank, Knee, Shin, Ankle };

inline constexpr std::size_t kMaxLaneCapsules = 64;
inline constexpr std::size_t kMaxLaneSizes = 4;  // cone sizes, travel widths

struct LaneCapsule {
  int leg = 0;
  LaneBody body = LaneBody::Fixed;
  // Fixed: base frame; Platform: from p; Crank, Knee, Ankle: from the body's
  // joint at its angles 0, in the base frame; Shin: likewise, its upper joint at 0.
  Eigen::Vector3d a, b;
  double radius = 0;
  double reach = 0;  // from its segment's middle: half its length and its radius
};

// One point leg's constants in the base frame for one field (the platform's
// rotation fixed). Offsets are from the platform position p.
struct LaneLeg {
  LegPattern pattern = LegPattern::CrankRod;
  Eigen::Vector3d anchor_offset, end_offset;  // anchor point and end joint centre: p + offset
  Eigen::Vector3d leg_base;                   // the reach bounds' centre
  Range reach;
  // The reach bounds' cuts on the squared distance (-1: none): beyond
  // `far_out` or within `near_out` decided unreachable, between `near_in`
  // and `far_in` kept (lanes_simd.cpp's band between).
  double far_out2 = 0, far_in2 = 0, near_out2 = -1, near_in2 = -1;
  // Crank: its circle's centre `origin`, axis, radius rho and plane (u, v);
  // slide: the ball at q = 0 (`origin`) and the slide's axis; extensible:
  // `origin` the ball's centre.
  Eigen::Vector3d actuator_centre, origin, axis, u, v;
  double rho = 0, rod = 0, offset = 0;
  double slide_start = 0;  // Extensible: where the slide starts along the leg from the ball (a cylinder's body)
  bool prismatic = false, limited = false;
  double lo = 0, hi = 0, mid = 0, half_width = 0;  // the travel (revolute: mid +- half_width)
  int width = -1;  // a revolute travel's index in LaneDevice::travel_widths (-1: its own arctangent)
  double cos_mid = 1, sin_mid = 0, cos_half_width = 1, sin_half_width = 0;
  bool universal = false;
  Eigen::Vector3d universal_axis;  // its first axis (a crank's at q = 0)
  struct Rule {
    bool triple = true;  // else along, or with `angle` the sign of sin(joint)
    bool angle = false;
    LaneJoint joint = LaneJoint::Upper;
    LanePoint points[3] = {LanePoint::Actuator, LanePoint::Actuator, LanePoint::Actuator};
    Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
    bool fixed_axis = false;  // a triple's axis: `axis`, else the candidate's actuator axis
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    double wanted = 1;  // the branch's sign
  };
  std::vector<Rule> rules;
  // A crank's one triple rule on its actuator, ball and end reads the closed
  // form's sign (lanes.cpp's branch_candidate): the candidate it keeps (0:
  // the + root, 1: the -), the other not computed; -1: the rules decide.
  int branch_candidate = -1;
  struct Cone {
    bool at_ball = true;
    // At the ball: the socket (a crank's at q = 0), the link along +-the
    // rod; at the end: the socket along +-the rod, the link fixed.
    Eigen::Vector3d fixed;
    double along = 1;  // the rod-aligned axis's sign
    double half_angle_deg = 0;
    int size = -1;  // its index in LaneDevice::cone_sizes (-1: its own arctangent)
  };
  std::vector<Cone> cones;
  struct Stop {  // a passive revolute's range (Kinematics::stops: degrees, the angle nearest its middle)
    LaneJoint joint = LaneJoint::Ball;
    double lo_deg = 0, hi_deg = 0, mid = 0, cos_mid = 1, sin_mid = 0;
  };
  std::vector<Stop> stops;
  // A planar ball's angle: the one from `ball_link` (the rod at q = 0,
  // turned with the crank) to the rod, about `ball_normal`.
  Eigen::Vector3d ball_link = Eigen::Vector3d::UnitX(), ball_normal = Eigen::Vector3d::UnitZ();
  // A crank-parallelogram (closed_form.h's Parallelogram) in its actuator's
  // frame: `origin` and `frame` take it to the base frame; `end_local` =
  // frame^T (end - origin) at p = 0.
  bool parallelogram = false;
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  Eigen::Vector3d end_local, local_axis, across, thigh, knee_rest, to_upper, side_link, to_grip, upper_axis;
  double knee_sign = 1, lower_sign = 1, grip_sign = 1, thigh_phase = 0, height = 0, side = 0, phase = 0, bar = 0;
  double cos_phase = 1, sin_phase = 0, cos_thigh_phase = 1, sin_thigh_phase = 0, cos_level = 1, sin_level = 0;
  // A three-revolute leg (closed_form.cpp's three_revolute) in its actuator's
  // frame (`frame` to the base frame): `origin` the second joint's centre
  // (base frame), `local_axis` the actuator's, the second and third joints'
  // axes and the links after them; |second_link + R3(t3) third_link| = |end -
  // origin| is harmonic_b cos t3 + harmonic_c sin t3 = |end - origin|^2 / 2 -
  // harmonic_k0, its reach within [nearest, farthest].
  bool three = false;
  Eigen::Vector3d second_axis, third_axis, second_link, third_link;
  double harmonic_b = 0, harmonic_c = 0, harmonic_k0 = 0, nearest = 0, farthest = 0;
};

struct LaneDevice {
  std::vector<LaneLeg> legs;
  std::vector<int> coordinate;  // per Jacobian row (task order): platform coordinate 0..5
  double size = 1;
  int branch = 0;
  bool planar = false;  // z is the plane's, whatever the grid's
  bool cones = false;   // joint margins stored (cones or revolute stops)
  // The cones' half angles (deg) and the revolute travels' half widths, each
  // once: the margins of one size take one arctangent, of the widest angle.
  std::vector<double> cone_sizes, travel_widths;
  std::vector<LaneCapsule> capsules;
  std::vector<std::array<int, 2>> pairs;  // the capsules Kinematics::stops checks against each other
  // Reflecting y maps the device onto itself (lanes.cpp's mirrored): point
  // legs that pair up, each with a partner whose constants reflect its own
  // within 1e-12 of the size, and a fixed orientation with rx = rz = 0. The
  // sample at (x, -y, z) is then the one at (x, y, z) with legs swapped: the
  // same statuses, c(J), margins and clearance, to rounding.
  bool mirror_y = false;
};

// The device's lane constants for a field at the fixed task `fixed` (model
// order; its x, y, z unused) on `branch`; nullopt where lanes_refusal says why.
std::optional<LaneDevice> lane_device(const Kinematics& kin, const Eigen::VectorXd& fixed, int branch);

// Whether a field of the device on `g` takes its rows of the upper half in
// y from the lower half's: mirror_y, rows along x, more than one row in y,
// and y coordinates that are exact negatives of each other.
bool lanes_mirror_holds(const LaneDevice& device, const Grid& g);

// The scalar closed path at a row's sample t (its joint margin, degrees, and
// clearance, NaN where it does not assemble).
using LaneFallback = std::function<FieldSample(int t, double& joint_margin_deg, double& clearance)>;

// The lanes' own values in double before the Field's floats, per row sample
// (NaN where the scalar path decided): for tests that compare them finer
// than a float.
struct LaneValues {
  std::vector<double> cond, cond_orientation, reach_margin, joint_margin, clearance;
};

// The row's arrays of the stops (null: the device has none).
struct LaneStopsOut {
  float* joint_margin = nullptr;
  float* clearance = nullptr;
};

// A row's mirror image in y (lanes_mirror_holds): where its samples go, and
// the scalar closed path at its own points.
struct LaneMirror {
  detail::FieldRowOut out;
  LaneStopsOut stops;
  LaneFallback fallback;
};

// One grid row in lanes with the CPU's best instruction set (core/simd.h).
// Samples the lanes serve take method code `method`; the others are
// `fallback`'s. With `values`, also their doubles. With `mirror`, the
// lanes' samples also go to the mirror row, and the ones handed to the
// scalar path are computed there at the mirror row's own points.
void sample_row_lanes(const LaneDevice& device, const Grid& grid, const detail::GridRow& row,
                      const detail::FieldRowOut& out, const LaneStopsOut& stops, std::uint8_t method,
                      const LaneFallback& fallback, LaneValues* values = nullptr, const LaneMirror* mirror = nullptr);

}  // namespace linkscape::described
