// Slice images and their colour maps, on the synthetic fields of
// field_render_fixture.h. Needs no display.
#include <gtest/gtest.h>
#include <unistd.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkStringArray.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <numbers>
#include <set>
#include <sstream>

#include "core/mechanisms/parallel12r/field.h"
#include "render/field_vtk.h"
#include "render/slice_image.h"
#include "render/workspace_mesh.h"
#include "tests/render/field_render_fixture.h"

using namespace linkscape;
using namespace linkscape::render::testing;
namespace fs = std::filesystem;

// ---------------------------------------------------------------- slices

TEST(SliceImage, ColourMapIsViridis) {
  const auto a = render::colour_of(0), b = render::colour_of(0.5), c = render::colour_of(1);
  EXPECT_NEAR(a[0], 0.267004, 1e-6);
  EXPECT_NEAR(a[2], 0.329415, 1e-6);
  EXPECT_NEAR(b[0], 0.128, 0.003);  // matplotlib: viridis(0.5) = (0.128, 0.565, 0.551)
  EXPECT_NEAR(b[1], 0.565, 0.003);
  EXPECT_NEAR(c[1], 0.906157, 1e-6);
  EXPECT_EQ(render::colour_of(std::nan("")), c);
  EXPECT_EQ(render::colour_of(7), c);
  render::SliceStyle cond;
  EXPECT_DOUBLE_EQ(render::normalised_value(1, cond), 0);
  EXPECT_NEAR(render::normalised_value(std::sqrt(10.0), cond), 0.5, 1e-12);
  EXPECT_EQ(render::normalised_value(std::numeric_limits<double>::infinity(), cond), 1);
  EXPECT_EQ(render::normalised_value(std::nan(""), cond), 1);
  EXPECT_EQ(render::colour_lookup_table("viridis", 32)->GetNumberOfTableValues(), 32);
}

namespace {

// CIELAB lightness L* of an sRGB colour (D65), the measure a perceptual map keeps monotonic.
double lightness(const std::array<double, 3>& rgb) {
  auto linear = [](double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
  const double y = 0.2126 * linear(rgb[0]) + 0.7152 * linear(rgb[1]) + 0.0722 * linear(rgb[2]);
  return y > 216.0 / 24389 ? 116 * std::cbrt(y) - 16 : y * 24389.0 / 27;
}

}  // namespace

TEST(SliceImage, SequentialMapsGetLighterAndTheDivergingMapIsSymmetric) {
  for (const char* map : {"viridis", "cividis"}) {
    double previous = -1;
    for (int i = 0; i <= 100; ++i) {
      const double l = lightness(render::colour_of(i / 100.0, map));
      EXPECT_GT(l, previous) << map << " at " << i;
      previous = l;
    }
  }
  // Diverging: lightest near the middle, equal lightness at equal distances from it, blue below and red above.
  for (int i = 0; i < 50; ++i) {
    const double lo = lightness(render::colour_of(i / 100.0, "diverging"));
    const double hi = lightness(render::colour_of(1 - i / 100.0, "diverging"));
    EXPECT_NEAR(lo, hi, 3.0) << i;  // L* units; Moreland's map is symmetric to within a few
    EXPECT_LT(lo, lightness(render::colour_of(0.5, "diverging")) + 1e-9);
  }
  EXPECT_GT(render::colour_of(0, "diverging")[2], render::colour_of(0, "diverging")[0]);
  EXPECT_GT(render::colour_of(1, "diverging")[0], render::colour_of(1, "diverging")[2]);
  EXPECT_THROW(render::colour_of(0.5, "jet"), std::invalid_argument);
  EXPECT_EQ(render::colour_maps().size(), 3u);
}

TEST(SliceImage, ColourBarTicksAreRoundNumbers) {
  EXPECT_EQ(render::colour_bar_ticks(1, 10, true), (std::vector<double>{1, 2, 3, 5, 10}));
  // Too many for 1-2-3-5 (11 over 2.6 decades): 1-3.
  EXPECT_EQ(render::colour_bar_ticks(0.00895, 3.76, true), (std::vector<double>{0.01, 0.03, 0.1, 0.3, 1, 3}));
  // Twelve decades: every second one.
  EXPECT_EQ(render::colour_bar_ticks(1e-12, 1, true), (std::vector<double>{1e-12, 1e-10, 1e-8, 1e-6, 1e-4, 1e-2, 1}));
  // Under a decade, with no 1-2-3-5 value inside (an isotropic force over
  // 1.085-1.363 N had a bar without a number): round linear steps.
  EXPECT_EQ(render::colour_bar_ticks(1.085, 1.363, true), render::nice_ticks(1.085, 1.363, 5));
  EXPECT_GE(render::colour_bar_ticks(1.085, 1.363, true).size(), 3u);
  EXPECT_EQ(render::colour_bar_ticks(1.5, 4.5, true), render::nice_ticks(1.5, 4.5, 5));  // only 2 and 3 inside
  EXPECT_EQ(render::colour_bar_ticks(1, 5, true), (std::vector<double>{1, 2, 3, 5}));  // three or more: as before
  const std::vector<double> linear = render::colour_bar_ticks(-0.37, 14.6, false);
  EXPECT_EQ(linear, (std::vector<double>{0, 2, 4, 6, 8, 10, 12, 14}));
}

TEST(SliceImage, TheDivergingMapCentresZeroForSignedData) {
  Field f = cube_ball(8);
  std::fill(f.reachable.begin(), f.reachable.end(), true);  // margins of both signs count
  render::SliceStyle style;
  style.field = "reach";
  style.colour_map = "diverging";
  style.log_scale = false;
  const auto [lo, hi] = render::colour_range(f, style);
  EXPECT_DOUBLE_EQ(lo, -hi);
  style.colour_map = "nope";
  EXPECT_THROW(render::colour_range(f, style), std::invalid_argument);
}

TEST(SliceImage, RangesDefaultToReachableData) {
  const Field f = ball_field({-1.3, -1.3, 0}, {1.3, 1.3, 0.1}, {40, 40, 1});
  EXPECT_EQ(render::colour_range(f, {}), std::make_pair(1.0, 10.0));
  render::SliceStyle residual;
  residual.field = "residual";
  const auto [lo, hi] = render::colour_range(f, residual);
  EXPECT_GT(lo, 1e-9);
  EXPECT_LT(hi, 2e-9);
  EXPECT_THROW(render::normalised_value(1.5e-9, residual), std::invalid_argument);  // range unknown
  EXPECT_NEAR(render::normalised_value(lo, render::resolved_style(f, residual)), 0, 1e-12);
  render::SliceStyle iterations;
  iterations.field = "iterations";
  iterations.max = 100;
  EXPECT_EQ(render::colour_range(f, iterations).second, 100);
  render::SliceStyle bad_log;
  bad_log.min = 0;
  EXPECT_THROW(render::colour_range(f, bad_log), std::invalid_argument);
}

TEST(SliceImage, PngWithoutDisplayShowsGreyViridisAndContours) {
  ::unsetenv("DISPLAY");  // as under ctest: nothing here may need an X server
  Folder dir;
  // Slice z = 0 through a ball at c = (0.3, 0.2): asymmetric, so a flipped
  // axis would show. 130 x 104 samples of 0.02, drawn 2 px per sample.
  const Eigen::Vector3d c(0.3, 0.2, 0);
  const Field f = ball_field({-1.3, -1.04, -0.01}, {1.3, 1.04, 0.01}, {130, 104, 1}, c);
  render::SliceStyle style;
  style.scale = 2;
  render::write_slice_png(f, style, dir / "slice.png");
  EXPECT_EQ(dir.names(), std::vector<std::string>{"slice.png"});

  vtkNew<vtkPNGReader> reader;
  reader->SetFileName((dir / "slice.png").c_str());
  reader->Update();
  vtkImageData* png = reader->GetOutput();
  int dims[3];
  png->GetDimensions(dims);
  ASSERT_EQ(dims[0], 260);
  ASSERT_EQ(dims[1], 208);
  ASSERT_EQ(png->GetNumberOfScalarComponents(), 4);
  auto rendered = render::render_slice_rgba(f, style);
  for (int y = 0; y < 208; y += 7)
    for (int x = 0; x < 260; x += 5) ASSERT_EQ(pixel(png, x, y), pixel(rendered, x, y)) << x << "," << y;

  // Pixel of a point in the slice plane (VTK image: y up).
  auto at = [&](double px, double py) {
    return std::pair{int((px + 1.3) / 0.02 * 2), int((py + 1.04) / 0.02 * 2)};
  };
  auto colour = [&](double px, double py) {
    const auto [x, y] = at(px, py);
    return pixel(png, x, y);
  };
  const std::array<int, 4> grey{217, 217, 217, 255};
  EXPECT_EQ(colour(-1.2, -0.9), grey);
  EXPECT_EQ(colour(-1.0, 0.2), grey);  // |p - c| = 1.3
  EXPECT_NE(colour(1.2, 0.2), grey);   // |p - c| = 0.9: reachable, so x points right
  EXPECT_NE(colour(0.3, 1.0), grey);   // |p - c| = 0.8: reachable, so y points up
  EXPECT_EQ(colour(0.3, -0.9), grey);  // |p - c| = 1.1
  // Inside: viridis of the sample's cond (about 1 + 4 * 0.2).
  const auto [ix, iy] = at(0.5, 0.2);
  const double cond = f.cond[f.grid.index(ix / 2, iy / 2, 0)];
  EXPECT_NEAR(cond, 1.8, 0.06);
  const auto rgb = render::colour_of(render::normalised_value(cond, style));
  const auto inside = colour(0.5, 0.2);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(inside[k], rgb[k] * 255, 1.0);
  for (int y = 0; y < 208; ++y)
    for (int x = 0; x < 260; ++x) ASSERT_EQ(pixel(png, x, y)[3], 255);

  // White (not in viridis) within one pixel of the cond = 3 circle
  // (|p - c| = 0.5), none at 0.35 or 0.65; dark grey on the boundary.
  auto near_colour = [&](double px, double py, std::array<int, 3> want) {
    const auto [x0, y0] = at(px, py);
    for (int y = y0 - 1; y <= y0 + 1; ++y)
      for (int x = x0 - 1; x <= x0 + 1; ++x) {
        if (x < 0 || y < 0 || x >= 260 || y >= 208) continue;
        const auto p = pixel(png, x, y);
        if (p[0] == want[0] && p[1] == want[1] && p[2] == want[2]) return true;
      }
    return false;
  };
  int on = 0, off = 0, boundary = 0, boundary_tested = 0;
  for (int a = 0; a < 36; ++a) {
    const double t = a * std::numbers::pi / 18, ct = std::cos(t), st = std::sin(t);
    on += near_colour(c.x() + 0.5 * ct, c.y() + 0.5 * st, {255, 255, 255});
    off += near_colour(c.x() + 0.35 * ct, c.y() + 0.35 * st, {255, 255, 255});
    off += near_colour(c.x() + 0.65 * ct, c.y() + 0.65 * st, {255, 255, 255});
    const double bx = c.x() + 0.99 * ct, by = c.y() + 0.99 * st;
    if (by < 1.0 && bx < 1.25) {  // the box cuts the ball at y = 1.04 and touches it at x = 1.3
      ++boundary_tested;
      const bool found = near_colour(bx, by, {64, 64, 64});
      boundary += found;
      if (!found) std::cout << "no boundary pixel near angle " << a * 10 << " deg\n";
    }
  }
  EXPECT_EQ(on, 36);
  EXPECT_EQ(off, 0);
  EXPECT_EQ(boundary, boundary_tested);
}

TEST(SliceImage, SliceAxesFollowTheNormal) {
  // An x-normal slice: u = y (right), v = z (up); reachable only at z > 0.
  Field f = ball_field({0, -1, -1}, {0.1, 1, 1}, {1, 20, 10}, {0, 0, 0}, 1.0,
                       [](double) { return 1.0; });
  for (int k = 0; k < 10; ++k)
    for (int j = 0; j < 20; ++j) f.reachable[f.grid.index(0, j, k)] = f.grid.point(0, j, k).z() > 0;
  render::SliceStyle style;
  style.contour_levels.clear();
  style.draw_reach_boundary = false;
  auto image = render::render_slice_rgba(f, style);
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 20);
  EXPECT_EQ(dims[1], 10);
  EXPECT_EQ(pixel(image, 3, 1)[0], 217);  // bottom row: z < 0, grey
  EXPECT_NE(pixel(image, 3, 8)[0], 217);  // top: z > 0
}

// Every field colour-maps its reachable samples opaquely; only samples outside
// the workspace take the style's unreachable opacity (faint in the 3-D view).
TEST(SliceImage, ReachableSamplesAreOpaqueForEveryField) {
  parallel12r::Model m;
  FieldRequest r;
  r.grid = Grid::slice(Axis::Y, 0.5, -2, 2, -2, 2, 32, 32);
  r.method = parallel12r::IkMethod::Fallback;
  const Field f = *compute_field(m, r);
  for (const char* name : {"cond", "reach", "residual", "iterations", "status", "method"}) {
    render::SliceStyle style;
    style.field = name;
    style.log_scale = std::string(name) == "cond";
    style.contour_levels.clear();
    style.draw_reach_boundary = false;
    style.unreachable_alpha = 40;
    const auto image = render::render_slice_rgba(f, style);
    const auto* rgba = static_cast<const unsigned char*>(image->GetScalarPointer());
    int opaque = 0, faint = 0;
    for (int v = 0; v < 32; ++v)
      for (int u = 0; u < 32; ++u) {
        const unsigned char alpha = rgba[4 * (u + 32 * v) + 3];
        const bool reachable = f.reachable[f.grid.index(u, 0, v)];
        EXPECT_EQ(alpha, reachable ? 255 : 40) << name << " at " << u << "," << v;
        (reachable ? opaque : faint) += 1;
      }
    EXPECT_GT(opaque, 300) << name;
    EXPECT_GT(faint, 50) << name;
  }
}
