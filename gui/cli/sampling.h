// The options every command that samples a device shares, declared once and
// checked once: --mechanism --param --method --branch --pose --torque.
#pragma once

#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "core/haptics.h"
#include "core/mechanism.h"
#include "core/preset.h"
#include "gui/cli/device_help.h"

namespace linkscape::gui {

// --joint-limits and --interference: "on", "off", or empty (on where the
// device states them).
struct StopSwitches {
  std::string joint_limits, interference;
};

struct SamplingOptions {
  PresetChoice mechanism;
  StopSwitches stops;
  std::string method;  // empty: the device's first IK method
  int branch = 0;
  // The task pose, every coordinate: all but x, y, z are held fixed over a
  // grid. Empty: the command's default (the home pose).
  std::string pose;
  // Torque limit of the haptic fields: "continuous" or "peak" (core/haptics.h).
  std::string torque = "continuous";
};

// --mechanism and --param alone, for a command that takes a device without
// sampling it (eval, bench, design) and for the window.
void add_mechanism_options(CLI::App& app, PresetChoice& choice);

// --joint-limits and --interference, for every command that evaluates a device.
void add_stop_options(CLI::App& app, StopSwitches& switches);
// Sets preset.checks from the switches. Throws std::invalid_argument
// ("`command`: --joint-limits: ...") for a switch given for a device that
// states nothing of its kind.
void apply_stop_switches(const StopSwitches& switches, Preset& preset, const std::string& command);

// The six and the stop switches. `pose_default` ends the --pose help: what an absent pose means.
void add_sampling_options(CLI::App& app, SamplingOptions& options, const DeviceHelp& devices,
                          const std::string& pose_default);

// The options checked against the device they choose.
struct SampledDevice {
  Preset preset;  // with the --param overrides
  std::shared_ptr<const Mechanism> mechanism;
  std::optional<Eigen::VectorXd> pose;  // --pose; none: the command's default
  IkOptions ik;                         // method and branch (none for branch 0)
  haptics::TorqueRating torque = haptics::TorqueRating::Continuous;
};

// Throws std::invalid_argument, its message starting with "`command`: ",
// for an unknown preset, parameter, method or torque rating, a branch the
// device lacks, a stop switch for stops it does not state or a pose that is
// not all of its task coordinates.
SampledDevice check_sampling_options(const SamplingOptions& options, const std::string& command);

// A coordinate read by a sensor (a grip, info.fk_inputs) beyond the range the
// device states is no pose of it: throws std::invalid_argument, `what` first
// ("slice: --pose: ").
void check_read_coordinates(const MechanismInfo& info, const Eigen::VectorXd& x, const std::string& what);

// The IK method and branch of `info`'s, checked (eval's optional branch included).
IkOptions checked_ik(const MechanismInfo& info, const std::string& method, std::optional<int> branch,
                     const std::string& command);

// The IK --tolerance: kFinestTolerance..kCoarsestTolerance (core/mechanism.h),
// else std::invalid_argument("`command`: --tolerance ...").
void check_ik_tolerance(double tolerance, const std::string& command);

// `count` finite numbers, comma separated; else std::invalid_argument("`what`, got 'text'").
std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& what);

// A check for options taking criteria ('cond<3', several separated by
// commas, semicolons or spaces): a part with no comparison, what a shell
// leaves of an unquoted cond>3, is refused at once (before a missing
// required option is) with advice to quote it (task::quoting_hint).
CLI::Validator criteria_check();

// "x,y,z" (with `prefix` before each: "seed_x,...").
std::string joined_names(const std::vector<Quantity>& items, const std::string& prefix = "");

}  // namespace linkscape::gui
