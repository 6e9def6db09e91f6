// Fuzz target for sessions (gui/window/session.h). The input is a session file.
// load_session either throws std::invalid_argument or returns a session that
// save_session writes and load_session reads back unchanged, and saving that
// again writes the same bytes.
//
// Only the JSON side is fuzzed: camera_state/apply_camera need a vtkRenderer.
// session.cpp is compiled into this target with VTK linked for them.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>

#include "fuzz_check.h"
#include "gui/window/session.h"

namespace {

namespace fs = std::filesystem;
using linkscape::gui::Session;

// Files of this process, removed at exit.
struct Scratch {
  fs::path dir;
  Scratch() {
    dir = fs::temp_directory_path() / ("linkscape-fuzz-session-" + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

const Scratch& scratch() {
  static const Scratch s;
  return s;
}

std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return same(a.x(), b.x()) && same(a.y(), b.y()) && same(a.z(), b.z());
}
bool same(const std::optional<double>& a, const std::optional<double>& b) {
  return a.has_value() == b.has_value() && (!a || same(*a, *b));
}

// Field by field, bit for bit: what differs, or "" when the sessions are the same.
std::string difference(const Session& a, const Session& b) {
  if (a.mechanism != b.mechanism) return "mechanism";
  if (a.parameters.size() != b.parameters.size()) return "parameters";
  for (auto i = a.parameters.begin(), j = b.parameters.begin(); i != a.parameters.end(); ++i, ++j)
    if (i->first != j->first || !same(i->second, j->second)) return "parameters." + i->first;
  if (a.actuator_limits_deg.size() != b.actuator_limits_deg.size()) return "actuator_limits_deg";
  for (auto i = a.actuator_limits_deg.begin(), j = b.actuator_limits_deg.begin(); i != a.actuator_limits_deg.end(); ++i, ++j)
    if (i->first != j->first || !same(i->second[0], j->second[0]) || !same(i->second[1], j->second[1]))
      return "actuator_limits_deg." + i->first;
  if (a.pose.size() != b.pose.size()) return "actuators";
  for (Eigen::Index k = 0; k < a.pose.size(); ++k)
    if (!same(a.pose(k), b.pose(k))) return "actuators[" + std::to_string(k) + "]";
  if (a.task.size() != b.task.size()) return "task";
  for (Eigen::Index k = 0; k < a.task.size(); ++k)
    if (!same(a.task(k), b.task(k))) return "task[" + std::to_string(k) + "]";
  if (a.camera.has_value() != b.camera.has_value()) return "camera present";
  if (a.camera) {
    if (!same(a.camera->position, b.camera->position)) return "camera.position";
    if (!same(a.camera->focal_point, b.camera->focal_point)) return "camera.focal_point";
    if (!same(a.camera->view_up, b.camera->view_up)) return "camera.view_up";
    if (!same(a.camera->view_angle, b.camera->view_angle)) return "camera.view_angle_deg";
  }
  const auto &f = a.field, &g = b.field;
  if (f.field != g.field) return "field.field";
  if (f.normal != g.normal) return "field.normal";
  if (!same(f.position, g.position)) return "field.position";
  if (f.follow_endpoint != g.follow_endpoint) return "field.follow_endpoint";
  if (!same(f.threshold, g.threshold)) return "field.threshold";
  if (!same(f.range_min, g.range_min)) return "field.range_min";
  if (!same(f.range_max, g.range_max)) return "field.range_max";
  if (f.slice_resolution != g.slice_resolution) return "field.slice_resolution";
  if (f.volume_resolution != g.volume_resolution) return "field.volume_resolution";
  if (f.show_slice != g.show_slice || f.show_reach != g.show_reach || f.show_well_conditioned != g.show_well_conditioned)
    return "field.show_*";
  if (!same(f.reach_opacity, g.reach_opacity)) return "field.reach_opacity";
  if (!same(f.well_conditioned_opacity, g.well_conditioned_opacity)) return "field.well_conditioned_opacity";
  if (f.method != g.method) return "field.method";
  return "";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const fs::path input = scratch().dir / "input.json";
  const fs::path first = scratch().dir / "first.json", second = scratch().dir / "second.json";
  {
    std::ofstream out(input, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    FUZZ_CHECK(out.good(), "cannot write " << input);
  }
  Session loaded;
  try {
    loaded = linkscape::gui::load_session(input);
  } catch (const std::invalid_argument& e) {
    FUZZ_CHECK(std::string_view(e.what()).starts_with("session '" + input.string() + "': "), "message: " << e.what());
    return 0;
  }

  linkscape::gui::save_session(loaded, first);
  Session reloaded;
  try {
    reloaded = linkscape::gui::load_session(first);
  } catch (const std::invalid_argument& e) {
    FUZZ_CHECK(false, "a loaded session, saved, does not load again: " << e.what() << "\nsaved:\n" << read_all(first));
  }
  const std::string changed = difference(loaded, reloaded);
  FUZZ_CHECK(changed.empty(), changed << " changed in save and load; saved:\n" << read_all(first));
  linkscape::gui::save_session(reloaded, second);
  FUZZ_CHECK(read_all(first) == read_all(second), "saving the reloaded session wrote other bytes");
  return 0;
}
