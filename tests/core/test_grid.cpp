// The grids every device's field samples (core/field.h).
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <vector>

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

// A field re-sampled on the same grid gets its arrays' pages back, already
// mapped, instead of freshly zeroed ones (core/field.h).
TEST(SampleArrays, ALargeBlockFreedIsHandedOutAgainForTheSameSize) {
  using linkscape::SampleArray;
  constexpr std::size_t n = std::size_t(3) << 20;  // 12 MiB of floats
  const float* first;
  {
    SampleArray<float> a(n);
    a[n - 1] = 1.0f;
    first = a.data();
  }
  SampleArray<float> again(n);
  EXPECT_EQ(again.data(), first);
  SampleArray<float> other(n);  // the block is in use: a new one
  EXPECT_NE(other.data(), first);
}

TEST(SampleArrays, TheBlocksKeptAreBoundedAndTheOldestGoFirst) {
  using linkscape::SampleArray;
  constexpr std::size_t n = std::size_t(100) << 20;  // 400 MiB of floats each, never touched
  std::vector<const float*> freed;
  {
    SampleArray<float> a(n), b(n), c(n);
    freed = {a.data(), b.data(), c.data()};
  }  // destroyed c, b, a: at most 1 GiB is kept, so c (freed first) was let go
  SampleArray<float> x(n), y(n);
  EXPECT_EQ((std::set<const float*>{x.data(), y.data()}), (std::set<const float*>{freed[0], freed[1]}));
}
