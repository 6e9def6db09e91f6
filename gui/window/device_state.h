// The device the window shows and its pose, without any widget: the preset
// and the Mechanism made from it, the actuators q, the task coordinates x
// and the assembly branch; inverse and forward kinematics that keep the
// branch and refuse (saying why) a target the device does not reach, a pose
// that does not assemble or a step that would make it jump across a
// singular set; and the pose a new design keeps.
//
// A refused request leaves the pose as it was. Angles in radians, lengths
// in the device's length unit.
#pragma once

#include <Eigen/Core>
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/mechanism.h"
#include "core/preset.h"

namespace linkscape::gui {

// While dragging or animating, one step may move an actuator at most this
// much; a larger jump means the same branch continues on the other side of
// a singular set, which would make the device jump.
inline constexpr double kMaxTrackingStep = 0.6;  // rad

// The largest difference between two sets of angles, each taken modulo a turn.
double angle_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b);

// The branch of actuators q at task x: the IK solution nearest to q, or `fallback`.
int branch_of(const Mechanism& m, const Eigen::VectorXd& q, const Eigen::VectorXd& x, int fallback);

// A design and the pose the device takes in it (DeviceState::adopt), or why
// it cannot be taken (`refusal` set, nothing else).
struct DesignPlan {
  // How much of the pose the new design keeps.
  enum class Kept {
    Task,       // the same task coordinates (IK in the same branch)
    Actuators,  // the same actuators (FK), the task where they put it
    Home,       // neither: the device's home pose
  };
  Preset preset;
  std::shared_ptr<const Mechanism> mechanism;
  Eigen::VectorXd q, x;
  int branch = 0;
  Kept kept = Kept::Task;
  std::string refusal;
  bool ok() const { return refusal.empty(); }
};

class DeviceState {
 public:
  // The preset's device at its home pose. Throws std::invalid_argument for an invalid preset.
  explicit DeviceState(const Preset& preset);

  const Preset& preset() const { return preset_; }
  const Mechanism& mechanism() const { return *mechanism_; }
  const std::shared_ptr<const Mechanism>& shared_mechanism() const { return mechanism_; }
  const Eigen::VectorXd& actuators() const { return q_; }
  const Eigen::VectorXd& task() const { return x_; }
  Eigen::Vector3d endpoint() const { return x_.head<3>(); }
  int branch() const { return branch_; }
  // Why the last requested pose was refused; empty when it was taken.
  const std::string& refusal() const { return refusal_; }
  // The part the last refused IK names ("3": leg 3), else empty.
  const std::string& failing_part() const { return failed_ ? failed_->failing_part : kNone; }
  // The IK that named it (to draw the part red), else nullptr.
  const IkResult* failed() const { return failed_ ? &*failed_ : nullptr; }

  // Inverse kinematics to x in the current branch, seeded with the current
  // actuators. `tracking` (drags, animation) also refuses a step that would
  // make the device jump.
  bool set_task(const Eigen::VectorXd& x, bool tracking = false);
  // The driven point to `target`, the other task coordinates kept. Without
  // `branch` the current branch is tracked (as a drag); with it, any pose of
  // that branch is taken (the branch stays when that fails).
  bool move_endpoint_to(const Eigen::Vector3d& target, int branch = -1);
  // Forward kinematics from the current task (the seed; fk_inputs are read
  // from `task_inputs` where given). Refused when it does not converge or
  // the pose it finds does not assemble; the branch is the one nearest.
  bool set_actuators(const Eigen::VectorXd& q, const std::optional<Eigen::VectorXd>& task_inputs = std::nullopt);

  // The device with these design parameters and the pose it keeps: the same
  // task coordinates where the new design reaches them in this branch, else
  // the same actuators, else its home. Refused for an invalid design or one
  // that reaches none of them.
  DesignPlan with_parameters(const std::map<std::string, double>& parameters) const;
  // The device of `next` (a session's design) at the pose that fits the
  // saved actuators `pose` and task `task` (either may be empty): IK of the
  // task (the solution nearest the saved actuators, else in this branch),
  // else FK of the actuators, else home. Throws std::invalid_argument for an
  // invalid design or vectors of the wrong size; nothing changes.
  DesignPlan with_saved_pose(const Preset& next, const Eigen::VectorXd& pose, const Eigen::VectorXd& task) const;
  // This preset with these parameters and actuator travel (degrees) instead.
  Preset design_with(const std::map<std::string, double>& parameters,
                     const std::map<std::string, std::array<double, 2>>& limits_deg) const;
  // Each actuator's travel in degrees, by name.
  std::map<std::string, std::array<double, 2>> limits_deg() const;
  // Takes a plan: the design and its pose; the refusal clears.
  void adopt(const DesignPlan& plan);

  // Actuator limits in degrees by actuator name, the pose clamped into them
  // (by FK; where that fails the pose stays). False, with `why`, when the
  // device rejects them: nothing changes.
  bool set_actuator_limits(const std::map<std::string, std::array<double, 2>>& limits_deg, std::string& why);
  // Whether the device takes actuator limits (its factory accepts them).
  bool takes_limits() const;

 private:
  bool refuse(std::string why, const IkResult* failed = nullptr);
  void take(const Eigen::VectorXd& q, const Eigen::VectorXd& x, int branch);

  static inline const std::string kNone;
  Preset preset_;
  std::shared_ptr<const Mechanism> mechanism_;
  Eigen::VectorXd q_, x_;
  int branch_ = 0;
  std::string refusal_;
  std::optional<IkResult> failed_;
};

}  // namespace linkscape::gui
