// linkscape field: the fields sampled on a 3-D grid, as VTK image data or CSV.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "core/field.h"
#include "core/haptics.h"
#include "core/size_text.h"
#include "gui/cli/command.h"
#include "gui/cli/field_sampling.h"
#include "gui/cli/terminal.h"
#include "render/field_vtk.h"

namespace linkscape::gui {
namespace {

struct FieldCommandOptions {
  FieldOptions sampling;
  std::string resolution = "128";  // N or NXxNYxNZ
  std::vector<double> box;         // x_min,x_max,y_min,y_max,z_min,z_max; default +-reach
  std::vector<std::string> fields; // haptic arrays to add: force_iso, force_max, resolution, inertia
  std::string output;              // .vti or .csv
};

std::string megabytes(std::uintmax_t bytes) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << double(bytes) / 1e6 << " MB";
  return out.str();
}

void run_field(const FieldCommandOptions& o) {
  if (o.output.empty()) throw std::invalid_argument("field: --output is empty; give a file (.vti or .csv)");
  const std::string ext = extension_of(o.output);
  if (ext != ".vti" && ext != ".csv")
    throw std::invalid_argument("field: --output must end in .vti or .csv, got '" + o.output + "'");
  Sampling sampling = make_sampling(o.sampling, "field");
  for (const std::string& name : o.fields)
    if (!haptics::is_haptic_field(name))
      throw std::invalid_argument("field: --field adds force_iso, force_max, resolution or inertia (the other arrays, "
                                  "and a device's joint_margin and clearance, are always written), got '" + name + "'");
  if (!o.fields.empty()) sampling.with_haptics();
  if (std::count(o.fields.begin(), o.fields.end(), "inertia") && !sampling.device_data().has_inertia())
    throw std::invalid_argument("--field inertia: the preset gives no rotor_inertia_kgm2 for every actuator");
  const Grid grid = box_grid(sampling, o.box, o.resolution);
  check_peak_memory(grid, sampling.bytes_per_sample, ext == ".vti" ? kPeakVti : kPeakCsv, "field");
  const auto start = std::chrono::steady_clock::now();
  ProgressLine line(o.sampling.quiet);
  Field field = sample(sampling, grid, line);
  // The haptic arrays asked for; the device's own (its stops) always.
  std::erase_if(field.extras, [&](const Field::NamedArray& a) {
    return haptics::is_haptic_field(a.name) && std::find(o.fields.begin(), o.fields.end(), a.name) == o.fields.end();
  });
  line.step("writing " + o.output);
  if (ext == ".vti") render::write_vti(field, o.output);
  else render::write_field_csv(field, o.output);
  line.clear();
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(o.output, ec);
  summary(o.sampling.quiet, "field: wrote " + o.output + " (" + sampling.mechanism->info().name + ", " +
                                dimensions_text(grid) + " samples" +
                                (ec ? std::string() : ", " + megabytes(bytes)) + ") in " +
                                seconds_since(start));
}

Command add_field(CLI::App& program, const DeviceHelp& help) {
  auto o = std::make_shared<FieldCommandOptions>();
  CLI::App* cmd = program.add_subcommand(
      "field", "Sample c(J), reach margin and diagnostics on a 3-D grid; write VTK .vti or CSV");
  add_field_options(*cmd, o->sampling, help);
  cmd->add_option("--resolution", o->resolution, "Samples per axis: N or NXxNYxNZ")->capture_default_str();
  cmd->add_option("--box", o->box, "x_min,x_max,y_min,y_max,z_min,z_max; default the device's sampling box")
      ->delimiter(',')
      ->expected(6);
  cmd->add_option("--field", o->fields,
                  "Also write these haptic arrays (comma list): force_iso, force_max (N), resolution (mm), "
                  "inertia (kg); the kinematic arrays are always written")
      ->delimiter(',');
  cmd->add_option("-o,--output", o->output, "Output: .vti (ParaView) or .csv")->required();
  cmd->footer(field_csv_legend());

  return {cmd, Runs::Headless, "linkscape field --resolution 128 --output volume.vti    sampled volume for ParaView",
          [o](std::istream&, std::ostream&) {
            run_field(*o);
            return 0;
          }};
}

const RegisterCommand registered{30, add_field};

}  // namespace
}  // namespace linkscape::gui
