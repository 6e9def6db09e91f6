// The exported workspace of the real mechanism: the field engine of core
// feeding the isosurfaces of render, as `linkscape mesh` does.
#include <gtest/gtest.h>
#include <vtkPolyData.h>

#include <numbers>

#include "core/mechanisms/parallel12r/field.h"
#include "render/workspace_mesh.h"

using namespace linkscape;

namespace {

Field sample_cube(const parallel12r::Model& m, int n) {
  FieldRequest r;
  const double R = m.reach();
  r.grid = Grid::box({-R, -R, -R}, {R, R, R}, {n, n, n});
  return *compute_field(m, r);
}

}  // namespace

TEST(Workspace12R, ReachMeshIsAWatertightBallConvergingToTheAnalyticVolume) {
  const parallel12r::Model m;  // L1 = L2 = 1: the reachable set is the ball of radius 2
  const double analytic = 4.0 / 3.0 * std::numbers::pi * 8.0;
  double previous_error = 1.0;
  for (int n : {24, 48, 96}) {
    const auto mesh = render::extract_surface(sample_cube(m, n), {});
    const render::MeshStats s = render::mesh_stats(mesh);
    EXPECT_EQ(s.boundary_edges, 0u) << n;
    EXPECT_EQ(s.non_manifold_edges, 0u) << n;
    EXPECT_EQ(s.euler_characteristic, 2) << n;  // one sphere
    const double error = std::abs(s.volume - analytic) / analytic;
    EXPECT_LT(error, previous_error) << n;  // converges with resolution
    previous_error = error;
  }
  // Second order: measured 0.02 % at 96^3 (docs/performance.md).
  EXPECT_LT(previous_error, 1e-3);
}

TEST(Workspace12R, HollowShellForUnequalLinks) {
  parallel12r::Model m;
  m.L2 = 0.5;  // reachable between radii 0.5 and 1.5
  const auto mesh = render::extract_surface(sample_cube(m, 64), {});
  const render::MeshStats s = render::mesh_stats(mesh);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.euler_characteristic, 4);  // outer and inner sphere
  const double analytic = 4.0 / 3.0 * std::numbers::pi * (1.5 * 1.5 * 1.5 - 0.125);
  EXPECT_NEAR(s.volume, analytic, 5e-3 * analytic);
}

TEST(Workspace12R, WellConditionedRegionHasTheExtentsOfFigure5) {
  // Two components (y > 0 and y < 0, split by the singular actuator plane),
  // spanning 2.93 in x and 3.67 in z for L = 1 (cf. the grid measurement in
  // tests/core/mechanisms/parallel12r/test_paper_claims.cpp).
  const parallel12r::Model m;
  render::SurfaceRequest request;
  request.surface = render::Surface::WellConditioned;
  const auto mesh = render::extract_surface(sample_cube(m, 96), request);
  const render::MeshStats s = render::mesh_stats(mesh);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.euler_characteristic, 4);
  EXPECT_NEAR(s.max.x() - s.min.x(), 2.93, 0.05);
  EXPECT_NEAR(s.max.z() - s.min.z(), 3.67, 0.05);
  EXPECT_NEAR(s.max.y(), 1.81, 0.03);
}
