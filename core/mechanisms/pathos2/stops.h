// What bounds PATHOS-II beyond its legs' reach (docs/mechanisms/pathos2.md,
// "Stops"): the globular joints' cone and the R2, R3 ranges (Model's
// cone_limit, t2_limit, t3_limit), and its links as capsules: the three links
// of each leg (radius link_radius) and the hand's grip volume between the top
// plates (grip_radius). The paper states the rule, not the values: a preset
// states them in its "stops" block (make_pathos2).
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "core/interference.h"
#include "core/mechanisms/pathos2/pathos2.h"

namespace linkscape::pathos2 {

bool has_joint_limits(const Model& model);  // a limit below pi
bool has_capsules(const Model& model);      // link_radius > 0

// Capsule indices: 3 leg + link (link 0: R1 to R2, 1: R2 to R3, 2: R3 to the
// globular centre), then the grip volume where grip_radius > 0.
inline constexpr int kGripCapsule = 3 * kLegCount;
std::string capsule_name(int index);  // "leg 2 link 3", "grip"

// The capsules at a solved pose (world frame, cm). The grip spans the axis
// between the top plates, shortened by its radius so that it ends at the
// plates. `ik` needs every leg's cosines (any IkDetail) and no leg Unreachable.
std::vector<interference::Capsule> capsules(const Geometry& geometry, const Pose& pose, const PoseIkResult& ik);

struct Stops {
  double joint_margin_deg = std::numeric_limits<double>::infinity();  // < 0 beyond a limit
  int joint_leg = -1;    // 0-based
  int joint = -1;        // 0 globular cone, 1 R2, 2 R3
  double joint_angle_deg = 0.0, joint_limit_deg = 0.0;
  double clearance = std::numeric_limits<double>::infinity();  // cm, < 0 where two capsules overlap
  std::array<int, 2> pair{-1, -1};  // capsule indices
  bool hold() const { return joint_margin_deg >= 0 && clearance >= 0; }
  // The leg to blame (0-based): the joint's, else the first leg of the pair; -1 where they hold.
  int leg_at_fault() const;
};

// The margins of a solved pose. `ik` from inverse() with IkDetail::Full or
// Field (the limited angles set), no leg Unreachable. Checked pairs: every
// link of a leg against every link of another leg (but two R1 links, both
// fixed to the base), and the grip against the links that do not end on a
// top plate (R1 and R2 links); a leg's own links meet at its joints.
Stops stops(const Geometry& geometry, const Pose& pose, const PoseIkResult& ik);

// Why they do not hold: "leg 2 globular joint at 63.5 deg beyond its 60.0
// deg cone", "leg 1 link 3 hits leg 4 link 2 (overlap 0.21 cm)"; "" where they hold.
std::string stop_reason(const Stops& stops);

}  // namespace linkscape::pathos2
