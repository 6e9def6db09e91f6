// The text of `linkscape describe FILE` (described::describe) and a leg's
// asserted pattern.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>

#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/preset.h"
#include "tests/core/mechanisms/described/designs.h"

namespace linkscape::described {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(DescribedDescribe, FiveBarLegsPatternsRulesAndReach) {
  const std::string text = describe(load_preset("five-bar"));
  EXPECT_TRUE(has(text, "mobility: 2 ")) << text;
  EXPECT_TRUE(has(text, "legs: 2 (2 in closed form, 0 numeric)")) << text;
  EXPECT_TRUE(has(text, "  leg left: planar-dyad\n")) << text;
  EXPECT_TRUE(has(text, "    actuator q1 (revolute), travel 0 .. 210 deg\n")) << text;
  EXPECT_TRUE(has(text, "    branch: triple [tip1, elbow1, q1] free (branch bit 0)\n")) << text;
  EXPECT_TRUE(has(text, "    branch: triple [q2, elbow2, tip2] free (branch bit 1)\n")) << text;
  // Links of 10 and 14 cm: from 4 (folded) to 24 (stretched).
  EXPECT_TRUE(has(text, "    reach: 4 .. 24 cm from its base to its anchor\n")) << text;
}

// The size is named by the lengths it sums: one per run of fixed steps
// between joints. Two translations in one run make one length that is not
// their sum, so the size is then said in words.
TEST(DescribedDescribe, TheSizeIsNamedByTheLengthsItSums) {
  Preset p = load_preset("five-bar");
  EXPECT_TRUE(has(describe(p), "size 24 cm (a + b)\n")) << describe(p);
  nlohmann::json doc = nlohmann::json::parse(p.description);
  nlohmann::json& chain = doc["legs"][0]["chain"];
  ASSERT_TRUE(chain[1].contains("translate"));
  chain.insert(chain.begin() + 2, nlohmann::json{{"translate", {0, "d", 0}}});  // beside a, before the elbow
  p.description = doc.dump();
  const std::string text = describe(p);
  EXPECT_TRUE(has(text, "(the first leg's link lengths)\n")) << text;
  EXPECT_FALSE(has(text, "a + d")) << text;
}

// Where every command starts: a home outside a travel (written in radians
// where degrees are read) is named with the actuator's angle.
TEST(DescribedDescribe, HomeAndAnActuatorOutsideItsTravel) {
  Preset p = load_preset("five-bar");
  EXPECT_TRUE(has(describe(p), "home: ok\n")) << describe(p);
  p.limits_deg["q1"] = Range{0.17, 3.5};
  const std::string text = describe(p);
  EXPECT_TRUE(has(text, "home: out-of-limits; q1 = ")) << text;
  EXPECT_TRUE(has(text, " deg is outside its travel 0.17 .. 3.5 deg\n")) << text;
  EXPECT_FALSE(has(text, "q2 = ")) << text;
}

TEST(DescribedDescribe, StewartAndPathosLegs) {
  const std::string stewart = describe(load_preset("stewart"));
  EXPECT_TRUE(has(stewart, "  leg 6: extensible\n")) << stewart;  // named "leg 6": not "leg leg 6"
  EXPECT_TRUE(has(stewart, "actuator l6 (prismatic), travel 10 .. 18 cm")) << stewart;
  EXPECT_TRUE(has(stewart, "branch: none")) << stewart;
  EXPECT_TRUE(has(stewart, "reach: 0 .. unbounded cm")) << stewart;
  const std::string pathos = describe(load_preset("pathos2-described"));
  EXPECT_TRUE(has(pathos, "legs: 6 (6 in closed form, 0 numeric)")) << pathos;
  EXPECT_TRUE(has(pathos, "branch: angle t3_4 sign + (design)")) << pathos;
  EXPECT_TRUE(has(pathos, "1 extra(s)")) << pathos;
}

// The bound about each leg's first joint: a crank of 8 cm carrying a rod of
// 17 cm; a carriage on its rail carrying a rod of 25 cm.
TEST(DescribedDescribe, ReachAboutTheFirstJoint) {
  const std::string delta = describe(load_preset("delta-described"));
  EXPECT_TRUE(has(delta, "    reach about its first joint: within 17 .. 17 cm of a circle of radius 8 cm round q1's axis\n"))
      << delta;
  const std::string linear = describe(load_preset("linear-delta"));
  EXPECT_TRUE(has(linear, "reach about its first joint: within 25 cm of the line along h1\n")) << linear;
  EXPECT_FALSE(has(describe(load_preset("stewart")), "reach about its first joint")) << "a slide further on: no bound";
}

// The sampled reach: the five-bar's two revolutes on a grid, the Delta's
// crank and the ball its rod turns on; the Falcon's knee and ankle move its
// end too, more than a grid samples.
TEST(DescribedDescribe, TheSampledReachIsNamed) {
  const std::string five_bar = describe(load_preset("five-bar"));
  EXPECT_TRUE(has(five_bar, "    reach sampled within its travel: 33124 samples of the 2 joints that move its end; every "
                            "assembly within 0.48 cm of a sample's end\n"))
      << five_bar;
  const std::string delta = describe(load_preset("delta-described"));
  EXPECT_TRUE(has(delta, "    reach sampled within its travel: 67270 samples of the 2 joints that move its end; every "
                         "assembly within 2.6 cm of a sample's end\n"))
      << delta;
  const std::string falcon = describe(load_preset("falcon"));
  EXPECT_TRUE(has(falcon, "    reach sampled within its travel: no (4 freedoms move its end; a grid samples three at most)\n"))
      << falcon;
}

// The five-bar with its left leg changed: `pattern` asserted (if not empty),
// `steps` appended to its chain.
Preset five_bar_with(const std::string& pattern, const nlohmann::json& steps = nlohmann::json::array()) {
  Preset p = load_preset("five-bar");
  nlohmann::json d = nlohmann::json::parse(p.description);
  nlohmann::json& left = d["legs"][0];
  if (!pattern.empty()) left["pattern"] = pattern;
  for (const auto& step : steps) left["chain"].push_back(step);
  p.description = d.dump();
  return p;
}

// A rod ending in a universal joint (the Omnid's arm with universal knees
// and platform joints): named, and why its fields are not in lanes.
TEST(DescribedDescribe, ARodEndingInAUniversalJointIsNamed) {
  const std::string text = describe(testing_support::omnid_with_universal_joints());
  EXPECT_TRUE(has(text, "  leg 1: crank-rod (ending in a universal joint: it holds the orientation too)\n")) << text;
  EXPECT_TRUE(has(text, "not in lanes: leg 1: holds more than one wrench")) << text;
  EXPECT_TRUE(has(describe(load_preset("omnid-delta")), "  leg 1: crank-rod\n"));
}

TEST(DescribedDescribe, ALegOfNoKnownPatternIsNumeric) {
  // PATHOS-II with the second joint of legs 1-3 set 0.5 cm off the
  // actuator's axis: three revolutes to a spherical joint whose first two
  // axes do not meet, of no known pattern.
  Preset p = load_preset("pathos2-described");
  nlohmann::json d = nlohmann::json::parse(p.description);
  d["legs"][0]["chain"][1]["translate"][0] = 0.5;
  d["legs"][0]["pattern"] = "numeric";
  p.description = d.dump();
  const std::string text = describe(p);
  EXPECT_TRUE(has(text, "legs: 6 (3 in closed form, 3 numeric)")) << text;
  // Its joints in order, the actuated one starred, beside the patterns' steps.
  EXPECT_TRUE(has(text, "  leg 1: numeric (its joints: revolute*, revolute, revolute, spherical; the closed forms' "
                        "steps: docs/described-mechanisms.md)\n"))
      << text;
  EXPECT_TRUE(has(text, "  leg 4: three-revolute\n")) << text;
  // What refuses its anchors near the reach's edge: its joints after the
  // actuator sampled about the actuator's axis (without a travel: no turns within it).
  EXPECT_TRUE(has(text, "    reach sampled about its first joint: 262735 samples of the joints after it, as distance "
                        "from its axis and height along it; every assembly within 0.13 cm of one\n"))
      << text;
  // The field's path: the closed forms and the numerical solver.
  EXPECT_TRUE(has(text, "field: the closed forms of 3 legs and the numerical solver for the others, one pose at a "
                        "time (not in lanes: leg 1: "))
      << text;
  // With every leg of no known pattern, the numerical solver alone.
  d["legs"][1]["chain"][1]["translate"][0] = 0.5;
  p.description = d.dump();
  EXPECT_TRUE(has(describe(p), "legs: 6 (0 in closed form, 6 numeric)")) << describe(p);
  EXPECT_TRUE(has(describe(p), "field: the numerical solver, one pose at a time (no leg in closed form)\n"))
      << describe(p);
  // The same leg asserted numeric where it is a planar dyad is refused.
  try {
    describe(five_bar_with("numeric"));
    FAIL() << "a planar dyad asserted numeric was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(has(e.what(), "names \"numeric\" but the leg is solved as \"planar-dyad\"")) << e.what();
  }
}

// The described Delta's elbows written as two revolutes at one point: a
// universal joint the patterns do not read so, named in a hint; written as
// a universal, the legs take their closed form.
// Two revolutes at one point with crossing axes, written as two joints,
// are solved as the universal joint they make: in closed form, with the
// same actuators as the leg written with a universal.
TEST(DescribedDescribe, TwoRevolutesAtOnePointAreTakenAsAUniversal) {
  Preset p = load_preset("delta-described");
  nlohmann::json d = nlohmann::json::parse(p.description);
  nlohmann::json& chain = d["legs"][0]["chain"];
  chain[2] = {{"joint", "universal"}, {"name", "elbow#"}, {"axes", {{0, 1, 0}, {0, 0, 1}}}};
  p.description = d.dump();
  const std::string universal = describe(p);
  EXPECT_TRUE(has(universal, "legs: 3 (3 in closed form, 0 numeric)")) << universal;
  EXPECT_FALSE(has(universal, "taken as one universal joint")) << universal;
  const Kinematics written_universal(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));

  chain[2] = {{"joint", "revolute"}, {"name", "elbow#"}, {"axis", {0, 1, 0}}};  // the branch rule names it
  chain.insert(chain.begin() + 3, nlohmann::json{{"joint", "revolute"}, {"name", "eb#"}, {"axis", {0, 0, 1}}});
  p.description = d.dump();
  const std::string text = describe(p);
  EXPECT_TRUE(has(text, "legs: 3 (3 in closed form, 0 numeric)")) << text;
  EXPECT_TRUE(has(text, "    revolutes elbow1 and eb1 meet at one point with crossing axes: taken as one universal "
                        "joint\n")) << text;
  const Kinematics two_revolutes(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
  int compared = 0;
  for (const double x : {-8.0, 0.0, 5.0})
    for (const double z : {-30.0, -22.0, -14.0}) {
      const Eigen::Vector3d at(x, 2.0, z);
      const PoseSolution a = written_universal.inverse(at, 0, 1e-10), b = two_revolutes.inverse(at, 0, 1e-10);
      ASSERT_EQ(a.status, b.status) << at.transpose();
      if (a.status != Status::Ok) continue;
      ++compared;
      EXPECT_LT((a.q - b.q).norm(), 1e-12) << at.transpose();
      // And as the numerical reference solves the two revolutes.
      const PoseSolution n = two_revolutes.inverse(at, 0, 1e-10, LegSolver::Numeric);
      ASSERT_EQ(n.status, Status::Ok) << at.transpose();
      EXPECT_LT((n.q - b.q).norm(), 1e-9) << at.transpose();
    }
  EXPECT_GE(compared, 4);
}

// A platform coordinate the description holds (not a task coordinate) that
// the legs as written do not: Tsai's 3-UPU holds its orientation by its
// legs, the same device with balls at the top (3-UPS) does not.
TEST(DescribedDescribe, CoordinatesHeldByTheDescriptionAloneAreNamed) {
  const Preset upu = testing_support::tsai_three_upu();
  const std::string upu_text = describe(upu);
  EXPECT_TRUE(has(upu_text, "3 held")) << upu_text;
  EXPECT_FALSE(has(upu_text, "held by the description alone")) << upu_text;
  Preset ups = upu;
  nlohmann::json d = nlohmann::json::parse(ups.description);
  d["legs"][0]["chain"][2] = {{"joint", "spherical"}, {"name", "top#"}};
  ups.description = d.dump();
  const std::string ups_text = describe(ups);
  EXPECT_TRUE(has(ups_text, "  held by the description alone: rx, ry, rz (the legs as written leave the platform free"))
      << ups_text;
  const std::string falcon = describe(load_preset("falcon"));
  EXPECT_FALSE(has(falcon, "held by the description alone")) << falcon;
  const std::string five_bar = describe(load_preset("five-bar"));
  EXPECT_TRUE(has(five_bar, "  held by the description alone: rz (")) << five_bar;
}

TEST(DescribedDescribe, AnAssertedPatternIsChecked) {
  EXPECT_NO_THROW(describe(five_bar_with("planar-dyad")));
  try {
    describe(five_bar_with("crank-rod"));
    FAIL() << "a wrong pattern was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(has(e.what(), "description.legs \"left\": pattern: the description names \"crank-rod\" but the leg is "
                              "solved as \"planar-dyad\""))
        << e.what();
  }
  try {
    describe(five_bar_with("scara"));
    FAIL() << "an unknown pattern was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(has(e.what(), "unknown pattern \"scara\" (known: crank-rod")) << e.what();
  }
}

// A rule that gives both of a leg's assemblies at home the same sign
// chooses nothing between them: describe says so (the rule a designer had
// written for a biglide picked both carriages on one side, a singular pose).
TEST(DescribedDescribe, ARuleThatDoesNotSeparateTheAssembliesIsNamed) {
  EXPECT_FALSE(has(describe(load_preset("five-bar")), "warning:"));
  Preset p = load_preset("five-bar");
  nlohmann::json d = nlohmann::json::parse(p.description);
  d["legs"][0]["branch"] = {{"along", {"q1", "elbow1"}}, {"direction", {0, 1, 0}}};  // both elbows lie above
  p.description = d.dump();
  const std::string text = describe(p);
  EXPECT_TRUE(has(text, "    warning: its branch rules give the same signs to two of its assemblies at home (q1 = "))
      << text;
  EXPECT_EQ(text.find("warning:"), text.rfind("warning:")) << "the right leg's triple separates them: " << text;
}

// The "along" rule names two joints and a unit direction.
TEST(DescribedDescribe, AnAlongRuleIsChecked) {
  auto with_rule = [](const nlohmann::json& rule) {
    Preset p = load_preset("linear-delta");
    nlohmann::json d = nlohmann::json::parse(p.description);
    d["legs"][0]["branch"] = rule;
    p.description = d.dump();
    return p;
  };
  auto message = [&](const nlohmann::json& rule) {
    try {
      describe(with_rule(rule));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_TRUE(has(message({{"along", {"elbow#", "anchor"}}}), "branch: \"along\" needs a \"direction\" [x, y, z] (base frame)"));
  EXPECT_TRUE(has(message({{"along", {"elbow#"}}, {"direction", {0, 0, 1}}}), "branch.along: must name two joints [A, B]"));
  EXPECT_TRUE(has(message({{"along", {"elbow#", "anchor"}}, {"direction", {0, 0, 2}}}), "is not a unit vector"));
  EXPECT_TRUE(has(message({{"along", {"elbow#", "anchor"}}, {"direction", {0, 0, 1}}, {"sign", "-1"}}), "accepted"));
  // The sign chooses the solution: rods below their carriages reach home
  // within the travel; rods above need the carriages 22 cm below it.
  const auto below = described::make_mechanism(with_rule({{"along", {"elbow#", "anchor"}}, {"direction", {0, 0, 1}}, {"sign", "-1"}}));
  const auto above = described::make_mechanism(with_rule({{"along", {"elbow#", "anchor"}}, {"direction", {0, 0, 1}}, {"sign", "1"}}));
  EXPECT_EQ(below->inverse(below->home_task()).status, Status::Ok);
  EXPECT_EQ(above->inverse(above->home_task()).status, Status::OutOfLimits);
}

TEST(DescribedDescribe, APresetWithoutADescriptionIsRefused) {
  EXPECT_THROW(describe(load_preset("delta")), std::invalid_argument);
}

}  // namespace
}  // namespace linkscape::described

namespace linkscape {
namespace {

// describe lists each leg's passive-joint limits and links, or says there are none.
TEST(DescribedDescribe, LimitsAndLinks) {
  const std::string falcon = described::describe(load_preset("falcon"));
  EXPECT_NE(falcon.find("    limit: joint knee2: 10 .. 170 deg\n"), std::string::npos) << falcon;
  EXPECT_NE(falcon.find("    link: thigh, radius 5 mm, length 60 mm\n"), std::string::npos) << falcon;
  EXPECT_NE(falcon.find("    link: motor arm, radius 12 mm"), std::string::npos) << falcon;
  const std::string delta = described::describe(load_preset("delta-described"));
  EXPECT_NE(delta.find("    limit: ball joint wrist3: 45 deg cone\n"), std::string::npos) << delta;
  EXPECT_NE(delta.find("links: none given a radius"), std::string::npos) << delta;
  const std::string five_bar = described::describe(load_preset("five-bar"));
  EXPECT_NE(five_bar.find("passive-joint limits: none stated"), std::string::npos) << five_bar;
}

}  // namespace
}  // namespace linkscape
