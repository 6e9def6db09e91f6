// The headless commands, run as a user runs them: the real binary, its
// output and its exit code.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <numbers>
#include <sstream>

#include "core/csv.h"
#include "core/mechanisms/parallel12r/parallel12r.h"
#include "tests/core/mechanisms/parallel12r/reference_12r.h"
#include "cli_runner.h"

using linkscape::testing::ConfigurationSampler;
using linkscape::testing::paper_forward;


TEST(Cli, EvalInverseAgreesWithIndependentForwardForEveryMethod) {
  // Targets from random configurations of L1 = 1, L2 = 1.3 plus two points
  // outside the reach; every solution written must reproduce its target
  // through the printed Eqs. 11-13 to 1e-9 relative.
  ConfigurationSampler sample(81, 0.2);
  std::ostringstream csv;
  csv << "x,y,z\n";
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d q = sample();
    const Eigen::Vector3d p = paper_forward(1.0, 1.3, q.x(), q.y(), q.z());
    csv << linkscape::format_number(p.x()) << "," << linkscape::format_number(p.y()) << ","
        << linkscape::format_number(p.z()) << "\n";
  }
  csv << "3,3,3\n0.05,0.1,0.0\n";
  const fs::path input = temp_file("targets.csv", csv.str());
  for (const char* method : {"paper", "planar", "newton", "dls"}) {
    const CommandResult r = run_linkscape("eval --mechanism parallel-12r --param L1=1 --param L2=1.3 --method " +
                      std::string(method) + " --ik " + input.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(r.out.substr(0, r.out.find('\n')),
              "x,y,z,branch,status,alpha,beta,gamma,cond,det,residual,iterations");
    int solved = 0, unreachable = 0;
    // The status column is text, so the rows are split here by hand.
    std::istringstream lines(r.out);
    std::string line;
    std::getline(lines, line);
    while (std::getline(lines, line)) {
      std::vector<std::string> f;
      std::stringstream ss(line);
      std::string field;
      while (std::getline(ss, field, ',')) f.push_back(field);
      f.resize(12);
      if (f[4] == "unreachable") {
        ++unreachable;
        continue;
      }
      if (f[4] != "ok") continue;
      ++solved;
      const Eigen::Vector3d target(std::stod(f[0]), std::stod(f[1]), std::stod(f[2]));
      const Eigen::Vector3d back = paper_forward(1.0, 1.3, std::stod(f[5]), std::stod(f[6]), std::stod(f[7]));
      EXPECT_LT((back - target).norm(), 1e-9 * target.norm()) << method << ": " << line;
    }
    EXPECT_EQ(unreachable, 2) << method;
    // Closed forms find both branches of every target; the iterative methods
    // from their default seeds find at least one for nearly every target.
    const bool closed = std::string(method) == "paper" || std::string(method) == "planar";
    EXPECT_GE(solved, closed ? 2 * n : n * 9 / 10) << method;
  }
}

TEST(Cli, EvalInverseSingleBranch) {
  const fs::path input = temp_file("one.csv", "x,y,z\n0,1,1\n");
  const CommandResult r = run_linkscape("eval --param L1=1 --param L2=1 --branch 1 --ik " + input.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  // One row: branch 1 of the Fig. 5 optimum is (0, 0, pi/2) with c(J) = 1.
  ASSERT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 2) << r.out;
  std::string row = r.out.substr(r.out.find('\n') + 1);
  EXPECT_EQ(row.substr(0, 13), "0,1,1,1,ok,0,") << row;  // a zero cell is 0, never -0
  // The status column is text; put a number in its place to parse the rest.
  const auto ok = row.find("ok");
  std::ostringstream csv;
  csv << "x,y,z,branch,status,alpha,beta,gamma,cond,det,residual,iterations\n"
      << row.substr(0, ok) << '0' << row.substr(ok + 2);
  const linkscape::Table t = parse(csv.str());
  EXPECT_NEAR(t.rows[0][5], 0.0, 1e-15);
  EXPECT_NEAR(t.rows[0][6], 0.0, 1e-15);
  EXPECT_NEAR(t.rows[0][7], std::numbers::pi / 2, 1e-15);
  EXPECT_NEAR(t.rows[0][8], 1.0, 1e-12);
}

TEST(Cli, EvalForwardMatchesEquations) {
  const fs::path input = temp_file("angles.csv", "alpha,beta,gamma\n0,0,1.5707963267948966\n0.3,-0.4,2.1\n");
  const CommandResult r = run_linkscape("eval -m parallel-12r --fk " + input.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto rows = parse_cells(r.out);
  ASSERT_EQ(rows.size(), 2u);
  const auto& row = rows[1];
  EXPECT_EQ(row.at("status"), "ok");
  const Eigen::Vector3d expected = paper_forward(15, 15, 0.3, -0.4, 2.1);
  EXPECT_NEAR(std::stod(row.at("x")), expected.x(), 1e-12);
  EXPECT_NEAR(std::stod(row.at("y")), expected.y(), 1e-12);
  EXPECT_NEAR(std::stod(row.at("z")), expected.z(), 1e-12);
  EXPECT_NEAR(std::stod(rows[0].at("cond")), 1.0, 1e-12);  // the Fig. 5 optimum
  // Beyond alpha's travel (+-90 deg): out of limits, as the Delta says it,
  // with the pose the linkage takes there (the equations' still); at the
  // folded, stretched pose q = 0: singular.
  const fs::path outside = temp_file("angles-outside.csv", "alpha,beta,gamma\n3,1,2\n0,0,0\n");
  const auto limits = parse_cells(run_linkscape("eval -m parallel-12r --fk " + outside.string()).out);
  ASSERT_EQ(limits.size(), 2u);
  EXPECT_EQ(limits[0].at("status"), "out-of-limits");
  const Eigen::Vector3d beyond = paper_forward(15, 15, 3, 1, 2);
  EXPECT_NEAR(std::stod(limits[0].at("x")), beyond.x(), 1e-12);
  EXPECT_NEAR(std::stod(limits[0].at("z")), beyond.z(), 1e-12);
  EXPECT_EQ(limits[1].at("status"), "singular");
}

TEST(Cli, OutputFileIsWrittenWhole) {
  const fs::path input = temp_file("angles2.csv", "alpha,beta,gamma\n0.1,0.2,0.3\n");
  const fs::path output = fs::temp_directory_path() / "linkscape_cli_tests" / "fk_out.csv";
  fs::remove(output);
  const CommandResult r = run_linkscape("eval --fk " + input.string() + " --output " + output.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::ifstream in(output);
  const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(parse_cells(written).size(), 1u) << written;
  for (const auto& e : fs::directory_iterator(output.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

TEST(Cli, BadArgumentsAndInputExitWithTwo) {
  const fs::path good = temp_file("good.csv", "x,y,z\n0,1,1\n");
  const fs::path bad_number = temp_file("bad_number.csv", "x,y,z\n0,one,1\n");
  const fs::path bad_header = temp_file("bad_header.csv", "a,b,c\n0,1,1\n");
  const fs::path bad_preset = temp_file("bad_preset.json", "{ \"mechanism\": \"parallel-12r\", ");
  const std::pair<std::string, std::string> cases[] = {
      {"eval --ik " + good.string() + " --mechanism nonsense", "unknown mechanism"},
      {"eval --ik " + good.string() + " --param L3=2", "unknown parameter"},
      {"eval --ik " + good.string() + " --param L1=-1", "L1 must be a length in"},
      {"eval --ik " + good.string() + " --param L1", "key=value"},
      {"eval --ik /no/such/file.csv", "cannot open"},
      {"eval --ik " + bad_number.string(), ":2:"},
      {"eval --ik " + bad_header.string(), "missing column 'x'"},
      {"eval --ik " + good.string() + " --method magic", "unknown IK method"},
      {"eval --ik " + good.string() + " --branch 3", "--branch"},
      {"eval --ik " + good.string() + " --fk " + good.string(), "excludes"},
      {"eval", "exactly one of"},
      {"eval --ik " + good.string() + " --mechanism " + bad_preset.string(), bad_preset.string()},
      {"eval --ik " + good.string() + " --seed 1,2", "--seed"},
      {"frobnicate", ""},
  };
  for (const auto& [args, message] : cases) {
    const CommandResult r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  }
}

TEST(Cli, HelpExplainsEveryOption) {
  const CommandResult top = run_linkscape("--help");
  EXPECT_EQ(top.exit_code, 0);
  for (const char* word : {"--mechanism", "--param", "--screenshot", "eval"})
    EXPECT_NE(top.out.find(word), std::string::npos) << word;
  const CommandResult eval = run_linkscape("eval --help");
  EXPECT_EQ(eval.exit_code, 0);
  for (const char* word : {"--ik", "--fk", "--method", "--branch", "--seed", "--output", "paper", "dls"})
    EXPECT_NE(eval.out.find(word), std::string::npos) << word;
}

TEST(Cli, ScreenshotShowsTheLinkage) {
  SKIP_WITHOUT_WINDOW();
  if (!std::getenv("DISPLAY")) GTEST_SKIP() << "needs an X server (ctest runs this under tests/with-xvfb.sh)";
  const fs::path png = fs::temp_directory_path() / "linkscape_cli_tests" / "window.png";
  fs::remove(png);
  const CommandResult r = run_linkscape("--screenshot " + png.string() + " --size 1000x700");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 20000u);  // a blank window compresses to a few KiB
}

TEST(Cli, WindowWithoutDisplaySaysSoAndShowsHeadlessCommands) {
  SKIP_WITHOUT_WINDOW();
  const CommandResult r = run_linkscape("", "env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("no display"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("linkscape eval"), std::string::npos) << r.out;
}

// Every command registers itself (gui/cli/command.h); the help lists them in
// their order, and the footer gives each its example line.
TEST(Cli, HelpListsEveryCommandInItsOrderWithAnExample) {
  const CommandResult r = run_linkscape("--help", "COLUMNS=120 QT_QPA_PLATFORM=offscreen");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const std::size_t listed = r.out.find("Subcommands:");
  ASSERT_NE(listed, std::string::npos) << r.out;
  std::size_t at = listed;
  for (const char* command : {"eval", "slice", "field", "mesh", "fit", "sweep", "design", "bench"}) {
    const std::size_t next = r.out.find(std::string("\n  ") + command + " ", at);
    ASSERT_NE(next, std::string::npos) << command << " after position " << at << ":\n" << r.out;
    at = next + 1;
    // The example: its command line on a line of its own, what it does indented below.
    const std::size_t example = r.out.find(std::string("\n  linkscape ") + command, at);
    ASSERT_NE(example, std::string::npos) << command;
    const std::size_t end = r.out.find('\n', example + 1);
    EXPECT_EQ(r.out.compare(end, 7, "\n      "), 0) << command << ": no description below its example";
  }
}

TEST(Cli, ABuildWithoutTheWindowSaysSoAndRunsEveryCommand) {
  if (kWindowBuilt) GTEST_SKIP() << "this build has the window (the test is for -DLINKSCAPE_WINDOW=OFF)";
  const CommandResult r = run_linkscape("", "QT_QPA_PLATFORM=offscreen");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("this build has no window"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("linkscape eval"), std::string::npos) << r.out;
  const CommandResult fk = run_shell("printf 'alpha,beta,gamma\\n0.1,0.2,0.3\\n' | " + std::string(LINKSCAPE_BINARY) +
                                     " eval -m parallel-12r --fk - 2>&1");
  EXPECT_EQ(fk.exit_code, 0) << fk.out;
  EXPECT_EQ(parse(fk.out).rows.size(), 1u) << fk.out;
}

// ---- field commands -----------------------------------------------------------

namespace {

const fs::path kOut = fs::temp_directory_path() / "linkscape_cli_tests";

// Width and height from a PNG's IHDR chunk.
std::pair<int, int> png_size(const fs::path& png) {
  std::ifstream in(png, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), 24);
  auto be32 = [&](int o) { return (h[o] << 24) | (h[o + 1] << 16) | (h[o + 2] << 8) | h[o + 3]; };
  return {be32(16), be32(20)};
}

const std::string kNoDisplay = "env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM";

}  // namespace

TEST(CliSlice, WritesPngAndFiguresWithoutADisplay) {
  fs::create_directories(kOut);
  const fs::path png = kOut / "slice.png";
  fs::remove(png);
  CommandResult r = run_linkscape("slice --param L1=1 --param L2=1 --plane x=0.25 --size 120x80 -q --output " +
                                      png.string(), kNoDisplay);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(png_size(png), std::make_pair(120, 80));
  for (const char* ext : {".png", ".svg", ".pdf"}) {
    const fs::path fig = kOut / (std::string("figure") + ext);
    fs::remove(fig);
    r = run_linkscape("slice --param L1=1 --param L2=1 --plane z=0.5 --size 60x60 --figure -q --output " + fig.string(),
                      kNoDisplay);
    ASSERT_EQ(r.exit_code, 0) << ext << r.out;
    EXPECT_GT(fs::file_size(fig), 5000u) << ext;
  }
}

TEST(CliSlice, FigureLinesAreVectorPathsAndTheLegendNamesOnlyDrawnOnes) {
  fs::create_directories(kOut);
  const fs::path svg = kOut / "lines.svg";
  // c(J) >= 1 everywhere: a contour at 0.5 has no line, so the legend must not list it.
  const CommandResult r = run_linkscape("slice --size 60x60 --contour 0.5,3 --figure -q --output " + svg.string(), kNoDisplay);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::ifstream in(svg);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The reach boundary of a 60 x 60 slice crosses well over a hundred cells: one path of that many lines.
  std::size_t longest = 0;
  for (std::size_t at = text.find(" d=\""); at != std::string::npos; at = text.find(" d=\"", at + 1)) {
    const std::size_t end = text.find('"', at + 4);
    const std::string d = text.substr(at + 4, end - at - 4);
    longest = std::max<std::size_t>(longest, std::count(d.begin(), d.end(), 'L'));
  }
  EXPECT_GT(longest, 100u) << "contours and the reach boundary are drawn as vector paths";
  EXPECT_NE(text.find("= 3<"), std::string::npos) << "the c(J) = 3 contour is drawn and listed";
  EXPECT_EQ(text.find("0.5<"), std::string::npos) << "no line at 0.5, so no legend entry";
  EXPECT_EQ(text.find("0.5, 3<"), std::string::npos);
  EXPECT_NE(text.find("reach boundary"), std::string::npos);
}

TEST(CliSlice, AWidePlotLeavesTheLegendOnThePage) {
  fs::create_directories(kOut);
  const fs::path svg = kOut / "wide.svg";
  // 360 x 240 mm: the plot takes the page's whole width, so the legend has only the right margin.
  const CommandResult r = run_linkscape("slice -m haply-2diy --plane z=0 --extent -160,200,-60,180 --size 36x24 "
                                        "--figure -q --output " + svg.string(), kNoDisplay);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::ifstream in(svg);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t label = text.find(">reach boundary<");
  ASSERT_NE(label, std::string::npos);
  const std::size_t tag = text.rfind("<text", label);
  const double x = std::stod(text.substr(text.find(" x=\"", tag) + 4));
  const double font_px = std::stod(text.substr(text.find("font-size=\"", tag) + 11));
  // DejaVu Sans averages under 0.6 em a character; the page is 1400 wide.
  EXPECT_LE(x + 0.6 * font_px * std::string("reach boundary").size(), 1400.0) << "x = " << x;
}

TEST(CliSlice, CsvHasOneRowPerSampleAndAgreesWithEval) {
  const fs::path csv = kOut / "slice.csv";
  const CommandResult r = run_linkscape("slice --param L1=1 --param L2=1 --plane x=0.25 --extent 0.2,1.8,-1,1 "
                                        "--size 8x6 -q --output " + csv.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::ifstream in(csv);
  const linkscape::Table t = linkscape::read_csv(in, "slice.csv");
  ASSERT_EQ(t.rows.size(), 48u);
  // Every sample's cond equals `eval` at the same point (branch 0).
  std::ostringstream targets;
  targets << "x,y,z\n";
  for (const auto& row : t.rows)
    targets << linkscape::format_number(row[t.column("x_cm")]) << "," << linkscape::format_number(row[t.column("y_cm")])
            << "," << linkscape::format_number(row[t.column("z_cm")]) << "\n";
  const fs::path input = temp_file("slice_points.csv", targets.str());
  const CommandResult e = run_linkscape("eval --param L1=1 --param L2=1 --branch 0 --ik " + input.string());
  ASSERT_EQ(e.exit_code, 0) << e.out;
  std::istringstream lines(e.out);
  std::string line;
  std::getline(lines, line);
  for (const auto& row : t.rows) {
    ASSERT_TRUE(std::getline(lines, line));
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, ',')) f.push_back(field);
    f.resize(12);
    const double cond = row[t.column("cond")];
    if (f[4] != "ok") {
      EXPECT_FALSE(std::isfinite(cond)) << line;  // no value where unreachable, inf where singular
      continue;
    }
    EXPECT_NEAR(cond, std::stod(f[8]), 1e-6 * cond) << line;
  }
}

TEST(CliField, WritesVtiAndCsv) {
  for (const char* name : {"volume.vti", "volume.csv"}) {
    const fs::path out = kOut / name;
    fs::remove(out);
    const CommandResult r = run_linkscape("field --resolution 6x5x4 -q --output " + out.string(), kNoDisplay);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    ASSERT_TRUE(fs::exists(out)) << name;
  }
  std::ifstream in(kOut / "volume.csv");
  EXPECT_EQ(linkscape::read_csv(in, "volume.csv").rows.size(), 120u);
}

TEST(CliMesh, ReachMeshIsWatertightWithTheAnalyticVolume) {
  const fs::path stl = kOut / "reach.stl";
  const CommandResult r = run_linkscape("mesh --param L1=1 --param L2=0.6 --surface reach --resolution 64 -q --output " +
                                        stl.string(), kNoDisplay);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("watertight"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("NOT watertight"), std::string::npos) << r.out;
  // The shell between radii 0.4 and 1.6; printed as "(error X %)".
  const auto at = r.out.find("(error ");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_LT(std::abs(std::stod(r.out.substr(at + 7))), 1.0) << r.out;
  EXPECT_TRUE(fs::exists(stl));
}

// A region cut by the box is said to be (the Falcon's reach passes its
// file's box at x, y = +-90 mm; the Delta's lies inside its box), and a
// planar device's mesh, its plane's region extruded along z, gives its area.
TEST(CliMesh, SaysWhereTheBoxCutsTheRegionAndAPlanarArea) {
  const auto run = [](const std::string& device) {
    const CommandResult r = run_linkscape("mesh -m " + device + " --resolution 24 -q --output " +
                                          (kOut / (device + ".stl")).string(), kNoDisplay);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    return r.out;
  };
  const std::string falcon = run("falcon");
  EXPECT_NE(falcon.find("reaches the box's faces at x = -90, x = 90, y = -90, y = 90 and may go on"), std::string::npos)
      << falcon;
  EXPECT_EQ(run("delta").find("reaches the box"), std::string::npos);
  const std::string five_bar = run("five-bar");
  EXPECT_NE(five_bar.find("planar: the region of the plane z = 0"), std::string::npos) << five_bar;
  EXPECT_EQ(five_bar.find("faces at z"), std::string::npos) << five_bar;
  const auto at = five_bar.find("its area in the plane ");
  ASSERT_NE(at, std::string::npos) << five_bar;
  EXPECT_NEAR(std::stod(five_bar.substr(at + 22)), 503.1, 1.0) << five_bar;  // at this resolution
  // A decimation that loses the shape says so (the 12R's reach to a few triangles).
  const CommandResult coarse = run_linkscape("mesh --resolution 24 --decimate 100 -q --output " +
                                             (kOut / "coarse.stl").string(), kNoDisplay);
  EXPECT_EQ(coarse.exit_code, 0) << coarse.out;
  EXPECT_NE(coarse.out.find("decimated from "), std::string::npos) << coarse.out;
  EXPECT_NE(coarse.out.find("note: the decimation changed the volume by more than 5 %"), std::string::npos) << coarse.out;
  const CommandResult fine = run_linkscape("mesh --resolution 24 --decimate 0.05 -q --output " +
                                           (kOut / "fine.stl").string(), kNoDisplay);
  EXPECT_EQ(fine.out.find("note: the decimation"), std::string::npos) << fine.out;
}

// A six-DOF device's well-conditioned region: both measures by default, or
// one by name; the region of both lies within each one's.
TEST(CliMesh, ASixDofDevicesMeasuresOneByOneOrBoth) {
  const auto volume = [](const std::string& surface) {
    const CommandResult r = run_linkscape("mesh -m pathos2 --resolution 16 -q --surface '" + surface + "' --output " +
                                          (kOut / "pathos2-cond.stl").string(), kNoDisplay);
    EXPECT_EQ(r.exit_code, 0) << surface << ": " << r.out;
    const auto at = r.out.find("volume ");
    return at == std::string::npos ? -1.0 : std::stod(r.out.substr(at + 7));
  };
  const double both = volume("cond<4"), position = volume("cond_jp<4"), orientation = volume("cond_jo<4");
  EXPECT_GT(both, 0);
  EXPECT_GT(position, 10 * both);  // cond(Jp) alone holds far more
  EXPECT_LE(both, orientation * (1 + 1e-9));
  const CommandResult one = run_linkscape("mesh -m delta --surface 'cond_jo<3' -q --output " +
                                          (kOut / "never.stl").string(), kNoDisplay);
  EXPECT_EQ(one.exit_code, 2) << one.out;  // a device of one measure has no cond_jo
}

// --unit mm: the 12R's reach in cm written in mm, said in the file.
TEST(CliMesh, WritesTheUnitAsked) {
  const fs::path obj = kOut / "reach-mm.obj";
  const CommandResult r = run_linkscape("mesh --param L1=1 --param L2=0.6 --resolution 32 -q --unit mm --output " +
                                        obj.string(), kNoDisplay);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("(points in mm)"), std::string::npos) << r.out;
  std::ifstream in(obj);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "# length unit: mm");
  double largest = 0;  // the outer radius 1.6 cm is 16 mm
  while (std::getline(in, line))
    if (line.rfind("v ", 0) == 0) {
      std::istringstream v(line.substr(2));
      double x, y, z;
      v >> x >> y >> z;
      largest = std::max(largest, std::sqrt(x * x + y * y + z * z));
    }
  EXPECT_NEAR(largest, 16.0, 0.5);
}

TEST(CliFieldCommands, BadArgumentsExitWithTwoAndWriteNothing) {
  const fs::path out = kOut / "never.png";
  fs::remove(out);
  const std::pair<std::string, std::string> cases[] = {
      {"slice --plane w=1 --output " + out.string(), "axis must be x, y or z"},
      {"slice --plane x=abc --output " + out.string(), "--plane"},
      {"slice --size 10by10 --output " + out.string(), "--size"},
      {"slice --field speed --output " + out.string(), "--field"},
      {"slice --output " + (kOut / "never.gif").string(), ".png or .csv"},
      {"slice --extent 1,1,0,1 --output " + out.string(), "min < max"},
      {"slice --method magic --output " + out.string(), "unknown IK method"},
      {"slice --range 5,1 --output " + out.string(), ""},
      {"slice --plane x=0", "--output"},
      {"field --resolution 1 --output " + (kOut / "never.vti").string(), "--resolution"},
      {"field --resolution 4000 --output " + (kOut / "never.vti").string(), "GiB at peak"},
      {"field --output " + (kOut / "never.xyz").string(), ".vti or .csv"},
      {"mesh --surface 'cond<0.5' --output " + (kOut / "never.stl").string(), "--surface"},
      {"mesh --surface volume --output " + (kOut / "never.stl").string(), "--surface"},
      {"mesh --output " + (kOut / "never.3mf").string(), ".stl, .obj, .ply, .off or .vtp"},
      {"mesh --decimate -1 --output " + (kOut / "never.stl").string(), "--decimate"},
      {"mesh --unit furlong --output " + (kOut / "never.stl").string(), "--unit expects mm, cm, m or in"},
  };
  for (const auto& [args, message] : cases) {
    const CommandResult r = run_linkscape(args + " -q", kNoDisplay);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  }
  for (const auto& e : fs::directory_iterator(kOut))
    EXPECT_EQ(e.path().filename().string().rfind("never", 0), std::string::npos) << e.path();
}

TEST(CliBench, QuickRunReportsEveryFigure) {
  const fs::path csv = kOut / "bench.csv";
  const CommandResult r = run_linkscape("bench --quick --param L1=1 --param L2=1 --csv " + csv.string(), kNoDisplay);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  for (const char* what : {"M points/s", "slice", "reach isosurface", "c<3 isosurface", "volume error", "peak resident memory"})
    EXPECT_NE(r.out.find(what), std::string::npos) << what << "\n" << r.out;
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "measurement,value,unit");
}

TEST(CliBench, ChartAndCsvCoverEveryMethod) {
  const fs::path png = kOut / "methods.png", sweeps = kOut / "sweeps.svg", csv = kOut / "methods_bench.csv";
  for (const fs::path& p : {png, sweeps, csv}) fs::remove(p);
  const CommandResult r = run_linkscape("bench --quick --param L1=1 --param L2=1 --chart " + png.string() +
                                            " --sweeps " + sweeps.string() + " --csv " + csv.string(),
                                        kNoDisplay);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  // The existing figures are still reported.
  for (const char* what : {"M points/s", "reach isosurface", "peak resident memory", "stability sweeps"})
    EXPECT_NE(r.out.find(what), std::string::npos) << what;
  // Every method appears in the CSV (long form) and in the method table.
  std::ifstream in(csv);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.substr(0, text.find('\n')), "measurement,value,unit");
  std::ifstream table_in(kOut / "methods_bench.methods.csv");
  const std::string table((std::istreambuf_iterator<char>(table_in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(table.rfind("family,method,parameter,samples,not_ok,time_per_evaluation_s,", 0), 0u);
  for (const char* method : {"ik/paper", "ik/planar", "ik/newton", "ik/dls", "ik/fallback", "jacobian/analytic",
                             "jacobian/central-difference", "jacobian/forward-difference", "jacobian/complex-step",
                             "conditioning/closed-form", "conditioning/closed-form-fast", "conditioning/svd",
                             "conditioning/normal-equations", "field/reach volume", "field/c<3 volume"})
  {
    EXPECT_NE(text.find(std::string("method ") + method), std::string::npos) << method;
    const std::string name = std::string(method);
    const std::string family = name.substr(0, name.find('/')), rest = name.substr(name.find('/') + 1);
    EXPECT_NE(table.find("\n" + family + "," + rest + ","), std::string::npos) << method;  // quoted only where needed
  }
  EXPECT_TRUE(fs::exists(kOut / "methods_bench.sweeps.csv"));
  // The chart: a full-size PNG with real content, and an SVG.
  EXPECT_EQ(png_size(png), std::make_pair(1600, 1200));
  EXPECT_GT(fs::file_size(png), 40000u);
  EXPECT_GT(fs::file_size(sweeps), 20000u);
}

TEST(CliSlice, MethodFieldShowsWhichIkMethodServedEachSample) {
  const fs::path png = kOut / "method.png", csv = kOut / "method.csv";
  CommandResult r = run_linkscape("slice --param L1=1 --param L2=1 --method fallback --field method --plane y=4e-5 "
                                  "--size 40x40 -q --output " + png.string(), kNoDisplay);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(png_size(png), std::make_pair(40, 40));
  // At a tolerance near rounding, planar misses it at some samples and
  // Newton (seeded by planar) takes over there.
  r = run_linkscape("slice --param L1=1 --param L2=1 --method fallback --tolerance 3e-15 --plane y=4e-5 --size 60x60 "
                    "-q --output " + csv.string(), kNoDisplay);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::ifstream in(csv);
  const linkscape::Table t = linkscape::read_csv(in, "method.csv");
  std::set<int> used;
  for (const auto& row : t.rows)
    if (!std::isnan(row[t.column("method_used")])) used.insert(int(row[t.column("method_used")]));  // empty: none served
  EXPECT_TRUE(used.count(1)) << "planar";  // IkMethod::Planar
  EXPECT_TRUE(used.count(2)) << "newton";  // IkMethod::Newton, where planar missed the tolerance
  r = run_linkscape("slice --field method --figure -q --output " + (kOut / "never.svg").string(), kNoDisplay);
  EXPECT_EQ(r.exit_code, 2) << r.out;
}

// The shell's completion asks the program for an option's values: the lists
// the commands check against.
TEST(Cli, CompletesTheValuesAnOptionAccepts) {
  const CommandResult maps = run_linkscape("--complete-values=colour-map");
  ASSERT_EQ(maps.exit_code, 0) << maps.out;
  EXPECT_EQ(maps.out, "viridis\ncividis\ndiverging\n");
  const CommandResult methods = run_linkscape("--complete-values=method");
  for (const char* method : {"planar", "newton", "closed"})
    EXPECT_NE(methods.out.find(std::string(method) + "\n"), std::string::npos) << method << " in\n" << methods.out;
  const CommandResult criteria = run_linkscape("--complete-values=criterion");
  EXPECT_NE(criteria.out.find("cond<\n"), std::string::npos) << criteria.out;
  EXPECT_NE(criteria.out.find("force_iso>\n"), std::string::npos) << criteria.out;
  const CommandResult free = run_linkscape("--complete-values=output");  // a file: no list
  EXPECT_EQ(free.exit_code, 0);
  EXPECT_EQ(free.out, "");
}

// linkscape --shortcuts: the window's menu keys, made without a display (the
// manual page's WINDOW section).
TEST(Cli, PrintsTheWindowsShortcuts) {
  const CommandResult r = run_linkscape("--shortcuts", "DISPLAY=");
  if (!kWindowBuilt) {
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_NE(r.out.find("no window"), std::string::npos) << r.out;
    return;
  }
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("File > Save session"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Help > Documentation"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("F1\n"), std::string::npos) << r.out;
}
