// The described five-bar and Stewart platform (assets/mechanisms/*.json)
// through the real binary: eval --ik against the closed forms (circle
// intersection; leg lengths), eval --fk back, and slice, mesh and a bad
// branch as for every device.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>

#include "cli_runner.h"
#include "core/mechanism.h"
#include "core/preset.h"

using namespace cli_runner;

namespace {

const std::string kFiveBar = std::string(LINKSCAPE_SOURCE_DIR) + "/assets/mechanisms/five-bar.json";
const std::string kStewart = std::string(LINKSCAPE_SOURCE_DIR) + "/assets/mechanisms/stewart.json";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string scientific(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

}  // namespace

// 10^4 points near home (inside the reach), branch 0: the angles eval writes are the
// circle-intersection angles with both elbows out (d = 6, a = 10, b = 14,
// base joints at (-+3, 0)), and eval --fk of them, seeded 1 cm off, gives
// the points back to 1e-9 of the size.
TEST(CliDescribedDevices, FiveBarEvalMatchesCircleIntersectionAndRoundTrips) {
  const double d = 6, a = 10, b = 14;
  std::mt19937_64 rng(15201);
  std::uniform_real_distribution<double> ux(-8, 8), uy(10, 22);
  // A planar device's task is x, y, z with z = 0, the device's plane.
  std::string targets = "x,y,z\n";
  std::vector<Eigen::Vector2d> points, angles;
  while (points.size() < 10000) {
    const Eigen::Vector2d p(ux(rng), uy(rng));
    // Both legs reach, 0.5 cm inside a + b (the box's corners do not).
    if ((p - Eigen::Vector2d(-d / 2, 0)).norm() > a + b - 0.5 || (p - Eigen::Vector2d(d / 2, 0)).norm() > a + b - 0.5)
      continue;
    Eigen::Vector2d q;
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector2d v = p - Eigen::Vector2d(i == 0 ? -d / 2 : d / 2, 0);
      const double g = std::acos((a * a + v.squaredNorm() - b * b) / (2 * a * v.norm()));
      q(i) = std::atan2(v.y(), v.x()) + (i == 0 ? g : -g);
    }
    points.push_back(p);
    angles.push_back(q);
    targets += linkscape::format_number(p.x()) + "," + linkscape::format_number(p.y()) + ",0\n";
  }
  const auto ik = run_linkscape("eval -m " + kFiveBar + " --branch 0 --ik " +
                                temp_file("five_bar_x.csv", targets).string());
  ASSERT_EQ(ik.exit_code, 0) << ik.out.substr(0, 400);
  const auto rows = parse_cells(ik.out);
  ASSERT_EQ(rows.size(), points.size());
  // FK seeded 1 cm off each point (seed_ columns), as a device tracking its
  // handle would be.
  std::string back = "q1,q2,seed_x,seed_y,seed_z\n";
  double worst_angle = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].at("status"), "ok") << points[i].transpose();
    for (int k = 0; k < 2; ++k) {
      const double q = std::stod(rows[i].at(k == 0 ? "q1" : "q2"));
      worst_angle = std::max(worst_angle, std::abs(std::remainder(q - angles[i](k), 2 * std::numbers::pi)));
    }
    back += rows[i].at("q1") + "," + rows[i].at("q2") + "," + linkscape::format_number(points[i].x() + 0.7) + "," +
            linkscape::format_number(points[i].y() - 0.7) + ",0\n";
  }
  EXPECT_LT(worst_angle, 1e-9);
  const auto fk = run_linkscape("eval -m " + kFiveBar + " --fk " + temp_file("five_bar_q.csv", back).string());
  ASSERT_EQ(fk.exit_code, 0) << fk.out.substr(0, 400);
  const auto again = parse_cells(fk.out);
  ASSERT_EQ(again.size(), points.size());
  const double size = linkscape::make_mechanism(linkscape::load_preset(kFiveBar))->size();
  double worst = 0;
  for (std::size_t i = 0; i < again.size(); ++i) {
    ASSERT_EQ(again[i].at("status"), "ok") << points[i].transpose();
    const Eigen::Vector2d p(std::stod(again[i].at("x")), std::stod(again[i].at("y")));
    worst = std::max(worst, (p - points[i]).norm());
  }
  EXPECT_LT(worst, 1e-9 * size);
  RecordProperty("worst_angle_rad", scientific(worst_angle));
  RecordProperty("worst_round_trip_over_size", scientific(worst / size));
}

// 10^3 poses near home inside the travel: the leg lengths eval writes are
// |p + R a_i - b_i|;
// eval --fk seeded at each pose (seed_ columns) gives it back.
TEST(CliDescribedDevices, StewartEvalIsTheLegLengthsAndForwardFindsThePose) {
  const double rb = 15, rp = 10, sb = 20, sp = 20, deg = std::numbers::pi / 180;
  std::array<Eigen::Vector3d, 6> base, platform;
  for (int k = 0; k < 3; ++k)
    for (int e = 0; e < 2; ++e) {
      const double tb = 120.0 * k + (e == 0 ? -sb / 2 : sb / 2), tp = 120.0 * k + (e == 0 ? -60 + sp / 2 : 60 - sp / 2);
      base[std::size_t(2 * k + e)] = rb * Eigen::Vector3d(std::cos(tb * deg), std::sin(tb * deg), 0);
      platform[std::size_t(2 * k + e)] = rp * Eigen::Vector3d(std::cos(tp * deg), std::sin(tp * deg), 0);
    }
  std::mt19937_64 rng(15202);
  std::uniform_real_distribution<double> across(-2, 2), angle(-0.15, 0.15);
  std::string poses = "x,y,z,rx,ry,rz\n", lengths = "l1,l2,l3,l4,l5,l6,seed_x,seed_y,seed_z,seed_rx,seed_ry,seed_rz\n";
  std::vector<Eigen::Matrix<double, 6, 1>> pose_list, length_list;
  while (pose_list.size() < 1000) {
    Eigen::Matrix<double, 6, 1> x;
    x << across(rng), across(rng), 10.04 + across(rng), angle(rng), angle(rng), angle(rng);
    const Eigen::Matrix3d r = (Eigen::AngleAxisd(x(5), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(x(4), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(x(3), Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    Eigen::Matrix<double, 6, 1> l;
    for (int i = 0; i < 6; ++i) l(i) = (x.head<3>() + r * platform[std::size_t(i)] - base[std::size_t(i)]).norm();
    if (l.minCoeff() < 10.01 || l.maxCoeff() > 17.99) continue;  // inside the travel [10, 18] only
    pose_list.push_back(x);
    length_list.push_back(l);
    std::string row;
    for (int k = 0; k < 6; ++k) row += linkscape::format_number(x(k)) + (k < 5 ? "," : "\n");
    poses += row;
    for (int k = 0; k < 6; ++k) lengths += linkscape::format_number(l(k)) + ",";
    // Seeds 0.2 cm and 0.01 rad off.
    for (int k = 0; k < 6; ++k) lengths += linkscape::format_number(x(k) + (k < 3 ? 0.2 : 0.01)) + (k < 5 ? "," : "\n");
  }
  const auto ik = run_linkscape("eval -m " + kStewart + " --ik " + temp_file("stewart_x.csv", poses).string());
  ASSERT_EQ(ik.exit_code, 0) << ik.out.substr(0, 400);
  const auto rows = parse_cells(ik.out);
  ASSERT_EQ(rows.size(), pose_list.size());
  double worst_length = 0;
  const char* legs[] = {"l1", "l2", "l3", "l4", "l5", "l6"};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].at("status"), "ok") << pose_list[i].transpose();
    for (int k = 0; k < 6; ++k) {
      const double l = std::stod(rows[i].at(legs[k]));
      worst_length = std::max(worst_length, std::abs(l - length_list[i](k)) / length_list[i](k));
    }
  }
  EXPECT_LT(worst_length, 1e-9);
  const auto fk = run_linkscape("eval -m " + kStewart + " --fk " + temp_file("stewart_q.csv", lengths).string());
  ASSERT_EQ(fk.exit_code, 0) << fk.out.substr(0, 400);
  const auto found = parse_cells(fk.out);
  ASSERT_EQ(found.size(), pose_list.size());
  double worst_pose = 0;
  const char* names[] = {"x", "y", "z", "rx", "ry", "rz"};
  for (std::size_t i = 0; i < found.size(); ++i) {
    ASSERT_EQ(found[i].at("status"), "ok") << pose_list[i].transpose();
    for (int k = 0; k < 6; ++k)
      worst_pose = std::max(worst_pose, std::abs(std::stod(found[i].at(names[k])) - pose_list[i](k)));
  }
  EXPECT_LT(worst_pose, 1e-9 * 25);
  RecordProperty("worst_length_relative", scientific(worst_length));
  RecordProperty("worst_pose", scientific(worst_pose));
}

TEST(CliDescribedDevices, SliceAndMeshRunAndABadBranchIsRefused) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  for (const std::string& file : {kFiveBar, kStewart}) {
    const auto slice = run_linkscape("slice -m " + file + " --size 48x48 -o " + (dir / "described.csv").string() + " -q");
    ASSERT_EQ(slice.exit_code, 0) << slice.out;
    const linkscape::Table t = [&] {
      std::ifstream in(dir / "described.csv");
      return linkscape::read_csv(in, "described.csv");
    }();
    int reachable = 0;
    for (const auto& row : t.rows) reachable += row[t.column("reachable")] > 0;
    EXPECT_GT(reachable, 100) << file;
    const auto mesh = run_linkscape("mesh -m " + file + " --resolution 32 -o " + (dir / "described.stl").string() + " -q");
    ASSERT_EQ(mesh.exit_code, 0) << mesh.out;
    EXPECT_TRUE(contains(mesh.out, "watertight")) << mesh.out;
  }
  const auto branch = run_linkscape("eval -m " + kFiveBar + " --branch 4 --ik " +
                                    temp_file("five_bar_one.csv", "x,y,z\n0,17,0\n").string());
  EXPECT_EQ(branch.exit_code, 2) << branch.out;
}

// The five-bar is planar: a target off its plane z = 0 exits 2 naming the
// coordinate, the device and its plane (it once answered ok at z = 1e300).
TEST(CliDescribedDevices, FiveBarRefusesATargetOffItsPlane) {
  const auto off = run_linkscape("eval -m " + kFiveBar + " --ik " +
                                 temp_file("five_bar_off_plane.csv", "x,y,z\n0,17,1e300\n").string());
  EXPECT_EQ(off.exit_code, 2) << off.out;
  EXPECT_TRUE(contains(off.out, "z = 1e+300") && contains(off.out, "five-bar is planar") &&
              contains(off.out, "plane z = 0"))
      << off.out;
  // Without a z column its targets lie in its plane: the same rows as with z = 0.
  const auto in_plane = run_linkscape("eval -m " + kFiveBar + " --ik " + temp_file("five_bar_xy.csv", "x,y\n0,15\n").string());
  const auto with_z = run_linkscape("eval -m " + kFiveBar + " --ik " + temp_file("five_bar_xyz.csv", "x,y,z\n0,15,0\n").string());
  EXPECT_EQ(in_plane.exit_code, 0) << in_plane.out;
  EXPECT_EQ(in_plane.out, with_z.out);
  EXPECT_TRUE(contains(in_plane.out, "0,15,0,0,ok,")) << in_plane.out;
}

// A pose the Stewart reaches only with a leg beyond its travel: the row names
// that leg, and its length is indeed outside [lmin, lmax] (the column was
// left empty; the window said "leg leg 4").
TEST(CliDescribedDevices, AnOutOfLimitsRowNamesTheLegBeyondItsTravel) {
  const fs::path in = temp_file("stewart_out_of_limits.csv", "x,y,z,rx,ry,rz\n5,0,12,0,0.5,0\n0,0,40,0,0,0\n");
  const auto r = run_linkscape("eval -m stewart --ik " + in.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto rows = parse_cells(r.out);
  ASSERT_EQ(rows.size(), 2u) << r.out;
  const linkscape::Preset preset = linkscape::load_preset("stewart");
  const double lmin = preset.parameters.at("lmin"), lmax = preset.parameters.at("lmax");
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("status"), "out-of-limits") << r.out;
    const std::string leg = row.at("failing_leg");
    ASSERT_EQ(leg.rfind("leg ", 0), 0u) << r.out;
    const double length = std::stod(row.at("l" + leg.substr(4)));
    EXPECT_TRUE(length < lmin || length > lmax) << leg << " has length " << length << " within [" << lmin << ", " << lmax << "]";
  }
}

// A device's stops are fields like any other: the Falcon (passive ranges and
// link capsules) slices its joint margin and clearance, and `field` writes
// both, with units, without being asked; the described Delta has cones but
// no link radii, so it has no clearance to show.
TEST(CliDescribedDevices, TheStopsFieldsAreSlicedAndWritten) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  for (const char* field : {"joint_margin", "clearance"}) {
    const fs::path png = dir / (std::string("falcon_") + field + ".png");
    const CommandResult r = run_linkscape(std::string("slice -m falcon -q --size 48x48 --field ") + field + " -o " +
                                          png.string(), "QT_QPA_PLATFORM=offscreen");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(fs::exists(png)) << field;
  }
  const fs::path csv = dir / "falcon_stops.csv";
  const CommandResult f = run_linkscape("field -m falcon -q --resolution 8 -o " + csv.string());
  ASSERT_EQ(f.exit_code, 0) << f.out;
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_TRUE(contains(header, ",joint_margin_deg")) << header;
  EXPECT_TRUE(contains(header, ",clearance_mm")) << header;
  const CommandResult delta = run_linkscape("slice -m delta-described -q --field clearance -o " +
                                            (dir / "never.png").string(), "QT_QPA_PLATFORM=offscreen");
  EXPECT_EQ(delta.exit_code, 2) << delta.out;
  EXPECT_TRUE(contains(delta.out, "joint_margin")) << delta.out;  // what it has, listed
}
