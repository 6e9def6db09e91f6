#include "gui/session.h"

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
#include "core/preset.h"

namespace linkscape::gui {
namespace {

using nlohmann::json;

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
Eigen::Vector3d vec(const json& j) {
  if (!j.is_array() || j.size() != 3) throw std::invalid_argument("expected an array of 3 numbers");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

}  // namespace

void save_session(const Session& s, const std::filesystem::path& path) {
  json j;
  j["format"] = "linkscape-session";
  j["version"] = 1;
  j["mechanism"] = s.mechanism;
  j["parameters"] = s.parameters;
  if (!s.actuator_limits_deg.empty()) j["actuator_limits_deg"] = s.actuator_limits_deg;
  if (s.platform_pose) j["platform_pose"] = *s.platform_pose;
  else j["pose_rad"] = vec(s.pose);
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
                {"method", f.method}};
  if (f.range_min) j["field"]["range_min"] = *f.range_min;
  if (f.range_max) j["field"]["range_max"] = *f.range_max;
  const std::string text = j.dump(2) + "\n";
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp);
    out << text;
    if (!out) throw std::runtime_error("cannot write session '" + path.string() + "'");
  });
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

FieldChoices field_choices(const std::string& mechanism) {
  if (mechanism == pathos2::kMechanismName)
    return {{"cond", "cond_jo", "reach", "status"}, {}, {64, 128, 256, 512}, {24, 32, 48, 64}, 128, 48};
  return {{"cond", "reach", "residual", "iterations", "status", "method"},
          {"planar", "paper", "newton", "dls", "fallback"},
          {96, 192, 384, 768},
          {32, 48, 64, 96, 128},
          192,
          64};
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

double finite(const json& j, const std::string& key) {
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw std::invalid_argument(key + " must be a finite number");
  return v;
}

Eigen::Vector3d finite_vec(const json& j, const std::string& key) {
  const Eigen::Vector3d v = vec(j);
  if (!v.allFinite()) throw std::invalid_argument(key + " must be finite");
  return v;
}

// A preset recorded by an absolute path that is gone (a moved folder, an
// installed copy) still opens when its name is a preset on the search path.
std::string portable_mechanism(const std::string& recorded) {
  const std::filesystem::path p(recorded);
  if (!p.has_parent_path() || std::filesystem::exists(p)) return recorded;
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

}  // namespace

Session parse_session(const std::string& text, const std::string& origin) {
  Session s;
  try {
    const json j = json::parse(text);
    if (!j.is_object() || j.value("format", "") != "linkscape-session")
      throw std::invalid_argument("not a Linkscape session (no \"format\": \"linkscape-session\")");
    check_keys(j, "", {"format", "version", "mechanism", "parameters", "actuator_limits_deg", "platform_pose",
                       "pose_rad", "camera", "field"});
    if (j.contains("version") && j["version"].get<int>() != 1)
      throw std::invalid_argument("version " + j["version"].dump() + " is not supported (this program reads 1)");
    s.mechanism = portable_mechanism(j.at("mechanism").get<std::string>());
    s.parameters = j.value("parameters", std::map<std::string, double>{});
    for (const auto& [name, value] : s.parameters)
      if (!std::isfinite(value)) throw std::invalid_argument("parameters." + name + " must be a finite number");
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
    s.actuator_limits_deg = j.value("actuator_limits_deg", std::map<std::string, std::array<double, 2>>{});
    if (!s.actuator_limits_deg.empty() && preset.mechanism != parallel12r::kMechanismName)
      throw std::invalid_argument("actuator_limits_deg applies to parallel-12r sessions");
    for (const auto& [name, range] : s.actuator_limits_deg) {
      if (name != "alpha" && name != "beta" && name != "gamma")
        throw std::invalid_argument("actuator_limits_deg." + name + ": unknown actuator (known: alpha, beta, gamma)");
      if (!(range[0] < range[1]) || !std::isfinite(range[0]) || !std::isfinite(range[1]))
        throw std::invalid_argument("actuator_limits_deg." + name + " must be [lo, hi] with lo < hi");
      preset.limits_deg[name] = {range[0], range[1]};
    }
    try {
      validate(preset);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("actuator_limits_deg: ") + e.what());
    }
    const bool six_dof = preset.mechanism == pathos2::kMechanismName;
    if (six_dof) {
      if (!j.contains("platform_pose")) throw std::invalid_argument("a pathos2 session needs platform_pose");
      if (j.contains("pose_rad")) throw std::invalid_argument("pose_rad applies to parallel-12r sessions");
      s.platform_pose = j.at("platform_pose").get<std::array<double, 7>>();
      for (double v : *s.platform_pose)
        if (!std::isfinite(v)) throw std::invalid_argument("platform_pose must be finite");
      if (!((*s.platform_pose)[6] > 0)) throw std::invalid_argument("platform_pose: the grip h0 must be > 0");
    } else {
      if (j.contains("platform_pose")) throw std::invalid_argument("platform_pose applies to pathos2 sessions");
      s.pose = finite_vec(j.at("pose_rad"), "pose_rad");
    }
    if (j.contains("camera")) {
      const json& c = j["camera"];
      check_keys(c, "camera", {"position", "focal_point", "view_up", "view_angle_deg"});
      s.camera = CameraState{finite_vec(c.at("position"), "camera.position"),
                             finite_vec(c.at("focal_point"), "camera.focal_point"),
                             finite_vec(c.at("view_up"), "camera.view_up"), 30.0};
      if (c.contains("view_angle_deg")) s.camera->view_angle = finite(c["view_angle_deg"], "camera.view_angle_deg");
      if (!(s.camera->view_angle > 0 && s.camera->view_angle < 180))
        throw std::invalid_argument("camera.view_angle_deg must be in (0, 180)");
      if (s.camera->view_up.norm() == 0 || (s.camera->position - s.camera->focal_point).norm() == 0)
        throw std::invalid_argument("camera: view_up must be non-zero and position differ from focal_point");
    }
    const FieldChoices choices = field_choices(preset.mechanism);
    FieldSettings& d = s.field;
    d.slice_resolution = choices.default_slice_resolution;
    d.volume_resolution = choices.default_volume_resolution;
    if (six_dof) d.threshold = 5.0;
    if (j.contains("field")) {
      const json& f = j["field"];
      check_keys(f, "field", {"field", "normal", "position", "follow_endpoint", "threshold", "slice_resolution",
                              "volume_resolution", "show_slice", "show_reach", "show_well_conditioned",
                              "reach_opacity", "well_conditioned_opacity", "method", "range_min", "range_max"});
      d.field = f.value("field", d.field);
      d.normal = f.value("normal", d.normal);
      if (f.contains("position")) d.position = finite(f["position"], "field.position");
      d.follow_endpoint = f.value("follow_endpoint", d.follow_endpoint);
      if (f.contains("threshold")) d.threshold = finite(f["threshold"], "field.threshold");
      d.slice_resolution = f.value("slice_resolution", d.slice_resolution);
      d.volume_resolution = f.value("volume_resolution", d.volume_resolution);
      d.show_slice = f.value("show_slice", d.show_slice);
      d.show_reach = f.value("show_reach", d.show_reach);
      d.show_well_conditioned = f.value("show_well_conditioned", d.show_well_conditioned);
      if (f.contains("reach_opacity")) d.reach_opacity = finite(f["reach_opacity"], "field.reach_opacity");
      if (f.contains("well_conditioned_opacity"))
        d.well_conditioned_opacity = finite(f["well_conditioned_opacity"], "field.well_conditioned_opacity");
      d.method = f.value("method", d.method);
      if (f.contains("range_min")) d.range_min = finite(f["range_min"], "field.range_min");
      if (f.contains("range_max")) d.range_max = finite(f["range_max"], "field.range_max");
    }
    check_offered(d.field, choices.fields, "field.field");
    if (!choices.methods.empty()) check_offered(d.method, choices.methods, "field.method");
    else if (d.method != FieldSettings{}.method) throw std::invalid_argument("field.method applies to parallel-12r");
    check_offered(d.normal, std::vector<std::string>{"x", "y", "z"}, "field.normal");
    check_offered(d.slice_resolution, choices.slice_resolutions, "field.slice_resolution");
    check_offered(d.volume_resolution, choices.volume_resolutions, "field.volume_resolution");
    if (!(d.threshold >= 1.05 && d.threshold <= 100)) throw std::invalid_argument("field.threshold must be in [1.05, 100]");
    for (double o : {d.reach_opacity, d.well_conditioned_opacity})
      if (!(o >= 0 && o <= 1)) throw std::invalid_argument("field opacities must be in [0, 1]");
    if (d.range_min.has_value() != d.range_max.has_value())
      throw std::invalid_argument("field.range_min and field.range_max come together");
    if (d.range_min && !(*d.range_min < *d.range_max))
      throw std::invalid_argument("field.range_min must be below field.range_max");
  } catch (const json::exception& e) {
    throw std::invalid_argument("session '" + origin + "': " + e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("session '" + origin + "': " + e.what());
  }
  return s;
}

Session load_session(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot open session file '" + path.string() + "'");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_session(buffer.str(), path.string());
}

}  // namespace linkscape::gui
