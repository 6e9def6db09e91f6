// linkscape fit through the real binary: the CSV's header and first row,
// equal and independent links, the chart, a task no design meets, and the
// bad inputs that exit with 2. Coarse sampling keeps it quick; the search's
// accuracy is tested in tests/core/test_fit.cpp, the defaults' in
// docs/task-volumes.md.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <tuple>

#include "tests/gui/cli/cli_runner.h"

namespace {

const fs::path kOut = fs::temp_directory_path() / "linkscape_cli_fit";
const std::string kCoarse = " --resolution 16 --refinements 1 --places 1 --task-resolution 6 --tolerance 0.01 -q";

std::string out(const std::string& name) {
  fs::create_directories(kOut);
  fs::remove(kOut / name);
  return (kOut / name).string();
}

std::vector<std::map<std::string, std::string>> rows_of(const std::string& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return parse_cells(text.str());
}

}  // namespace

TEST(CliFit, EqualLinksFirstRowIsTheSmallestMeetingDesign) {
  const std::string csv = out("equal.csv"), chart = out("equal.svg");
  const CommandResult r = run_linkscape("fit --mechanism parallel-12r --task sphere:diameter=15 --criterion 'cond<3' "
                                        "--equal L1,L2 --output " + csv + " --chart " + chart + kCoarse);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("smallest design meeting it: L1 = "), std::string::npos) << r.out;
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("L1,L2,cx,cy,cz,size,meets,samples,failing,inscribed_diameter,fraction,ratio,", 0), 0u)
      << header;
  const auto rows = rows_of(csv);
  ASSERT_GT(rows.size(), 5u);
  EXPECT_EQ(rows[0].at("meets"), "1");
  const double smallest = std::stod(rows[0].at("size"));
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("L1"), row.at("L2"));
    // One verdict: meets exactly where no sample fails.
    EXPECT_EQ(row.at("meets"), row.at("failing") == "0" ? "1" : "0") << row.at("size");
    if (row.at("meets") == "1") {
      EXPECT_GE(std::stod(row.at("size")), smallest - 0.2);  // the answer is rounded up to 0.1 on each link
    }
  }
  EXPECT_TRUE(fs::exists(chart));
}

// The five-bar with its home fixed at (0, 17) cm (the shipped file's home
// follows its links): the designs too short to reach it cannot be built.
// They are counted, named, left out of the CSV and the chart (which had
// crashed reading their missing criteria).
TEST(CliFit, DesignsThatCannotBeBuiltAreCountedAndLeftOutOfTheChart) {
  std::ifstream in(std::string(LINKSCAPE_TEST_ASSETS) + "/mechanisms/five-bar.json");
  std::stringstream text;
  text << in.rdbuf();
  std::string five_bar = text.str();
  const std::string home = R"json("y": "sqrt(max(a^2 + b^2 - d^2 / 4, 0))")json";
  ASSERT_NE(five_bar.find(home), std::string::npos);
  five_bar.replace(five_bar.find(home), home.size(), R"("y": 17)");
  const std::string fixed = out("five-bar-fixed-home.json");
  std::ofstream(fixed) << five_bar;
  const std::string csv = out("unbuilt.csv"), chart = out("unbuilt.png");
  const CommandResult r = run_linkscape("fit -m " + fixed + " --task sphere:diameter=5 --criterion 'cond<3' --output " +
                                        csv + " --chart " + chart + kCoarse);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("could not be built"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the first not built: description.legs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("does not reach its anchor at home"), std::string::npos) << r.out;
  EXPECT_FALSE(rows_of(csv).empty());
  EXPECT_GT(fs::file_size(chart), 1000u);
  for (const auto& entry : fs::directory_iterator(kOut))  // no temporary left
    EXPECT_EQ(entry.path().filename().string().find(".unbuilt.tmp"), std::string::npos) << entry.path();
}

TEST(CliFit, WithoutEqualTheLinksVaryIndependently) {
  const std::string csv = out("free.csv");
  const CommandResult r = run_linkscape("fit --task sphere:diameter=15 --criterion 'cond<3' --output " + csv + kCoarse);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  int different = 0;
  for (const auto& row : rows_of(csv)) different += row.at("L1") != row.at("L2");
  EXPECT_GT(different, 10);
}

TEST(CliFit, ATaskNoDesignMeetsIsAResult) {
  const CommandResult r = run_linkscape("fit --task sphere:diameter=15 --criterion 'cond<3' --equal L1,L2 "
                                        "--bounds L1=2:5" + kCoarse);
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("no design in the bounds meets it; closest: L1 = 5"), std::string::npos) << r.out;
}

// With the centre fixed a larger design need not hold more (the task sits
// ever nearer the base): the 15 cm sphere about (0.7, -13, -8.4) cm is held
// at L1 = L2 = 12.4 (verify proves it) but not at the upper bound, so
// neither search may say that no design in the bounds does.
TEST(CliFit, AFixedCentreIsNotSaidToFailEverywhere) {
  const std::string task = "fit --task sphere:diameter=15,centre=0.7,-13,-8.4 --criterion 'cond<3' --equal L1,L2";
  const CommandResult sampled = run_linkscape(task + kCoarse);
  EXPECT_EQ(sampled.exit_code, 0) << sampled.out;
  EXPECT_EQ(sampled.out.find("no design in the bounds meets it"), std::string::npos) << sampled.out;
  EXPECT_NE(sampled.out.find("no design evaluated meets it (with the centre fixed"), std::string::npos) << sampled.out;
  const CommandResult certified = run_linkscape(task + " --certify --bracket 0.5 -q");
  EXPECT_NE(certified.out.find("note: the task's centre is fixed"), std::string::npos) << certified.out;
  const CommandResult proved = run_linkscape("verify --task sphere:diameter=15,centre=0.7,-13,-8.4 --criterion 'cond<3' "
                                             "--param L1=12.4 --param L2=12.4");
  EXPECT_EQ(proved.exit_code, 0) << proved.out;
}

TEST(CliFit, BadInputsExitWithTwoAndWriteNothing) {
  const std::string csv = out("never.csv");
  for (const auto& [args, expected] : std::vector<std::pair<std::string, std::string>>{
           {"--task sphere:diameter=0 --criterion 'cond<3'", "is empty"},
           {"--task box:size=10,0,5 --criterion 'cond<3'", "is empty"},
           {"--task sphere:diameter=15 --criterion 'cond<0.5'", "no pose meets it"},
           {"--task sphere:diameter=15 --criterion 'force_iso<2'", "bounded from below"},
           {"--task sphere:diameter=15 --criterion 'stiffness>2'", "unknown measure 'stiffness'"},
           {"--task sphere:diameter=15 --criterion 'cond<3' --equal L1,L2 --bounds L1=-5:-1", "bounds exclude every design"},
           {"--task sphere:diameter=15 --criterion 'cond<3' --bounds L1=9:3", "lo <= hi"},
           {"--task sphere:diameter=15 --criterion 'cond<3' --free L3", "unknown parameter 'L3'"},
           {"--task cone:diameter=15", "unknown shape"},
           {"--task sphere:diameter=15 --chart pareto.gif", "--chart must end in"},
           {"--task sphere:diameter=15 --criterion 'cond<3' --size 0", "positive and finite"},
           {"--task sphere:diameter=15 --criterion 'cond<3' --size 200", "no design within the bounds has size L1 + L2 = 200"},
           {"--task sphere:diameter=15 --criterion 'cond<3' --size 30 --bounds L1=20:25 --bounds L2=20:25", "they span 40 to 50"},
           {"--task sphere:diameter=15 --criterion 'cond<3' --size thirty", "--size"},
       }) {
    const CommandResult r = run_linkscape("fit " + args + " --output " + csv + kCoarse);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(expected), std::string::npos) << args << "\n" << r.out;
    EXPECT_FALSE(fs::exists(csv)) << args;
  }
}

// --size: every design evaluated has the size asked for, the first row has
// the largest ratio of them and the report says which it is.
TEST(CliFit, AtASizeTheFirstRowHasTheLargestMargin) {
  const std::string csv = out("margin.csv"), chart = out("margin.pdf");
  const CommandResult r = run_linkscape("fit --task sphere:diameter=15 --criterion 'cond<3' --size 30 --output " + csv +
                                        " --chart " + chart + kCoarse);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("held at 30 cm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("largest ratio at that size: L1 = "), std::string::npos) << r.out;
  const auto rows = rows_of(csv);
  ASSERT_GT(rows.size(), 5u);
  const double best = std::stod(rows[0].at("ratio"));
  EXPECT_GE(best, 1.0);
  for (const auto& row : rows) {
    EXPECT_NEAR(std::stod(row.at("size")), 30, 1e-9);
    EXPECT_LE(std::stod(row.at("ratio")), best);
  }
  EXPECT_TRUE(fs::exists(chart));
}

TEST(CliFit, AtASizeTooSmallTheClosestIsReported) {
  const CommandResult r = run_linkscape("fit --task sphere:diameter=15 --criterion 'cond<3' --size 12" + kCoarse);
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("no design in the bounds meets it; closest: L1 = "), std::string::npos) << r.out;
}

// A box of any aspect ratio is sized: a needle 1e8 times longer than thick
// fits where a shorter one would (the default sampling, where such boxes
// crashed the search).
TEST(CliFit, ABoxOfAnyAspectRatioIsSized) {
  const CommandResult r = run_linkscape("fit --task box:size=10,1e-7,1e-7 --equal L1,L2 --tolerance 0.01 -q");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("smallest design meeting it: L1 = "), std::string::npos) << r.out;
}

// --size holds a described device's size (its description's expression),
// as it does a compiled device's: every design evaluated has it.
TEST(CliFit, DescribedDevicesAreHeldAtTheSizeAsked) {
  for (const auto& [device, free] : std::vector<std::pair<std::string, std::string>>{
           {"five-bar", "a,b"}, {"delta-described", "La,Lb"}, {"stewart", "rb,rp"}}) {
    const std::string csv = out(device + "_size.csv");
    // Coarse: the described solver is slow, and this checks the sizes only.
    const CommandResult r = run_linkscape("fit -m " + device + " --free " + free + " --task sphere:diameter=4 --size 30 "
                                          "--output " + csv + " --resolution 8 --refinements 0 --places 1 "
                                          "--task-resolution 2 --tolerance 0.1 -q");
    ASSERT_EQ(r.exit_code, 0) << device << "\n" << r.out;
    EXPECT_NE(r.out.find("held at 30 cm"), std::string::npos) << r.out;
    const auto rows = rows_of(csv);
    ASSERT_GT(rows.size(), 3u) << device;
    for (const auto& row : rows) EXPECT_NEAR(std::stod(row.at("size")), 30, 1e-9) << device;
  }
}

// A sphere task on the planar five-bar is a disc in its plane: a 10 cm disc
// needs a five-bar of links about 10 cm long end to end (an invented z slab
// made it 50 and unreachable; a home fixed at (0, 17) cm, 17), centred in
// the plane.
TEST(CliFit, APlanarDeviceIsSizedByTheDiscInItsPlane) {
  const std::string csv = out("five_bar_disc.csv");
  const CommandResult r =
      run_linkscape("fit -m five-bar --free a,b --task sphere:diameter=10 --output " + csv + kCoarse);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("smallest design meeting it: a = "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the largest disc the placement found there is "), std::string::npos) << r.out;
  const auto rows = rows_of(csv);
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0].at("meets"), "1");
  EXPECT_GT(std::stod(rows[0].at("size")), 10) << r.out;
  EXPECT_LT(std::stod(rows[0].at("size")), 13) << r.out;
  EXPECT_EQ(rows[0].at("cz"), "0");
}

// Options outside their stated ranges exit with 2 before any work.
TEST(CliFit, OptionsOutsideTheirRangesExitWithTwo) {
  const std::string csv = out("never_ranges.csv");
  const std::string base = "fit --task sphere:diameter=15 --criterion 'cond<3' -q --output " + csv;
  for (const auto& [args, expected] : std::vector<std::pair<std::string, std::string>>{
           {" --equal L1,L2 --bounds L1=1:1e31", "must lie within -1e+06 to 1e+06"},
           {" --bounds L1=5:30 --bounds L1=6:20", "--bounds given twice for L1"},
           {" --equal L1,L2 --bounds L1=5:30 --bounds L2=6:20", "--bounds given twice for L1=L2"},
           {" --task-resolution 1000", "--task-resolution 2 to 256"},
           {" --refinements 50", "--refinements 0 to 10"},
       }) {
    const CommandResult r = run_linkscape(base + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(expected), std::string::npos) << args << "\n" << r.out;
    EXPECT_FALSE(fs::exists(csv)) << args;
  }
  // A planar device's task lies in its plane.
  const CommandResult off = run_linkscape("fit -m five-bar --task sphere:diameter=4,centre=0,17,3 -q --output " + csv);
  EXPECT_EQ(off.exit_code, 2) << off.out;
  EXPECT_NE(off.out.find("off five-bar's plane z = 0"), std::string::npos) << off.out;
  EXPECT_FALSE(fs::exists(csv));
  const CommandResult help = run_linkscape("fit --help", "COLUMNS=250");  // unwrapped
  EXPECT_NE(help.out.find("0 to 10"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("2 to 256"), std::string::npos) << help.out;
}

// An output that cannot be written stops fit and design before their
// searches: no report, nothing evaluated and no other output written (they
// used to write the ones before it, after the work); exit 1 for a missing
// folder, 2 for a path that is a folder.
TEST(CliFit, OutputsThatCannotBeWrittenStopBeforeAnyWork) {
  const std::string missing = (kOut / "no_such_folder" / "x.svg").string();
  fs::remove_all(kOut / "no_such_folder");
  const std::string folder = out("a_folder.svg");
  fs::create_directories(folder);
  const std::string csv = out("first.csv");
  for (const auto& [args, code, expected] : std::vector<std::tuple<std::string, int, std::string>>{
           {"fit --task sphere:diameter=15 --output " + csv + " --chart " + missing + kCoarse, 1,
            "no_such_folder' does not exist"},
           {"fit --task sphere:diameter=15 --output " + csv + " --chart " + folder + kCoarse, 2, "it is a folder"},
           {"design -m pathos2 --quick -q --table " + csv + " --chart " + missing, 1, "no_such_folder' does not exist"},
           {"design -m pathos2 --quick -q --table " + csv + " --chart " + folder, 2, "it is a folder"},
       }) {
    const CommandResult r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, code) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(expected), std::string::npos) << args << "\n" << r.out;
    EXPECT_EQ(r.out.find("evaluated"), std::string::npos) << args << "\n" << r.out;
    EXPECT_FALSE(fs::exists(csv)) << args;
  }
  fs::remove(folder);
}

// Seed 001's question at the default sampling: the report's verdict, the
// CSV's meets and the numbers printed agree, no line says 100 % beside a
// failing sample, and the design and centre printed, given back as a fixed
// task, meet it at the same samples.
TEST(CliFit, TheVerdictPrintedHoldsForTheDesignAndCentrePrinted) {
  const std::string csv = out("verdict.csv");
  const CommandResult r = run_linkscape("fit --mechanism parallel-12r --task sphere:diameter=15 --criterion 'cond<3' "
                                        "--equal L1,L2 -q --output " + csv);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto line_after = [&](const std::string& key) {
    const auto at = r.out.find(key);
    return at == std::string::npos ? std::string() : r.out.substr(at + key.size(), r.out.find('\n', at) - at - key.size());
  };
  EXPECT_EQ(line_after("  verdict: ").rfind("meets every criterion at all ", 0), 0u) << r.out;
  EXPECT_EQ(r.out.find("fails at"), std::string::npos) << r.out;
  const std::string design = line_after("smallest design meeting it: L1 = ");
  const std::string L = design.substr(0, design.find(','));
  const std::string centre = line_after("  centre (");
  std::string xyz = centre.substr(0, centre.find(')'));
  xyz.erase(std::remove(xyz.begin(), xyz.end(), ' '), xyz.end());
  const auto rows = rows_of(csv);
  EXPECT_EQ(rows[0].at("meets"), "1");
  EXPECT_EQ(rows[0].at("failing"), "0");
  EXPECT_EQ(rows[0].at("L1"), L);
  const CommandResult again = run_linkscape("fit --mechanism parallel-12r --task sphere:diameter=15,centre=" + xyz +
                                            " --criterion 'cond<3' --equal L1,L2 --bounds L1=" + L + ":" + L + " -q");
  ASSERT_EQ(again.exit_code, 0) << again.out;
  EXPECT_NE(again.out.find("verdict: meets every criterion at all " + rows[0].at("samples") + " samples"),
            std::string::npos) << again.out;
}

// A failing design's report counts its samples and never rounds up to 100 %.
TEST(CliFit, AFailingTaskIsCountedNotRoundedUp) {
  const CommandResult r = run_linkscape("fit --mechanism parallel-12r --task sphere:diameter=15,centre=0,15,15 "
                                        "--criterion 'cond<3' --equal L1,L2 --bounds L1=15:15 -q");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("no design in the bounds meets it"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("verdict: fails: "), std::string::npos) << r.out;
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);)
    if (line.find("(100 %)") != std::string::npos) {
      EXPECT_EQ(line.find("cond<3"), std::string::npos) << "cond<3 fails somewhere: " << line;
    }
}

// --centre-region keeps the centre in it; the report gives it from the home point.
TEST(CliFit, TheCentreStaysInTheRegionGiven) {
  const CommandResult r = run_linkscape("fit --mechanism parallel-12r --task sphere:diameter=10 --criterion 'cond<3' "
                                        "--equal L1,L2 --bounds L1=15:15 --centre-region box:min=-5,-30,-30,max=5,0,0" +
                                        kCoarse);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("centre free within box:min=-5,-30,-30,max=5,0,0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("from the home point (0, 15, 15) cm"), std::string::npos) << r.out;
  const auto at = r.out.find("  centre (");
  ASSERT_NE(at, std::string::npos) << r.out;
  std::istringstream centre(r.out.substr(at + 10));
  double x, y;
  char comma;
  centre >> x >> comma >> y;
  EXPECT_LE(y, 0) << r.out;
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {"--task sphere:diameter=10,centre=0,15,15 --centre-region box:min=0,0,0,max=1,1,1", "give one or the other"},
           {"--task sphere:diameter=10 --centre-region box:min=0,0,0", "give min and max"}}) {
    const CommandResult bad = run_linkscape("fit --mechanism parallel-12r " + args + " -q");
    EXPECT_EQ(bad.exit_code, 2) << args;
    EXPECT_NE(bad.out.find(message), std::string::npos) << bad.out;
  }
}

// "What torque is needed" is a fit: the smallest continuous torque, named in
// the report and the CSV; at that torque, evaluated on its own, the task meets.
TEST(CliFit, TheTorqueADesignNeedsIsAFit) {
  const std::string csv = out("torque.csv");
  const CommandResult r = run_linkscape("fit --task sphere:diameter=6,centre=0,15,15 --criterion 'force_iso>1' "
                                        "--free continuous_torque_Nm --bounds continuous_torque_Nm=0.01:0.3 -q -o " + csv);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("smallest ratings meeting it: L1 = 15, L2 = 15, continuous_torque_Nm = "), std::string::npos)
      << r.out;
  const auto rows = rows_of(csv);
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0].at("meets"), "1");
  const std::string tau = rows[0].at("continuous_torque_Nm");
  const CommandResult at = run_linkscape("fit --task sphere:diameter=6,centre=0,15,15 --criterion 'force_iso>1' "
                                         "--free continuous_torque_Nm --bounds continuous_torque_Nm=" + tau + ":" + tau +
                                         " -q");
  EXPECT_NE(at.out.find("verdict: meets every criterion"), std::string::npos) << at.out;
  const CommandResult mixed = run_linkscape("fit --task sphere:diameter=6 --free L1,continuous_torque_Nm "
                                            "--bounds continuous_torque_Nm=0.01:0.3 -q");
  EXPECT_EQ(mixed.exit_code, 2) << mixed.out;
}
