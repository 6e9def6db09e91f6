#include "gui/cli/field_sampling.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "core/status.h"
#include "core/size_text.h"

namespace linkscape::gui {
namespace {

constexpr double kProgramBytes = 96.0 * (1 << 20);

}  // namespace

void add_field_options(CLI::App& app, FieldOptions& o, const DeviceHelp& devices) {
  add_sampling_options(app, o.device, devices,
                       " over the grid, and the default slice passes through the position (default: the device's home pose)");
  app.add_option("--tolerance", o.tolerance,
                 "Accept a sample's IK solution when its residual <= tolerance * the device's size; a tighter value "
                 "shows where each method gives up")
      ->capture_default_str();
  app.add_flag("-q,--quiet", o.quiet, "No progress line on stderr");
}

void Sampling::with_haptics() {
  device_data();
  haptic = true;
  bytes_per_sample += 4 * sizeof(float);
}

std::optional<Field> Sampling::sample(const Grid& grid, const FieldProgress& progress) const {
  if (!haptic) return mechanism->compute_field(grid, task, ik, 0, progress);
  const haptics::DeviceData data = device_data();
  return haptics::sample_field(*mechanism, grid, task, ik, 0, progress, &data, torque);
}

void check_peak_memory(const Grid& grid, std::size_t bytes_per_sample, double factor, const std::string& what) {
  const double arrays = double(grid.size()) * double(bytes_per_sample);
  const double peak = arrays * factor + kProgramBytes;
  double limit = double(kFieldMemoryLimitBytes);
  std::string limit_source = "the field engine's limit";
  if (const std::optional<double> available = available_memory_bytes(); available && *available < limit) {
    limit = *available;
    limit_source = "the memory available now";
  }
  if (peak <= limit) return;
  std::ostringstream msg;
  msg << std::fixed << std::setprecision(2) << what << ": " << grid.dims[0] << "x" << grid.dims[1] << "x" << grid.dims[2] << " samples need about "
      << peak / (1 << 30) << " GiB at peak (field arrays " << arrays / (1 << 30) << " GiB x " << factor
      << " for the output), over " << limit / (1 << 30) << " GiB (" << limit_source << "); lower the resolution";
  throw std::invalid_argument(msg.str());
}

Sampling make_sampling(const FieldOptions& o, const std::string& command) {
  SampledDevice device = check_sampling_options(o.device, command);
  Sampling out;
  out.preset = std::move(device.preset);
  out.mechanism = device.mechanism;
  out.torque = device.torque;
  out.task = device.pose ? *device.pose : out.mechanism->home_task();
  out.ik = device.ik;
  check_ik_tolerance(o.tolerance, command);
  out.ik.tolerance = o.tolerance;
  // Field arrays: a second condition array where the device has a second
  // measure, the method used per sample where it has several methods.
  const MechanismInfo& info = out.mechanism->info();
  if (info.measures.size() > 1) out.bytes_per_sample += sizeof(float);
  if (info.ik_methods.size() > 1) out.bytes_per_sample += 1;
  return out;
}

std::string extension_of(const std::string& path) { return std::filesystem::path(path).extension().string(); }

// Samples the field, showing its progress on the terminal.
Field sample(const Sampling& sampling, const Grid& grid, ProgressLine& line) {
  FieldProgress progress;
  line.step("sampling");
  if (line.shown()) progress.report = [&](double f) { line.report(f); };
  std::optional<Field> field = sampling.sample(grid, progress);
  line.clear();
  return std::move(*field);
}

std::string megabytes(std::uintmax_t bytes) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << double(bytes) / 1e6 << " MB";
  return out.str();
}

// "192x192x192" or "512x512".
std::string dimensions_text(const Grid& grid) {
  std::string out;
  for (int n : grid.dims)
    if (n > 1) out += (out.empty() ? "" : "x") + std::to_string(n);
  return out.empty() ? "1" : out;
}

Grid box_grid(const Sampling& sampling, const std::vector<double>& box_option, const std::string& resolution) {
  std::vector<double> box = box_option;
  if (box.empty())
    box = {sampling.box_min().x(), sampling.box_max().x(), sampling.box_min().y(),
           sampling.box_max().y(), sampling.box_min().z(), sampling.box_max().z()};
  if (box.size() != 6 || !std::all_of(box.begin(), box.end(), [](double v) { return std::abs(v) <= 1e300; }) ||
      !(box[0] < box[1] && box[2] < box[3] && box[4] < box[5]))
    throw std::invalid_argument("--box expects x_min,x_max,y_min,y_max,z_min,z_max: within ±1e300, min < max on each axis");
  return Grid::box({box[0], box[2], box[4]}, {box[1], box[3], box[5]}, parse_grid_size(resolution, "--resolution"));
}

std::string field_csv_legend() {
  return "CSV: a column's unit is its suffix (x_cm, reach_margin_cm, force_iso_N); no\n"
         "suffix: a ratio, count or code. An empty cell has no value: cond, residual,\n"
         "method_used and the haptic arrays where the sample is not reachable (reachable 0).\n"
         "status: " + status_codes() + ".\n"
         "method_used: the device's code of the IK method that served (12R: 0 paper,\n"
         "1 planar, 2 newton, 3 dls; Delta: 0 closed, 1 newton; described devices:\n"
         "0 closed, 1 newton, 2 lanes; PATHOS-II 0).\n"
         "See docs/file-formats.md.";
}

}  // namespace linkscape::gui
