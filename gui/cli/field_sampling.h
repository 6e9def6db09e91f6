// What slice, field and mesh share: their sampling options (the shared six,
// --tolerance and --quiet), the device they choose, ready to sample, and
// the grid of --box and --resolution.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/field.h"
#include "gui/cli/sampling.h"
#include "gui/cli/terminal.h"

namespace linkscape::gui {

struct FieldOptions {
  SamplingOptions device;
  double tolerance = 1e-10;  // accept a sample when residual <= tolerance * the device's size
  bool quiet = false;        // no progress or summary on stderr
};

// The shared six, --tolerance and -q.
void add_field_options(CLI::App& app, FieldOptions& options, const DeviceHelp& devices);

// The footer of the commands that write field CSVs: the units convention
// and the legend of the status and method_used codes.
std::string field_csv_legend();

// What the sampling commands need of the chosen mechanism.
struct Sampling {
  Preset preset;
  std::shared_ptr<const Mechanism> mechanism;
  Eigen::VectorXd task;  // fields hold its non-position coordinates; the default slice passes through it
  IkOptions ik;
  haptics::TorqueRating torque = haptics::TorqueRating::Continuous;
  bool haptic = false;  // also the haptic fields (core/haptics.h)
  std::size_t bytes_per_sample = Field::bytes_per_sample();  // the field arrays
  std::string length_unit() const { return mechanism->info().length_unit; }
  Eigen::Vector3d box_min() const { return mechanism->default_box().min(); }
  Eigen::Vector3d box_max() const { return mechanism->default_box().max(); }
  haptics::DeviceData device_data() const { return haptics::device_data(preset, mechanism->info()); }
  // Asks for the haptic fields; checks the preset's actuator data at once.
  void with_haptics();
  std::optional<Field> sample(const Grid& grid, const FieldProgress& progress) const;
};

// The options checked (messages start with "`command`: ").
Sampling make_sampling(const FieldOptions& options, const std::string& command);

// Samples the field, showing its progress on the terminal.
Field sample(const Sampling& sampling, const Grid& grid, ProgressLine& line);

// Peak memory of a whole command as a multiple of its field arrays, measured
// with /usr/bin/time -v at 256^3 (parallel-12r, 285 MiB of arrays): a .vti
// export compresses the arrays in place (333 MiB, 1.17x), a mesh
// adds the isosurface and its OpenMesh copy (523 MiB, 1.8x), a CSV streams
// (323 MiB, 1.13x). Rounded up, plus the program itself.
constexpr double kPeakVti = 1.3, kPeakMesh = 2.0, kPeakCsv = 1.25;

// Refuses a command whose estimated peak exceeds the memory limit of the
// field engine or the memory available now, whichever is smaller.
void check_peak_memory(const Grid& grid, std::size_t bytes_per_sample, double factor, const std::string& what);

// The grid of --box (default: the device's sampling box) and --resolution.
Grid box_grid(const Sampling& sampling, const std::vector<double>& box, const std::string& resolution);

// "192x192x192" or "512x512".
std::string dimensions_text(const Grid& grid);

std::string extension_of(const std::string& path);

}  // namespace linkscape::gui
