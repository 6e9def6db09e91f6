#include "gui/window/session.h"

#include "core/haptics.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include <vtkCamera.h>
#include <vtkRenderer.h>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/field.h"
#include "core/field_names.h"
#include "core/json_checked.h"
#include "core/preset.h"
#include "core/task.h"
#include "render/slice_image.h"

namespace linkscape::gui {
namespace {

using nlohmann::json;

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
Eigen::Vector3d vec(const json& j, const std::string& key) {
  if (!j.is_array() || j.size() != 3 || !std::all_of(j.begin(), j.end(), [](const json& v) { return v.is_number(); }))
    throw std::invalid_argument(key + " must be an array of 3 numbers, got " + j.dump());
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

// The device a session describes: its preset with the session's parameters and actuator limits.
std::shared_ptr<const Mechanism> session_mechanism(const Session& s) {
  Preset preset = load_preset(s.mechanism);
  for (const auto& [name, value] : s.parameters) preset.parameters[name] = value;
  for (const auto& [name, range] : s.actuator_limits_deg) preset.limits_deg[name] = {range[0], range[1]};
  return make_mechanism(preset);
}

json by_name(const Eigen::VectorXd& values, const std::vector<Quantity>& names, const std::string& what) {
  if (values.size() != Eigen::Index(names.size()))
    throw std::invalid_argument("session: " + what + " has " + std::to_string(values.size()) + " values, the device " +
                                std::to_string(names.size()));
  json j = json::object();
  for (std::size_t k = 0; k < names.size(); ++k) j[names[k].name] = values(Eigen::Index(k));
  return j;
}

json fit_outcome_json(const FitOutcome& r) {
  json j = {{"report", r.report}, {"status", r.status}, {"design", r.design}};
  if (r.centre) j["centre"] = vec(*r.centre);
  return j;
}

}  // namespace

void save_session(const Session& s, const std::filesystem::path& path) {
  json j;
  j["format"] = "linkscape-session";
  j["version"] = 1;
  j["mechanism"] = s.mechanism;
  j["parameters"] = s.parameters;
  if (!s.actuator_limits_deg.empty()) j["actuator_limits_deg"] = s.actuator_limits_deg;
  if (s.checks != StopChecks{})
    j["stops"] = {{"joint_limits", s.checks.joint_limits}, {"interference", s.checks.interference}};
  // By name, in the device's own terms (its description lists the order).
  const auto mechanism = session_mechanism(s);  // kept alive while its description is read
  const MechanismInfo& info = mechanism->info();
  if (s.pose.size() > 0) j["actuators"] = by_name(s.pose, info.actuators, "actuators");
  if (s.task.size() > 0) j["task"] = by_name(s.task, info.task, "task");
  if (s.camera)
    j["camera"] = {{"position", vec(s.camera->position)},
                   {"focal_point", vec(s.camera->focal_point)},
                   {"view_up", vec(s.camera->view_up)},
                   {"view_angle_deg", s.camera->view_angle}};
  const FieldSettings& f = s.field;
  j["field"] = {{"field", f.field},
                {"normal", f.normal},
                {"position", f.position},
                {"follow_endpoint", f.follow_endpoint},
                {"threshold", f.threshold},
                {"slice_resolution", f.slice_resolution},
                {"volume_resolution", f.volume_resolution},
                {"show_slice", f.show_slice},
                {"show_reach", f.show_reach},
                {"show_well_conditioned", f.show_well_conditioned},
                {"reach_opacity", f.reach_opacity},
                {"well_conditioned_opacity", f.well_conditioned_opacity},
                {"colour_map", f.colour_map},
                {"log_scale", f.log_scale},
                };
  if (!f.method.empty()) j["field"]["method"] = f.method;
  if (f.range_min) j["field"]["range_min"] = *f.range_min;
  if (f.range_max) j["field"]["range_max"] = *f.range_max;
  j["field"]["slice_opacity"] = f.slice_opacity;
  if (s.task_volume)
    j["task_volume"] = {{"volume", s.task_volume->volume}, {"criteria", s.task_volume->criteria}, {"shown", s.task_volume->shown}};
  if (s.fit)
    j["fit"] = {{"free", s.fit->free},         {"bounds", s.fit->bounds},
                {"equal", s.fit->equal},       {"mode", s.fit->largest_margin ? "largest-margin" : "smallest-size"},
                {"size", s.fit->size},         {"centre_free", s.fit->centre_free}};
  if (s.fit && !s.fit->centre_region.empty()) j["fit"]["centre_region"] = s.fit->centre_region;
  if (s.fit_result) j["fit_result"] = fit_outcome_json(*s.fit_result);
  if (!s.view.empty()) j["view"] = s.view;
  const std::string text = j.dump(2) + "\n";
  write_text_atomically(path, text);
}

CameraState camera_state(vtkRenderer* renderer) {
  vtkCamera* c = renderer->GetActiveCamera();
  CameraState cam;
  c->GetPosition(cam.position.data());
  c->GetFocalPoint(cam.focal_point.data());
  c->GetViewUp(cam.view_up.data());
  cam.view_angle = c->GetViewAngle();
  return cam;
}

void apply_camera(vtkRenderer* renderer, const CameraState& cam) {
  vtkCamera* c = renderer->GetActiveCamera();
  c->SetPosition(cam.position.data());
  c->SetFocalPoint(cam.focal_point.data());
  c->SetViewUp(cam.view_up.data());
  c->SetViewAngle(cam.view_angle);
  renderer->ResetCameraClippingRange();
}

FieldChoices field_choices(const MechanismInfo& info) {
  FieldChoices c;
  c.fields = device_fields(info, info.eval_columns.ik_diagnostics);
  if (info.ik_methods.size() > 1)
    for (const NamedItem& m : info.ik_methods) c.methods.push_back(m.name);
  // Haptic measures (core/haptics.h); inertia shows only where the preset
  // gives every rotor inertia (the window says so otherwise).
  for (const haptics::FieldInfo& f : haptics::all_field_infos()) c.fields.push_back(f.name);
  // Coarse choices for slow devices, fine ones for fast ones; sessions of
  // every earlier per-device list stay valid.
  c.slice_resolutions = {64, 96, 128, 192, 256, 384, 512, 768};
  c.volume_resolutions = {24, 32, 48, 64, 96, 128};
  c.default_slice_resolution = 192;
  c.default_volume_resolution = 64;
  return c;
}

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}
std::string joined(const std::vector<int>& values) {
  std::string out;
  for (int v : values) out += (out.empty() ? "" : ", ") + std::to_string(v);
  return out;
}

void check_keys(const json& object, const std::string& where, const std::vector<std::string>& known) {
  if (!object.is_object()) throw std::invalid_argument(where + " must be a JSON object");
  for (const auto& [key, value] : object.items())
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw std::invalid_argument("unknown key '" + (where.empty() ? "" : where + ".") + key + "' (known: " +
                                  joined(known) + ")");
}

// "stops": a switch for each kind of stop the device states, as booleans.
StopChecks read_stop_checks(const json& j, const Preset& preset) {
  check_keys(j, "stops", {"joint_limits", "interference"});
  const StopChecks stated = stated_stops(preset);
  StopChecks out;
  const auto take = [&](const char* key, bool states, const char* what, bool& check) {
    if (!j.contains(key)) return;
    if (!j[key].is_boolean()) throw std::invalid_argument(std::string("stops.") + key + " must be true or false");
    if (!states) throw std::invalid_argument(std::string("stops.") + key + ": the device states no " + what);
    check = j[key].get<bool>();
  };
  take("joint_limits", stated.joint_limits, "passive-joint limits", out.joint_limits);
  take("interference", stated.interference, "link radii", out.interference);
  return out;
}

// An integer the file gives as an integer within int's range: 1e300 or 100.7
// is an error, never converted (out of range it would be undefined).
int whole_number(const json& j, const std::string& key) {
  if (!j.is_number_integer() || j.get<long long>() < -2147483647LL || j.get<long long>() > 2147483647LL)
    throw std::invalid_argument(key + " must be a whole number, got " + j.dump());
  return j.get<int>();
}

double finite(const json& j, const std::string& key) {
  if (!j.is_number()) throw std::invalid_argument(key + " must be a number, got " + j.dump());
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw std::invalid_argument(key + " must be a finite number");
  return v;
}

Eigen::Vector3d finite_vec(const json& j, const std::string& key) {
  const Eigen::Vector3d v = vec(j, key);
  if (!v.allFinite()) throw std::invalid_argument(key + " must be finite");
  return v;
}

// A preset recorded by an absolute path that is gone (a moved folder, an
// installed copy) still opens when its name is a preset on the search path.
std::string portable_mechanism(const std::string& recorded) {
  const std::filesystem::path p(recorded);
  std::error_code ec;  // a path the system cannot even look up (a name over NAME_MAX) is simply not there
  if (!p.has_parent_path() || std::filesystem::exists(p, ec)) return recorded;
  const std::string name = p.stem().string();
  const auto known = available_presets();
  return std::find(known.begin(), known.end(), name) != known.end() ? name : recorded;
}

template <typename T>
void check_offered(const T& value, const std::vector<T>& offered, const std::string& key) {
  if (std::find(offered.begin(), offered.end(), value) == offered.end()) {
    std::ostringstream msg;
    msg << key << " '" << value << "' is not one the window offers (" << joined(offered) << ")";
    throw std::invalid_argument(msg.str());
  }
}

Eigen::VectorXd read_named(const json& j, const std::vector<Quantity>& names, const std::string& key) {
  std::vector<std::string> known;
  for (const Quantity& q : names) known.push_back(q.name);
  check_keys(j, key, known);
  Eigen::VectorXd v(Eigen::Index(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    if (!j.contains(names[k].name))
      throw std::invalid_argument(key + " needs every one of " + joined(known) + " (" + names[k].name + " is missing)");
    v(Eigen::Index(k)) = finite(j[names[k].name], key + "." + names[k].name);
  }
  return v;
}

Eigen::VectorXd read_array(const json& j, const std::vector<Quantity>& names, const std::string& key) {
  std::vector<std::string> known;
  for (const Quantity& q : names) known.push_back(q.name);
  if (!j.is_array() || j.size() != names.size())
    throw std::invalid_argument(key + " expects " + std::to_string(names.size()) + " numbers (" + joined(known) +
                                ") for this device");
  Eigen::VectorXd v(Eigen::Index(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) v(Eigen::Index(k)) = finite(j[k], key + "[" + std::to_string(k) + "]");
  return v;
}

}  // namespace

bool is_session_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  try {  // checked like every session: a deeply nested file must not overflow the stack
    const json j = parse_json_checked(text, kMaxPresetNesting);
    return j.is_object() && j.value("format", "") == "linkscape-session";
  } catch (const std::exception&) {
    return false;
  }
}

namespace {

// The texts --task and --criterion take, checked the same way.
void check_task_setting(const TaskSetting& setting) {
  task::parse_task(setting.volume);
  for (const std::string& c : setting.criteria) task::parse_criterion(c);
}

// The Fit tab's settings; the device's own checks (parameter names) are the
// tab's, when it applies them.
FitSetting parse_fit(const json& f) {
  check_keys(f, "fit", {"free", "bounds", "equal", "mode", "size", "centre_free", "centre_region"});
  FitSetting fit;
  fit.free = f.value("free", std::vector<std::string>{});
  fit.bounds = f.value("bounds", std::map<std::string, std::array<double, 2>>{});
  for (const auto& [name, range] : fit.bounds)
    if (!(range[0] < range[1]) || !std::isfinite(range[0]) || !std::isfinite(range[1]))
      throw std::invalid_argument("fit.bounds." + name + " must be two finite numbers, the first below the second");
  fit.equal = f.value("equal", std::string());
  const std::string mode = f.value("mode", std::string("smallest-size"));
  if (mode != "smallest-size" && mode != "largest-margin")
    throw std::invalid_argument("fit.mode must be smallest-size or largest-margin, got '" + mode + "'");
  fit.largest_margin = mode == "largest-margin";
  if (f.contains("size")) fit.size = finite(f["size"], "fit.size");
  if (fit.size < 0) throw std::invalid_argument("fit.size must not be negative");
  fit.centre_free = f.value("centre_free", true);
  fit.centre_region = f.value("centre_region", std::string());
  if (!fit.centre_region.empty()) {
    try {
      task::parse_centre_region(fit.centre_region);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("fit.centre_region: ") + e.what());
    }
  }
  return fit;
}

// The Fit tab's last result: texts, the design's finite parameter values and its centre.
FitOutcome parse_fit_outcome(const json& r) {
  check_keys(r, "fit_result", {"report", "status", "design", "centre"});
  FitOutcome out;
  for (const char* key : {"report", "status"})
    if (r.contains(key) && !r[key].is_string())
      throw std::invalid_argument(std::string("fit_result.") + key + " must be text");
  out.report = r.value("report", std::string());
  out.status = r.value("status", std::string());
  if (r.contains("design")) {
    // Its names are the device's parameters, checked when Apply sets them.
    if (!r["design"].is_object()) throw std::invalid_argument("fit_result.design must be a JSON object");
    for (const auto& [name, value] : r["design"].items()) {
      if (!value.is_number() || !std::isfinite(value.get<double>()))
        throw std::invalid_argument("fit_result.design." + name + " must be a finite number");
      out.design[name] = value.get<double>();
    }
  }
  if (r.contains("centre")) out.centre = finite_vec(r["centre"], "fit_result.centre");
  return out;
}

// The View menu's toggles: names (the window ignores one it has no action
// for, e.g. from a later version) with true or false.
std::map<std::string, bool> parse_view(const json& v) {
  if (!v.is_object()) throw std::invalid_argument("view must be a JSON object of toggles");
  std::map<std::string, bool> out;
  for (const auto& [name, on] : v.items()) {
    if (name.empty() || !on.is_boolean())
      throw std::invalid_argument("view." + name + " must be true or false, got " + on.dump());
    out[name] = on.get<bool>();
  }
  return out;
}

}  // namespace

bool valid_task_setting(const TaskSetting& setting) {
  try {
    check_task_setting(setting);
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

Session parse_session(const std::string& text, const std::string& origin) {
  Session s;
  try {
    // As presets are read: no key given twice, no nesting deep enough to overflow the stack.
    const json j = parse_json_checked(text, kMaxPresetNesting);
    if (!j.is_object() || j.value("format", "") != "linkscape-session")
      throw std::invalid_argument("not a Linkscape session (no \"format\": \"linkscape-session\")");
    check_keys(j, "", {"format", "version", "mechanism", "parameters", "actuator_limits_deg", "stops", "actuators",
                       "task", "pose_rad", "platform_pose", "camera", "field", "task_volume", "fit", "fit_result",
                       "view"});
    if (j.contains("version") && whole_number(j["version"], "version") != 1)
      throw std::invalid_argument("version " + j["version"].dump() + " is not supported (this program reads 1)");
    if (!j.contains("mechanism") || !j["mechanism"].is_string())
      throw std::invalid_argument("mechanism must be a preset's name or file, got " +
                                  (j.contains("mechanism") ? j["mechanism"].dump() : std::string("none")));
    s.mechanism = portable_mechanism(j["mechanism"].get<std::string>());
    if (j.contains("parameters")) {
      if (!j["parameters"].is_object()) throw std::invalid_argument("parameters must be an object of numbers");
      for (const auto& [name, value] : j["parameters"].items()) s.parameters[name] = finite(value, "parameters." + name);
    }
    // The mechanism's own rules: a known preset, known parameter names, a
    // valid model (e.g. L1 > 0), known actuator names.
    Preset preset = load_preset(s.mechanism);
    std::vector<std::string> overrides;
    for (const auto& [name, value] : s.parameters) overrides.push_back(name + "=" + format_number(value));
    try {
      apply_overrides(preset, overrides);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("parameters: ") + e.what());
    }
    // Actuator limits by the device's actuator names; the device says whether it takes them.
    const std::vector<Quantity> actuators = make_mechanism(preset)->info().actuators;
    s.actuator_limits_deg = j.value("actuator_limits_deg", std::map<std::string, std::array<double, 2>>{});
    for (const auto& [name, range] : s.actuator_limits_deg) {
      const bool known = std::any_of(actuators.begin(), actuators.end(), [&name = name](const Quantity& q) { return q.name == name; });
      if (!known) {
        std::vector<std::string> names;
        for (const Quantity& q : actuators) names.push_back(q.name);
        throw std::invalid_argument("actuator_limits_deg." + name + ": unknown actuator (known: " + joined(names) + ")");
      }
      if (!(range[0] < range[1]) || !std::isfinite(range[0]) || !std::isfinite(range[1]))
        throw std::invalid_argument("actuator_limits_deg." + name + " must be [lo, hi] with lo < hi");
      preset.limits_deg[name] = {range[0], range[1]};
    }
    std::shared_ptr<const Mechanism> mechanism;
    try {
      mechanism = make_mechanism(preset);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("actuator_limits_deg: ") + e.what());
    }
    if (j.contains("stops")) s.checks = read_stop_checks(j["stops"], preset);
    const MechanismInfo& info = mechanism->info();
    // The pose: by name, or as the arrays of older files.
    if (j.contains("actuators") && j.contains("pose_rad"))
      throw std::invalid_argument("actuators and pose_rad say the same; give one");
    if (j.contains("task") && j.contains("platform_pose"))
      throw std::invalid_argument("task and platform_pose say the same; give one");
    if (j.contains("actuators")) s.pose = read_named(j["actuators"], info.actuators, "actuators");
    if (j.contains("pose_rad")) s.pose = read_array(j["pose_rad"], info.actuators, "pose_rad");
    if (j.contains("task")) s.task = read_named(j["task"], info.task, "task");
    if (j.contains("platform_pose")) s.task = read_array(j["platform_pose"], info.task, "platform_pose");
    if (s.pose.size() == 0 && s.task.size() == 0)
      throw std::invalid_argument("the session has no pose (task or actuators)");
    // Task coordinates the window's sliders cannot show are refused, not clamped.
    for (std::size_t k = 0; k < info.task.size(); ++k)
      if (s.task.size() > 0 && !info.task[k].range.contains(s.task(Eigen::Index(k))))
        throw std::invalid_argument("task." + info.task[k].name + " = " + format_number(s.task(Eigen::Index(k))) +
                                    " is outside the window's range [" + format_number(info.task[k].range.lo) + ", " +
                                    format_number(info.task[k].range.hi) + "]");
    if (j.contains("camera")) {
      const json& c = j["camera"];
      check_keys(c, "camera", {"position", "focal_point", "view_up", "view_angle_deg"});
      for (const char* key : {"position", "focal_point", "view_up"})
        if (!c.contains(key)) throw std::invalid_argument(std::string("camera.") + key + " is missing");
      s.camera = CameraState{finite_vec(c["position"], "camera.position"),
                             finite_vec(c["focal_point"], "camera.focal_point"),
                             finite_vec(c["view_up"], "camera.view_up"), 30.0};
      if (c.contains("view_angle_deg")) s.camera->view_angle = finite(c["view_angle_deg"], "camera.view_angle_deg");
      // Beyond these the view is blank or degenerate (VTK's clipping range
      // and view-up arithmetic lose every digit): refused, not shown empty.
      constexpr double kFarthest = 1e6, kNearest = 1e-6;  // in the preset's length unit
      for (const auto& [name, p] : {std::pair{"position", s.camera->position}, {"focal_point", s.camera->focal_point}})
        if (p.cwiseAbs().maxCoeff() > kFarthest)
          throw std::invalid_argument(std::string("camera.") + name + " must lie within " + format_number(kFarthest) +
                                      " of the origin in every coordinate");
      const Eigen::Vector3d view = s.camera->focal_point - s.camera->position;
      if (!(view.norm() >= kNearest))
        throw std::invalid_argument("camera: position must be at least " + format_number(kNearest) +
                                    " from focal_point");
      if (!(s.camera->view_angle >= 1 && s.camera->view_angle <= 179))
        throw std::invalid_argument("camera.view_angle_deg must be in [1, 179]");
      if (!(s.camera->view_up.cross(view).norm() > 1e-6 * s.camera->view_up.norm() * view.norm()))
        throw std::invalid_argument("camera.view_up must be non-zero and not along the view direction");
    }
    const FieldChoices choices = field_choices(info);
    FieldSettings& d = s.field;
    d.slice_resolution = choices.default_slice_resolution;
    d.volume_resolution = choices.default_volume_resolution;
    if (j.contains("field")) {
      const json& f = j["field"];
      check_keys(f, "field", {"field", "normal", "position", "follow_endpoint", "threshold", "slice_resolution",
                              "volume_resolution", "show_slice", "show_reach", "show_well_conditioned",
                              "reach_opacity", "well_conditioned_opacity", "method", "range_min", "range_max",
                              "colour_map", "log_scale", "slice_opacity"});
      d.field = f.value("field", d.field);
      d.normal = f.value("normal", d.normal);
      if (f.contains("position")) d.position = finite(f["position"], "field.position");
      d.follow_endpoint = f.value("follow_endpoint", d.follow_endpoint);
      if (f.contains("threshold")) d.threshold = finite(f["threshold"], "field.threshold");
      if (f.contains("slice_resolution")) d.slice_resolution = whole_number(f["slice_resolution"], "field.slice_resolution");
      if (f.contains("volume_resolution"))
        d.volume_resolution = whole_number(f["volume_resolution"], "field.volume_resolution");
      d.show_slice = f.value("show_slice", d.show_slice);
      d.show_reach = f.value("show_reach", d.show_reach);
      d.show_well_conditioned = f.value("show_well_conditioned", d.show_well_conditioned);
      if (f.contains("reach_opacity")) d.reach_opacity = finite(f["reach_opacity"], "field.reach_opacity");
      if (f.contains("well_conditioned_opacity"))
        d.well_conditioned_opacity = finite(f["well_conditioned_opacity"], "field.well_conditioned_opacity");
      d.method = f.value("method", d.method);
      if (f.contains("range_min")) d.range_min = finite(f["range_min"], "field.range_min");
      if (f.contains("range_max")) d.range_max = finite(f["range_max"], "field.range_max");
      d.colour_map = f.value("colour_map", d.colour_map);
      d.log_scale = f.value("log_scale", d.log_scale);
      if (f.contains("slice_opacity")) d.slice_opacity = finite(f["slice_opacity"], "field.slice_opacity");
    }
    check_offered(d.colour_map, render::colour_maps(), "field.colour_map");
    check_offered(d.field, choices.fields, "field.field");
    if (!choices.methods.empty() && !d.method.empty()) {
      check_offered(d.method, choices.methods, "field.method");
    } else if (choices.methods.empty()) {
      // One method: nothing to choose. Files written before the one window
      // carried "planar" for every device.
      if (!d.method.empty() && d.method != info.ik_methods.front().name && d.method != "planar")
        throw std::invalid_argument("field.method '" + d.method + "': the device has one IK method (" +
                                    info.ik_methods.front().name + ")");
      d.method.clear();
    }
    check_offered(d.normal, std::vector<std::string>{"x", "y", "z"}, "field.normal");
    // A slice outside the device's box is drawn nowhere.
    if (j.contains("field") && j["field"].contains("position")) {
      const Eigen::AlignedBox3d box = mechanism->default_box();
      const int axis = int(parse_axis(d.normal));
      if (!(d.position >= box.min()(axis) && d.position <= box.max()(axis)))
        throw std::invalid_argument("field.position " + format_number(d.position) + " is outside the device's box along " +
                                    d.normal + " [" + format_number(box.min()(axis)) + ", " +
                                    format_number(box.max()(axis)) + "]");
    }
    check_offered(d.slice_resolution, choices.slice_resolutions, "field.slice_resolution");
    check_offered(d.volume_resolution, choices.volume_resolutions, "field.volume_resolution");
    if (!(d.threshold >= 1.05 && d.threshold <= 100)) throw std::invalid_argument("field.threshold must be in [1.05, 100]");
    for (double o : {d.reach_opacity, d.well_conditioned_opacity, d.slice_opacity})
      if (!(o >= 0 && o <= 1)) throw std::invalid_argument("field opacities must be in [0, 1]");
    if (d.range_min.has_value() != d.range_max.has_value())
      throw std::invalid_argument("field.range_min and field.range_max come together");
    if (d.range_min && !(*d.range_min < *d.range_max))
      throw std::invalid_argument("field.range_min must be below field.range_max");
    // A range the view cannot draw would leave the slice and its colour bar blank.
    render::SliceStyle style;
    style.field = d.field;
    style.log_scale = d.log_scale;
    if (d.range_min && render::uses_log_scale(style) && !(*d.range_min > 0))
      throw std::invalid_argument("field.range_min must be above 0 on a logarithmic colour scale (\"log_scale\": "
                                  "false draws a linear one), got " + format_number(*d.range_min));
    if (j.contains("task_volume")) {
      const json& t = j["task_volume"];
      check_keys(t, "task_volume", {"volume", "criteria", "shown"});
      TaskSetting setting;
      setting.volume = t.at("volume").get<std::string>();
      setting.criteria = t.value("criteria", std::vector<std::string>{});
      setting.shown = t.value("shown", true);
      try {
        check_task_setting(setting);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string("task_volume: ") + e.what());
      }
      s.task_volume = setting;
    }
    if (j.contains("fit")) s.fit = parse_fit(j["fit"]);
    if (j.contains("fit_result")) s.fit_result = parse_fit_outcome(j["fit_result"]);
    if (j.contains("view")) s.view = parse_view(j["view"]);
  } catch (const json::exception& e) {
    throw std::invalid_argument("session '" + origin + "': " + json_error_text(e));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("session '" + origin + "': " + e.what());
  }
  return s;
}

Session load_session(const std::filesystem::path& path) {
  const std::string unreadable = why_not_a_readable_file(path);
  if (!unreadable.empty()) throw std::invalid_argument("session file '" + path.string() + "' " + unreadable);
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot open session file '" + path.string() + "'");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_session(buffer.str(), path.string());
}

}  // namespace linkscape::gui
