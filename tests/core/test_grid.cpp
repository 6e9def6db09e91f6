// The grids every device's field samples (core/field.h).
#include <gtest/gtest.h>

#include <stdexcept>

#include "core/field.h"

using namespace linkscape;

TEST(Grid, SamplesSitAtCellCentresInVtkOrder) {
  const Grid g = Grid::slice(Axis::Y, 0.25, -1, 1, 0, 2, 4, 2);
  EXPECT_EQ(g.dims, (std::array<int, 3>{4, 1, 2}));
  EXPECT_TRUE(g.point(0, 0, 0).isApprox(Eigen::Vector3d(-0.75, 0.25, 0.5)));
  EXPECT_TRUE(g.point(3, 0, 1).isApprox(Eigen::Vector3d(0.75, 0.25, 1.5)));
  EXPECT_EQ(g.index(1, 0, 1), 5u);
  const Grid b = Grid::box({-1, -1, -1}, {1, 1, 1}, {2, 2, 2});
  EXPECT_TRUE(b.point(1, 1, 1).isApprox(Eigen::Vector3d(0.5, 0.5, 0.5)));
  EXPECT_THROW(Grid::slice(Axis::X, 0, 1, 1, 0, 1, 4, 4), std::invalid_argument);
  EXPECT_THROW(Grid::box({0, 0, 0}, {1, 1, 1}, {0, 2, 2}), std::invalid_argument);
  EXPECT_THROW(parse_axis("w"), std::invalid_argument);
}
