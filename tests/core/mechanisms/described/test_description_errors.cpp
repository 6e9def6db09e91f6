// Malformed descriptions are refused with a message that names the place in
// the file (docs/described-mechanisms.md, "Errors").
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/mechanism.h"
#include "core/preset.h"

namespace linkscape {
namespace {

using nlohmann::json;

json delta_description() {
  std::ifstream in(std::string(LINKSCAPE_TEST_ASSETS) + "/mechanisms/delta-described.json");
  return json::parse(in);
}

// The message parse_preset gives for the Delta's description after `edit`.
std::string error_after(const std::function<void(json&)>& edit) {
  json doc = delta_description();
  edit(doc);
  try {
    parse_preset(doc.dump(), "broken.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
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
                  {"parameter_info.La.range[1]", "evaluates to"});
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

TEST(DescriptionErrors, UnknownKeyIsNamedWithTheKnownOnes) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["anchors"] = json::array(); });
  expect_contains(m, {"description.legs[0]", "unknown key 'anchors'", "anchor"});
}

TEST(DescriptionErrors, ExpressionWithAnUnknownVariable) {
  const std::string m = error_after([](json& d) { d["description"]["legs"][0]["chain"][1]["translate"][0] = "Lc"; });
  expect_contains(m, {"description.legs[0] \"1\": chain[1].translate[0]", "cannot evaluate 'Lc'", "La"});
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

}  // namespace
}  // namespace linkscape
