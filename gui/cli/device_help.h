// What the help says each device accepts, from the devices themselves: every
// registered device, made from its shipped preset.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/mechanism.h"

namespace linkscape::gui {

struct DeviceHelp {
  std::vector<std::shared_ptr<const Mechanism>> devices;

  // "name: text; name: text" over the devices (those for which `text` says something).
  std::string per_device(const std::function<std::string(const MechanismInfo&)>& text) const;
};

// Every registered device whose shipped preset loads.
DeviceHelp device_help();

// Item names joined by `separator`, each followed by " (description)" if `described`.
template <class Items>
std::string names(const Items& items, const char* separator, bool described = false) {
  std::string out;
  for (const auto& item : items)
    out += (out.empty() ? "" : separator) + item.name + (described ? " (" + item.description + ")" : "");
  return out;
}

// "x,y,z (cm), rx,ry,rz (rad)": the names, each run of one unit followed by it.
std::string with_units(const std::vector<Quantity>& items);
// The columns eval --fk reads: the actuators, then the task coordinates FK
// takes as inputs (a grip read by its own sensor).
std::vector<Quantity> fk_columns(const MechanismInfo& info);

// Each device's assembly branches: "parallel-12r: up, down; ...".
std::string branches_help(const DeviceHelp& help);

}  // namespace linkscape::gui
