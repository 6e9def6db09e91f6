#include "gui/cli/sampling.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "core/task.h"

namespace linkscape::gui {

void add_mechanism_options(CLI::App& app, PresetChoice& choice) {
  std::string presets;
  for (const auto& n : available_presets()) presets += (presets.empty() ? "" : ", ") + n;
  app.add_option("-m,--mechanism", choice.name_or_path,
                 "Preset name (" + presets + ") or path to a preset .json file")
      ->capture_default_str();
  app.add_option("-p,--param", choice.params,
                 "Override a model parameter, key=value in the preset's unit (repeatable), e.g. L1=1");
}

void add_stop_options(CLI::App& app, StopSwitches& switches) {
  app.add_option("--joint-limits", switches.joint_limits,
                 "on or off: whether a pose with a passive joint beyond its limit is out of limits (default on where "
                 "the device states limits; off, the device is taken as stating none: no joint_margin field)")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option("--interference", switches.interference,
                 "on or off: whether a pose with two links overlapping is out of limits (default on where the device "
                 "gives its links a radius; off, the device is taken as giving none: no clearance field)")
      ->check(CLI::IsMember({"on", "off"}));
}

void apply_stop_switches(const StopSwitches& switches, Preset& preset, const std::string& command) {
  if (switches.joint_limits.empty() && switches.interference.empty()) return;
  const StopChecks stated = stated_stops(preset);
  const auto take = [&](const std::string& value, bool states, const char* option, const char* what, bool& check) {
    if (value.empty()) return;
    if (!states)
      throw std::invalid_argument(command + ": " + option + " " + value + ": " + preset_reference(preset) +
                                  " states no " + what + " (docs/described-mechanisms.md)");
    check = value == "on";
  };
  take(switches.joint_limits, stated.joint_limits, "--joint-limits", "passive-joint limits", preset.checks.joint_limits);
  take(switches.interference, stated.interference, "--interference", "link radii (capsules)", preset.checks.interference);
}

void add_sampling_options(CLI::App& app, SamplingOptions& s, const DeviceHelp& help, const std::string& pose_default) {
  add_mechanism_options(app, s.mechanism);
  add_stop_options(app, s.stops);
  app.add_option("--method", s.method,
                 "IK method per sample, one of the device's (default: its first; " +
                     help.per_device([](const MechanismInfo& i) { return names(i.ik_methods, ", "); }) +
                     "); where a method falls back to another, the one that served is recorded per sample")
      ->capture_default_str();
  app.add_option("--branch", s.branch, "Assembly branch evaluated, an index of the device's (" + branches_help(help) + ")")
      ->capture_default_str();
  app.add_option("--pose", s.pose,
                 "The task pose, all of the device's task coordinates comma separated (" +
                     help.per_device([](const MechanismInfo& i) { return i.task.size() > 3 ? with_units(i.task) : ""; }) +
                     "): the coordinates after x, y, z (orientation, grip) are held fixed" + pose_default);
  app.add_option("--torque", s.torque,
                 "Torque limit of the haptic fields and force criteria (force_iso, force_max): continuous or peak, "
                 "from the preset's actuator_data (docs/haptic-measures.md)")
      ->capture_default_str();
}

IkOptions checked_ik(const MechanismInfo& info, const std::string& method, std::optional<int> branch,
                     const std::string& command) {
  IkOptions ik;
  if (!method.empty()) index_of(info.ik_methods, method, "IK method for " + info.name);
  ik.method = method;
  if (branch && (*branch < 0 || *branch >= int(info.branches.size())))
    throw std::invalid_argument(command + ": --branch must be 0.." + std::to_string(info.branches.size() - 1) +
                                " for " + info.name + ", got " + std::to_string(*branch));
  ik.branch = branch;
  return ik;
}

void check_read_coordinates(const MechanismInfo& info, const Eigen::VectorXd& x, const std::string& what) {
  for (std::size_t k = 0; k < info.task.size() && Eigen::Index(k) < x.size(); ++k) {
    const Quantity& c = info.task[k];
    const double v = x(Eigen::Index(k));
    if (std::count(info.fk_inputs.begin(), info.fk_inputs.end(), c.name) && !c.range.contains(v))
      throw std::invalid_argument(what + c.name + " = " + format_number(v) + " is outside " + info.name + "'s range " +
                                  format_number(c.range.lo) + " to " + format_number(c.range.hi) + " " + c.unit);
  }
}

SampledDevice check_sampling_options(const SamplingOptions& s, const std::string& command) {
  SampledDevice out;
  out.preset = chosen_preset(s.mechanism);
  apply_stop_switches(s.stops, out.preset, command);
  out.mechanism = make_mechanism(out.preset);
  out.torque = haptics::parse_torque_rating(s.torque);
  const MechanismInfo& info = out.mechanism->info();
  if (!s.pose.empty()) {
    const auto v = parse_numbers(s.pose, info.task.size(),
                                 command + ": --pose expects " + joined_names(info.task) + " for " + info.name);
    out.pose = Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
    check_read_coordinates(info, *out.pose, command + ": --pose: ");
  }
  out.ik = checked_ik(info, s.method, s.branch, command);
  if (s.branch == 0) out.ik.branch.reset();
  return out;
}

void check_ik_tolerance(double tolerance, const std::string& command) {
  if (!(tolerance >= kFinestTolerance && tolerance <= kCoarsestTolerance))
    throw std::invalid_argument(command + ": --tolerance must lie between 1e-15 (double precision closes a chain to a "
                                "few 1e-16 of the device's size) and 1e-3 (an ok answer further off is not the "
                                "device's pose), got " + format_number(tolerance));
}

std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    const std::optional<double> x = parse_number(part);
    if (!x || !std::isfinite(*x)) throw std::invalid_argument(what + ", got '" + text + "'");
    v.push_back(*x);
  }
  if (v.size() != count || (!text.empty() && text.back() == ','))
    throw std::invalid_argument(what + ", got '" + text + "'");
  return v;
}

CLI::Validator criteria_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        for (const std::string& part : task::split_criteria(text))
          if (const std::string hint = task::quoting_hint(part); !hint.empty())
            return "'" + part + "' has no comparison" + hint;
        return "";
      },
      "CRITERIA");
}

std::string joined_names(const std::vector<Quantity>& items, const std::string& prefix) {
  std::string out;
  for (const Quantity& q : items) out += (out.empty() ? "" : ",") + prefix + q.name;
  return out;
}

}  // namespace linkscape::gui
