// Malformed descriptions are refused with a message that names the place in
// the file (docs/described-mechanisms.md, "Errors").
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/json_checked.h"
#include "core/mechanism.h"
#include "core/preset.h"

namespace linkscape {
namespace {

using nlohmann::json;

json delta_description() {
  std::ifstream in(std::string(LINKSCAPE_TEST_ASSETS) + "/mechanisms/delta-described.json");
  return json::parse(in);
}

// The message parse_preset gives for a preset's text; another kind of
// exception is a failure (the command line would exit 1 without a place).
std::string error_of_text(const std::string& text) {
  try {
    parse_preset(text, "broken.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("not std::invalid_argument: ") + e.what();
  }
  return "no error";
}

// The message parse_preset gives for the Delta's description after `edit`.
std::string error_after(const std::function<void(json&)>& edit) {
  json doc = delta_description();
  edit(doc);
  return error_of_text(doc.dump());
}

// The Delta's preset text with the value "@" replaced by `text` (JSON that
// nlohmann::json cannot hold: too deep, or with a key twice).
std::string delta_text_with(const std::function<void(json&)>& place, const std::string& text) {
  json doc = delta_description();
  place(doc);
  std::string dumped = doc.dump();
  dumped.replace(dumped.find("\"@\""), 3, text);
  return dumped;
}

void expect_contains(const std::string& message, const std::vector<std::string>& parts) {
  for (const std::string& p : parts) EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' not in: " << message;
}

TEST(DescriptionErrors, TheShippedDescriptionIsValid) {
  EXPECT_EQ(error_after([](json&) {}), "no error");
}

TEST(DescriptionErrors, UnknownJointTypeNamesLegStepAndJoint) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["chain"][2]["joint"] = "ball"; });
  expect_contains(m, {"broken.json", "description.legs[0] \"1\"", "chain[2]", "elbow1", "unknown joint type 'ball'",
                      "revolute, prismatic, universal, spherical"});
}

TEST(DescriptionErrors, NonUnitAxisNamesTheAxis) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["chain"][0]["axis"] = {0, 1, 1}; });
  expect_contains(m, {"description.legs[0] \"1\"", "chain[0] (joint \"q1\").axis", "not a unit vector", "1.41"});
}

TEST(DescriptionErrors, BadRangesNameTheirPlace) {
  // A joint's travel (degrees), a parameter's range and an extra's range share one reader.
  expect_contains(error_after([](json& d) { d["description"]["legs"][0]["chain"][0]["range_deg"] = {30, -30}; }),
                  {"chain[0] (joint \"q1\").range_deg", "needs lo < hi"});
  expect_contains(error_after([](json& d) { d["description"]["legs"][0]["chain"][0]["range_deg"] = {30}; }),
                  {"chain[0] (joint \"q1\").range_deg", "must be [lo, hi]"});
  expect_contains(error_after([](json& d) { d["description"]["parameter_info"]["La"]["range"] = {5, "La / 0"}; }),
                  {"parameter_info.La.range[1]", "'La / 0' evaluates to +infinity (a division by zero, or past 1e308?)"});
  expect_contains(error_after([](json& d) { d["description"]["parameter_info"]["La"]["range"] = {5, "sqrt(-La)"}; }),
                  {"parameter_info.La.range[1]", "'sqrt(-La)' evaluates to no number (NaN: a square root"});
  expect_contains(error_after([](json& d) { d["description"]["parameter_info"]["La"]["range"] = {9, 3}; }),
                  {"parameter_info.La.range", "needs lo < hi"});
  expect_contains(error_after([](json& d) {
                    d["description"]["extras"] = {{"grip", {{"home", 1}, {"range", "wide"}}}};
                  }),
                  {"extras.grip.range", "must be [lo, hi]"});
}

TEST(DescriptionErrors, MissingActuatorNamesTheLeg) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["chain"][0].erase("actuated"); });
  expect_contains(m, {"description.legs[0] \"1\": chain", "no actuated joint"});
}

TEST(DescriptionErrors, ALegThatDoesNotReachItsAnchorAtHome) {
  // Forearms too short for the home pose: the legs miss their anchors.
  const std::string m = error_after([](json& d) { d["description"]["home"]["z"] = -40; });
  expect_contains(m, {"broken.json", "leg", "does not reach its anchor at home", "misses by"});
}

// A leg of 61 joint variables (the Delta's, with 18 more spherical joints
// at each wrist: idle turns that leave the device as it was) once overran a
// fixed-size matrix on the stack. Either a limit on joints refuses it by name,
// or it is the same device: the same actuator angles as the shipped
// described Delta.
TEST(DescriptionErrors, ALegWithManyJointVariablesIsSolvedOrRefused) {
  json doc = delta_description();
  json& chain = doc["description"]["legs"][0]["chain"];
  for (int k = 0; k < 18; ++k) chain.push_back({{"joint", "spherical"}, {"name", "idle" + std::to_string(k) + "#"}});
  std::shared_ptr<const Mechanism> many;
  try {
    many = make_mechanism(parse_preset(doc.dump(), "long-legs.json"));
  } catch (const std::invalid_argument& e) {
    expect_contains(e.what(), {"long-legs.json", "description.legs"});
    return;
  }
  const auto shipped = make_mechanism(parse_preset(delta_description().dump(), "delta-described.json"));
  const Eigen::VectorXd home = shipped->home_task();
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, -1, 1), Eigen::Vector3d(-3, 2, -2)}) {
    Eigen::VectorXd x = home;
    x.head<3>() += offset;
    const IkResult expected = shipped->inverse(x), got = many->inverse(x);
    ASSERT_EQ(expected.status, Status::Ok) << x.transpose();
    ASSERT_EQ(got.status, Status::Ok) << x.transpose();
    EXPECT_LT((got.solutions[0].q - expected.solutions[0].q).cwiseAbs().maxCoeff(), 1e-9) << x.transpose();
    FkOptions fo;
    fo.seed = home;
    const FkResult back = many->forward(got.solutions[0].q, fo);
    EXPECT_EQ(back.status, Status::Ok);
    EXPECT_LT((back.x - x).norm(), 1e-9 * many->size()) << x.transpose();
  }
}

TEST(DescriptionErrors, WrongDegreeOfFreedomCount) {
  // A fourth freedom of the platform (rz) with three actuators.
  const std::string m = error_after([](json& d) { d["description"]["task"] = {"x", "y", "z", "rz"};
                                                    d["description"]["home"]["rz"] = 0; });
  expect_contains(m, {"broken.json", "freedom", "3 actuator"});
}

// A crank of no length turns without moving its rod: three actuators that
// hold nothing pass the freedom count (each counts as a freedom) but leave
// home singular, where the device is refused.
TEST(DescriptionErrors, ADeviceSingularAtHomeIsRefused) {
  const std::string crank = error_after([](json& d) { d["parameters"]["La"] = 0; });
  expect_contains(crank, {"broken.json", "singular at home", "actuator does not move its anchor", "move home"});
  // The shipped design is not: this is the crank's length, not the check.
  EXPECT_EQ(error_after([](json&) {}), "no error");
}

// A branch rule that is 0 at home cannot choose an assembly there: a
// direction normal to a planar device's plane, a triple naming one joint
// twice. Each had loaded, and a field mixed both elbows.
// The message parse_preset gives for the five-bar's preset after `edit`.
std::string five_bar_after(const std::function<void(json&)>& edit) {
  std::ifstream in(std::string(LINKSCAPE_TEST_ASSETS) + "/mechanisms/five-bar.json");
  json d = json::parse(in);
  edit(d);
  return error_of_text(d.dump());
}

TEST(DescriptionErrors, ABranchRuleThatIsZeroAtHomeIsRefused) {
  const std::string normal = five_bar_after([](json& d) {
    d["description"]["legs"][0]["branch"] = {{"along", {"q1", "elbow1"}}, {"direction", {0, 0, 1}}};
  });
  expect_contains(normal, {"broken.json", "legs \"left\"", "branch rule 1 is 0 at home", "planar"});
  const std::string twice = five_bar_after([](json& d) {
    d["description"]["legs"][1]["branch"] = {{"triple", {"q2", "q2", "tip2"}}};
  });
  expect_contains(twice, {"legs \"right\"", "branch rule 1 is 0 at home", "one joint twice"});
  EXPECT_EQ(five_bar_after([](json&) {}), "no error");
}

// Distal links of no length (b = 0, home where the cranks' tips meet): the
// freedom count fails, and the message names the link, not only the count.
TEST(DescriptionErrors, ALinkOfNoLengthIsNamedWhereTheFreedomsDoNotMatch) {
  const std::string m = five_bar_after([](json& d) {
    d["parameters"]["b"] = 0;
    d["description"]["home"] = {{"x", 0}, {"y", std::sqrt(91.0)}};
  });
  expect_contains(m, {"0 freedom(s) at home", "leg \"left\" has a link of no length after joint elbow1"});
  // A length so large that the size is not finite is named as such, not as
  // the other links' lack of length (the home a fixed point, not one that
  // follows the links).
  const std::string huge = five_bar_after([](json& d) {
    d["parameters"]["b"] = 1e300;
    d["description"]["home"] = {{"x", 0}, {"y", 17}};
  });
  expect_contains(huge, {"description.size", "not finite", "a length far too large?"});
}

TEST(DescriptionErrors, UnknownKeyIsNamedWithTheKnownOnes) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["anchors"] = json::array(); });
  expect_contains(m, {"description.legs[0]", "unknown key 'anchors'", "anchor"});
}

TEST(DescriptionErrors, ExpressionWithAnUnknownVariable) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["chain"][1]["translate"][0] = "Lc"; });
  expect_contains(m, {"description.legs[0] \"1\": chain[1].translate[0]", "cannot evaluate 'Lc'", "La"});
}

// A mistyped joint type is named as such on an actuated joint too (it had
// said "only revolute and prismatic joints can be actuated"); two transforms
// in one step are refused, not read in a guessed order.
TEST(DescriptionErrors, AMistypedActuatedJointAndTwoTransformsInOneStep) {
  const std::string typo = error_after([](json& d) { d["description"]["legs"][0]["chain"][0]["joint"] = "revolut"; });
  expect_contains(typo, {"chain[0]", "unknown joint type 'revolut'", "known: revolute"});
  const std::string two = error_after([](json& d) {
    d["description"]["legs"][0]["chain"].insert(d["description"]["legs"][0]["chain"].begin(), json{{"rz", 30}, {"ry", 0}});
  });
  expect_contains(two, {"chain[0]", "one transform a step, got ry, rz", "a step of its own"});
}

TEST(DescriptionErrors, ActuatedSphericalJointIsRefused) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["chain"][2]["actuated"] = true; });
  expect_contains(m, {"chain[2] (joint \"elbow1\")", "only revolute and prismatic joints can be actuated"});
}

TEST(DescriptionErrors, ALegOnAnUnknownPlatform) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["platform"] = "plate"; });
  expect_contains(m, {"description.legs[0] \"1\": platform", "unknown platform body 'plate'"});
}

TEST(DescriptionErrors, ADescriptionOnACompiledDeviceIsRefused) {
  const std::string m = error_after([](json& d) { d["mechanism"] = "delta"; });
  expect_contains(m, {"broken.json", "\"description\" belongs to a preset whose mechanism is \"described\""});
}

TEST(DescriptionErrors, ABranchRuleNamingAnotherLegsJoint) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["branch"]["triple"][1] = "elbow9"; });
  expect_contains(m, {"description.legs[0] \"1\": branch", "names no joint of this leg: 'elbow9'"});
}

TEST(DescriptionErrors, DeepNestingIsRefusedWithItsPlace) {
  // 60,000 levels overflowed the stack; a shipped preset is 8 levels deep.
  const std::string deep = std::string(60000, '[') + "1" + std::string(60000, ']');
  const std::string m = error_of_text(delta_text_with([](json& d) { d["description"]["size"] = "@"; }, deep));
  expect_contains(m, {"broken.json", "nested deeper than 64 levels", "at /description/size/0/0/0"});
  // At the limit the nesting is read, and the value is refused for what it is.
  const std::string at_limit = std::string(62, '[') + "1" + std::string(62, ']');
  expect_contains(error_of_text(delta_text_with([](json& d) { d["description"]["size"] = "@"; }, at_limit)),
                  {"description.size", "must be a number or an expression string"});
}

TEST(DescriptionErrors, AKeyGivenTwiceIsRefused) {
  const std::string home = R"({"x": 0, "y": 0, "z": -15, "z": -16})";
  const std::string m = error_of_text(delta_text_with([](json& d) { d["description"]["home"] = "@"; }, home));
  expect_contains(m, {"broken.json", "/description/home/z: the key 'z' is given twice"});
  const std::string legs = R"([{"name": "a"}, {"name": "b", "name": "c"}])";
  expect_contains(error_of_text(delta_text_with([](json& d) { d["description"]["legs"] = "@"; }, legs)),
                  {"/description/legs/1/name: the key 'name' is given twice"});
}

TEST(DescriptionErrors, AFileLargerThanAPresetMayBeIsRefused) {
  const std::string padded = delta_description().dump() + std::string(kMaxPresetBytes, ' ');
  expect_contains(error_of_text(padded), {"broken.json", "larger than a preset may be (1048576 bytes)"});
  // From a file, too: it is read only up to the limit.
  const std::string path = testing::TempDir() + "/large-preset.json";
  std::ofstream(path) << padded;
  try {
    load_preset(path);
    ADD_FAILURE() << "a preset of " << padded.size() << " bytes loaded";
  } catch (const std::invalid_argument& e) {
    expect_contains(e.what(), {"large-preset.json", "larger than a preset may be"});
  }
  std::remove(path.c_str());
}

TEST(DescriptionErrors, TooManyLegsAreRefusedBeforeAnyWork) {
  // 640 legs took minutes to refuse, 3,200 ran out of memory.
  const auto start = std::chrono::steady_clock::now();
  const std::string m = error_after([](json& d) {
    json& legs = d["description"]["legs"];
    legs[0].erase("copies");
    legs[0]["name"] = "leg #";
    legs[0]["branch"]["sign"] = 1;  // no free branch rules: nothing else refuses the file early
    for (int l = 2; l <= 640; ++l) {
      json leg = legs[0];
      leg["first"] = l;
      legs.push_back(leg);
    }
  });
  expect_contains(m, {"broken.json", "description.legs", "more than 64 legs"});
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  // Copies count, and each group stays within the limit.
  expect_contains(error_after([](json& d) {
                    json& legs = d["description"]["legs"];
                    legs[0]["copies"] = 40;
                    legs[0]["branch"]["sign"] = 1;
                    legs.push_back(legs[0]);
                    legs[1]["first"] = 41;
                  }),
                  {"description.legs", "more than 64 legs, copies counted"});
}

TEST(DescriptionErrors, CopiesAndFirstDoNotWrap) {
  // 2^32 + 3 read as an int is 3: the file was taken as three copies.
  expect_contains(error_after([](json& d) { d["description"]["legs"][0]["copies"] = 4294967299ULL; }),
                  {"description.legs[0].copies", "must be a whole number from 1 to 64", "4294967299"});
  expect_contains(error_after([](json& d) { d["description"]["legs"][0]["copies"] = -3; }),
                  {"description.legs[0].copies", "must be a whole number from 1 to 64"});
  // first + k past INT_MAX.
  expect_contains(error_after([](json& d) { d["description"]["legs"][0]["first"] = 2147483647; }),
                  {"description.legs[0].first", "must be a whole number from 0 to 1000000"});
}

TEST(DescriptionErrors, TooManyJointVariablesInALegAreRefused) {
  // Nine spherical joints are 27 variables (more than 48 overflowed a fixed-size matrix).
  const std::string m = error_after([](json& d) {
    json& chain = d["description"]["legs"][0]["chain"];
    for (int s = 0; s < 7; ++s) chain.push_back({{"joint", "spherical"}, {"name", std::string("extra").append(std::to_string(s)).append("_#")}});
  });
  expect_contains(m, {"description.legs[0] \"1\": chain[10] (joint \"extra5_1\")", "more than 24 joint variables"});
}

TEST(DescriptionErrors, TooManyPlatformsExtrasOrParametersAreRefused) {
  expect_contains(error_after([](json& d) {
                    for (int b = 0; b < 65; ++b) d["description"]["platforms"].push_back({{"name", std::string("b").append(std::to_string(b))}});
                  }),
                  {"description.platforms", "more than 64 platform bodies"});
  expect_contains(error_after([](json& d) {
                    for (int e = 0; e < 17; ++e)
                      d["description"]["extras"][std::string("e").append(std::to_string(e))] = {{"home", 0}, {"range", {-1, 1}}};
                  }),
                  {"description.extras", "more than 16 extras"});
  expect_contains(error_after([](json& d) {
                    for (int p = 0; p < 253; ++p) d["parameters"][std::string("p").append(std::to_string(p))] = 1;
                  }),
                  {"broken.json", "parameters", "more than 256 parameters"});
}

TEST(DescriptionErrors, AnOverlongExpressionIsRefused) {
  std::string sum = "1";
  while (sum.size() <= 1000) sum += "+1";
  expect_contains(error_after([&](json& d) { d["description"]["size"] = sum; }),
                  {"description.size", "an expression of 1001 characters (at most 1000)"});
}

TEST(DescriptionErrors, ExpressionsHaveNoSideEffects) {
  // An assignment changed the parameter for every later expression (and --param was ignored).
  expect_contains(error_after([](json& d) { d["description"]["size"] = "(La=6)+Lb"; }),
                  {"broken.json", "description.size", "'(La=6)+Lb' assigns with '='"});
  // Only the last of several expressions counted.
  expect_contains(error_after([](json& d) { d["description"]["legs"][0]["chain"][1]["translate"][0] = "14,5"; }),
                  {"chain[1].translate[0]", "'14,5' is 2 expressions"});
  // A NUL byte ended the expression early ("La" was read); a line break is no better.
  expect_contains(error_after([](json& d) {
                    d["description"]["legs"][0]["chain"][1]["translate"][0] = std::string("La\0*2", 5);
                  }),
                  {"chain[1].translate[0]", "control character 0x00 at 2"});
  expect_contains(error_after([](json& d) { d["description"]["size"] = "La +\nLb"; }),
                  {"description.size", "control character 0x0a at 4"});
  // Comparisons and function arguments stay.
  EXPECT_EQ(error_after([](json& d) { d["description"]["size"] = "(La == 8) * max(La, Lb) + min(0, 1)"; }), "no error");
}

TEST(DescriptionErrors, ReservedNamesAreNotParameters) {
  // A parameter k replaced the copy index: three legs on top of each other.
  for (const char* name : {"k", "pi", "deg", "sin", "_pi"}) {
    const std::string m = error_after([&](json& d) { d["parameters"][name] = 1; });
    expect_contains(m, {"broken.json", "parameters." + std::string(name), "a name the expressions define themselves",
                        "reserved: ", "_e", "atan2", "deg", "k", "pi", "sqrt"});
  }
  expect_contains(error_after([](json& d) {
                    d["description"]["extras"] = {{"deg", {{"home", 0}, {"range", {-1, 1}}}}};
                  }),
                  {"description.extras.deg", "a name the expressions define themselves"});
}

TEST(DescriptionErrors, ActuatorLimitsNameAnActuatorAndAnInterval) {
  expect_contains(error_after([](json& d) { d["actuator_limits_deg"]["q9"] = {-10, 10}; }),
                  {"broken.json", "actuator_limits_deg.q9", "names no actuator", "q1, q2, q3"});
  expect_contains(error_after([](json& d) { d["actuator_limits_deg"]["q2"] = {30, -30}; }),
                  {"broken.json", "actuator_limits_deg.q2", "needs lo < hi, got [30, -30]"});
  expect_contains(error_after([](json& d) { d["actuator_limits_deg"]["q2"] = {30, 30}; }),
                  {"actuator_limits_deg.q2", "needs lo < hi"});
}

TEST(DescriptionErrors, EveryTypeErrorNamesTheFileAndThePlace) {
  const std::vector<std::pair<std::function<void(json&)>, std::vector<std::string>>> cases = {
      {[](json& d) { d["title"] = 5; }, {"title: must be a string, got 5"}},
      {[](json& d) { d["parameters"]["La"] = "8"; }, {"parameters.La: must be a number, got \"8\""}},
      {[](json& d) { d["actuator_limits_deg"]["q1"] = {"a", 90}; }, {"actuator_limits_deg.q1[0]: must be a number"}},
      {[](json& d) { d["actuator_data"] = {{"source", 1}}; }, {"actuator_data.source: must be a string"}},
      {[](json& d) { d["description"]["space"] = 3; }, {"description.space: must be a string, got 3"}},
      {[](json& d) { d["description"]["legs"][0]["name"] = 1; }, {"description.legs[0].name: must be a string"}},
      {[](json& d) { d["description"]["legs"][0]["platform"] = 1; },
       {"description.legs[0] \"1\": platform: must be a string"}},
      {[](json& d) { d["description"]["legs"][0]["chain"][0]["joint"] = 5; },
       {"chain[0].joint: must be a string, got 5"}},
      {[](json& d) { d["description"]["legs"][0]["chain"][0]["name"] = true; }, {"chain[0].name: must be a string"}},
      {[](json& d) { d["description"]["legs"][0]["chain"][0]["actuated"] = "yes"; },
       {"chain[0] (joint \"q1\").actuated: must be true or false, got \"yes\""}},
      {[](json& d) { d["description"]["legs"][0]["branch"]["triple"][1] = 7; }, {"branch: must be a string, got 7"}},
      {[](json& d) { d["description"]["platforms"] = json::array({json{{"name", 5}}}); }, {"description.platforms[0].name: must be a string"}},
      {[](json& d) { d["description"]["parameter_info"]["La"]["unit"] = 3; },
       {"description.parameter_info.La.unit: must be a string"}},
      {[](json& d) { d["description"]["parameter_info"]["La"]["in_panel"] = "no"; },
       {"description.parameter_info.La.in_panel: must be true or false"}},
      {[](json& d) { d["description"]["extras"] = {{"grip", {{"home", 1}, {"range", {0, 2}}, {"unit", 2}}}}; },
       {"description.extras.grip.unit: must be a string"}},
  };
  for (const auto& [edit, parts] : cases) {
    std::vector<std::string> expected = parts;
    expected.push_back("preset broken.json: ");
    expect_contains(error_after(edit), expected);
  }
}

}  // namespace
}  // namespace linkscape
