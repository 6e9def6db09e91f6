// PATHOS-II through the command line: eval round trips, fields and meshes
// at a pose, the design study, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "cli_runner.h"
#include "core/csv.h"
#include "core/mechanisms/pathos2/pathos2.h"

using namespace linkscape;

namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

}  // namespace

TEST(CliPathos2, EvalInverseThenForwardRecoversThePose) {
  // Random poses around the Table 3 home pose: IK writes q1..q6; FK of those
  // angles (each row seeded by the previous answer) returns the same pose.
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1, 1);
  std::string poses = "x,y,z,rx,ry,rz,h0\n";
  for (int i = 0; i < 40; ++i)
    poses += number(3 * u(rng)) + "," + number(3 * u(rng)) + "," + number(22.5 + 3 * u(rng)) + "," +
             number(0.1 * u(rng)) + "," + number(0.1 * u(rng)) + "," + number(std::numbers::pi / 6 + 0.1 * u(rng)) +
             ",7\n";
  poses += "0,0,80,0,0,0,7\n";  // far above the upper plate
  // Poses over the paper's workspace: the preset's assumed stops off (its globular cones bind first).
  const std::string stops_off = " --joint-limits off --interference off";
  const auto ik = run_linkscape("eval -m pathos2 --ik " + temp_file("p2_poses.csv", poses).string() + stops_off);
  ASSERT_EQ(ik.exit_code, 0) << ik.out;
  const auto rows = parse_cells(ik.out);
  ASSERT_EQ(rows.size(), 41u);
  EXPECT_EQ(rows.back().at("status"), "unreachable");
  EXPECT_FALSE(rows.back().at("failing_leg").empty());  // names the leg that fails
  std::string angles = "q1,q2,q3,q4,q5,q6,h0\n";
  std::vector<std::vector<double>> expected;
  for (const auto& row : rows) {
    if (row.at("status") != "ok") continue;
    EXPECT_GE(std::stod(row.at("cond_jp")), 1.0);
    EXPECT_GE(std::stod(row.at("cond_jo")), 1.0);
    for (int k = 1; k <= 6; ++k) angles += row.at("q" + std::to_string(k)) + ",";
    angles += "7\n";
    expected.push_back({std::stod(row.at("x")), std::stod(row.at("y")), std::stod(row.at("z")),
                        std::stod(row.at("rx")), std::stod(row.at("ry")), std::stod(row.at("rz"))});
  }
  ASSERT_GT(expected.size(), 30u);
  const auto fk = run_linkscape("eval -m pathos2 --fk " + temp_file("p2_angles.csv", angles).string() + stops_off);
  ASSERT_EQ(fk.exit_code, 0) << fk.out;
  const auto f = parse_cells(fk.out);
  ASSERT_EQ(f.size(), expected.size());
  const char* names[] = {"x", "y", "z", "rx", "ry", "rz"};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    ASSERT_EQ(f[i].at("status"), "ok") << "row " << i;
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(std::stod(f[i].at(names[k])), expected[i][k], 1e-8) << "row " << i;
  }
}

// A pose 3e-9 from a J-singular one (its 6x6 J's condition past the
// device's bound): the row is singular with c(J) inf, as the measures say
// (it had been ok beside them); 1e-7 away it is ok with finite ones.
TEST(CliPathos2, APoseWhoseJacobianIsSingularIsASingularRow) {
  const std::string poses = "x,y,z,rx,ry,rz,h0\n"
                            "-3.061771302330916,3.9049519876790533,20.855703346809335,0.3456525370457612,"
                            "0.11389359550488122,0.44547817268925294,7\n"
                            "-3.061771363566344,3.904952065778095,20.8557033139234,0.3456525439588122,"
                            "0.1138935977827532,0.44547817112684085,7\n";
  const auto ik = run_linkscape("eval -m pathos2 --ik " + temp_file("p2_near_singular.csv", poses).string() +
                                " --joint-limits off --interference off");
  ASSERT_EQ(ik.exit_code, 0) << ik.out;
  const auto rows = parse_cells(ik.out);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("status"), "ok");
  EXPECT_TRUE(std::isfinite(std::stod(rows[0].at("cond_jp"))));
  EXPECT_EQ(rows[1].at("status"), "singular");
  EXPECT_EQ(rows[1].at("cond_jp"), "inf");
}

TEST(CliPathos2, SliceFieldAndMeshAtAPose) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  const auto slice = run_linkscape("slice -m pathos2 --field cond_jo --size 64x64 --figure -o " +
                                   (dir / "p2_slice.png").string(), "env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM");
  ASSERT_EQ(slice.exit_code, 0) << slice.out;
  EXPECT_GT(fs::file_size(dir / "p2_slice.png"), 20000u);

  // The CSV slice through a tilted pose: one row per sample with both condition numbers.
  const auto csv = run_linkscape("slice -m pathos2 --pose 1,0,23,0.1,0,0.5,6 --size 24x20 -o " +
                                 (dir / "p2_slice.csv").string());
  ASSERT_EQ(csv.exit_code, 0) << csv.out;
  std::ifstream in(dir / "p2_slice.csv");
  const Table t = read_csv(in, "slice");
  EXPECT_EQ(t.rows.size(), 24u * 20u);
  EXPECT_NO_THROW(t.column("cond_orientation"));
  for (const auto& row : t.rows) EXPECT_DOUBLE_EQ(row[t.column("z_cm")], 23.0);  // the plane through the pose

  const auto mesh = run_linkscape("mesh -m pathos2 --resolution 48 -o " + (dir / "p2_reach.stl").string());
  ASSERT_EQ(mesh.exit_code, 0) << mesh.out;
  EXPECT_NE(mesh.out.find("watertight"), std::string::npos) << mesh.out;
  EXPECT_EQ(mesh.out.find("NOT watertight"), std::string::npos) << mesh.out;
}

TEST(CliPathos2, QuickDesignStudyWritesTablesAndChart) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  // Fig. 6's trend is the paper's, without the preset's assumed stops.
  const auto r = run_linkscape("design --quick -q --joint-limits off --interference off --table " + (dir / "t2.csv").string() + " --sweep " +
                               (dir / "l0.csv").string() + " --chart " + (dir / "design.png").string(),
                               "env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("best G"), std::string::npos);
  std::ifstream sweep_file(dir / "l0.csv");
  std::string header;
  std::getline(sweep_file, header);
  EXPECT_EQ(header, "l0_cm,status,dLx_cm,dLy_cm,dLz_cm,dRx_rad,dRy_rad,dRz_rad");
  // The workspace grows as l0 shrinks (paper Fig. 6): dLx + dLy + dLz falls with l0.
  std::vector<double> total;
  for (std::string line; std::getline(sweep_file, line);) {
    std::istringstream cells(line);
    std::string c[5];
    for (auto& x : c) std::getline(cells, x, ',');
    total.push_back(std::stod(c[2]) + std::stod(c[3]) + std::stod(c[4]));
  }
  ASSERT_GE(total.size(), 3u);
  for (std::size_t i = 1; i < total.size(); ++i) EXPECT_LT(total[i], total[i - 1]);
  EXPECT_GT(fs::file_size(dir / "design.png"), 30000u);
  // The search: a design not evaluated has no ranges and no G (empty, not 0).
  std::ifstream table_file(dir / "t2.csv");
  std::getline(table_file, header);
  EXPECT_EQ(header, "l2_cm,l3_cm,lp_cm,rz_deg,outcome,dLx_cm,dLy_cm,dLz_cm,G");
  int evaluated = 0, not_evaluated = 0;
  for (std::string line; std::getline(table_file, line);) {
    const std::vector<std::string> c = csv_cells(line);
    ASSERT_EQ(c.size(), 9u) << line;
    for (int k = 5; k < 9; ++k) {
      if (c[4] == "evaluated") EXPECT_TRUE(parse_number(c[k])) << line;
      else EXPECT_EQ(c[k], "") << line;
    }
    (c[4] == "evaluated" ? evaluated : not_evaluated) += 1;
  }
  EXPECT_GT(evaluated, 0);
  EXPECT_GT(not_evaluated, 0);  // the grid starts at l2 = 0: legs without an elbow
}

TEST(CliPathos2, BadArgumentsExitWithTwo) {
  for (const std::string args : {
           "slice -m pathos2 --pose 1,2,3 -o /tmp/x.png",           // too few numbers
           "slice -m pathos2 --pose 0,0,22,0,0,0,0 -o /tmp/x.png",  // zero grip
           "slice -m pathos2 --method newton -o /tmp/x.png",        // 12R-only option
           "slice --field cond_jo -o /tmp/x.png",                   // 12R has no cond(Jo)
           "eval -m pathos2 --param L1=3 --ik /dev/null",           // a 12R parameter
           "design -m parallel-12r --table /tmp/x.csv",             // the study is for pathos2
           "design --table /tmp/x.txt",                             // wrong extension
       }) {
    const auto r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
  }
}
