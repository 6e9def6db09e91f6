// Automatic colour ranges from percentiles, centred diverging ranges,
// integer ticks and the legends of categorical fields.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/status.h"
#include "render/colour_scale.h"
#include "tests/render/field_fixture.h"

namespace linkscape::render {
namespace {

// 100 reachable samples of force 0.01 .. 1.00 N plus one spike of 3.74 N,
// and one unreachable sample whose value must not count.
Field spiky_field() {
  Field f = testing::sized_field(Grid::slice(Axis::Z, 0, 0, 102, 0, 1, 102, 1));
  Field::NamedArray force{"force_iso", "isotropic force", "N", "", {}};
  force.values.resize(f.grid.size());
  for (int i = 0; i < 102; ++i) {
    f.reachable[i] = i < 101;
    f.cond[i] = 2;
    f.reach_margin[i] = i < 101 ? 0.5f + 0.01f * i : -1.0f;
    force.values[i] = i < 100 ? 0.01f * (i + 1) : i == 100 ? 3.74f : 50.0f;
    f.iterations[i] = std::uint16_t(i % 7);
    f.status[i] = std::uint8_t(i < 101 ? Status::Ok : Status::Unreachable);
    f.method_used[i] = i < 101 ? std::uint8_t(i % 2) : Field::kNoMethod;
  }
  f.extras.push_back(force);
  return f;
}

TEST(ColourScale, PercentileInterpolatesBetweenRanks) {
  EXPECT_DOUBLE_EQ(percentile({4, 1, 3, 2}, 0.5), 2.5);  // numpy.percentile([1,2,3,4], 50)
  EXPECT_DOUBLE_EQ(percentile({1, 2, 3, 4, 5}, 0.99), 4.96);
  EXPECT_DOUBLE_EQ(percentile({7}, 0.3), 7);
  EXPECT_THROW(percentile({}, 0.5), std::invalid_argument);
  EXPECT_THROW(percentile({1}, 1.5), std::invalid_argument);
}

TEST(ColourScale, ASpikeDoesNotSetTheAutomaticRange) {
  const Field f = spiky_field();
  SliceStyle style;
  style.field = "force_iso";
  style.log_scale = false;
  const AutoRange r = robust_range(f, style);
  // The 99th percentile of the 101 reachable values, not the spike (nor the unreachable 50 N).
  std::vector<double> values;
  for (int i = 0; i < 101; ++i) values.push_back(f.extras[0].values[i]);
  EXPECT_NEAR(r.hi, percentile(values, 0.99), 1e-12);
  EXPECT_LT(r.hi, 1.01);
  EXPECT_TRUE(r.clipped_high);
  EXPECT_TRUE(r.clipped_low);  // 0.01 lies below the 1st percentile
  // The full range, as colour_range gives it, is set by the spike.
  EXPECT_NEAR(colour_range(f, style).second, 3.74, 1e-6);
}

TEST(ColourScale, TheDivergingMapIsCentredOnZero) {
  const Field f = spiky_field();
  SliceStyle style;
  style.field = "reach";
  style.colour_map = "diverging";
  const AutoRange r = robust_range(f, style);  // every reachable margin is positive
  EXPECT_DOUBLE_EQ(r.lo, -r.hi);
  EXPECT_GT(r.hi, 1.4);
  // A field of one sign keeps its own range: centred on 0 it had been drawn
  // in one half of the map (an isotropic force of 1.09-1.36 N, one shade).
  style.field = "force_iso";
  style.log_scale = false;
  const AutoRange positive = robust_range(f, style);
  EXPECT_GT(positive.lo, 0);
  EXPECT_FALSE(render::centres_zero("force_iso", 1.09, 1.36));
  EXPECT_TRUE(render::centres_zero("clearance", 1, 2));  // a margin, negative past its stop
}

TEST(ColourScale, CountsGetWholeNumbers) {
  const Field f = spiky_field();
  SliceStyle style;
  style.field = "iterations";
  const AutoRange r = robust_range(f, style);
  EXPECT_EQ(r.lo, std::floor(r.lo));
  EXPECT_EQ(r.hi, std::floor(r.hi));
  for (double t : integer_ticks(0, 3)) EXPECT_EQ(t, std::round(t)) << t;
  EXPECT_EQ(integer_ticks(0, 3).size(), 4u);  // 0, 1, 2, 3: nice_ticks would give halves
  EXPECT_EQ(integer_ticks(0, 100).front(), 0);
}

TEST(ColourScale, CategoricalLegendsNameTheirCodes) {
  Field f = spiky_field();
  SliceStyle style;
  style.field = "status";
  const std::vector<LegendEntry> status = categorical_legend(f, style);
  ASSERT_EQ(status.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(status[k].label, to_string(Status(k)));
    EXPECT_EQ(status[k].value, k);
  }
  // Each status its own colour, as the slice draws it with categorical_style.
  for (int k = 1; k < 5; ++k) EXPECT_NE(status[k].rgb, status[k - 1].rgb);
  style.field = "method";
  const std::vector<LegendEntry> methods = categorical_legend(f, style);
  ASSERT_EQ(methods.size(), 2u);  // the codes reachable samples hold
  EXPECT_EQ(methods[0].label, "method code 0");  // no names recorded
  EXPECT_EQ(methods[1].label, "method code 1");
  f.method_names = {"closed", "newton"};  // as a device's sampler names its codes
  const std::vector<LegendEntry> named = categorical_legend(f, style);
  ASSERT_EQ(named.size(), 2u);
  EXPECT_EQ(named[0].label, "closed");
  EXPECT_EQ(named[1].label, "newton");
  EXPECT_EQ(named[1].rgb, methods[1].rgb);  // the code keeps its colour
  style.field = "cond";
  EXPECT_TRUE(categorical_legend(f, style).empty());
}

}  // namespace
}  // namespace linkscape::render
