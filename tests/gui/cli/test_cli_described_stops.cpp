// The Falcon's stops through the real binary: --joint-limits and
// --interference switch each off for field, slice, mesh and eval (the
// samples a stop held back are then reachable); joint_margin and clearance are criteria of fit and sweep; verify
// refuses them; and the bad inputs exit with 2 naming what is wrong.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "cli_runner.h"

using namespace cli_runner;

namespace {

const fs::path kDir = fs::temp_directory_path() / "linkscape_cli_stops";

std::string path(const std::string& name) {
  fs::create_directories(kDir);
  fs::remove(kDir / name);
  return (kDir / name).string();
}

std::string text_of(const std::string& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

constexpr int kOutOfLimits = 4;  // the status code files store (core/status.h)

}  // namespace

namespace {

// The Falcon with shins of 16 mm radius (the file's: 4), whose legs collide
// over part of the box, as a preset file.
std::string thick_falcon() {
  std::string text = text_of(std::string(LINKSCAPE_SOURCE_DIR) + "/assets/mechanisms/falcon.json");
  const std::string shin = "\"radius\": 4, \"link\": \"shin\"";
  const auto at = text.find(shin);
  if (at == std::string::npos) return "";
  text.replace(at, shin.size(), "\"radius\": 16, \"link\": \"shin\"");
  return temp_file("falcon-thick.json", text).string();
}

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

}  // namespace

// The thick-shinned Falcon's field, then with a stop switched off (the
// links with the joint limits already off: their collisions lie beyond the
// joints' stops too): the stop's column is gone, and the samples it held
// back are reachable; eval --ik agrees point by point (the reasons' words
// are tested in tests/core/test_task_stops.cpp, StopChecks.*).
TEST(CliDescribedStops, ASwitchedOffStopHoldsNoSampleBack) {
  const std::string falcon = thick_falcon();
  ASSERT_FALSE(falcon.empty());
  struct Case {
    std::string before, after;
    const char* column;  // the stop's field
  };
  for (const Case& c : {Case{"", "--joint-limits off", "joint_margin_deg"},
                        Case{"--joint-limits off", "--joint-limits off --interference off", "clearance_mm"}}) {
    std::vector<std::map<std::string, std::string>> field[2];
    for (int k = 0; k < 2; ++k) {
      const std::string file = path(std::string(c.column) + std::to_string(k) + ".csv");
      const CommandResult r = run_linkscape("field -m " + falcon + " -q --resolution 10 " + (k ? c.after : c.before) +
                                            " -o " + file);
      ASSERT_EQ(r.exit_code, 0) << r.out;
      field[k] = parse_cells(text_of(file));
    }
    ASSERT_EQ(field[0].size(), 1000u);
    ASSERT_EQ(field[1].size(), 1000u);
    EXPECT_EQ(field[0][0].count(c.column), 1u) << c.before;
    EXPECT_EQ(field[1][0].count(c.column), 0u) << c.after << " keeps its field";
    std::string freed = "x,y,z\n", out = "x,y,z\n";
    std::size_t n_freed = 0, n_out = 0;
    for (std::size_t s = 0; s < field[0].size(); ++s) {
      const bool was_out = std::stoi(field[0][s].at("status")) == kOutOfLimits;
      const bool is_out = std::stoi(field[1][s].at("status")) == kOutOfLimits;
      const std::string point = field[0][s].at("x_mm") + "," + field[0][s].at("y_mm") + "," + field[0][s].at("z_mm") + "\n";
      if (is_out) EXPECT_TRUE(was_out) << "a switch off adds no stop";
      if (was_out && !is_out) freed += point, ++n_freed;
      if (is_out) out += point, ++n_out;
    }
    ASSERT_GT(n_freed, 0u) << c.after;
    const std::string freed_file = temp_file(std::string("freed_") + c.column + ".csv", freed).string();
    const std::string out_file = temp_file(std::string("out_") + c.column + ".csv", out).string();
    const CommandResult before = run_linkscape("eval -m " + falcon + " " + c.before + " --ik " + freed_file);
    const CommandResult after = run_linkscape("eval -m " + falcon + " " + c.after + " --ik " + freed_file);
    const CommandResult still = run_linkscape("eval -m " + falcon + " " + c.after + " --ik " + out_file);
    for (const CommandResult* r : {&before, &after, &still}) ASSERT_EQ(r->exit_code, 0) << r->out;
    EXPECT_EQ(count(before.out, ",out-of-limits,"), n_freed) << before.out.substr(0, 2000);
    EXPECT_EQ(count(after.out, ",ok,"), n_freed) << after.out.substr(0, 2000);
    EXPECT_EQ(count(still.out, ",out-of-limits,"), n_out) << still.out.substr(0, 2000);
    std::printf("%s: %zu samples freed, %zu still out of limits for another reason\n", c.after.c_str(), n_freed, n_out);
  }
}

// slice and mesh take the switches too: a slice of a switched-off stop's
// field is refused listing the fields left, and the reach mesh grows; a
// mesh's surface may bound a margin to the stops.
TEST(CliDescribedStops, SliceAndMeshTakeTheSwitches) {
  const CommandResult slice = run_linkscape("slice -m falcon -q --joint-limits off --field joint_margin -o " +
                                            path("never.png"), "QT_QPA_PLATFORM=offscreen");
  EXPECT_EQ(slice.exit_code, 2) << slice.out;
  EXPECT_TRUE(contains(slice.out, "clearance")) << slice.out;
  double volume[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const CommandResult mesh = run_linkscape(std::string("mesh -m falcon --resolution 24 ") +
                                             (k ? "--joint-limits off --interference off " : "") + "-o " +
                                             path("reach" + std::to_string(k) + ".stl"));
    ASSERT_EQ(mesh.exit_code, 0) << mesh.out;
    const auto at = mesh.out.find("\nvolume ");
    ASSERT_NE(at, std::string::npos) << mesh.out;
    volume[k] = std::stod(mesh.out.substr(at + 8));
  }
  EXPECT_GT(volume[1], 1.02 * volume[0]) << "the stops bound the Falcon's reach";
  // The region keeping 10 deg from every joint stop lies inside the reach.
  const CommandResult margin = run_linkscape("mesh -m falcon --resolution 24 --surface 'joint_margin>10' -o " +
                                             path("margin.stl"));
  ASSERT_EQ(margin.exit_code, 0) << margin.out;
  const double inside = std::stod(margin.out.substr(margin.out.find("\nvolume ") + 8));
  EXPECT_GT(inside, 0.2 * volume[0]);
  EXPECT_LT(inside, 0.98 * volume[0]);
  const CommandResult wrong = run_linkscape("mesh -m falcon --surface 'joint_margin<10' -o " + path("never.stl"));
  EXPECT_EQ(wrong.exit_code, 2) << wrong.out;
  EXPECT_TRUE(contains(wrong.out, "joint_margin is bounded from below")) << wrong.out;
}

// fit and sweep take joint_margin and clearance as criteria: the report
// and the CSV carry them, and a design meets them exactly where its worst
// values clear the bounds. The Falcon's worst joint margin over this task
// rises from about 25.5 deg at b = 80 mm to 31.6 at 122 and falls to 23.7 at
// 130, so a bound of 26 deg is met by some designs and not others.
TEST(CliDescribedStops, FitAndSweepTakeTheStopsAsCriteria) {
  const std::string task = " --task sphere:diameter=30,centre=0,0,120 --resolution 16 --refinements 1 --places 1 "
                           "--task-resolution 6 -q";
  const std::string csv = path("fit.csv");
  const CommandResult fit = run_linkscape("fit -m falcon --free b --bounds b=80:130 --tolerance 0.05 --criterion "
                                          "'joint_margin>26, clearance>2'" + task + " -o " + csv);
  ASSERT_EQ(fit.exit_code, 0) << fit.out;
  EXPECT_TRUE(contains(fit.out, "joint_margin>26: worst ")) << fit.out;
  EXPECT_TRUE(contains(fit.out, "clearance>2: worst ")) << fit.out;
  // Each margin in its unit; with every stop on, no "stops off" line.
  EXPECT_TRUE(contains(fit.out, " deg, ") && contains(fit.out, " mm, ")) << fit.out;
  EXPECT_FALSE(contains(fit.out, "stops off")) << fit.out;
  const CommandResult without = run_linkscape("fit -m falcon --free b --bounds b=80:130 --tolerance 0.05 "
                                              "--interference off --criterion 'joint_margin>26'" + task + " -o " + path("off.csv"));
  ASSERT_EQ(without.exit_code, 0) << without.out;
  EXPECT_TRUE(contains(without.out, "stops off: link interference (the device states them")) << without.out;
  const auto rows = parse_cells(text_of(csv));
  ASSERT_GT(rows.size(), 2u);
  int met = 0;
  for (const auto& row : rows) {
    const bool meets = row.at("meets") == "1";
    const double joint = std::stod(row.at("worst_joint_margin")), gap = std::stod(row.at("worst_clearance"));
    EXPECT_EQ(meets, joint > 26 && gap > 2 && row.at("failing_reach") == "0") << row.at("b");
    met += meets;
  }
  EXPECT_GT(met, 0);
  EXPECT_LT(met, int(rows.size()));
  // The answer (first) meets them; the bound keeps it off the lower bound
  // of b, where a design fails it.
  EXPECT_EQ(rows.front().at("meets"), "1");
  EXPECT_GT(std::stod(rows.front().at("b")), 80);
  EXPECT_TRUE(contains(fit.out, "smallest design meeting it: a = 60, b = 8") ||
              contains(fit.out, "smallest design meeting it: a = 60, b = 9"))
      << fit.out;
  const std::string table = path("sweep.csv");
  const CommandResult sweep = run_linkscape("sweep -m falcon --free b --bounds b=80:130 --grid 3 --criterion "
                                            "'joint_margin>26'" + task + " -o " + table);
  ASSERT_EQ(sweep.exit_code, 0) << sweep.out;
  const auto swept = parse_cells(text_of(table));
  ASSERT_EQ(swept.size(), 3u);
  for (const auto& row : swept)
    EXPECT_EQ(row.at("meets") == "1", std::stod(row.at("worst_joint_margin")) > 26) << row.at("b");
}

// verify has no enclosure of a stop's margin; a device without the field,
// or a switch for a stop the device does not state, is an input error.
TEST(CliDescribedStops, RefusalsNameWhatIsWrong) {
  const CommandResult verify =
      run_linkscape("verify -m falcon --task sphere:diameter=5,centre=0,0,120 --criterion 'clearance>0.5'");
  EXPECT_EQ(verify.exit_code, 2) << verify.out;
  EXPECT_TRUE(contains(verify.out, "criterion 'clearance>0.5' cannot be certified")) << verify.out;
  const CommandResult unknown =
      run_linkscape("fit -m delta-described --free La --task sphere:diameter=2 --criterion 'clearance>1' -q");
  EXPECT_EQ(unknown.exit_code, 2) << unknown.out;
  EXPECT_TRUE(contains(unknown.out, "unknown measure 'clearance' for delta-described (known: reach, cond, joint_margin"))
      << unknown.out;
  const CommandResult stated = run_linkscape("field -m delta-described --interference off -q --resolution 4 -o " +
                                             path("never.csv"));
  EXPECT_EQ(stated.exit_code, 2) << stated.out;
  EXPECT_TRUE(contains(stated.out, "field: --interference off: delta-described states no link radii")) << stated.out;
  const CommandResult compiled = run_linkscape("eval -m delta --interference on --ik -", "", "</dev/null");
  EXPECT_EQ(compiled.exit_code, 2) << compiled.out;
  EXPECT_TRUE(contains(compiled.out, "eval: --interference on: delta states no link radii")) << compiled.out;
  const CommandResult word = run_linkscape("field -m falcon --joint-limits no -q --resolution 4 -o " + path("never.csv"));
  EXPECT_EQ(word.exit_code, 2) << word.out;
  EXPECT_TRUE(contains(word.out, "--joint-limits")) << word.out;
  EXPECT_FALSE(fs::exists(kDir / "never.csv"));
  const CommandResult wrong_side = run_linkscape("fit -m falcon --free b --task sphere:diameter=2 --criterion "
                                                 "'joint_margin<5' -q");
  EXPECT_EQ(wrong_side.exit_code, 2) << wrong_side.out;
  EXPECT_TRUE(contains(wrong_side.out, "joint_margin is bounded from below (joint_margin>VALUE)")) << wrong_side.out;
}
