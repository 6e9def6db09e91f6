// Sessions open exactly as saved or not at all: a value the window cannot
// honour is an error naming its key, never a silent clamp.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/preset.h"
#include "gui/window/session.h"

using namespace linkscape;
using namespace linkscape::gui;
using nlohmann::json;

namespace {

json good_12r() {
  return json::parse(R"({"format": "linkscape-session", "version": 1, "mechanism": "parallel-12r",
    "parameters": {"L1": 15, "L2": 15}, "pose_rad": [0.1, 1.2, 0.3],
    "field": {"field": "cond", "normal": "x", "method": "planar", "slice_resolution": 192, "volume_resolution": 64}})");
}

// The message for `session`, or "" if it opened.
std::string error_of_text(const std::string& session) {
  try {
    parse_session(session, "s.json");
    return "";
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
}

std::string error_of(const json& session) { return error_of_text(session.dump()); }

}  // namespace

TEST(Session, AGoodSessionOpensAndRoundTrips) {
  const Session s = parse_session(good_12r().dump(), "s.json");
  EXPECT_EQ(s.mechanism, "parallel-12r");
  EXPECT_DOUBLE_EQ(s.pose.y(), 1.2);
  const auto file = std::filesystem::temp_directory_path() / "linkscape_session_roundtrip.json";
  save_session(s, file);
  const Session back = load_session(file);
  EXPECT_EQ(back.mechanism, s.mechanism);
  EXPECT_EQ(back.parameters, s.parameters);
  EXPECT_EQ(back.pose, s.pose);
  EXPECT_EQ(back.field.field, s.field.field);
  std::filesystem::remove(file);
}

TEST(Session, ValuesTheWindowCannotHonourAreErrorsNamingTheKey) {
  struct Case {
    const char* pointer;
    json value;
    const char* expected;
  };
  const Case cases[] = {
      {"/parameters/L1", -1, "L1"},
      {"/parameters/L3", 1, "L3"},
      {"/field/field", "conditioning", "field.field"},
      {"/field/normal", "w", "field.normal"},
      {"/field/method", "magic", "field.method"},
      {"/field/volume_resolution", 100, "field.volume_resolution"},
      {"/field/slice_resolution", 193, "field.slice_resolution"},
      {"/field/slice_resolution", 1e300, "field.slice_resolution"},
      {"/field/volume_resolution", 64.5, "field.volume_resolution"},
      {"/version", 1.5, "version"},
      {"/field/threshold", 0.5, "field.threshold"},
      {"/field/reach_opacity", 2, "opacities"},
      {"/field/range_min", 5, "range_max"},
      {"/field/colour", "red", "field.colour"},
      {"/actuator_limits_deg", json::parse(R"({"alpha": [10, -10]})"), "alpha"},
      {"/actuator_limits_deg", json::parse(R"({"delta": [0, 10]})"), "delta"},
      {"/camera", json::parse(R"({"position": [1, 0, 0], "focal_point": [0, 0, 0], "view_up": [0, 0, 1], "view_angle_deg": 0})"), "view_angle"},
      // Extreme values that used to give a blank view:
      {"/camera", json::parse(R"({"position": [1e300, 0, 0], "focal_point": [0, 0, 0], "view_up": [0, 0, 1]})"), "camera.position"},
      {"/camera", json::parse(R"({"position": [1, 0, 0], "focal_point": [0, 0, 1e12], "view_up": [0, 0, 1]})"), "camera.focal_point"},
      {"/camera", json::parse(R"({"position": [1e-12, 0, 0], "focal_point": [0, 0, 0], "view_up": [0, 0, 1]})"), "position must be at least"},
      {"/camera", json::parse(R"({"position": [1, 0, 0], "focal_point": [0, 0, 0], "view_up": [1, 0, 0]})"), "view_up"},
      {"/camera", json::parse(R"({"position": [1, 0, 0], "focal_point": [0, 0, 0], "view_up": [0, 0, 1], "view_angle_deg": 1e-9})"), "view_angle"},
      {"/field", json::parse(R"({"range_min": 0, "range_max": 3})"), "field.range_min must be above 0 on a logarithmic"},
      {"/field", json::parse(R"({"position": 1e9})"), "field.position 1e+09 is outside the device's box"},
      {"/mechanism", "no-such-mechanism", "no-such-mechanism"},
      {"/version", 2, "version"},
      {"/platform_pose", json::array({0, 0, 22.5, 0, 0, 0, 7}), "platform_pose"},
      {"/extra", true, "extra"},
      // Values of the wrong JSON type name their key (they gave "type must be number, but is string").
      {"/parameters/L1", "15", "parameters.L1 must be a number"},
      {"/field/threshold", "3", "field.threshold must be a number"},
      {"/mechanism", 5, "mechanism must be a preset's name"},
      {"/camera", json::parse(R"({"position": [1, 0, 0], "focal_point": [0, 0, 0]})"), "camera.view_up is missing"},
      {"/camera", json::parse(R"({"position": [1, "0", 0], "focal_point": [0, 0, 0], "view_up": [0, 0, 1]})"),
       "camera.position must be an array of 3 numbers"},
  };
  for (const Case& c : cases) {
    json s = good_12r();
    s[json::json_pointer(c.pointer)] = c.value;
    const std::string message = error_of(s);
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.pointer << " gave: '" << message << "'";
    EXPECT_NE(message.find("s.json"), std::string::npos) << message;
  }
}

// Read as presets are: a key given twice is not resolved by a guess, and
// nesting that would overflow the stack is refused with its place.
TEST(Session, AKeyGivenTwiceOrDeepNestingIsRefused) {
  std::string twice = good_12r().dump();
  twice.insert(1, "\"mechanism\": \"pathos2\", ");
  EXPECT_NE(error_of_text(twice).find("given twice"), std::string::npos) << error_of_text(twice);
  std::string deep = good_12r().dump();
  deep.insert(deep.size() - 1, ", \"extra\": " + std::string(100000, '[') + std::string(100000, ']'));
  EXPECT_NE(error_of_text(deep).find("nested deeper than"), std::string::npos) << error_of_text(deep).substr(0, 200);
}

TEST(Session, ErrorsCarryNoJsonLibraryCode) {
  json s = good_12r();
  s["mechanism"] = 5;
  EXPECT_EQ(error_of(s).find("json.exception"), std::string::npos) << error_of(s);
  EXPECT_NE(error_of(s).find("s.json"), std::string::npos) << error_of(s);
  EXPECT_EQ(error_of_text("{\"format\": ").find("json.exception"), std::string::npos) << error_of_text("{");
}

TEST(Session, AMechanismPathTooLongToLookUpIsAnUnknownMechanism) {
  json s = good_12r();
  s["mechanism"] = "presets/" + std::string(300, 'x') + ".json";  // one name over NAME_MAX
  const std::string error = error_of(s);  // not a std::filesystem::filesystem_error out of the loader
  EXPECT_NE(error.find("s.json"), std::string::npos) << error;
  EXPECT_NE(error.find(std::string(300, 'x')), std::string::npos) << error;
}

TEST(Session, TheTaskVolumeIsCheckedAsTheCommandLineChecksIt) {
  json s = good_12r();
  s["task_volume"] = {{"volume", "sphere:diameter=12,centre=0,15,15"}, {"criteria", {"cond<3"}}, {"shown", true}};
  EXPECT_EQ(error_of(s), "");
  EXPECT_EQ(parse_session(s.dump(), "s.json").task_volume->criteria, std::vector<std::string>{"cond<3"});
  for (const auto& [key, bad] : std::vector<std::pair<std::string, json>>{
           {"volume", "cube:1"}, {"volume", "sphere:diameter=-2"}, {"criteria", json::array({"cond<0.5"})}}) {
    json b = s;
    b["task_volume"][key] = bad;
    EXPECT_NE(error_of(b).find("task_volume"), std::string::npos) << key << ": " << error_of(b);
  }
  json unknown = s;
  unknown["task_volume"]["colour"] = "red";
  EXPECT_NE(error_of(unknown).find("task_volume.colour"), std::string::npos) << error_of(unknown);
}

TEST(Session, TheFitTabsSettingsRoundTripAndAreChecked) {
  Session s = parse_session(good_12r().dump(), "s.json");
  s.fit = FitSetting{{"L1", "L2"}, {{"L1", {5.0, 25.0}}, {"L2", {6.0, 20.0}}}, "L1,L2", true, 31.5, false};
  const auto file = std::filesystem::temp_directory_path() / "linkscape_session_fit.json";
  save_session(s, file);
  const Session back = load_session(file);
  std::filesystem::remove(file);
  ASSERT_TRUE(back.fit);
  EXPECT_EQ(*back.fit, *s.fit);
  json with_fit = good_12r();
  with_fit["fit"] = {{"free", {"L1"}}, {"bounds", {{"L1", {5, 25}}}}, {"mode", "smallest-size"}};
  EXPECT_EQ(error_of(with_fit), "");
  for (const auto& [key, bad] : std::vector<std::pair<std::string, json>>{
           {"bounds", {{"L1", {25, 5}}}}, {"mode", "fastest"}, {"size", -1}, {"colour", "red"}}) {
    json b = with_fit;
    b["fit"][key] = bad;
    EXPECT_NE(error_of(b).find("fit"), std::string::npos) << key << ": " << error_of(b);
  }
}

// Slice opacity, the centre region, the Fit tab's last result and the View
// menu's toggles: saved, read back equal, and checked like every key.
TEST(Session, TheViewTheRegionAndTheFitResultRoundTripAndAreChecked) {
  Session s = parse_session(good_12r().dump(), "s.json");
  s.field.slice_opacity = 0.35;
  s.fit = FitSetting{{"L1"}, {}, "", false, 0, true, "box:min=-5,-30,-30,max=5,0,0"};
  s.fit_result = FitOutcome{"the report\nline 2", "smallest design meeting it", {{"L1", 12.25}, {"L2", 12.25}},
                            Eigen::Vector3d(0.5, 14.0, 9.75)};
  s.view = {{"parallelProjectionAction", true}, {"showTimingsAction", false}};
  const auto file = std::filesystem::temp_directory_path() / "linkscape_session_view.json";
  save_session(s, file);
  const Session back = load_session(file);
  std::filesystem::remove(file);
  EXPECT_EQ(back.field.slice_opacity, 0.35);
  EXPECT_TRUE(back.field == s.field);
  ASSERT_TRUE(back.fit && back.fit_result);
  EXPECT_EQ(back.fit->centre_region, s.fit->centre_region);
  EXPECT_TRUE(*back.fit_result == *s.fit_result);
  EXPECT_EQ(back.view, s.view);
  // Without them (older files): the defaults.
  const Session plain = parse_session(good_12r().dump(), "s.json");
  EXPECT_EQ(plain.field.slice_opacity, 1.0);
  EXPECT_FALSE(plain.fit_result);
  EXPECT_TRUE(plain.view.empty());
  struct Case {
    const char* pointer;
    json value;
    const char* expected;
  };
  const Case cases[] = {
      {"/field/slice_opacity", 1.5, "opacities"},
      {"/fit", {{"centre_region", "box:min=0,0,0"}}, "fit.centre_region"},
      {"/fit_result", {{"design", {{"L1", "twelve"}}}}, "fit_result"},
      {"/fit_result", {{"centre", {1, 2}}}, "array of 3"},
      {"/fit_result", {{"chart", true}}, "fit_result.chart"},
      {"/view", {{"parallelProjectionAction", "yes"}}, "view.parallelProjectionAction"},
      {"/view", json::array({true}), "view"},
  };
  for (const Case& c : cases) {
    json bad = good_12r();
    bad[json::json_pointer(c.pointer)] = c.value;
    const std::string message = error_of(bad);
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.pointer << ": " << message;
  }
}

TEST(Session, OnlyTextsTheCommandLineTakesAreValidTaskSettings) {
  EXPECT_TRUE(valid_task_setting({"sphere:diameter=12", {"cond<3", "force_iso>1"}, true}));
  EXPECT_FALSE(valid_task_setting({"sphere:diameter=12", {"cond<3;"}, true}));
  EXPECT_FALSE(valid_task_setting({"cube:1", {}, true}));
}

TEST(Session, Pathos2SessionsAreCheckedAgainstTheirOwnChoices) {
  json s = json::parse(R"({"format": "linkscape-session", "version": 1, "mechanism": "pathos2",
    "parameters": {"l2": 14}, "platform_pose": [0, 0, 22.5, 0, 0, 0.52, 7],
    "field": {"field": "cond_jo", "volume_resolution": 48, "slice_resolution": 128}})");
  EXPECT_EQ(error_of(s), "");
  s["field"]["volume_resolution"] = 64 + 1;
  EXPECT_NE(error_of(s).find("volume_resolution"), std::string::npos);
  s["field"]["volume_resolution"] = 48;
  s["field"]["field"] = "residual";  // a 12R field
  EXPECT_NE(error_of(s).find("field.field"), std::string::npos);
  s["field"]["field"] = "cond";
  s["parameters"]["l2"] = -3;
  EXPECT_NE(error_of(s).find("l2"), std::string::npos);
}

TEST(Session, APresetRecordedByAVanishedPathOpensByItsName) {
  json s = good_12r();
  s["mechanism"] = "/a/folder/that/is/gone/parallel-12r.json";
  const Session opened = parse_session(s.dump(), "s.json");
  EXPECT_EQ(opened.mechanism, "parallel-12r");
  // A shipped preset is saved by name, so the session is portable.
  EXPECT_EQ(preset_reference(load_preset("parallel-12r")), "parallel-12r");
}

TEST(Session, ThePoseIsSavedByNameAndOlderArraysStillOpen) {
  // A saved session names the device's actuators and task coordinates.
  Session s = parse_session(good_12r().dump(), "s.json");
  s.task = Eigen::Vector3d(3, 4, 12);
  const auto file = std::filesystem::temp_directory_path() / "linkscape_session_by_name.json";
  save_session(s, file);
  std::ifstream in(file);
  const json saved = json::parse(in);
  EXPECT_FALSE(saved.contains("pose_rad"));
  EXPECT_DOUBLE_EQ(saved["actuators"]["beta"].get<double>(), 1.2);
  EXPECT_DOUBLE_EQ(saved["task"]["z"].get<double>(), 12.0);
  const Session back = load_session(file);
  EXPECT_EQ(back.pose, s.pose);
  EXPECT_EQ(back.task, s.task);
  std::filesystem::remove(file);
  // PATHOS-II's platform_pose is its task, in order.
  const Session p = parse_session(R"({"format": "linkscape-session", "mechanism": "pathos2",
    "platform_pose": [0, 0, 22.5, 0, 0, 0.52, 7]})", "p.json");
  ASSERT_EQ(p.task.size(), 7);
  EXPECT_DOUBLE_EQ(p.task(6), 7.0);
  EXPECT_EQ(p.pose.size(), 0);
}

TEST(Session, APoseByNameIsCheckedAgainstTheDevice) {
  struct Case {
    json pose;  // merged into a 12R session without pose_rad
    const char* expected;
  };
  const Case cases[] = {
      {json::parse(R"({"actuators": {"alpha": 0.1, "beta": 1.2}})"), "gamma"},                  // incomplete
      {json::parse(R"({"actuators": {"alpha": 0.1, "beta": 1.2, "gamma": 0, "q4": 1}})"), "q4"},  // unknown name
      {json::parse(R"({"task": {"x": 1, "y": 2, "z": 1e9}})"), "task.z"},                        // outside the sliders
      {json::parse(R"({"task": {"x": 1, "y": 2, "z": "3"}})"), "number"},                         // not a number
      {json::parse(R"({"pose_rad": [0.1, 0.2]})"), "pose_rad"},                                   // wrong length
      {json::parse(R"({"pose_rad": [0.1, 0.2, 0.3], "actuators": {"alpha": 0, "beta": 0, "gamma": 0}})"), "pose_rad"},
      {json::object(), "no pose"},
  };
  for (const Case& c : cases) {
    json s = good_12r();
    s.erase("pose_rad");
    for (const auto& [key, value] : c.pose.items()) s[key] = value;
    const std::string message = error_of(s);
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.pose.dump() << " gave: '" << message << "'";
  }
}

TEST(Session, FieldChoicesComeFromTheDescription) {
  const auto twelve = make_mechanism(load_preset("parallel-12r"));
  const auto six = make_mechanism(load_preset("pathos2"));
  const FieldChoices a = field_choices(twelve->info()), b = field_choices(six->info());
  // One IK method: no method field and nothing to choose; a second measure: its own field.
  EXPECT_EQ(std::count(a.fields.begin(), a.fields.end(), "method"), 1);
  EXPECT_EQ(a.methods.size(), twelve->info().ik_methods.size());
  EXPECT_EQ(std::count(b.fields.begin(), b.fields.end(), "method"), 0);
  EXPECT_TRUE(b.methods.empty());
  EXPECT_EQ(std::count(b.fields.begin(), b.fields.end(), six->info().measures[1].name), 1);
  // The same resolutions for every device, holding both earlier per-device lists.
  EXPECT_EQ(a.slice_resolutions, b.slice_resolutions);
  EXPECT_EQ(a.volume_resolutions, b.volume_resolutions);
  for (int n : {96, 192, 384, 768, 64, 128, 256, 512})
    EXPECT_EQ(std::count(a.slice_resolutions.begin(), a.slice_resolutions.end(), n), 1) << n;
  for (int n : {32, 48, 64, 96, 128, 24})
    EXPECT_EQ(std::count(a.volume_resolutions.begin(), a.volume_resolutions.end(), n), 1) << n;
  // A one-method device accepts the "planar" older files carry, and nothing else.
  json p = json::parse(R"({"format": "linkscape-session", "mechanism": "pathos2",
    "platform_pose": [0, 0, 22.5, 0, 0, 0.52, 7], "field": {"method": "planar"}})");
  EXPECT_EQ(error_of(p), "");
  p["field"]["method"] = "newton";
  EXPECT_NE(error_of(p).find("field.method"), std::string::npos);
}
