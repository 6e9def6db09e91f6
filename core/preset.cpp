#include "core/preset.h"

#include "core/csv.h"
#include "core/haptics.h"
#include "core/json_checked.h"
#include "core/mechanism.h"
#include "core/spelling.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace linkscape {
namespace fs = std::filesystem;

std::vector<fs::path> preset_search_path() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("LINKSCAPE_ASSETS"); env && *env)
    dirs.push_back(fs::path(env) / "mechanisms");
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(exe.parent_path().parent_path() / "share/linkscape/mechanisms");
  dirs.push_back(fs::path(LINKSCAPE_SOURCE_ASSETS) / "mechanisms");
  return dirs;
}

std::vector<std::string> available_presets() {
  std::vector<std::string> names;
  for (const fs::path& dir : preset_search_path()) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec))
      if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

std::vector<std::string> described_presets() {
  std::vector<std::string> names;
  for (const std::string& name : available_presets()) {
    try {
      if (load_preset(name).mechanism == "described") names.push_back(name);
    } catch (const std::invalid_argument&) {
      // A broken file is reported where it is opened, not here.
    }
  }
  return names;
}

std::string why_not_a_readable_file(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_regular_file(status)) return "";
  if (ec && ec != std::errc::no_such_file_or_directory) return "cannot be read: " + ec.message();
  if (!fs::exists(status)) return "does not exist";
  if (fs::is_directory(status)) return "is a folder, not a file";
  return "is not a regular file (a pipe or device cannot be read as one)";
}

namespace {

fs::path resolve_preset(const std::string& name_or_path) {
  const fs::path given(name_or_path);
  // The error_code forms: a name the file system refuses (too long, say) is
  // a name that names no preset, not an exception of another kind.
  std::error_code ec;
  if (given.extension() == ".json" || given.has_parent_path()) {
    const std::string unreadable = why_not_a_readable_file(given);
    if (!unreadable.empty()) throw std::invalid_argument("preset file '" + name_or_path + "' " + unreadable);
    return given;
  }
  for (const fs::path& dir : preset_search_path()) {
    const fs::path candidate = dir / (name_or_path + ".json");
    if (fs::is_regular_file(candidate, ec)) return candidate;
  }
  const std::vector<std::string> presets = available_presets();
  std::string known;
  for (const auto& n : presets) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown mechanism '" + name_or_path + "'" + did_you_mean(name_or_path, presets) +
                              " (known presets: " +
                              (known.empty() ? "none found" : known) + "; or give a path to a .json preset)");
}

// "actuator_data": {"source": text, "all": rating, "<actuator>": rating}, a
// rating being an object of the keys of motor_parameters() (core/actuator_data.h),
// each a positive number.
// Actuator names are checked against the device in core/haptics.cpp.
ActuatorDataSpec parse_actuator_data(const nlohmann::json& doc) {
  if (!doc.is_object()) throw std::invalid_argument("actuator_data must be an object");
  ActuatorDataSpec spec;
  spec.given = true;
  for (const auto& [key, value] : doc.items()) {
    if (key == "source") {
      spec.source = string_at(value, "actuator_data.source");
      continue;
    }
    const std::string where = "actuator_data." + key;
    if (!value.is_object()) throw std::invalid_argument(where + " must be an object of ratings");
    ActuatorRating& r = key == "all" ? spec.all : spec.per_actuator[key];
    for (const auto& [name, number] : value.items()) {
      const MotorParameter* rating = motor_parameter(name);
      if (!rating) {
        std::string known;
        for (const MotorParameter& p : motor_parameters()) known += (known.empty() ? "" : ", ") + std::string(p.name);
        throw std::invalid_argument("unknown key " + where + "." + name + " (known: " + known + ")");
      }
      const double v = number_at(number, where + "." + name);
      if (!std::isfinite(v) || !(v > 0))
        throw std::invalid_argument(where + "." + name + " must be a positive finite number, got " + number.dump());
      r.*(rating->field) = v;
    }
  }
  return spec;
}

}  // namespace

Preset parse_preset(const std::string& text, const std::string& origin) {
  using nlohmann::json;
  Preset p;
  try {
    if (text.size() > kMaxPresetBytes)
      throw std::invalid_argument("the file is larger than a preset may be (" + std::to_string(kMaxPresetBytes) +
                                  " bytes)");
    const json doc = parse_json_checked(text, kMaxPresetNesting);
    if (!doc.is_object()) throw std::invalid_argument("top level must be a JSON object");
    for (const auto& [key, value] : doc.items())
      if (key != "mechanism" && key != "title" && key != "length_unit" && key != "parameters" &&
          key != "actuator_limits_deg" && key != "actuator_data" && key != "description" && key != "stops")
        throw std::invalid_argument("unknown key '" + key +
                                    "' (known: mechanism, title, length_unit, parameters, actuator_limits_deg, "
                                    "actuator_data, description, stops)");
    for (const char* key : {"mechanism", "length_unit", "parameters"})
      if (!doc.contains(key)) throw std::invalid_argument(std::string("missing key '") + key + "'");
    p.mechanism = string_at(doc.at("mechanism"), "mechanism");
    p.title = doc.contains("title") ? string_at(doc.at("title"), "title") : p.mechanism;
    p.length_unit = string_at(doc.at("length_unit"), "length_unit");
    if (!haptics::is_length_unit(p.length_unit)) {
      std::string known;
      for (const std::string& u : haptics::length_units()) known += (known.empty() ? "" : ", ") + u;
      throw std::invalid_argument("length_unit must be one of " + known + ", got '" + p.length_unit + "'");
    }
    if (!doc.at("parameters").is_object()) throw std::invalid_argument("parameters must be an object {name: number}");
    for (const auto& [key, value] : doc.at("parameters").items())
      p.parameters[key] = number_at(value, "parameters." + key);
    if (doc.contains("actuator_limits_deg")) {
      if (!doc.at("actuator_limits_deg").is_object())
        throw std::invalid_argument("actuator_limits_deg must be an object {actuator: [lo, hi]}");
      for (const auto& [key, value] : doc.at("actuator_limits_deg").items()) {
        const std::string where = "actuator_limits_deg." + key;
        if (!value.is_array() || value.size() != 2) throw std::invalid_argument(where + " must be [lo, hi]");
        p.limits_deg[key] = {number_at(value[0], where + "[0]"), number_at(value[1], where + "[1]")};
        if (!std::isfinite(p.limits_deg[key].lo) || !std::isfinite(p.limits_deg[key].hi))
          throw std::invalid_argument(where + " must be finite");
      }
    }
    if (doc.contains("actuator_data")) p.actuator_data = parse_actuator_data(doc.at("actuator_data"));
    if (doc.contains("description")) {
      if (p.mechanism != "described")
        throw std::invalid_argument("a \"description\" belongs to a preset whose mechanism is \"described\"");
      p.description = doc.at("description").dump();
    }
    if (doc.contains("stops")) {
      if (p.mechanism == "described")
        throw std::invalid_argument("a described device states its stops in its description (\"cone\", \"radius\")");
      if (!doc.at("stops").is_object()) throw std::invalid_argument("stops must be an object {name: value}");
      p.stops = doc.at("stops").dump();
    }
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument("preset " + origin + ": " + json_error_text(e));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("preset " + origin + ": " + e.what());
  }
  try {
    validate(p);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("preset " + origin + ": " + e.what());
  }
  return p;
}

Preset load_preset(const std::string& name_or_path) {
  const fs::path file = resolve_preset(name_or_path);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot read preset file '" + file.string() + "'");
  // One byte past the limit is enough for parse_preset to refuse the file.
  std::string text(kMaxPresetBytes + 1, '\0');
  in.read(text.data(), std::streamsize(text.size()));
  if (in.bad()) throw std::invalid_argument("cannot read preset file '" + file.string() + "'");
  text.resize(std::size_t(in.gcount()));
  Preset p = parse_preset(text, file.string());
  p.source = file;
  return p;
}

std::string preset_reference(const Preset& preset) {
  if (preset.source.empty()) return preset.mechanism;
  const std::string name = preset.source.stem().string();
  for (const fs::path& dir : preset_search_path()) {
    const fs::path candidate = dir / (name + ".json");
    std::error_code ec;
    if (!fs::is_regular_file(candidate, ec)) continue;
    // The first hit is what load_preset(name) would read.
    return fs::equivalent(candidate, preset.source, ec) ? name : fs::absolute(preset.source).string();
  }
  return fs::absolute(preset.source).string();
}

void apply_overrides(Preset& preset, const std::vector<std::string>& overrides) {
  const std::vector<std::string> names = overrides.empty() ? std::vector<std::string>{} : parameter_names(preset);
  std::vector<std::string> given;
  for (const std::string& pair : overrides) {
    const auto eq = pair.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("--param expects key=value, got '" + pair + "'");
    const std::string key = pair.substr(0, eq), text = pair.substr(eq + 1);
    // As a key given twice in a preset: which value counts would be a guess.
    if (std::find(given.begin(), given.end(), key) != given.end())
      throw std::invalid_argument("--param " + key + " is given twice");
    given.push_back(key);
    if (motor_parameter(key)) {  // a motor rating, for every actuator (core/actuator_data.h)
      const double value = parse_number_or_throw(text, "parameter " + key);
      check_rating("parameter " + key, value);
      preset.parameters[key] = value;
      continue;
    }
    if (std::find(names.begin(), names.end(), key) == names.end()) {
      std::string known, motors;
      std::vector<std::string> candidates = names;
      for (const auto& k : names) known += (known.empty() ? "" : ", ") + k;
      for (const MotorParameter& p : motor_parameters()) {
        motors += (motors.empty() ? "" : ", ") + std::string(p.name);
        candidates.push_back(p.name);
      }
      const std::string device = preset.source.empty() ? preset.mechanism : preset.source.stem().string();
      throw std::invalid_argument("unknown parameter '" + key + "' for " + device + did_you_mean(key, candidates) +
                                  " (known: " + known +
                                  "; motor ratings: " + motors + ")");
    }
    preset.parameters[key] = parse_number_or_throw(text, "parameter " + key);
  }
  try {
    const auto mechanism = make_mechanism(preset);  // the new values, validated
    // Ratings, the preset's and those given as parameters, hold together (a
    // continuous torque above the peak, an actuator the device lacks) in
    // every command, not only where a haptic measure reads them.
    if (preset.actuator_data.given ||
        std::any_of(given.begin(), given.end(), [](const std::string& k) { return motor_parameter(k) != nullptr; }))
      haptics::device_data(preset, mechanism->info());
  } catch (const std::invalid_argument& e) {
    std::string with;
    for (const std::string& pair : overrides) with += (with.empty() ? " with " : " ") + ("--param " + pair);
    throw std::invalid_argument(preset_reference(preset) + with + ": " + e.what());
  }
}

std::vector<std::string> parameter_names(const Preset& preset) {
  const auto mechanism = make_mechanism(preset);  // kept alive while its description is read
  std::vector<std::string> names;
  for (const Quantity& q : mechanism->info().parameters) names.push_back(q.name);
  return names;
}

StopChecks stated_stops(const Preset& preset) {
  Preset all = preset;
  all.checks = {};
  const auto mechanism = make_mechanism(all);
  const std::vector<NamedItem>& fields = mechanism->info().extra_fields;
  const auto lists = [&](const char* name) {
    return std::any_of(fields.begin(), fields.end(), [&](const NamedItem& f) { return f.name == name; });
  };
  return {lists("joint_margin"), lists("clearance")};
}

std::map<std::string, double> stops_numbers(const Preset& preset, const std::vector<std::string>& known) {
  std::map<std::string, double> out;
  if (preset.stops.empty()) return out;
  const nlohmann::json doc = nlohmann::json::parse(preset.stops);
  for (const auto& [key, value] : doc.items()) {
    if (key == "source") {
      string_at(value, "stops.source");
      continue;
    }
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      std::string names = "source";
      for (const std::string& k : known) names += ", " + k;
      throw std::invalid_argument("unknown key 'stops." + key + "' (known: " + names + ")");
    }
    out[key] = number_at(value, "stops." + key);
  }
  return out;
}

void validate(const Preset& preset) { make_mechanism(preset); }

void require_parameters(const Preset& preset, std::initializer_list<const char*> names) {
  std::string missing;
  for (const char* name : names)
    if (!preset.parameters.count(name)) missing += (missing.empty() ? "" : ", ") + std::string(name);
  if (!missing.empty())
    throw std::invalid_argument(preset.mechanism + ": the preset's parameters lack " + missing +
                                " (a design states each; there is no default)");
}

}  // namespace linkscape
