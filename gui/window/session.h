// A saved exploration: mechanism, parameters, pose, camera, field settings
// (slice opacity included), the Task and Fit tabs (the Fit tab's last result
// too) and the View menu's toggles, as JSON. Everything the window needs to
// come back as it was.
// Generic over devices: the pose is saved as the device's task coordinates
// and actuator values by name (core/mechanism.h); older files with pose_rad
// (the actuator values) or platform_pose (the task coordinates) still open.
#pragma once

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/mechanism.h"

class vtkRenderer;

namespace linkscape::gui {

struct CameraState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d focal_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d view_up = Eigen::Vector3d::UnitZ();
  double view_angle = 30.0;  // degrees
};

struct FieldSettings {
  std::string field = "cond";  // one of field_choices(...).fields
  std::string normal = "x";    // slice plane normal
  double position = 0.0;       // plane position, length unit
  bool follow_endpoint = false;
  double threshold = 3.0;      // c(J) contour and well-conditioned surface
  std::optional<double> range_min, range_max;
  int slice_resolution = 192;  // samples per side
  int volume_resolution = 64;  // samples per axis
  bool show_slice = true, show_reach = true, show_well_conditioned = true;
  double reach_opacity = 0.10, well_conditioned_opacity = 0.22;
  double slice_opacity = 1.0;  // lower: the linkage shows through the slice
  std::string method;  // IK method per sample; empty: the device's default
  std::string colour_map = "viridis";  // render::colour_maps()
  bool log_scale = true;               // for the fields drawn on a log scale by default (c(J), residual, haptic)
  bool operator==(const FieldSettings&) const = default;
};

// The Task tab: the task volume (as --task takes it, centre included), its
// criteria (as --criterion takes them) and whether it is drawn.
struct TaskSetting {
  std::string volume;
  std::vector<std::string> criteria;
  bool shown = true;
  bool operator==(const TaskSetting&) const = default;
};

// Whether the texts are ones --task and --criterion take (what a session
// file must hold to be read again).
bool valid_task_setting(const TaskSetting& setting);

// The Fit tab: what its next Run searches. Bounds per parameter, [lo, hi]
// in its unit; `equal` as the Hold equal box takes it ("L1,L2;L3,L4").
struct FitSetting {
  std::vector<std::string> free;
  std::map<std::string, std::array<double, 2>> bounds;
  std::string equal;
  bool largest_margin = false;  // the mode: false, the smallest size; true, the largest margin at `size`
  double size = 0;              // the device's size unit
  bool centre_free = true;
  std::string centre_region;  // where a free centre may go (as --centre-region takes it); empty: anywhere
  bool operator==(const FitSetting&) const = default;
};

// The Fit tab's last result as a session keeps it: the report and the
// verdict as shown, and the design chosen (the parameters Apply sets, and
// where the search placed the task when the centre was free).
struct FitOutcome {
  std::string report, status;
  std::map<std::string, double> design;
  std::optional<Eigen::Vector3d> centre;
  bool operator==(const FitOutcome&) const = default;
};

struct Session {
  std::string mechanism = default_mechanism();  // preset name or path
  std::map<std::string, double> parameters;  // overrides, e.g. L1, L2
  std::map<std::string, std::array<double, 2>> actuator_limits_deg;  // per actuator name: [lo, hi]
  // The pose in the device's order (info().actuators, info().task; rad and
  // length unit). Either may be empty: the window solves for the other.
  Eigen::VectorXd pose;  // actuator values
  Eigen::VectorXd task;  // task coordinates
  std::optional<CameraState> camera;
  FieldSettings field;
  std::optional<TaskSetting> task_volume;  // none: the Task tab as it starts
  std::optional<FitSetting> fit;           // none: the Fit tab as it starts
  // How the window shows things, beyond the document's values:
  std::optional<FitOutcome> fit_result;  // the Fit tab's last result; none: not run
  std::map<std::string, bool> view;      // the View menu's checkable toggles, by their actions' object names
};

// The camera of a renderer, and back.
CameraState camera_state(vtkRenderer* renderer);
void apply_camera(vtkRenderer* renderer, const CameraState& camera);

// What the window offers for a device's fields, from its description: its
// combo boxes are filled from here and sessions are checked against it.
// Fields: "cond" (the first measure), the second measure's name where there
// is one, "reach", "residual" and "iterations" where the IK reports them,
// "status", "method" where there is more than one IK method, and the haptic
// measures force_iso, force_max, resolution, inertia (core/haptics.h). The
// resolutions are the same for every device.
struct FieldChoices {
  std::vector<std::string> fields;   // values of FieldSettings::field
  std::vector<std::string> methods;  // IK methods per sample (empty: the device has one)
  std::vector<int> slice_resolutions, volume_resolutions;
  int default_slice_resolution = 0, default_volume_resolution = 0;
};
FieldChoices field_choices(const MechanismInfo& info);

// Atomic write. Throws std::runtime_error if the file cannot be written.
// The mechanism is written as a preset name wherever the preset was found on
// the preset search path, so that sessions open on other machines and in
// installed copies.
void save_session(const Session& session, const std::filesystem::path& path);
// Reads and checks a session: every key known, every value one the window
// can honour (parameters valid for the mechanism, names and resolutions
// the window offers, finite numbers in range). Throws std::invalid_argument
// naming the file, the key and the problem; never clamps.
Session load_session(const std::filesystem::path& path);
Session parse_session(const std::string& json_text, const std::string& origin);
// Whether a file is JSON that says it is a session ("format":
// "linkscape-session"); false for anything else, including unreadable files.
bool is_session_file(const std::filesystem::path& path);

}  // namespace linkscape::gui
