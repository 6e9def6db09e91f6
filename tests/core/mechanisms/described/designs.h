// The shipped described presets and random designs of them, for tests that
// run over every description.
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/preset.h"

namespace linkscape::testing_support {

inline const std::vector<std::string>& shipped_descriptions() {
  static const std::vector<std::string> names{"delta-described", "pathos2-described", "five-bar",
                                              "stewart",         "three-rrr",         "linear-delta",
                                              "hexapod-rus",     "haply-2diy",        "falcon",
                                              "omnid-delta",     "three-rpr"};
  return names;
}

// The Omnid's arm with universal knees and platform joints in Tsai's
// translational arrangement (the knee's axes along the motor's and square to
// the tube, the platform joint's the same in reverse order): rods ending in
// a universal joint (3-RUU). `knee_ranges`: the knees' "ranges_deg", if any.
inline Preset omnid_with_universal_joints(const nlohmann::json& knee_ranges = nullptr) {
  Preset p = load_preset("omnid-delta");
  nlohmann::json d = nlohmann::json::parse(p.description);
  nlohmann::json& chain = d["legs"][0]["chain"];
  chain[2] = {{"joint", "universal"}, {"name", "knee#"}, {"axes", {{0, 1, 0}, {0, 0, 1}}}};
  if (!knee_ranges.is_null()) chain[2]["ranges_deg"] = knee_ranges;
  chain[4] = {{"joint", "universal"}, {"name", "platform#"}, {"axes", {{0, 0, 1}, {0, 1, 0}}}};
  p.description = d.dump();
  return p;
}

// Tsai's 3-UPU (Tsai 1996): slides between universal joints whose axes are
// parallel in pairs, the base's on a circle of radius R, the platform's of r
// (cm); it holds the platform's orientation by its legs.
inline Preset tsai_three_upu(double R = 12, double r = 5) {
  Preset p;
  p.mechanism = described::kMechanismName;
  p.length_unit = "cm";
  p.parameters = {{"R", R}, {"r", r}};
  p.description = R"({
    "space": "spatial", "task": ["x", "y", "z"], "home": {"x": 0, "y": 0, "z": 16}, "size": "R + r",
    "legs": [{ "name": "#", "copies": 3,
      "base": [{"rz": "k*120*deg"}, {"translate": ["R", 0, 0]}],
      "chain": [
        {"joint": "universal", "name": "base#", "axes": [[0, 1, 0], [1, 0, 0]]},
        {"joint": "prismatic", "name": "l#", "axis": [0, 0, 1], "actuated": true, "range": [5, 40]},
        {"joint": "universal", "name": "top#", "axes": [[1, 0, 0], [0, 1, 0]]}],
      "anchor": [{"rz": "k*120*deg"}, {"translate": ["r", 0, 0]}]}]})";
  return p;
}

// The Gough-Stewart platform with its cylinders written as designers write
// them: universal joint, a 4 cm body, the stroke (6 cm shorter), a 2 cm rod
// end, the ball: the same device, its actuators shifted by 6 cm.
inline Preset stewart_with_cylinder_bodies() {
  Preset p = load_preset("stewart");
  nlohmann::json d = nlohmann::json::parse(p.description);
  for (nlohmann::json& leg : d["legs"]) {
    nlohmann::json& chain = leg["chain"];
    chain[1]["range"] = {"lmin - 6", "lmax - 6"};
    chain.insert(chain.begin() + 1, nlohmann::json{{"translate", {0, 0, 4}}});
    chain.insert(chain.begin() + 3, nlohmann::json{{"translate", {0, 0, 2}}});
  }
  p.description = d.dump();
  return p;
}

// Planar legs whose revolutes stand for the balls of the slide patterns:
// a 3-RPR (an actuated slide between two revolutes: extensible) or, with
// `carried`, a 3-PRR (tangential slides carrying rods: slide-rod), on
// regular triangles of radii rb and rp (the platform's turned by 60 deg for
// the 3-RPR, whose legs would otherwise meet at its centre), rods of length L.
inline Preset planar_slide_legs(bool carried, double rb = 10, double rp = 3, double L = 8) {
  nlohmann::json d = {{"space", "planar"}, {"task", {"x", "y", "rz"}}, {"home", {{"x", 0}, {"y", 0}, {"rz", 0}}}};
  for (int k = 0; k < 3; ++k) {
    const std::string n = std::to_string(k + 1);
    const double turn = 120.0 * k;
    nlohmann::json leg = {{"name", n},
                          {"base", {{{"rz", std::to_string(turn) + " * deg"}}, {{"translate", {"rb", 0, 0}}}}},
                          {"anchor", {{{"rz", std::to_string(turn + (carried ? 0 : 60)) + " * deg"}},
                                      {{"translate", {"rp", 0, 0}}}}}};
    if (carried) {
      leg["chain"] = {{{"joint", "prismatic"}, {"name", "s" + n}, {"axis", {0, 1, 0}}, {"actuated", true}, {"range", {-8, 8}}},
                      {{"joint", "revolute"}, {"name", "elbow" + n}, {"axis", {0, 0, 1}}},
                      {{"translate", {"-L", 0, 0}}},
                      {{"joint", "revolute"}, {"name", "tip" + n}, {"axis", {0, 0, 1}}}};
      // The carriage behind the foot of the anchor on its line (the base's
      // frame: each leg's own tangent).
      const double a = turn * 3.14159265358979323846 / 180;
      leg["branch"] = {{"along", {"elbow" + n, "anchor"}}, {"direction", {-std::sin(a), std::cos(a), 0}}, {"sign", "-1"}};
    } else {
      leg["chain"] = {{{"joint", "revolute"}, {"name", "pivot" + n}, {"axis", {0, 0, 1}}},
                      {{"joint", "prismatic"}, {"name", "d" + n}, {"axis", {-1, 0, 0}}, {"actuated", true}, {"range", {4, 14}}},
                      {{"joint", "revolute"}, {"name", "tip" + n}, {"axis", {0, 0, 1}}}};
    }
    d["legs"].push_back(leg);
  }
  d["size"] = "rb";
  const nlohmann::json preset = {{"mechanism", "described"},
                                 {"title", carried ? "3-PRR" : "3-RPR"},
                                 {"length_unit", "cm"},
                                 {"parameters", {{"rb", rb}, {"rp", rp}, {"L", L}}},
                                 {"description", d}};
  return parse_preset(preset.dump(), carried ? "3-PRR" : "3-RPR");
}

inline described::Kinematics load_described(const std::string& name) {
  const Preset p = load_preset(name);
  return described::Kinematics(described::build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
}

// Random designs: every panel parameter drawn within its slider span; a
// design that does not assemble at home (or changes its mobility) is skipped.
inline std::vector<described::Kinematics> random_designs(const std::string& name, int count, std::mt19937_64& rng) {
  const Preset p = load_preset(name);
  const described::Model base = described::build_model(p.description, p.parameters, p.limits_deg, p.length_unit);
  std::vector<described::Kinematics> out;
  for (int tries = 0; int(out.size()) < count && tries < 20 * count; ++tries) {
    std::map<std::string, double> params = p.parameters;
    for (const auto& [param, info] : base.parameter_info)
      if (info.in_panel && info.range.hi > info.range.lo)
        params[param] = std::uniform_real_distribution<double>(info.range.lo, info.range.hi)(rng);
    try {
      out.emplace_back(described::build_model(p.description, params, p.limits_deg, p.length_unit));
    } catch (const std::invalid_argument&) {
    }
  }
  EXPECT_EQ(int(out.size()), count) << name;
  return out;
}

}  // namespace linkscape::testing_support
