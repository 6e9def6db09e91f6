#include "gui/cli/device_help.h"

#include <algorithm>
#include <exception>

#include "core/preset.h"

namespace linkscape::gui {

std::string DeviceHelp::per_device(const std::function<std::string(const MechanismInfo&)>& text) const {
  std::string out;
  for (const auto& device : devices)
    if (const std::string t = text(device->info()); !t.empty())
      out += (out.empty() ? "" : "; ") + device->info().name + ": " + t;
  return out;
}

DeviceHelp device_help() {
  DeviceHelp help;
  for (const std::string& name : registered_mechanisms()) {
    try {
      help.devices.push_back(make_mechanism(load_preset(name)));
    } catch (const std::exception&) {
      // No usable shipped preset of that name: the help leaves the device out.
    }
  }
  return help;
}

std::vector<Quantity> fk_columns(const MechanismInfo& info) {
  std::vector<Quantity> columns = info.actuators;
  for (const Quantity& q : info.task)
    if (std::count(info.fk_inputs.begin(), info.fk_inputs.end(), q.name)) columns.push_back(q);
  return columns;
}

std::string with_units(const std::vector<Quantity>& items) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k) {
    out += items[k].name;
    const bool last = k + 1 == items.size();
    const bool unit = !items[k].unit.empty() && (last || items[k + 1].unit != items[k].unit);
    if (unit) out += " (" + items[k].unit + ")";
    if (!last) out += unit ? ", " : ",";
  }
  return out;
}

std::string branches_help(const DeviceHelp& help) {
  return help.per_device([](const MechanismInfo& i) {
    std::string out;
    for (const std::string& branch : i.branches) out += (out.empty() ? "" : ", ") + branch;
    return out;
  });
}

}  // namespace linkscape::gui
