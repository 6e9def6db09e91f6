#include "gui/cli/completion.h"

#include <algorithm>

#include "core/field_names.h"
#include "core/haptics.h"
#include "render/slice_image.h"

namespace linkscape::gui {
namespace {

void add_unique(std::vector<std::string>& values, const std::string& value) {
  if (std::find(values.begin(), values.end(), value) == values.end()) values.push_back(value);
}

// What a criterion or a surface starts with: its measure and comparison.
std::vector<std::string> criterion_stems(const DeviceHelp& help) {
  std::vector<std::string> stems{"reach"};
  for (const auto& device : help.devices) {
    add_unique(stems, "cond<");
    const std::vector<NamedItem>& stops = device->info().extra_fields;  // margins: bounded from below
    for (const std::string& field : device_fields(device->info(), false)) {
      const bool margin = std::any_of(stops.begin(), stops.end(), [&](const NamedItem& f) { return f.name == field; });
      if (field != "cond" && field != "reach" && field != "status" && field != "method")
        add_unique(stems, field + (margin ? ">" : "<"));
    }
  }
  for (const haptics::FieldInfo& f : haptics::all_field_infos()) add_unique(stems, f.name + (f.larger_is_better ? ">" : "<"));
  return stems;
}

}  // namespace

std::vector<std::string> completion_values(const std::string& option, const DeviceHelp& help) {
  const std::string name = option.substr(option.find_first_not_of('-') == std::string::npos
                                             ? option.size()
                                             : option.find_first_not_of('-'));
  std::vector<std::string> values;
  if (name == "method") {
    for (const auto& device : help.devices)
      for (const NamedItem& method : device->info().ik_methods) add_unique(values, method.name);
  } else if (name == "field") {
    for (const auto& device : help.devices)
      for (const std::string& field : device_fields(device->info())) add_unique(values, field);
    for (const haptics::FieldInfo& f : haptics::all_field_infos()) add_unique(values, f.name);
  } else if (name == "colour-map") {
    values = render::colour_maps();
  } else if (name == "torque") {
    values = {"continuous", "peak"};
  } else if (name == "unit") {
    values = haptics::length_units();
  } else if (name == "plane") {
    values = {"x=", "y=", "z="};
  } else if (name == "surface" || name == "criterion") {
    values = criterion_stems(help);
  }
  return values;
}

}  // namespace linkscape::gui
