// Fuzz target for presets (core/preset.h). The input is a preset's JSON text,
// optionally followed by --param overrides, one per line, as a user types them:
//
//   { "mechanism": "parallel-12r", "parameters": { "L1": 15, "L2": 15 } }
//   --param L1=12
//
// parse_preset either throws std::invalid_argument or returns a preset of a
// known mechanism, or a described one (docs/described-mechanisms.md), that
// builds its model; apply_overrides either throws std::invalid_argument or
// leaves a preset that still builds, holding the values given.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/mechanism.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/mechanisms/described/model.h"
#include "core/mechanisms/parallel12r/mechanism.h"
#include "core/mechanisms/pathos2/mechanism.h"
#include "core/preset.h"
#include "fuzz_check.h"

namespace {

using linkscape::Preset;
namespace parallel12r = linkscape::parallel12r;
namespace pathos2 = linkscape::pathos2;

constexpr std::string_view kOverrideMark = "\n--param ";

bool close(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max({1.0, std::abs(a), std::abs(b)}); }

// The model a preset builds is valid, and the preset is of its mechanism only.
void check_builds(const Preset& p) {
  const bool described = p.mechanism == linkscape::described::kMechanismName;
  const std::vector<std::string> known = linkscape::registered_mechanisms();
  FUZZ_CHECK(described || std::find(known.begin(), known.end(), p.mechanism) != known.end(),
             "mechanism '" << p.mechanism << "'");
  FUZZ_CHECK(described == !p.description.empty(), "a " << p.mechanism << " preset with a description of "
                                                       << p.description.size() << " characters");
  linkscape::validate(p);
  const std::vector<std::string> names = linkscape::parameter_names(p);
  for (const auto& [key, value] : p.parameters)
    FUZZ_CHECK(std::find(names.begin(), names.end(), key) != names.end(), "parameter '" << key << "' is not one of the mechanism's");
  bool other_refused = false;
  if (p.mechanism == parallel12r::kMechanismName) {
    const parallel12r::Model m = linkscape::make_parallel12r(p);
    FUZZ_CHECK(std::isfinite(m.L1) && m.L1 > 0 && std::isfinite(m.L2) && m.L2 > 0, "L1 " << m.L1 << " L2 " << m.L2);
    for (const auto& [name, value] : p.parameters)
      FUZZ_CHECK(value == (name == "L1" ? m.L1 : m.L2), name << " = " << value << " in the preset");
    for (const auto* r : {&m.alpha_limits, &m.beta_limits, &m.gamma_limits})
      FUZZ_CHECK(std::isfinite(r->lo) && std::isfinite(r->hi) && r->lo < r->hi, "range [" << r->lo << ", " << r->hi << "]");
    try {
      linkscape::make_pathos2(p);
    } catch (const std::invalid_argument&) {
      other_refused = true;
    }
  } else if (p.mechanism == pathos2::kMechanismName) {
    const pathos2::Model m = linkscape::make_pathos2(p);
    // to_parameters is the inverse of from_parameters (degrees round trip to 1e-12).
    const pathos2::Model back = pathos2::Model::from_parameters(m.to_parameters());
    const double a[] = {m.l0, m.lb, m.l1, m.l2, m.l3, m.lp, m.h0, m.theta_t, m.theta_g, m.db, m.lx, m.tilt_sign,
                        m.base_phase, m.plate_phase, m.cone_limit, m.t2_limit, m.t3_limit};
    const double b[] = {back.l0, back.lb, back.l1, back.l2, back.l3, back.lp, back.h0, back.theta_t, back.theta_g,
                        back.db, back.lx, back.tilt_sign, back.base_phase, back.plate_phase, back.cone_limit,
                        back.t2_limit, back.t3_limit};
    for (std::size_t i = 0; i < std::size(a); ++i)
      FUZZ_CHECK(close(a[i], b[i]), "value " << i << " of the model: " << a[i] << " after to/from_parameters " << b[i]);
    FUZZ_CHECK(m.branch == back.branch, "branches changed in to/from_parameters");
    try {
      linkscape::make_parallel12r(p);
    } catch (const std::invalid_argument&) {
      other_refused = true;
    }
  } else {
    // Any other device: it holds every parameter it was given.
    const auto m = linkscape::make_mechanism(p);
    for (const auto& [key, value] : p.parameters)
      FUZZ_CHECK(m->parameters().count(key) && close(m->parameters().at(key), value), "parameter '" << key << "'");
    // A described device is within the format's limits: one actuator a leg.
    if (described)
      FUZZ_CHECK(!m->info().actuators.empty() && m->info().actuators.size() <= std::size_t(linkscape::described::kMaxLegs),
                 m->info().actuators.size() << " actuators");
    other_refused = true;
  }
  FUZZ_CHECK(other_refused, "a " << p.mechanism << " preset also built the other mechanism's model");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::size_t mark = input.find(kOverrideMark);
  const std::string json = input.substr(0, mark);
  std::vector<std::string> overrides;
  for (std::size_t at = mark; at != std::string::npos;) {
    const std::size_t begin = at + kOverrideMark.size();
    at = input.find(kOverrideMark, begin);
    overrides.push_back(input.substr(begin, at == std::string::npos ? std::string::npos : at - begin));
  }

  Preset preset;
  try {
    preset = linkscape::parse_preset(json, "fuzz.json");
  } catch (const std::invalid_argument& e) {
    FUZZ_CHECK(std::string_view(e.what()).starts_with("preset fuzz.json: "), "message: " << e.what());
    return 0;
  }
  check_builds(preset);

  // No overrides change nothing.
  Preset same = preset;
  linkscape::apply_overrides(same, {});
  FUZZ_CHECK(same.parameters == preset.parameters, "apply_overrides without overrides changed the parameters");

  Preset changed = preset;
  try {
    linkscape::apply_overrides(changed, overrides);
  } catch (const std::invalid_argument&) {
    return 0;
  }
  check_builds(changed);
  // Each key holds the last value given for it (as std::stod reads it); the others are as loaded.
  std::map<std::string, double> expected = preset.parameters;
  for (const std::string& pair : overrides) {
    const std::size_t eq = pair.find('=');
    FUZZ_CHECK(eq != std::string::npos && eq > 0, "accepted override '" << pair << "'");
    expected[pair.substr(0, eq)] = std::strtod(pair.c_str() + eq + 1, nullptr);
  }
  for (const auto& [key, value] : changed.parameters) FUZZ_CHECK(std::isfinite(value), key << " = " << value);
  FUZZ_CHECK(changed.parameters == expected, "parameters after the overrides are not the values given");
  return 0;
}
