// The Delta through the same headless commands as every device.
#include <gtest/gtest.h>

#include <random>

#include "cli_runner.h"
#include "core/mechanism.h"
#include "core/preset.h"

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

// 10^5 seeded actuator values in the preset's ranges: --fk gives x,y,z; --ik
// of those gives q (branch 0, every elbow out); --fk of that q lands on the
// same x,y,z within 1e-9 of the device's size, and where the original q was
// on branch 0 the angles agree.
TEST(CliDelta, ForwardAndInverseRoundTripAtAHundredThousandPoints) {
  const auto m = linkscape::make_mechanism(linkscape::load_preset("delta"));
  const double size = m->size();
  std::mt19937_64 rng(2024);
  std::string angles = "q1,q2,q3\n";
  for (int n = 0; n < 100000; ++n) {
    for (int k = 0; k < 3; ++k) {
      const auto r = m->info().actuators[std::size_t(k)].range;
      angles += linkscape::format_number(std::uniform_real_distribution<double>(r.lo, r.hi)(rng)) + (k < 2 ? "," : "\n");
    }
  }
  // The linkage's round trip: its ball joints' cones off.
  const auto fk = run_linkscape("eval -m delta --joint-limits off --fk " + temp_file("delta_q.csv", angles).string());
  ASSERT_EQ(fk.exit_code, 0) << fk.out.substr(0, 400);
  const auto fk_rows = parse_cells(fk.out);
  ASSERT_EQ(fk_rows.size(), 100000u);
  std::string targets = "x,y,z\n";
  std::vector<std::size_t> source;
  for (std::size_t i = 0; i < fk_rows.size(); ++i) {
    if (fk_rows[i].at("status") != "ok") continue;
    targets += fk_rows[i].at("x") + "," + fk_rows[i].at("y") + "," + fk_rows[i].at("z") + "\n";
    source.push_back(i);
  }
  ASSERT_GT(source.size(), 90000u);  // most of the box of ranges assembles
  const auto ik = run_linkscape("eval -m delta --joint-limits off --branch 0 --ik " + temp_file("delta_x.csv", targets).string());
  ASSERT_EQ(ik.exit_code, 0) << ik.out.substr(0, 400);
  const auto ik_rows = parse_cells(ik.out);
  ASSERT_EQ(ik_rows.size(), source.size());
  std::string back = "q1,q2,q3\n";
  std::vector<std::size_t> solved;
  double worst_angle = 0;
  for (std::size_t i = 0; i < ik_rows.size(); ++i) {
    const auto& r = ik_rows[i];
    if (r.at("status") != "ok") continue;
    back += r.at("q1") + "," + r.at("q2") + "," + r.at("q3") + "\n";
    solved.push_back(i);
    // Same branch as the original: the same angles.
    const auto& q0 = fk_rows[source[i]];
    const Eigen::Vector3d a(std::stod(q0.at("q1")), std::stod(q0.at("q2")), std::stod(q0.at("q3")));
    const Eigen::Vector3d b(std::stod(r.at("q1")), std::stod(r.at("q2")), std::stod(r.at("q3")));
    if ((a - b).cwiseAbs().maxCoeff() < 0.5)
      worst_angle = std::max(worst_angle, (a - b).cwiseAbs().maxCoeff());
  }
  EXPECT_GT(solved.size(), source.size() / 2);  // branch 0 serves most of the workspace
  EXPECT_LT(worst_angle, 1e-9);
  const auto again = run_linkscape("eval -m delta --joint-limits off --fk " + temp_file("delta_q2.csv", back).string());
  ASSERT_EQ(again.exit_code, 0);
  const auto again_rows = parse_cells(again.out);
  ASSERT_EQ(again_rows.size(), solved.size());
  double worst = 0;
  for (std::size_t i = 0; i < solved.size(); ++i) {
    const auto& t = ik_rows[solved[i]];
    const auto& r = again_rows[i];
    ASSERT_EQ(r.at("status"), "ok");
    const Eigen::Vector3d p0(std::stod(t.at("x")), std::stod(t.at("y")), std::stod(t.at("z")));
    const Eigen::Vector3d p1(std::stod(r.at("x")), std::stod(r.at("y")), std::stod(r.at("z")));
    worst = std::max(worst, (p1 - p0).norm());
  }
  EXPECT_LT(worst, 1e-9 * size);
  RecordProperty("worst_round_trip_over_size", std::to_string(worst / size));
}

TEST(CliDelta, UnreachableTargetsGetAStatusAndBothIkMethodsAgree) {
  const fs::path in = temp_file("delta_targets.csv", "x,y,z\n0,0,-16.5\n3,2,-18\n-4,1,-20\n0,0,-40\n60,0,-10\n");
  const auto closed = run_linkscape("eval -m delta --branch 0 --ik " + in.string());
  const auto newton = run_linkscape("eval -m delta --ik " + in.string() + " --method newton");
  ASSERT_EQ(closed.exit_code, 0) << closed.out;
  ASSERT_EQ(newton.exit_code, 0) << newton.out;
  const auto a = parse_cells(closed.out), b = parse_cells(newton.out);
  ASSERT_EQ(a.size(), 5u);
  ASSERT_EQ(b.size(), 5u);
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(a[std::size_t(i)].at("status"), "ok");
    ASSERT_EQ(b[std::size_t(i)].at("status"), "ok");
    for (const char* q : {"q1", "q2", "q3"})
      EXPECT_NEAR(std::stod(a[std::size_t(i)].at(q)), std::stod(b[std::size_t(i)].at(q)), 1e-10);
  }
  EXPECT_EQ(a[3].at("status"), "unreachable");
  EXPECT_EQ(a[4].at("status"), "unreachable");
  EXPECT_EQ(a[3].at("q1"), "");  // never a number for a target that has none
}

// Without --branch, every assembly is a row, as the described Delta gives
// them: the same branches, statuses and angles.
TEST(CliDelta, WithoutABranchEveryAssemblyIsARowAsTheDescribedDeltaGives) {
  const fs::path in = temp_file("delta_branches.csv", "x,y,z\n0,0,-20\n3,2,-18\n-4,1,-20\n0,0,-40\n");
  const auto compiled = run_linkscape("eval -m delta --ik " + in.string());
  const auto described = run_linkscape("eval -m delta-described --ik " + in.string());
  ASSERT_EQ(compiled.exit_code, 0) << compiled.out;
  ASSERT_EQ(described.exit_code, 0) << described.out;
  const auto a = parse_cells(compiled.out), b = parse_cells(described.out);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 3u * 8u + 1u);  // three targets close on all eight branches
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (const char* c : {"x", "y", "z", "branch", "status"}) EXPECT_EQ(a[i].at(c), b[i].at(c)) << "row " << i << " " << c;
    if (a[i].at("q1").empty()) continue;
    for (const char* q : {"q1", "q2", "q3"}) EXPECT_NEAR(std::stod(a[i].at(q)), std::stod(b[i].at(q)), 1e-9) << "row " << i;
  }
  EXPECT_EQ(a.back().at("status"), "unreachable");
}

// The closed form's two assembly modes: without seed columns the working
// one; seeded near the other (found by Newton from above), the other.
TEST(CliDelta, ForwardSeedsPickTheAssemblyMode) {
  const auto m = linkscape::make_mechanism(linkscape::load_preset("delta"));
  const Eigen::VectorXd q = m->home_actuators();
  const Eigen::VectorXd working = m->forward(q).x;
  linkscape::FkOptions above;
  above.method = "newton";
  above.seed = working + Eigen::Vector3d(0, 0, 40);
  const linkscape::FkResult other = m->forward(q, above);
  // Its ball joints beyond their cones: out of limits, but a pose.
  ASSERT_EQ(other.status, linkscape::Status::OutOfLimits);
  ASSERT_GT((other.x - working).norm(), 5.0);
  std::string rows = "q1,q2,q3,seed_x,seed_y,seed_z\n";
  for (const Eigen::VectorXd& seed : {working, other.x}) {
    for (int k = 0; k < 3; ++k) rows += linkscape::format_number(q(k)) + ",";
    rows += linkscape::format_number(seed(0) + 0.5) + "," + linkscape::format_number(seed(1)) + "," +
            linkscape::format_number(seed(2) - 0.5) + "\n";
  }
  std::string unseeded = "q1,q2,q3\n";
  for (int k = 0; k < 3; ++k) unseeded += linkscape::format_number(q(k)) + (k < 2 ? "," : "\n");
  const auto seeded = run_linkscape("eval -m delta --fk " + temp_file("delta_modes.csv", rows).string());
  const auto plain = run_linkscape("eval -m delta --fk " + temp_file("delta_mode.csv", unseeded).string());
  ASSERT_EQ(seeded.exit_code, 0) << seeded.out;
  ASSERT_EQ(plain.exit_code, 0) << plain.out;
  const auto a = parse_cells(seeded.out), b = parse_cells(plain.out);
  ASSERT_EQ(a.size(), 2u);
  ASSERT_EQ(b.size(), 1u);
  const auto pose = [](const auto& row) {
    return Eigen::Vector3d(std::stod(row.at("x")), std::stod(row.at("y")), std::stod(row.at("z")));
  };
  EXPECT_LT((pose(a[0]) - working).norm(), 1e-9);
  EXPECT_LT((pose(a[1]) - other.x).norm(), 1e-9);
  EXPECT_LT((pose(b[0]) - working).norm(), 1e-9);
}

TEST(CliDelta, SliceFieldAndMeshRun) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  const auto slice = run_linkscape("slice -m delta --size 64x64 -o " + (dir / "delta.csv").string() + " -q");
  ASSERT_EQ(slice.exit_code, 0) << slice.out;
  const linkscape::Table t = [&] {
    std::ifstream in(dir / "delta.csv");
    return linkscape::read_csv(in, "delta.csv");
  }();
  int reachable = 0;
  for (const auto& row : t.rows) reachable += row[t.column("reachable")] > 0;
  EXPECT_GT(reachable, 200);
  const auto mesh = run_linkscape("mesh -m delta --resolution 48 -o " + (dir / "delta.stl").string() + " -q");
  ASSERT_EQ(mesh.exit_code, 0) << mesh.out;
  EXPECT_TRUE(contains(mesh.out, "watertight")) << mesh.out;
  const auto bad = run_linkscape("slice -m delta --field cond_jo -o " + (dir / "x.png").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.out;
  const auto branch = run_linkscape("slice -m delta --branch 8 -o " + (dir / "x.png").string());
  EXPECT_EQ(branch.exit_code, 2) << branch.out;
}
