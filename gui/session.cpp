#include "gui/session.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include <vtkCamera.h>
#include <vtkRenderer.h>

#include "core/atomic_file.h"

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

Session load_session(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot open session file '" + path.string() + "'");
  std::stringstream buffer;
  buffer << in.rdbuf();
  Session s;
  try {
    const json j = json::parse(buffer.str());
    if (j.value("format", "") != "linkscape-session") throw std::invalid_argument("not a Linkscape session (no \"format\": \"linkscape-session\")");
    s.mechanism = j.at("mechanism").get<std::string>();
    s.parameters = j.value("parameters", std::map<std::string, double>{});
    s.actuator_limits_deg = j.value("actuator_limits_deg", std::map<std::string, std::array<double, 2>>{});
    for (const auto& [name, range] : s.actuator_limits_deg)
      if (!(range[0] < range[1]) || !std::isfinite(range[0]) || !std::isfinite(range[1]))
        throw std::invalid_argument("actuator_limits_deg." + name + " must be [lo, hi] with lo < hi");
    if (j.contains("platform_pose")) {
      s.platform_pose = j.at("platform_pose").get<std::array<double, 7>>();
      for (double v : *s.platform_pose)
        if (!std::isfinite(v)) throw std::invalid_argument("platform_pose must be finite");
      if (!((*s.platform_pose)[6] > 0)) throw std::invalid_argument("platform_pose: the grip h0 must be > 0");
    } else {
      s.pose = vec(j.at("pose_rad"));
      if (!s.pose.allFinite()) throw std::invalid_argument("pose_rad must be finite");
    }
    if (j.contains("camera")) {
      const json& c = j["camera"];
      s.camera = CameraState{vec(c.at("position")), vec(c.at("focal_point")), vec(c.at("view_up")),
                             c.value("view_angle_deg", 30.0)};
    }
    if (j.contains("field")) {
      const json& f = j["field"];
      FieldSettings& d = s.field;
      d.field = f.value("field", d.field);
      d.normal = f.value("normal", d.normal);
      d.position = f.value("position", d.position);
      d.follow_endpoint = f.value("follow_endpoint", d.follow_endpoint);
      d.threshold = f.value("threshold", d.threshold);
      d.slice_resolution = f.value("slice_resolution", d.slice_resolution);
      d.volume_resolution = f.value("volume_resolution", d.volume_resolution);
      d.show_slice = f.value("show_slice", d.show_slice);
      d.show_reach = f.value("show_reach", d.show_reach);
      d.show_well_conditioned = f.value("show_well_conditioned", d.show_well_conditioned);
      d.reach_opacity = f.value("reach_opacity", d.reach_opacity);
      d.well_conditioned_opacity = f.value("well_conditioned_opacity", d.well_conditioned_opacity);
      d.method = f.value("method", d.method);
      if (f.contains("range_min")) d.range_min = f["range_min"].get<double>();
      if (f.contains("range_max")) d.range_max = f["range_max"].get<double>();
      if (d.slice_resolution < 8 || d.slice_resolution > 2048 || d.volume_resolution < 8 || d.volume_resolution > 512)
        throw std::invalid_argument("field resolutions out of range (slice 8..2048, volume 8..512)");
      if (!(d.threshold > 1)) throw std::invalid_argument("field threshold must be > 1");
    }
  } catch (const json::exception& e) {
    throw std::invalid_argument("session '" + path.string() + "': " + e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("session '" + path.string() + "': " + e.what());
  }
  return s;
}

}  // namespace linkscape::gui
