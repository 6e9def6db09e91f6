// linkscape describe: how Linkscape solves a described device, leg by leg.
#include <iostream>
#include <stdexcept>

#include "core/mechanisms/described/mechanism.h"
#include "core/mechanism.h"
#include "core/preset.h"
#include "gui/cli/command.h"
#include "gui/cli/device_help.h"
#include "gui/cli/sampling.h"

namespace linkscape::gui {
namespace {

Command add_describe(CLI::App& program, const DeviceHelp&) {
  auto choice = std::make_shared<PresetChoice>();
  auto file = std::make_shared<std::string>();
  CLI::App* cmd = program.add_subcommand(
      "describe",
      "Say how a described device is solved: each leg's pattern (a closed form, or numeric), its actuator and "
      "travel, branch rules and reach bounds, and the mobility (docs/described-mechanisms.md)");
  cmd->add_option("file", *file, "A described preset: a name (falcon, stewart, ...) or a .json file");
  add_mechanism_options(*cmd, *choice);
  return {cmd, Runs::Headless, "linkscape describe stewart    how each leg of a described device is solved",
          [choice, file, cmd](std::istream&, std::ostream& out) {
            PresetChoice c = *choice;
            if (!file->empty()) {
              if (cmd->get_option("--mechanism")->count() > 0)
                throw std::invalid_argument("describe: give the device as FILE or --mechanism, not both");
              c.name_or_path = *file;
            }
            if (file->empty() && cmd->get_option("--mechanism")->count() == 0)
              throw std::invalid_argument("describe: which device? Give a described preset, e.g. 'linkscape describe "
                                          "stewart' or a .json file");
            const Preset preset = chosen_preset(c);
            if (preset.description.empty())
              throw std::invalid_argument("describe: " + preset.mechanism +
                                          " is compiled (C++), not described; describe reads a preset with a "
                                          "\"description\" (docs/described-mechanisms.md)");
            out << described::describe(preset);
            // The columns eval reads, as its help gives them for the compiled devices.
            const std::shared_ptr<const Mechanism> device = make_mechanism(preset);
            const MechanismInfo& info = device->info();
            out << "eval columns: --ik " << with_units(info.task) << "; --fk " << with_units(fk_columns(info)) << "\n";
            return 0;
          }};
}

const RegisterCommand registered{85, add_describe};

}  // namespace
}  // namespace linkscape::gui
