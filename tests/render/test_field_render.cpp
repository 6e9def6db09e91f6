// Field export (.vti, .csv), slice images and workspace meshes, on synthetic
// fields built here (no kinematics): a ball of radius 1 at the origin where
// reach_margin = 1 - |p| and cond = 1 + 4|p| (so cond < 3 is the ball of
// radius 0.5). Needs no display: ctest runs it with DISPLAY unset.
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

using namespace linkscape;
namespace fs = std::filesystem;

namespace {

// A request for one of the two workspace surfaces (the other members at their defaults).
render::SurfaceRequest surface_request(render::Surface surface, double cond_threshold = 3.0) {
  render::SurfaceRequest r;
  r.surface = surface;
  r.cond_threshold = cond_threshold;
  return r;
}

// A field of `dims` samples on the box [lo, hi] (cell-centred), filled from
// the distance d of each sample to `centre`: reachable inside radius `radius`.
Field ball_field(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::array<int, 3> dims,
                 const Eigen::Vector3d& centre = Eigen::Vector3d::Zero(), double radius = 1.0,
                 std::function<double(double)> margin = {}) {
  Field f;
  f.grid.origin = lo;
  f.grid.dims = dims;
  for (int a = 0; a < 3; ++a) f.grid.spacing[a] = (hi[a] - lo[a]) / dims[a];
  const std::size_t n = f.grid.size();
  f.cond.resize(n);
  f.reach_margin.resize(n);
  f.residual.resize(n);
  f.reachable.resize(n);
  f.status.resize(n);
  f.iterations.resize(n);
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const std::size_t s = f.grid.index(i, j, k);
        const double d = (f.grid.point(i, j, k) - centre).norm();
        const float m = float(margin ? margin(d) : radius - d);
        const bool inside = m > 0;
        f.reach_margin[s] = m;
        f.reachable[s] = inside;
        f.cond[s] = inside ? float(1 + 4 * d) : std::numeric_limits<float>::infinity();
        f.residual[s] = inside ? float(1e-9 * (1 + d)) : std::numeric_limits<float>::infinity();
        f.status[s] = inside ? 0 : 3;
        f.iterations[s] = std::uint16_t(inside ? 3 + int(10 * d) : 50);
      }
  f.mechanism = "test-ball";
  f.length_unit = "mm";
  f.method = "synthetic";
  f.parameters = {{"L1", 15.0}, {"L2", 15.5}};
  f.branch = 1;
  return f;
}

Field cube_ball(int n, double half = 1.3) {
  return ball_field(Eigen::Vector3d::Constant(-half), Eigen::Vector3d::Constant(half), {n, n, n});
}

// A fresh folder per test, removed afterwards; `leftovers()` lists any file
// that is not one of the expected outputs (temporaries are hidden ".*.tmp*").
class Folder {
 public:
  Folder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("linkscape_field_render_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~Folder() { fs::remove_all(path_); }
  fs::path operator/(const std::string& name) const { return path_ / name; }
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(path_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  fs::path path_;
};

std::string string_of(vtkFieldData* fd, const char* name) {
  auto* a = vtkStringArray::SafeDownCast(fd->GetAbstractArray(name));
  return a && a->GetNumberOfValues() == 1 ? a->GetValue(0) : "<missing>";
}
double number_of(vtkFieldData* fd, const char* name, int component = 0) {
  vtkDataArray* a = fd->GetArray(name);
  return a ? a->GetComponent(component / a->GetNumberOfComponents(), component % a->GetNumberOfComponents())
           : std::nan("");
}

std::array<int, 4> pixel(vtkImageData* image, int x, int y) {
  auto* p = static_cast<unsigned char*>(image->GetScalarPointer(x, y, 0));
  return {p[0], p[1], p[2], p[3]};
}

const double kBallVolume = 4.0 / 3.0 * std::numbers::pi;

}  // namespace

// ---------------------------------------------------------------- image data

TEST(FieldVtk, ImageDataHasEveryArrayAtCellCentres) {
  const Field f = cube_ball(8);
  auto image = render::to_image_data(f);
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 8);
  EXPECT_EQ(dims[2], 8);
  EXPECT_NEAR(image->GetOrigin()[0], -1.3 + 0.5 * 2.6 / 8, 1e-12);
  EXPECT_NEAR(image->GetSpacing()[1], 2.6 / 8, 1e-12);
  double p[3];
  image->GetPoint(vtkIdType(f.grid.index(3, 5, 7)), p);
  EXPECT_TRUE((Eigen::Vector3d(p) - f.grid.point(3, 5, 7)).norm() < 1e-12);
  for (const char* name : {"cond", "reach_margin", "residual", "reachable", "status", "iterations"})
    ASSERT_NE(image->GetPointData()->GetArray(name), nullptr) << name;
  const std::size_t s = f.grid.index(4, 4, 4);
  EXPECT_EQ(image->GetPointData()->GetArray("cond")->GetComponent(vtkIdType(s), 0), f.cond[s]);
  EXPECT_EQ(image->GetPointData()->GetArray("iterations")->GetComponent(vtkIdType(s), 0), f.iterations[s]);
}

// Every compressor (the default, LZ4, and the others the size/time table of
// docs/performance.md compares) reads back to the same arrays.
class FieldVtkCompression : public ::testing::TestWithParam<render::VtiCompression> {};

TEST_P(FieldVtkCompression, VtiRoundTripCarriesArraysAndMetadata) {
  Folder dir;
  const Field f = cube_ball(12);
  render::write_vti(f, dir / "field.vti", GetParam());
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName((dir / "field.vti").c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0] * dims[1] * dims[2], 12 * 12 * 12);
  // c(J) and the residual exist only where the device reaches the sample:
  // NaN elsewhere (not +inf), with `reachable` beside them.
  const double none = std::numeric_limits<double>::quiet_NaN();
  const std::pair<const char*, std::function<double(std::size_t)>> arrays[] = {
      {"cond", [&](std::size_t s) { return f.reachable[s] ? double(f.cond[s]) : none; }},
      {"reach_margin", [&](std::size_t s) { return double(f.reach_margin[s]); }},
      {"residual", [&](std::size_t s) { return f.reachable[s] ? double(f.residual[s]) : none; }},
      {"reachable", [&](std::size_t s) { return double(f.reachable[s]); }},
      {"status", [&](std::size_t s) { return double(f.status[s]); }},
      {"iterations", [&](std::size_t s) { return double(f.iterations[s]); }},
  };
  for (const auto& [name, expected] : arrays) {
    vtkDataArray* a = image->GetPointData()->GetArray(name);
    ASSERT_NE(a, nullptr) << name;
    ASSERT_EQ(a->GetNumberOfTuples(), vtkIdType(f.grid.size()));
    std::size_t mismatches = 0;
    std::size_t nans = 0;
    for (std::size_t s = 0; s < f.grid.size(); ++s) {
      const double read = a->GetComponent(vtkIdType(s), 0), want = expected(s);
      mismatches += std::isnan(want) ? !std::isnan(read) : read != want;
      nans += std::isnan(read);
    }
    EXPECT_EQ(mismatches, 0u) << name;
    if (std::string(name) == "cond") {
      EXPECT_GT(nans, 0u);  // the ball's outside
      double range[2];
      a->GetRange(range);  // what ParaView's automatic range reads: finite
      EXPECT_TRUE(std::isfinite(range[1])) << range[1];
    }
  }
  vtkFieldData* fd = image->GetFieldData();
  EXPECT_EQ(string_of(fd, "mechanism"), "test-ball");
  EXPECT_EQ(string_of(fd, "length_unit"), "mm");
  EXPECT_EQ(string_of(fd, "method"), "synthetic");
  EXPECT_EQ(number_of(fd, "branch"), 1);
  EXPECT_EQ(number_of(fd, "param_L1"), 15.0);
  EXPECT_EQ(number_of(fd, "param_L2"), 15.5);
  EXPECT_EQ(number_of(fd, "grid_samples", 0), 12);
  EXPECT_EQ(number_of(fd, "grid_samples", 2), 12);
  EXPECT_EQ(fd->GetArray("resolution"), nullptr);  // the haptic array's name is not reused
  EXPECT_EQ(dir.names(), std::vector<std::string>{"field.vti"});
}

using Compressor = render::VtiCompression::Type;
INSTANTIATE_TEST_SUITE_P(EveryCompressor, FieldVtkCompression,
                         ::testing::Values(render::VtiCompression{}, render::VtiCompression{Compressor::None, 1},
                                           render::VtiCompression{Compressor::LZ4, 9},
                                           render::VtiCompression{Compressor::ZLib, 5},
                                           render::VtiCompression{Compressor::LZMA, 1}));

TEST(FieldVtk, VtiRejectsACompressionLevelOutsideOneToNine) {
  Folder dir;
  const Field f = cube_ball(4);
  for (int level : {0, 10})
    EXPECT_THROW(render::write_vti(f, dir / "f.vti", {Compressor::ZLib, level}), std::invalid_argument) << level;
  EXPECT_TRUE(dir.names().empty());
}

TEST(FieldVtk, CsvHasOneShortestRowPerSampleXFastest) {
  Folder dir;
  Field f = ball_field({0, 0, 0}, {3, 2, 2}, {3, 2, 2});
  f.cond[1] = 0.1f;
  f.reachable[1] = 1;  // cond is written where the sample is reachable
  render::write_field_csv(f, dir / "field.csv");
  std::ifstream in(dir / "field.csv");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 1u + 12u);
  EXPECT_EQ(lines[0], "x_mm,y_mm,z_mm,cond,reach_margin_mm,residual_mm,reachable,iterations,status");
  EXPECT_EQ(lines[1].substr(0, 12), "0.5,0.5,0.5,");
  EXPECT_EQ(lines[2].substr(0, 16), "1.5,0.5,0.5,0.1,");  // x fastest; 0.1f written as 0.1
  EXPECT_EQ(lines[4].substr(0, 12), "0.5,1.5,0.5,");
  // The far corner (2.5, 1.5, 1.5) is unreachable: no cond and no residual.
  EXPECT_EQ(lines[12].substr(0, 13), "2.5,1.5,1.5,,");
  EXPECT_NE(lines[12].find(",,0,50,3"), std::string::npos) << lines[12];
  EXPECT_EQ(dir.names(), std::vector<std::string>{"field.csv"});
}

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

// ---------------------------------------------------------------- meshes

TEST(WorkspaceMesh, ReachBallIsClosedAndConverges) {
  double previous_error = 1;
  for (int n : {32, 64}) {
    const Field f = cube_ball(n);
    auto mesh = render::extract_surface(f, surface_request(render::Surface::Reach));
    const auto s = render::mesh_stats(mesh);
    const double error = std::abs(s.volume - kBallVolume) / kBallVolume;
    std::cout << "reach ball " << n << "^3: " << s.vertices << " vertices, " << s.faces << " faces, volume "
              << s.volume << " (error " << 100 * error << " %), area " << s.area << " (sphere "
              << 4 * std::numbers::pi << ")\n";
    EXPECT_EQ(s.boundary_edges, 0u);
    EXPECT_EQ(s.non_manifold_edges, 0u);
    EXPECT_EQ(s.euler_characteristic, 2);
    EXPECT_GT(s.volume, 0);
    EXPECT_LT(error, previous_error);
    previous_error = error;
    EXPECT_NEAR(s.max.x(), 1.0, 2.6 / n);
    EXPECT_NEAR(s.min.z(), -1.0, 2.6 / n);
    // Outward: normals point away from the centre.
    vtkDataArray* normals = mesh->GetPointData()->GetNormals();
    ASSERT_NE(normals, nullptr);
    for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); i += 97) {
      double p[3], nrm[3];
      mesh->GetPoint(i, p);
      normals->GetTuple(i, nrm);
      ASSERT_GT(Eigen::Vector3d(p).dot(Eigen::Vector3d(nrm)), 0.9);
    }
  }
  EXPECT_LT(previous_error, 0.01);
}

TEST(WorkspaceMesh, WellConditionedBallOfHalfRadius) {
  const Field f = cube_ball(64);
  const render::SurfaceRequest request = surface_request(render::Surface::WellConditioned, 3.0);
  const auto s = render::mesh_stats(render::extract_surface(f, request));
  const double expected = kBallVolume / 8;
  std::cout << "cond < 3 ball 64^3: " << s.faces << " faces, volume " << s.volume << " (error "
            << 100 * (s.volume - expected) / expected << " %)\n";
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_EQ(s.euler_characteristic, 2);
  EXPECT_NEAR(s.volume, expected, 0.02 * expected);
  EXPECT_NEAR(s.max.y(), 0.5, 0.02);
}

TEST(WorkspaceMesh, WellConditionedStaysInsideReach) {
  // cond < 3 out to |p| = 0.5 but reach only to 0.4: the surface is the reach ball.
  const Field f = ball_field(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1), {40, 40, 40}, {0, 0, 0},
                             0.4);
  const auto wc = render::mesh_stats(render::extract_surface(f, surface_request(render::Surface::WellConditioned, 3.0)));
  const auto reach = render::mesh_stats(render::extract_surface(f, surface_request(render::Surface::Reach)));
  EXPECT_EQ(wc.boundary_edges, 0u);
  EXPECT_LE(wc.volume, reach.volume * (1 + 1e-6));
  EXPECT_LE(wc.max.x(), reach.max.x() + 1e-6);
}

TEST(WorkspaceMesh, BallCutByTheBoxIsClosedOnTheBoxFaces) {
  const Field f = cube_ball(40, 0.8);
  const auto s = render::mesh_stats(render::extract_surface(f, surface_request(render::Surface::Reach)));
  std::cout << "ball cut by [-0.8, 0.8]^3: " << s.faces << " faces, volume " << s.volume << "\n";
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_EQ(s.euler_characteristic, 2);
  EXPECT_NEAR(s.min.x(), -0.8, 1e-5);
  EXPECT_NEAR(s.max.z(), 0.8, 1e-5);
  EXPECT_NEAR(s.volume, 3.4865, 0.005 * 3.4865);  // ball and cube intersection, by Monte Carlo (2e6 points)
}

TEST(WorkspaceMesh, HollowShellKeepsItsCavityInward) {
  // Reachable for 0.4 < |p| < 1: two spheres, the inner one facing the cavity.
  const Field f = ball_field(Eigen::Vector3d::Constant(-1.2), Eigen::Vector3d::Constant(1.2), {48, 48, 48},
                             {0, 0, 0}, 1.0, [](double d) { return 0.3 - std::abs(d - 0.7); });
  const auto s = render::mesh_stats(render::extract_surface(f, surface_request(render::Surface::Reach)));
  const double expected = kBallVolume * (1 - 0.4 * 0.4 * 0.4);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.euler_characteristic, 4);
  EXPECT_NEAR(s.volume, expected, 0.02 * expected);
}

TEST(WorkspaceMesh, DecimationKeepsTheBallClosed) {
  const Field f = cube_ball(64);
  const auto full = render::mesh_stats(render::extract_surface(f, surface_request(render::Surface::Reach)));
  render::SurfaceRequest request = surface_request(render::Surface::Reach);
  request.decimate_error = 0.005;  // an eighth of the sample spacing
  const auto s = render::mesh_stats(render::extract_surface(f, request));
  const double change = std::abs(s.volume - full.volume) / full.volume;
  std::cout << "decimated (error 0.005): " << full.faces << " -> " << s.faces << " faces, volume change "
            << 100 * change << " %\n";
  EXPECT_LT(s.faces, full.faces / 2);
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_EQ(s.euler_characteristic, 2);
  // Every decimated face stays within the tolerance of the original surface,
  // so the volume changes by at most about error * area (here 1.5 %).
  EXPECT_LT(std::abs(s.volume - full.volume), request.decimate_error * full.area);
  double worst = 0;
  auto decimated = render::extract_surface(f, request);
  for (vtkIdType c = 0; c < decimated->GetNumberOfCells(); ++c) {
    double centroid[3] = {0, 0, 0}, p[3];
    vtkIdType n;
    const vtkIdType* ids;
    decimated->GetCellPoints(c, n, ids);
    for (int k = 0; k < 3; ++k) {
      decimated->GetPoint(ids[k], p);
      for (int a = 0; a < 3; ++a) centroid[a] += p[a] / 3;
    }
    worst = std::max(worst, std::abs(Eigen::Vector3d(centroid).norm() - 1));
  }
  std::cout << "decimated: worst face-centre distance to the unit sphere " << worst << "\n";
  EXPECT_LT(worst, request.decimate_error + 0.003);  // + the marching-cubes error at 64^3
}

TEST(WorkspaceMesh, LightSurfaceIsTheSameClosedBallWithAQuarterOfTheFaces) {
  const Field f = cube_ball(64);
  for (render::Surface surface : {render::Surface::Reach, render::Surface::WellConditioned}) {
    const render::SurfaceRequest request = surface_request(surface, 3.0);
    const auto full = render::mesh_stats(render::extract_surface(f, request));
    auto light_mesh = render::extract_light_surface(f, request);
    const auto light = render::mesh_stats(light_mesh);
    std::cout << render::to_string(surface) << " light: " << full.faces << " -> " << light.faces << " faces, volume "
              << full.volume << " -> " << light.volume << "\n";
    EXPECT_LT(light.faces, full.faces / 3);
    EXPECT_GT(light.faces, full.faces / 6);
    EXPECT_EQ(light.boundary_edges, 0u);
    EXPECT_EQ(light.non_manifold_edges, 0u);
    EXPECT_EQ(light.euler_characteristic, 2);
    EXPECT_NEAR(light.volume, full.volume, 0.03 * full.volume);
    ASSERT_NE(light_mesh->GetPointData()->GetNormals(), nullptr);
  }
  // Cut by the box: closed within half a fine sample of the box faces.
  const Field cut = cube_ball(40, 0.8);
  const auto s = render::mesh_stats(render::extract_light_surface(cut, surface_request(render::Surface::Reach)));
  EXPECT_EQ(s.boundary_edges, 0u);
  EXPECT_EQ(s.euler_characteristic, 2);
  const double half_sample = 0.5 * 1.6 / 40;
  EXPECT_NEAR(s.min.x(), -0.8, half_sample + 1e-5);
  EXPECT_NEAR(s.max.z(), 0.8, half_sample + 1e-5);
  EXPECT_THROW(render::extract_light_surface(cut, surface_request(render::Surface::Reach), 0), std::invalid_argument);
}

TEST(WorkspaceMesh, LightSurfaceIsTheFullSurfaceOfEveryOtherSample) {
  // A ball cut by the box on a grid with even and odd sample counts: the
  // light surface must be the full surface of the field sampled only at
  // every other sample (a grid twice as coarse whose samples are the fine
  // ones 0, 2, 4, ...), closed on that grid's box faces in the same way.
  const Eigen::Vector3d lo(-1.2, -0.9, -1.0), hi(0.9, 1.1, 1.3), centre(0.1, 0.3, -0.1);
  const std::array<int, 3> dims{40, 33, 27};
  const Field fine = ball_field(lo, hi, dims, centre, 1.0);
  Eigen::Vector3d coarse_lo = lo - 0.5 * fine.grid.spacing, coarse_hi;
  std::array<int, 3> coarse_dims;
  for (int a = 0; a < 3; ++a) {
    coarse_dims[a] = (dims[a] + 1) / 2;
    coarse_hi[a] = coarse_lo[a] + coarse_dims[a] * 2 * fine.grid.spacing[a];
  }
  const Field coarse = ball_field(coarse_lo, coarse_hi, coarse_dims, centre, 1.0);
  const auto request = surface_request(render::Surface::Reach);
  const auto light = render::mesh_stats(render::extract_light_surface(fine, request));
  const auto expected = render::mesh_stats(render::extract_surface(coarse, request));
  const auto full = render::mesh_stats(render::extract_surface(fine, request));
  EXPECT_EQ(light.faces, expected.faces);
  EXPECT_EQ(light.vertices, expected.vertices);
  EXPECT_EQ(light.boundary_edges, 0u);
  EXPECT_EQ(light.euler_characteristic, 2);
  EXPECT_NEAR(light.volume, expected.volume, 1e-6 * expected.volume);
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(light.min[a], expected.min[a], 1e-5) << a;
    EXPECT_NEAR(light.max[a], expected.max[a], 1e-5) << a;
  }
  // The ball leaves the box at its largest x and y and its smallest z: the
  // full surface ends on the box faces, the light one on its coarse grid's
  // (half a fine sample beyond or before them).
  EXPECT_NEAR(full.max.x(), hi.x(), 1e-5);
  EXPECT_NEAR(full.max.y(), hi.y(), 1e-5);
  EXPECT_NEAR(full.min.z(), lo.z(), 1e-5);
  EXPECT_NEAR(light.max.x(), coarse_hi.x(), 1e-5);
  EXPECT_NEAR(light.max.y(), coarse_hi.y(), 1e-5);
  EXPECT_NEAR(light.min.z(), coarse_lo.z(), 1e-5);
  EXPECT_LT(light.faces, full.faces / 3);
}

TEST(WorkspaceMesh, ExportsReadBackWithVtkReaders) {
  Folder dir;
  const Field f = cube_ball(32);
  render::SurfaceRequest request = surface_request(render::Surface::Reach);
  auto mesh = render::extract_surface(f, request);
  const auto s = render::mesh_stats(mesh);
  const vtkIdType points = mesh->GetNumberOfPoints(), faces = vtkIdType(s.faces);
  ASSERT_EQ(std::size_t(points), s.vertices);
  for (const char* name : {"mesh.stl", "mesh.obj", "mesh.ply", "mesh.off", "mesh.vtp"})
    render::write_mesh(mesh, dir / name, f, request);
  EXPECT_EQ(dir.names(), (std::vector<std::string>{"mesh.obj", "mesh.off", "mesh.ply", "mesh.stl", "mesh.vtp"}));

  auto check = [&](vtkPolyData* read, const char* what) {
    EXPECT_EQ(read->GetNumberOfPolys(), faces) << what;
    EXPECT_EQ(read->GetNumberOfPoints(), points) << what;
    const auto r = render::mesh_stats(read);
    EXPECT_EQ(r.boundary_edges, 0u) << what;
    EXPECT_NEAR(r.volume, s.volume, 1e-6 * s.volume) << what;
  };
  {
    // STL stores three corners per triangle; vtkSTLReader merges coincident
    // points (Merging on by default), which restores the shared vertices.
    vtkNew<vtkSTLReader> reader;
    reader->SetFileName((dir / "mesh.stl").c_str());
    reader->Update();
    check(reader->GetOutput(), "stl");
  }
  {
    vtkNew<vtkOBJReader> reader;
    reader->SetFileName((dir / "mesh.obj").c_str());
    reader->Update();
    check(reader->GetOutput(), "obj");
  }
  {
    vtkNew<vtkPLYReader> reader;
    reader->SetFileName((dir / "mesh.ply").c_str());
    reader->Update();
    check(reader->GetOutput(), "ply");
  }
  {
    std::ifstream off(dir / "mesh.off");
    std::string magic;
    long v = 0, fc = 0, e = -1;
    off >> magic >> v >> fc >> e;
    EXPECT_EQ(magic, "OFF");
    EXPECT_EQ(v, points);
    EXPECT_EQ(fc, faces);
  }
  {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((dir / "mesh.vtp").c_str());
    reader->Update();
    vtkPolyData* read = reader->GetOutput();
    check(read, "vtp");
    EXPECT_NE(read->GetPointData()->GetNormals(), nullptr);
    vtkFieldData* fd = read->GetFieldData();
    EXPECT_EQ(string_of(fd, "mechanism"), "test-ball");
    EXPECT_EQ(string_of(fd, "method"), "synthetic");
    EXPECT_EQ(string_of(fd, "surface"), "reach");
    EXPECT_EQ(number_of(fd, "cond_threshold"), 3.0);
    EXPECT_EQ(number_of(fd, "param_L2"), 15.5);
    EXPECT_EQ(number_of(fd, "grid_samples", 1), 32);
  }
}

// A mesh written in another length unit: its points scaled (read back with
// VTK's readers against the mesh in the field's unit) and the unit said in
// each format that has room for it; a unit without a conversion is refused.
TEST(WorkspaceMesh, WritesPointsInTheUnitAsked) {
  Folder dir;
  const Field f = cube_ball(16);  // in mm
  auto mesh = render::extract_surface(f, surface_request(render::Surface::Reach));
  const auto s = render::mesh_stats(mesh);
  for (const char* name : {"m.stl", "m.obj", "m.ply", "m.vtp"}) render::write_mesh(mesh, dir / name, f, {}, "cm");
  auto bounds_in_cm = [&](vtkPolyData* read, const char* what) {
    const auto r = render::mesh_stats(read);
    EXPECT_NEAR(r.max.x(), 0.1 * s.max.x(), 1e-6) << what;
    EXPECT_NEAR(r.volume, 1e-3 * s.volume, 1e-6 * s.volume) << what;
  };
  {
    vtkNew<vtkSTLReader> reader;
    reader->SetFileName((dir / "m.stl").c_str());
    reader->Update();
    bounds_in_cm(reader->GetOutput(), "stl");
    std::ifstream stl(dir / "m.stl", std::ios::binary);
    std::string header(80, '\0');
    stl.read(header.data(), 80);
    EXPECT_NE(header.find("length unit: cm"), std::string::npos) << header;
  }
  {
    vtkNew<vtkOBJReader> reader;
    reader->SetFileName((dir / "m.obj").c_str());
    reader->Update();
    bounds_in_cm(reader->GetOutput(), "obj");
    std::ifstream obj(dir / "m.obj");
    std::string first;
    std::getline(obj, first);
    EXPECT_EQ(first, "# length unit: cm");
  }
  {
    vtkNew<vtkPLYReader> reader;
    reader->SetFileName((dir / "m.ply").c_str());
    reader->Update();
    bounds_in_cm(reader->GetOutput(), "ply");
    std::ifstream ply(dir / "m.ply", std::ios::binary);
    std::string magic, format, comment;
    std::getline(ply, magic);
    std::getline(ply, format);
    std::getline(ply, comment);
    EXPECT_EQ(magic, "ply");
    EXPECT_EQ(format.rfind("format ", 0), 0u) << format;
    EXPECT_EQ(comment, "comment length unit: cm");
  }
  {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((dir / "m.vtp").c_str());
    reader->Update();
    bounds_in_cm(reader->GetOutput(), "vtp");
    EXPECT_EQ(string_of(reader->GetOutput()->GetFieldData(), "length_unit"), "cm");
  }
  EXPECT_THROW(render::write_mesh(mesh, dir / "x.stl", f, {}, "furlong"), std::invalid_argument);
  Field unitless = f;
  unitless.length_unit = "unit";
  EXPECT_THROW(render::write_mesh(mesh, dir / "x.stl", unitless, {}, "mm"), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir / "x.stl"));
}

// ---------------------------------------------------------------- errors

TEST(FieldRenderErrors, BadArgumentsThrowInvalidArgument) {
  Folder dir;
  const Field empty;  // 1x1x1 grid, no samples in the arrays
  EXPECT_THROW(render::to_image_data(empty), std::invalid_argument);
  EXPECT_THROW(render::write_vti(empty, dir / "e.vti"), std::invalid_argument);
  EXPECT_THROW(render::write_field_csv(empty, dir / "e.csv"), std::invalid_argument);
  EXPECT_THROW(render::render_slice_rgba(empty, {}), std::invalid_argument);
  EXPECT_THROW(render::extract_surface(empty, {}), std::invalid_argument);
  Field short_array = cube_ball(4);
  short_array.iterations.pop_back();
  EXPECT_THROW(render::to_image_data(short_array), std::invalid_argument);

  const Field slice = ball_field({-1, -1, 0}, {1, 1, 0.1}, {10, 10, 1});
  render::SliceStyle unknown;
  unknown.field = "torque";
  EXPECT_THROW(render::colour_range(slice, unknown), std::invalid_argument);
  EXPECT_THROW(render::write_slice_png(slice, unknown, dir / "s.png"), std::invalid_argument);
  render::SliceStyle zero_scale;
  zero_scale.scale = 0;
  EXPECT_THROW(render::render_slice_rgba(slice, zero_scale), std::invalid_argument);
  EXPECT_THROW(render::render_slice_rgba(cube_ball(4), {}), std::invalid_argument);  // not a slice
  EXPECT_THROW(render::extract_surface(slice, {}), std::invalid_argument);           // not a volume
  EXPECT_THROW(render::extract_surface(cube_ball(4), surface_request(render::Surface::WellConditioned, 0.5)),
               std::invalid_argument);

  const Field volume = cube_ball(8);
  auto mesh = render::extract_surface(volume, {});
  try {
    render::write_mesh(mesh, dir / "mesh.xyz", volume, {});
    ADD_FAILURE() << "no exception for .xyz";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(".stl"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(".xyz"), std::string::npos) << e.what();
  }
  EXPECT_THROW(render::write_mesh(nullptr, dir / "mesh.stl", volume, {}), std::invalid_argument);
  EXPECT_TRUE(dir.names().empty());
}

TEST(FieldRenderErrors, MissingFolderThrowsAndLeavesNothing) {
  Folder dir;
  const fs::path missing = dir / "missing";
  const Field volume = cube_ball(8);
  const Field slice = ball_field({-1, -1, 0}, {1, 1, 0.1}, {10, 10, 1});
  auto mesh = render::extract_surface(volume, {});
  EXPECT_THROW(render::write_vti(volume, missing / "f.vti"), std::runtime_error);
  EXPECT_THROW(render::write_field_csv(volume, missing / "f.csv"), std::runtime_error);
  EXPECT_THROW(render::write_slice_png(slice, {}, missing / "s.png"), std::runtime_error);
  for (const char* name : {"m.stl", "m.obj", "m.ply", "m.off", "m.vtp"})
    EXPECT_THROW(render::write_mesh(mesh, missing / name, volume, {}), std::runtime_error) << name;
  EXPECT_FALSE(fs::exists(missing));
  EXPECT_TRUE(dir.names().empty());
}

TEST(FieldRenderErrors, FailedWriteKeepsTheOldFile) {
  Folder dir;
  const Field volume = cube_ball(8);
  {
    std::ofstream old(dir / "keep.stl");
    old << "old";
  }
  // A folder in the way of the rename makes the write fail after the temporary exists.
  fs::create_directory(dir / "blocked.stl");
  auto mesh = render::extract_surface(volume, {});
  EXPECT_THROW(render::write_mesh(mesh, dir / "blocked.stl", volume, {}), std::exception);
  EXPECT_EQ(dir.names(), (std::vector<std::string>{"blocked.stl", "keep.stl"}));
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
