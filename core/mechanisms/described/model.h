// A described mechanism: a parallel device read from a preset's
// "description" (docs/described-mechanisms.md). The model is the description
// with every expression evaluated for one set of parameters; only the
// platform bodies' frames may depend on the extras (a grip), and they are
// evaluated per pose.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/preset.h"
#include "core/range.h"

namespace linkscape::described {

// One step of a chain: a fixed transform or a joint about/along `axis`
// through the current origin (local frame).
struct Step {
  enum class Kind { Fixed, Revolute, Prismatic, Spherical };
  Kind kind = Kind::Fixed;
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  // Fixed only
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();              // unit; Revolute, Prismatic
  std::string name;       // joint name (a universal's halves are "u.1", "u.2")
  std::string joint;      // the joint it belongs to as written ("u" for both halves)
  int actuator = -1;      // index into Model::actuators, -1 if passive
  int variable = 0;       // first tangent slot in the leg's variables
};

// Which inverse-kinematics solution a leg takes: the sign of a quantity of
// its joint centres and axes.
struct BranchRule {
  enum class Kind { Triple, Angle, Along };
  Kind kind = Kind::Triple;
  // Step indices (Triple: A, B, C; Along: A, B; -2: the anchor), Angle: A.
  std::array<int, 3> steps{-1, -1, -1};
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // Along: unit, base frame
  int fixed_sign = 0;                    // +1/-1 fixed by the design, 0: a free assembly branch
  int free_index = -1;                   // bit in the device's branch number (free rules)
};

// A passive joint's limit (docs/described-mechanisms.md, "Joint limits").
struct JointLimit {
  enum class Kind { Range, Cone };
  Kind kind = Kind::Range;
  int step = -1;    // the limited step in Leg::steps (a revolute, a universal's half, a spherical joint)
  int sphere = -1;  // Cone: the spherical joint's index in LegState::spheres
  Range range;      // Range: radians, of the angle from the chain as written
  // Cone: the socket's axis (frame before the joint) and the link's axis
  // (frame after it; the same as written); the angle between them stays
  // within half_angle (radians).
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ(), link_axis = Eigen::Vector3d::UnitZ();
  double half_angle = 0.0;
  std::string label;  // as messages name it: "joint knee2", "ball joint elbow2"
};

// A link as a capsule: the segment a-b swept by a ball of `radius`
// (docs/described-mechanisms.md, "Link interference").
struct LinkCapsule {
  enum class On { Chain, Base, Platform };
  On on = On::Chain;
  // Chain: the step whose frame holds a and b (-1: the leg's base anchor);
  // Base: a and b in the base frame; Platform: in the leg's platform body's frame.
  int frame = -1;
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  double radius = 0.0;
  std::string name;  // "thigh", "link q1-knee1", "base link", "platform link"
};

struct Leg {
  std::string name;
  // How messages name the leg: "leg 2" for a leg named "2", the name itself
  // where it already says so ("leg 1", "Leg A").
  std::string label() const;
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();  // base frame <- leg base anchor
  std::vector<Step> steps;
  int platform = 0;                                        // platform body index
  Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();  // body frame <- anchor
  int variables = 0;  // tangent dimension: 1 per revolute/prismatic, 3 per spherical
  int spheres = 0;    // spherical joints (their rotations are stored apart)
  std::vector<BranchRule> rules;
  std::vector<int> actuators;  // indices into Model::actuators, in chain order
  std::string pattern;  // the closed-form pattern the description asserts ("": none)
  std::vector<JointLimit> limits;     // its passive joints' limits
  std::vector<LinkCapsule> capsules;  // its links, base and platform links included
};

struct Actuator {
  std::string name;
  int leg = 0, step = 0;
  bool prismatic = false;
  Range range;             // radians or the length unit
  bool limited = false;    // false: a full turn, no limit
};

// A task coordinate: a platform coordinate (x, y, z, rx, ry, rz) or an extra.
struct TaskCoordinate {
  std::string name;
  int platform_coordinate = -1;  // 0..5 for x..rz, -1 for an extra
  int extra = -1;                // index into Model::extras
};

struct Extra {
  std::string name, unit, description;
  double home = 0.0;
  Range range;
};

class ExpressionSet;  // the compiled expressions of the platform frames (model.cpp)

struct Model {
  std::string length_unit;
  bool planar = false;
  std::vector<TaskCoordinate> task;
  std::array<bool, 6> free{};        // platform coordinates in the task
  std::array<double, 6> fixed{};     // values of the others
  std::vector<Extra> extras;
  Eigen::VectorXd home;              // task values
  std::vector<std::string> platform_names;
  std::vector<Leg> legs;
  std::vector<Actuator> actuators;
  int free_rules = 0;                // assembly branches: 2^free_rules
  double size = 1.0;
  std::string size_text;  // what size measures, as written ("a + b") or said
  std::map<std::string, double> parameters;
  struct ParameterInfo {
    Range range;
    std::string unit, description;
    bool in_panel = true;
  };
  std::map<std::string, ParameterInfo> parameter_info;
  std::optional<Eigen::AlignedBox3d> box;  // the sampling box, where the description gives one
  // The platform bodies' frames (platform frame <- body) for the extras' values;
  // valid until the thread asks again.
  std::shared_ptr<const ExpressionSet> frames;
  const std::vector<Eigen::Isometry3d>& platform_frames(const Eigen::VectorXd& extras) const;

  int driven() const;  // task coordinates that are not extras
  bool has_joint_limits() const;
  bool has_capsules() const;
};

// The format's limits (docs/described-mechanisms.md, "Limits"), far above
// every real device: they bound the work and memory a file can ask for, and
// are checked before the work. The file's size and nesting depth are a
// preset's (core/json_checked.h).
inline constexpr int kMaxLegs = 64;                  // after copies
inline constexpr int kMaxLegVariables = 24;          // joint variables per leg (a spherical joint counts 3)
inline constexpr int kMaxPlatforms = 64;             // platform bodies
inline constexpr int kMaxExtras = 16;
inline constexpr int kMaxParameters = 256;
inline constexpr std::size_t kMaxExpressionLength = 1000;  // characters
inline constexpr int kMaxFirstNumber = 1000000;      // a leg's "first"

// Reads and evaluates a description. `description_json` is the preset's
// "description" value as JSON text; `limits_deg` the preset's
// actuator_limits_deg. Throws std::invalid_argument naming the place
// ("description.legs[2] \"3\": chain[4] (joint \"s3\"): ...").
Model build_model(const std::string& description_json, const std::map<std::string, double>& parameters,
                  const std::map<std::string, Range>& limits_deg, const std::string& length_unit);

// Drops the passive-joint limits or the link capsules that `checks` turns off.
void switch_off_stops(Model& model, const StopChecks& checks);

}  // namespace linkscape::described
