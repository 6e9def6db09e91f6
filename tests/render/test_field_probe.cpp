// The window's pick read-out and line probe read the Field: trilinear where
// the samples around a point hold values, the nearest sample otherwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <filesystem>
#include <fstream>

#include "core/csv.h"
#include "core/status.h"
#include "render/field_probe.h"
#include "tests/render/field_fixture.h"

namespace linkscape::render {
namespace {

// A field whose continuous arrays are linear in x, y, z (trilinear
// interpolation reproduces them exactly) and whose codes vary per sample.
double cond_at(const Eigen::Vector3d& p) { return 2 + 0.5 * p.x() + 0.25 * p.y() + 0.125 * p.z(); }
double margin_at(const Eigen::Vector3d& p) { return 1 - 0.1 * p.x() + 0.2 * p.z(); }

Field linear_field() {
  Field f = testing::sized_field(Grid::box({0, 0, 0}, {4, 3, 2}, {4, 3, 2}));  // unit cells, samples at .5
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) {
        const std::size_t s = f.grid.index(i, j, k);
        const Eigen::Vector3d p = f.grid.point(i, j, k);
        f.cond[s] = float(cond_at(p));
        f.reach_margin[s] = float(margin_at(p));
        f.residual[s] = 1e-9f;
        f.reachable[s] = 1;
        f.status[s] = std::uint8_t(Status::Ok);
        f.iterations[s] = std::uint16_t(i + 10 * j);
        f.method_used[s] = 1;
      }
  f.method_names = {"paper", "planar"};  // as a device's sampler names its codes
  Field::NamedArray force{"force_iso", "isotropic force", "N", "", {}};
  force.values.assign(f.cond.begin(), f.cond.end());
  f.extras.push_back(force);
  return f;
}

TEST(FieldProbe, TrilinearInsideReachableCellsReproducesALinearField) {
  const Field f = linear_field();
  const Eigen::Vector3d p(1.3, 1.7, 0.9);
  const auto s = probe_point(f, p);
  ASSERT_TRUE(s);
  const ProbeValue* cond = s->find("cond");
  ASSERT_NE(cond, nullptr);
  EXPECT_EQ(cond->sampling, Sampling::Trilinear);
  EXPECT_NEAR(cond->value, cond_at(p), 1e-6);
  EXPECT_NEAR(s->find("reach")->value, margin_at(p), 1e-6);
  EXPECT_EQ(s->find("reach")->unit, "cm");
  EXPECT_EQ(s->find("force_iso")->unit, "N");
  EXPECT_NEAR(s->find("force_iso")->value, cond_at(p), 1e-6);
  // Codes are never blended: the nearest sample (1, 1, 0) + 0.5.
  EXPECT_EQ(s->nearest, (std::array<int, 3>{1, 1, 0}));
  EXPECT_EQ(s->find("iterations")->sampling, Sampling::Nearest);
  EXPECT_EQ(s->find("iterations")->value, 11);
  EXPECT_EQ(s->find("status")->label, "ok");
  EXPECT_EQ(s->find("method")->label, "planar");
}

TEST(FieldProbe, AnUnreachableNeighbourFallsBackToTheNearestSample) {
  Field f = linear_field();
  const std::size_t hole = f.grid.index(2, 1, 0);
  f.reachable[hole] = 0;
  f.cond[hole] = std::numeric_limits<float>::infinity();
  f.status[hole] = std::uint8_t(Status::Unreachable);
  // Nearest is (1, 1, 0), reachable: its own value.
  const auto s = probe_point(f, {1.9, 1.6, 0.6});
  ASSERT_TRUE(s);
  EXPECT_EQ(s->find("cond")->sampling, Sampling::Nearest);
  EXPECT_FLOAT_EQ(s->find("cond")->value, f.cond[f.grid.index(1, 1, 0)]);
  // The reach margin is defined everywhere: still interpolated.
  EXPECT_EQ(s->find("reach")->sampling, Sampling::Trilinear);
  // At the unreachable sample itself: no value, and the status says why.
  const auto at_hole = probe_point(f, {2.6, 1.5, 0.5});
  ASSERT_TRUE(at_hole);
  EXPECT_TRUE(std::isnan(at_hole->find("cond")->value));
  EXPECT_EQ(at_hole->find("status")->label, "unreachable");
  EXPECT_EQ(at_hole->find("reachable")->label, "no");
}

TEST(FieldProbe, OutsideTheCellsThereIsNothing) {
  const Field f = linear_field();
  EXPECT_TRUE(probe_point(f, {0, 0, 0}));  // a corner of the outer cells
  EXPECT_FALSE(probe_point(f, {-0.01, 1, 1}));
  EXPECT_FALSE(probe_point(f, {1, 1, 2.01}));
}

TEST(FieldProbe, ASliceIsReadOnItsPlane) {
  Field f = testing::sized_field(Grid::slice(Axis::Z, 0.5, 0, 4, 0, 3, 4, 3));
  std::fill(f.reachable.begin(), f.reachable.end(), std::uint8_t(1));
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) f.cond[f.grid.index(i, j, 0)] = float(cond_at(f.grid.point(i, j, 0)));
  const Eigen::Vector3d p(2.2, 0.8, 0.5);
  const auto s = probe_point(f, p);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->find("cond")->sampling, Sampling::Trilinear);
  EXPECT_NEAR(s->find("cond")->value, cond_at(p), 1e-6);
  EXPECT_FALSE(probe_point(f, {2.2, 0.8, 2.0}));  // off the plane's cell
}

TEST(FieldProbe, LineProfileFollowsTheFieldAndReadsBackAsCsv) {
  const Field f = linear_field();
  const Eigen::Vector3d a(0.5, 0.5, 0.5), b(3.5, 2.5, 1.5);
  const LineProfile line = probe_line(f, "cond", a, b, 11);
  ASSERT_EQ(line.values.size(), 11u);
  EXPECT_NEAR(line.distance.back(), (b - a).norm(), 1e-12);
  for (std::size_t k = 0; k < line.values.size(); ++k) EXPECT_NEAR(line.values[k], cond_at(line.points[k]), 1e-6);

  const auto path = std::filesystem::temp_directory_path() / "linkscape_line_probe_test.csv";
  write_profile_csv(probe_line(f, "reach", a, b, 9), path);
  {
    std::ifstream in(path);
    const Table t = read_csv(in, path.string());
    ASSERT_EQ(t.rows.size(), 9u);
    const std::size_t dist = t.column("distance (cm)"), value = t.column("reach (cm)"), tri = t.column("trilinear");
    const std::size_t x = t.column("x (cm)");
    for (const auto& row : t.rows) {
      const Eigen::Vector3d p(row[x], row[x + 1], row[x + 2]);
      EXPECT_NEAR(row[dist], (p - a).norm(), 1e-9);
      EXPECT_NEAR(row[value], margin_at(p), 1e-6);
      EXPECT_EQ(row[tri], 1);
    }
  }
  // Beyond the box a point has no value: an empty cell.
  write_profile_csv(probe_line(f, "reach", a, {5.5, 0.5, 0.5}, 3), path);
  std::ifstream in(path);
  std::string text, last;
  while (std::getline(in, text)) last = text;
  std::filesystem::remove(path);
  const std::vector<std::string> cells = csv_cells(last);
  ASSERT_EQ(cells.size(), 6u);
  EXPECT_EQ(cells[0], "5");
  EXPECT_EQ(cells[4], "");
}

TEST(FieldProbe, BadRequestsSayWhatWasExpected) {
  const Field f = linear_field();
  EXPECT_THROW(probe_line(f, "cond", {0, 0, 0}, {1, 1, 1}, 1), std::invalid_argument);
  try {
    probe_line(f, "nonsense", {0, 0, 0}, {1, 1, 1}, 5);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("force_iso"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace linkscape::render
