// linkscape export-model: a device as a MuJoCo model (MJCF) for simulators (docs/model-export.md).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/mechanisms/described/mjcf.h"
#include "core/preset.h"
#include "gui/cli/command.h"
#include "gui/cli/sampling.h"

namespace linkscape::gui {
namespace {

struct ExportModelOptions {
  PresetChoice mechanism;
  std::string output;  // .xml
};

// A compiled device exports through its described twin, the preset named
// "<name>-described", with the parameters they share; a changed parameter
// the twin lacks is refused rather than dropped.
Preset described_preset(const PresetChoice& choice) {
  Preset preset = chosen_preset(choice);
  if (!preset.description.empty()) return preset;
  const std::string twin = preset.mechanism + "-described";
  const auto presets = available_presets();
  if (std::find(presets.begin(), presets.end(), twin) == presets.end())
    throw std::invalid_argument("export-model: " + preset.mechanism +
                                " is compiled and has no described twin ('" + twin +
                                "'): only devices with a chain description can be written as MJCF");
  Preset described = load_preset(twin);
  const Preset defaults = load_preset(preset.mechanism);
  for (const auto& [name, value] : preset.parameters) {
    if (described.parameters.count(name) || motor_parameter(name)) described.parameters[name] = value;
    else if (const auto d = defaults.parameters.find(name); d == defaults.parameters.end() || d->second != value)
      throw std::invalid_argument("export-model: " + name + " of " + preset.mechanism + " has no counterpart in " +
                                  twin + "; export " + twin + " with its own parameters");
  }
  described.actuator_data = preset.actuator_data;
  validate(described);
  return described;
}

void run_export_model(const ExportModelOptions& o, std::ostream& out) {
  if (std::filesystem::path(o.output).extension() != ".xml")
    throw std::invalid_argument("export-model: --output must end in .xml (MJCF), got '" + o.output + "'");
  check_output(o.output);
  const Preset preset = described_preset(o.mechanism);
  write_text_atomically(o.output, described::mjcf_model(preset));
  out << "wrote " << o.output << ": " << preset.title << " as MJCF (lengths in m; joint values as Linkscape's)\n";
}

Command add_export_model(CLI::App& program, const DeviceHelp&) {
  auto o = std::make_shared<ExportModelOptions>();
  CLI::App* cmd = program.add_subcommand(
      "export-model",
      "Write the device as a MuJoCo model (MJCF): legs as chains of bodies welded to the platform, the design's "
      "dimensions, motors on the actuators (docs/model-export.md)");
  add_mechanism_options(*cmd, o->mechanism);
  cmd->add_option("-o,--output", o->output, "Output: .xml")->required();
  return {cmd, Runs::Headless, "linkscape export-model -m falcon -o falcon.xml    the device for MuJoCo",
          [o](std::istream&, std::ostream& out) {
            run_export_model(*o, out);
            return 0;
          }};
}

const RegisterCommand registered{90, add_export_model};

}  // namespace
}  // namespace linkscape::gui
