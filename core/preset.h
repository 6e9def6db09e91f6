// Mechanism presets: JSON files in assets/mechanisms/ naming a mechanism,
// its parameters and actuator ranges. Users pass a preset name or a path.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include "core/actuator_data.h"
#include "core/range.h"

namespace linkscape {

// Which bounds beyond its actuators' travel a device checks where it states
// them: its passive joints' limits and its links' interference
// (docs/described-mechanisms.md, "Joint limits" and "Link interference").
// Both on by default; one off, the device is made as if it stated none of
// that kind (no status, field or criterion of it).
struct StopChecks {
  bool joint_limits = true;
  bool interference = true;
  bool operator==(const StopChecks&) const = default;
};

struct Preset {
  std::string mechanism;    // the registered device it describes (core/mechanisms/registry.cpp)
  std::string title;        // human-readable description
  std::string length_unit;  // e.g. "cm"
  std::map<std::string, double> parameters;
  std::map<std::string, Range> limits_deg;  // actuator ranges, degrees
  ActuatorDataSpec actuator_data;           // torques, encoders, inertias (core/haptics.h)
  // A described mechanism's "description" as JSON text (docs/described-mechanisms.md);
  // empty for the compiled devices.
  std::string description;
  // A compiled device's assumed or published "stops" (its passive joints'
  // limits, its links' radii) as JSON text; the device reads it
  // (docs/mechanisms/); empty where the file has none.
  std::string stops;
  std::filesystem::path source;             // file it was read from
  StopChecks checks;                        // as the user switched them (not read from the file)
};

// Folders searched for preset names, in order: $LINKSCAPE_ASSETS/mechanisms,
// <executable>/../share/linkscape/mechanisms, the source tree's assets.
std::vector<std::filesystem::path> preset_search_path();
// Names of all presets found on the search path.
std::vector<std::string> available_presets();
// The presets among them that describe their mechanism in the file
// ("mechanism": "described"; docs/described-mechanisms.md) and load.
std::vector<std::string> described_presets();

// `name_or_path` is a preset name (a file stem on the search path) or a path
// to a .json file.
// Throws std::invalid_argument naming the file and the problem.
Preset load_preset(const std::string& name_or_path);

// Why `path` cannot be read as a file ("does not exist", "is a folder, not a
// file", "is not a regular file ..." for a pipe or device, whose read could
// block), or "" when it can.
std::string why_not_a_readable_file(const std::filesystem::path& path);
Preset parse_preset(const std::string& json_text, const std::string& origin);

// Throws where a compiled device's preset leaves out a parameter of its
// design (one with no default derived from the others), naming them.
void require_parameters(const Preset& preset, std::initializer_list<const char*> names);

// How a session or a report should name the preset: its name where the
// preset search path finds this very file under it (portable between
// machines and installed copies), else its absolute path.
std::string preset_reference(const Preset& preset);

// Applies "key=value" overrides to the preset's parameters. Throws
// std::invalid_argument for a malformed pair, a key that is not one of the
// mechanism's parameter_names(), a bad number or an invalid resulting model.
void apply_overrides(Preset& preset, const std::vector<std::string>& overrides);

// Names --param accepts for the preset's mechanism.
std::vector<std::string> parameter_names(const Preset& preset);
// What the preset's device states of StopChecks' bounds (each true where it
// states it), whatever preset.checks asks.
StopChecks stated_stops(const Preset& preset);

// A compiled device's "stops" block as numbers by key (its "source" text
// skipped); throws std::invalid_argument naming a key not in `known` (listed)
// or a value that is not a number.
std::map<std::string, double> stops_numbers(const Preset& preset, const std::vector<std::string>& known);

// Builds the preset's model; throws std::invalid_argument if it is invalid.
void validate(const Preset& preset);

}  // namespace linkscape
