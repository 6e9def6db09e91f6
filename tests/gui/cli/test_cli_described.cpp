// Described devices (docs/described-mechanisms.md) through the real binary:
// every headless command works with one, and a malformed description is
// refused with exit code 2 and a message naming the place in the file.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "cli_runner.h"

namespace {

using nlohmann::json;
using cli_runner::run_linkscape;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

json shipped(const std::string& name) {
  std::ifstream in(std::string(LINKSCAPE_TEST_ASSETS) + "/mechanisms/" + name + ".json");
  return json::parse(in);
}

// Writes the described Delta after `edit` and runs `eval --ik` on its home.
cli_runner::CommandResult eval_broken(const std::string& file, const std::function<void(json&)>& edit) {
  json doc = shipped("delta-described");
  edit(doc);
  const fs::path preset = cli_runner::temp_file(file, doc.dump(2));
  const fs::path targets = cli_runner::temp_file("described_targets.csv", "x,y,z\n0,0,-16\n");
  return run_linkscape("eval -m " + preset.string() + " --ik " + targets.string());
}

TEST(CliDescribed, MalformedDescriptionsExitTwoNamingThePlace) {
  struct Case {
    const char* file;
    std::function<void(json&)> edit;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"unknown_joint.json", [](json& d) { d["description"]["legs"][0]["chain"][2]["joint"] = "ball"; },
       {"unknown_joint.json", "legs[0] \"1\": chain[2] (joint \"elbow1\")", "unknown joint type 'ball'"}},
      {"non_unit_axis.json", [](json& d) { d["description"]["legs"][0]["chain"][0]["axis"] = {0, 2, 0}; },
       {"non_unit_axis.json", "chain[0] (joint \"q1\").axis", "not a unit vector (norm 2)"}},
      {"no_actuator.json", [](json& d) { d["description"]["legs"][0]["chain"][0].erase("actuated"); },
       {"no_actuator.json", "legs[0] \"1\": chain", "no actuated joint"}},
      {"wrong_dof.json",
       [](json& d) {
         d["description"]["task"] = {"x", "y", "z", "rz"};
         d["description"]["home"]["rz"] = 0;
       },
       {"wrong_dof.json", "4 freedom(s)", "3 actuator(s)"}},
      {"no_reach.json", [](json& d) { d["description"]["home"]["z"] = -40; },
       {"no_reach.json", "does not reach its anchor at home", "misses by"}},
  };
  for (const Case& c : cases) {
    const auto r = eval_broken(c.file, c.edit);
    EXPECT_EQ(r.exit_code, 2) << c.file << ": " << r.out;
    for (const std::string& part : c.expected) EXPECT_TRUE(contains(r.out, part)) << c.file << ": '" << part << "' not in " << r.out;
  }
}

TEST(CliDescribed, EveryHeadlessCommandRunsADescribedDevice) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  const std::string m = "-m delta-described";
  const auto slice = run_linkscape("slice " + m + " --size 48x48 --figure -o " + (dir / "dd.png").string());
  EXPECT_EQ(slice.exit_code, 0) << slice.out;
  EXPECT_GT(fs::file_size(dir / "dd.png"), 1000u);
  const auto field = run_linkscape("field " + m + " --resolution 16 -q -o " + (dir / "dd.vti").string());
  EXPECT_EQ(field.exit_code, 0) << field.out;
  EXPECT_TRUE(fs::exists(dir / "dd.vti"));
  const auto mesh = run_linkscape("mesh " + m + " --resolution 24 -o " + (dir / "dd.stl").string());
  EXPECT_EQ(mesh.exit_code, 0) << mesh.out;
  EXPECT_GT(fs::file_size(dir / "dd.stl"), 1000u);
  // The reachable surface of the described Delta is closed (the mesh report counts boundary edges).
  EXPECT_TRUE(contains(mesh.out, "watertight") || contains(mesh.out, "boundary edges: 0")) << mesh.out;
  const fs::path q = cli_runner::temp_file("described_q.csv", "q1,q2,q3\n0.4,0.5,0.6\n");
  const auto fk = run_linkscape("eval " + m + " --fk " + q.string());
  ASSERT_EQ(fk.exit_code, 0) << fk.out;
  const auto rows = cli_runner::parse_cells(fk.out);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("status"), "ok");
}

// describe names the columns eval reads for the device, which eval's help
// gives only for the compiled devices: the grip is an input of FK too.
TEST(CliDescribed, DescribeNamesTheColumnsEvalReads) {
  const auto r = run_linkscape("describe pathos2-described");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "eval columns: --ik x,y,z (cm), rx,ry,rz (rad), h0 (cm); --fk q1,q2,q3,q4,q5,q6 (rad), "
                              "h0 (cm)\n"))
      << r.out;
}

}  // namespace
