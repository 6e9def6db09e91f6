// linkscape export-model: a device as a MuJoCo model (MJCF) for simulators (docs/model-export.md).
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

void run_export_model(const ExportModelOptions& o, std::ostream& out) {
  if (std::filesystem::path(o.output).extension() != ".xml")
    throw std::invalid_argument("export-model: --output must end in .xml (MJCF), got '" + o.output + "'");
  check_output(o.output);
  Preset preset;
  try {
    preset = described::described_twin(chosen_preset(o.mechanism));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("export-model: ") + e.what());
  }
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
