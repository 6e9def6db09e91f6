// The devices Linkscape knows, by preset mechanism name. Adding a device adds
// one line here and its folder beside this file.
#include <algorithm>
#include <stdexcept>
#include <utility>

#include "core/mechanism.h"
#include "core/mechanisms/delta/mechanism.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/mechanisms/parallel12r/mechanism.h"
#include "core/mechanisms/pathos2/mechanism.h"
#include "core/preset.h"

namespace linkscape {
namespace {

using Factory = std::shared_ptr<const Mechanism> (*)(const Preset&);

struct Device {
  std::string name;
  Factory factory;
  bool reads_stops;  // its factory reads a preset's "stops" block
};

const std::vector<Device>& registry() {
  static const std::vector<Device> devices = {
      {"parallel-12r", &parallel12r::make_mechanism, false},
      {"pathos2", &pathos2::make_mechanism, true},
      {"delta", &delta::make_mechanism, true},
  };
  return devices;
}

}  // namespace

std::vector<std::string> registered_mechanisms() {
  std::vector<std::string> names;
  for (const Device& d : registry()) names.push_back(d.name);
  return names;
}

namespace {

std::shared_ptr<const Mechanism> make_linkage(const Preset& preset) {
  // Described devices are files, not entries of the list (docs/described-mechanisms.md).
  if (preset.mechanism == described::kMechanismName) return described::make_mechanism(preset);
  for (const Device& d : registry()) {
    if (d.name != preset.mechanism) continue;
    if (!d.reads_stops && !preset.stops.empty())
      throw std::invalid_argument(d.name + " takes no \"stops\" block (its links and passive joints are not modelled)");
    return d.factory(preset);
  }
  std::string known;
  for (const auto& n : registered_mechanisms()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unsupported mechanism '" + preset.mechanism + "' (supported: " + known +
                              ", or \"described\" with a description)");
}

}  // namespace

std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset) {
  // Motor ratings among the parameters are the haptic measures' (core/haptics.h), not the linkage's.
  const auto is_motor = [](const auto& entry) { return motor_parameter(entry.first) != nullptr; };
  if (std::none_of(preset.parameters.begin(), preset.parameters.end(), is_motor)) return make_linkage(preset);
  Preset linkage = preset;
  std::erase_if(linkage.parameters, is_motor);
  return make_linkage(linkage);
}

std::string default_mechanism() { return registry().front().name; }

std::map<std::string, double> design_parameters(const Mechanism& mechanism, const Preset& preset) {
  std::map<std::string, double> out = mechanism.parameters();
  for (const auto& [name, value] : preset.parameters)
    if (motor_parameter(name)) out[name] = value;
  return out;
}

Preset chosen_preset(const PresetChoice& choice) {
  Preset preset = load_preset(choice.name_or_path);
  apply_overrides(preset, choice.params);
  return preset;
}

int index_of(const std::vector<NamedItem>& items, const std::string& name, const std::string& what) {
  for (std::size_t k = 0; k < items.size(); ++k)
    if (items[k].name == name) return int(k);
  std::string known;
  for (const auto& item : items) known += (known.empty() ? "" : ", ") + item.name;
  throw std::invalid_argument("unknown " + what + " '" + name + "' (known: " + known + ")");
}

}  // namespace linkscape
