// FieldScene: slice texture colours and orientation, surfaces, colour bar and
// prop bookkeeping, checked on offscreen renders (tests/with-xvfb.sh in ctest).
#include <gtest/gtest.h>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkMapper.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPropCollection.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkWindowToImageFilter.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "offscreen_view.h"
#include "render/field_scene.h"
#include "render/image_io.h"
#include "render/scene_renderer.h"
#include "render/slice_image.h"
#include "render/workspace_mesh.h"

using namespace linkscape;
using render::FieldScene;
using render::SliceStyle;
using render::Surface;

namespace {

// A request for one of the two workspace surfaces (the other members at their defaults).
render::SurfaceRequest surface_request(render::Surface surface, double cond_threshold = 3.0) {
  render::SurfaceRequest r;
  r.surface = surface;
  r.cond_threshold = cond_threshold;
  return r;
}

constexpr float kInf = std::numeric_limits<float>::infinity();

// A ball of radius 1 at the origin sampled on `g`: reach_margin = 1 - |p|,
// cond = 1 + 4|p| inside and +inf outside.
Field ball_field(const Grid& g) {
  Field f;
  f.measure_titles = {"c(J)"};  // as a device's sampler names its measure
  f.grid = g;
  f.length_unit = "cm";
  const std::size_t n = g.size();
  f.cond.resize(n);
  f.reach_margin.resize(n);
  f.residual.resize(n);
  f.reachable.resize(n);
  f.status.resize(n);
  f.iterations.resize(n);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const std::size_t s = g.index(i, j, k);
        const double r = g.point(i, j, k).norm();
        const bool inside = r < 1;
        f.reach_margin[s] = float(1 - r);
        f.cond[s] = inside ? float(1 + 4 * r) : kInf;
        f.residual[s] = inside ? 1e-9f : kInf;
        f.reachable[s] = inside;
        f.status[s] = inside ? 0 : 1;
        f.iterations[s] = 3;
      }
  return f;
}

// 64 x 48 samples over [-1.6, 1.6] x [-1.2, 1.2] (spacing 0.05) at z = 0.
Grid ball_slice_grid() { return Grid::slice(Axis::Z, 0.0, -1.6, 1.6, -1.2, 1.2, 64, 48); }

using offscreen_view::Rgb;

int distance(const Rgb& a, const Rgb& b) {
  return std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

Rgb to_rgb(const std::array<double, 3>& c) {
  return {int(std::lround(c[0] * 255)), int(std::lround(c[1] * 255)), int(std::lround(c[2] * 255))};
}

// An offscreen 400 x 300 view with depth peeling possible, looking along
// -`normal` at the origin with parallel projection: 100 pixels per length
// unit, world origin at pixel (200, 150).
struct View {
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;

  View(const Eigen::Vector3d& normal, const Eigen::Vector3d& up) {
    renderer->SetBackground(0.1, 0.2, 0.3);
    window->SetOffScreenRendering(1);
    window->SetSize(400, 300);
    window->SetMultiSamples(0);
    window->SetAlphaBitPlanes(1);
    window->AddRenderer(renderer);
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->ParallelProjectionOn();
    camera->SetFocalPoint(0, 0, 0);
    const Eigen::Vector3d eye = 10 * normal;
    camera->SetPosition(eye.x(), eye.y(), eye.z());
    camera->SetViewUp(up.x(), up.y(), up.z());
    camera->SetParallelScale(1.5);
    camera->SetClippingRange(1, 20);
  }

  vtkSmartPointer<vtkImageData> grab() { return offscreen_view::grab(window); }
  static Rgb pixel(vtkImageData* image, int x, int y) { return offscreen_view::pixel(image, x, y); }
  static Rgb at(vtkImageData* image, double a, double b) { return offscreen_view::at(image, a, b); }
};

bool have_display() { return std::getenv("DISPLAY") != nullptr; }

int view_prop_count(vtkRenderer* renderer) { return renderer->GetViewProps()->GetNumberOfItems(); }

}  // namespace

TEST(FieldScene, RejectsBadArguments) {
  FieldScene scene;
  EXPECT_THROW(scene.add_to(nullptr), std::invalid_argument);
  const Field volume = ball_field(Grid::box({-1, -1, -1}, {1, 1, 1}, {4, 4, 4}));
  EXPECT_THROW(scene.set_slice(volume, SliceStyle{}), std::invalid_argument);
  Field bad = ball_field(ball_slice_grid());
  bad.cond.pop_back();
  EXPECT_THROW(scene.set_slice(bad, SliceStyle{}), std::invalid_argument);
  SliceStyle bad_style;
  bad_style.field = "speed";
  EXPECT_THROW(scene.set_slice(ball_field(ball_slice_grid()), bad_style), std::invalid_argument);
  EXPECT_FALSE(scene.slice_visible());  // nothing half-applied
  for (double opacity : {-0.1, 1.5, std::nan("")}) {
    EXPECT_THROW(scene.set_slice_opacity(opacity), std::invalid_argument);
    EXPECT_THROW(scene.set_surface_opacity(Surface::Reach, opacity), std::invalid_argument);
  }
  EXPECT_NO_THROW(scene.set_slice_opacity(0));
  EXPECT_NO_THROW(scene.set_surface_opacity(Surface::WellConditioned, 1));
}

TEST(FieldScene, SliceGeometryTitleAndPropBookkeeping) {
  FieldScene scene;
  vtkNew<vtkRenderer> renderer;
  scene.add_to(renderer);
  scene.add_to(renderer);  // idempotent
  const int props = view_prop_count(renderer);
  EXPECT_EQ(props, 6);  // slice, two surfaces and their light meshes, colour bar
  EXPECT_TRUE(renderer->GetUseDepthPeeling());
  EXPECT_EQ(renderer->GetMaximumNumberOfPeels(), 4);

  EXPECT_FALSE(scene.slice_visible());
  EXPECT_FALSE(scene.colour_bar_visible());
  // Off-centre slice along y: the plane spans the cell edges along x and z
  // and sits at the sample plane y = 0.3.
  const Grid g = Grid::slice(Axis::Y, 0.3, -1.0, 2.0, -0.5, 0.7, 30, 12);
  scene.set_slice(ball_field(g), SliceStyle{});
  EXPECT_TRUE(scene.slice_visible());
  EXPECT_TRUE(scene.colour_bar_visible());
  EXPECT_EQ(scene.colour_bar_title(), "c(J)");
  const auto b = scene.slice_bounds();
  EXPECT_NEAR(b[0], -1.0, 1e-9);
  EXPECT_NEAR(b[1], 2.0, 1e-9);
  EXPECT_NEAR(b[2], 0.3, 1e-9);
  EXPECT_NEAR(b[3], 0.3, 1e-9);
  EXPECT_NEAR(b[4], -0.5, 1e-9);
  EXPECT_NEAR(b[5], 0.7, 1e-9);

  // Fifty updates with new data and styles: same props.
  for (int n = 0; n < 50; ++n) {
    Field f = ball_field(Grid::slice(Axis::Z, 0.01 * n, -1.6, 1.6, -1.2, 1.2, 16 + n, 12 + n));
    SliceStyle style;
    style.field = n % 2 ? "reach" : "cond";
    style.scale = 1 + n % 3;
    scene.set_slice(f, style);
    EXPECT_EQ(view_prop_count(renderer), props);
  }
  EXPECT_EQ(scene.colour_bar_title(), "reach margin (cm)");  // n = 49 is odd

  scene.set_slice_visible(false);
  EXPECT_FALSE(scene.slice_visible());
  EXPECT_FALSE(scene.colour_bar_visible());
  scene.set_slice_visible(true);
  scene.set_colour_bar_visible(false);
  EXPECT_TRUE(scene.slice_visible());
  EXPECT_FALSE(scene.colour_bar_visible());
  scene.set_colour_bar_visible(true);

  // Surfaces: a mesh shows, nullptr or an empty mesh clears.
  const Field volume = ball_field(Grid::box({-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, {16, 16, 16}));
  auto mesh = render::extract_surface(volume, surface_request(Surface::Reach, 3.0));
  ASSERT_GT(mesh->GetNumberOfCells(), 0);
  scene.set_surface(Surface::Reach, mesh);
  EXPECT_EQ(scene.surface_faces(Surface::Reach), std::size_t(mesh->GetNumberOfCells()));
  EXPECT_TRUE(scene.surface_visible(Surface::Reach));
  EXPECT_FALSE(scene.surface_visible(Surface::WellConditioned));
  scene.set_surface_visible(Surface::Reach, false);
  EXPECT_FALSE(scene.surface_visible(Surface::Reach));
  scene.set_surface_visible(Surface::Reach, true);
  scene.set_surface(Surface::Reach, nullptr);
  EXPECT_EQ(scene.surface_faces(Surface::Reach), 0u);
  EXPECT_FALSE(scene.surface_visible(Surface::Reach));
  scene.set_surface(Surface::WellConditioned, mesh);
  vtkNew<vtkPolyData> empty;
  scene.set_surface(Surface::WellConditioned, empty);
  EXPECT_EQ(scene.surface_faces(Surface::WellConditioned), 0u);

  // A light mesh is drawn instead of the full one only while set_light(true),
  // and goes with its surface.
  auto light = render::extract_light_surface(volume, surface_request(Surface::Reach, 3.0));
  scene.set_surface(Surface::Reach, mesh);
  scene.set_light_surface(Surface::Reach, light);
  EXPECT_FALSE(scene.drawing_light(Surface::Reach));
  scene.set_light(true);
  EXPECT_TRUE(scene.drawing_light(Surface::Reach));
  EXPECT_TRUE(scene.surface_visible(Surface::Reach));
  EXPECT_EQ(scene.surface_faces(Surface::Reach), std::size_t(mesh->GetNumberOfCells()));  // the full mesh's
  scene.set_surface_visible(Surface::Reach, false);
  EXPECT_FALSE(scene.drawing_light(Surface::Reach));
  scene.set_surface_visible(Surface::Reach, true);
  scene.set_surface(Surface::Reach, mesh);  // new surfaces: no light mesh until one is given
  EXPECT_FALSE(scene.drawing_light(Surface::Reach));
  scene.set_light_surface(Surface::WellConditioned, light);  // no full mesh there: ignored
  EXPECT_FALSE(scene.drawing_light(Surface::WellConditioned));
  scene.set_light_surface(Surface::Reach, light);
  EXPECT_TRUE(scene.drawing_light(Surface::Reach));
  scene.set_light(false);
  EXPECT_FALSE(scene.drawing_light(Surface::Reach));
  scene.set_light(true);
  scene.clear();
  EXPECT_FALSE(scene.drawing_light(Surface::Reach));
  scene.set_light(false);
  EXPECT_FALSE(scene.slice_visible());
  EXPECT_FALSE(scene.surface_visible(Surface::Reach));
  EXPECT_FALSE(scene.colour_bar_visible());
  EXPECT_EQ(view_prop_count(renderer), props);
}

TEST(FieldScene, SliceShowsTheSliceImageColours) {
  if (!have_display()) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  FieldScene scene;
  View view(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY());
  scene.add_to(view.renderer);
  const Field slice = ball_field(ball_slice_grid());
  SliceStyle style;
  style.scale = 4;
  scene.set_slice(slice, style);
  auto image = view.grab();

  const Rgb background = View::pixel(image, 5, 5);  // outside the 3.2 x 2.4 plane
  EXPECT_LE(distance(background, {26, 51, 77}), 2);
  // Centre: the four samples around the origin have |p| = 0.025 * sqrt(2).
  const double r = 0.025 * std::sqrt(2.0);
  const Rgb centre_expected = to_rgb(render::colour_of(render::normalised_value(1 + 4 * r, style)));
  EXPECT_LE(distance(View::at(image, 0.003, 0.003), centre_expected), 3);
  // Inside the ball off-centre, against the sample's own viridis colour.
  const double ra = std::hypot(0.525, 0.325);  // sample centre at (0.525, 0.325)
  const Rgb off_expected = to_rgb(render::colour_of(render::normalised_value(1 + 4 * ra, style)));
  EXPECT_LE(distance(View::at(image, 0.53, 0.33), off_expected), 3);
  // Outside the ball: unreachable grey 0.85.
  const Rgb grey = View::at(image, 1.4, 1.0);
  EXPECT_LE(distance(grey, {217, 217, 217}), 2);

  scene.set_slice_visible(false);
  image = view.grab();
  EXPECT_LE(distance(View::at(image, 0.003, 0.003), background), 1);
  EXPECT_LE(distance(View::at(image, 1.4, 1.0), background), 1);

  scene.set_slice_visible(true);
  scene.set_slice_opacity(0.5);
  image = view.grab();
  const Rgb half = View::at(image, 1.4, 1.0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(half[c], (217 + background[c]) / 2.0, 3);
}

TEST(FieldScene, TextureAxesFollowTheSliceAxes) {
  if (!have_display()) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  // A slice normal to x: first axis y, second z. cond rises along y from 1
  // to 10; only z < 0 is reachable. Seen from +x with z up, +y is to the right.
  const Grid g = Grid::slice(Axis::X, 0.0, -1.6, 1.6, -1.2, 1.2, 64, 48);
  Field f = ball_field(g);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j) {
      const std::size_t s = g.index(0, j, k);
      const Eigen::Vector3d p = g.point(0, j, k);
      f.cond[s] = float(1 + 9 * (p.y() + 1.6) / 3.2);
      f.reach_margin[s] = float(-p.z());
      f.reachable[s] = p.z() < 0;
    }
  SliceStyle style;
  style.contour_levels.clear();
  style.draw_reach_boundary = false;
  FieldScene scene;
  View view(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ());
  scene.add_to(view.renderer);
  scene.set_slice(f, style);
  auto image = view.grab();
  auto expected = [&](double y) {
    const int j = int(std::floor((y + 1.6) / 0.05));
    return to_rgb(render::colour_of(render::normalised_value(f.cond[g.index(0, j, 0)], style)));
  };
  EXPECT_LE(distance(View::at(image, -1.4, -0.6), expected(-1.4)), 3);  // left: dark purple
  EXPECT_LE(distance(View::at(image, 1.4, -0.6), expected(1.4)), 3);    // right: yellow
  EXPECT_LE(distance(View::at(image, 0.0, 0.6), {217, 217, 217}), 2);   // top: unreachable
}

TEST(FieldScene, TranslucentSurfacesChangeOnlyTheirPixels) {
  if (!have_display()) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  FieldScene scene;
  View view(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY());
  scene.add_to(view.renderer);
  scene.set_slice(ball_field(ball_slice_grid()), SliceStyle{});
  const auto before = view.grab();

  const Field volume = ball_field(Grid::box({-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, {32, 32, 32}));
  auto reach = render::extract_surface(volume, surface_request(Surface::Reach, 3.0));
  scene.set_surface(Surface::Reach, reach);
  auto with = view.grab();
  EXPECT_TRUE(view.renderer->GetLastRenderingUsedDepthPeeling());
  // Over the slice inside the ball's outline the translucent sphere tints the
  // colour; at (1.4, 1.0), outside its outline, nothing changes.
  EXPECT_GE(distance(View::at(with, 0.2, 0.1), View::at(before, 0.2, 0.1)), 6);
  EXPECT_LE(distance(View::at(with, 1.4, 1.0), View::at(before, 1.4, 1.0)), 1);
  EXPECT_LE(distance(View::pixel(with, 5, 5), View::pixel(before, 5, 5)), 1);
  // The well-conditioned sphere (radius 0.5) alone over the slice tints the
  // centre only.
  scene.set_surface_visible(Surface::Reach, false);
  scene.set_surface(Surface::WellConditioned, render::extract_surface(volume, surface_request(Surface::WellConditioned, 3.0)));
  const auto inner = view.grab();
  EXPECT_GE(distance(View::at(inner, 0.1, 0.1), View::at(before, 0.1, 0.1)), 6);
  EXPECT_LE(distance(View::at(inner, 0.8, 0.1), View::at(before, 0.8, 0.1)), 1);
  // KNOWN ISSUE (VTK 9.1 dual depth peeling, Mesa llvmpipe): with both
  // spheres over the opaque slice the inner one adds nothing, although each
  // alone shows and both show without the slice. Reported, not asserted.
  scene.set_surface_visible(Surface::Reach, true);
  const auto both = view.grab();
  const int inner_effect = distance(View::at(both, 0.1, 0.1), View::at(with, 0.1, 0.1));
  RecordProperty("inner_surface_effect_behind_outer_over_slice", inner_effect);
  if (inner_effect < 6) std::printf("known issue: inner surface not visible behind outer over the opaque slice\n");
  scene.set_surface(Surface::WellConditioned, nullptr);

  // Without the slice, the sphere over the background.
  scene.set_slice_visible(false);
  const auto no_slice = view.grab();
  const Rgb background = View::pixel(no_slice, 5, 5);
  EXPECT_GE(distance(View::at(no_slice, 0.2, 0.1), background), 6);

  scene.set_surface(Surface::Reach, nullptr);
  const auto cleared = view.grab();
  EXPECT_LE(distance(View::at(cleared, 0.2, 0.1), background), 1);
}

TEST(SceneRenderer, BlendsTranslucentPropsInOnePassAndPeelsOnRequest) {
  if (!have_display()) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  // The View above with the window's renderer in place of VTK's.
  View view(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY());
  vtkNew<render::SceneRenderer> renderer;
  renderer->SetBackground(0.1, 0.2, 0.3);
  renderer->SetActiveCamera(view.renderer->GetActiveCamera());
  view.window->RemoveRenderer(view.renderer);
  view.window->AddRenderer(renderer);
  FieldScene scene;
  scene.add_to(renderer);
  scene.set_slice(ball_field(ball_slice_grid()), SliceStyle{});
  renderer->SetUseDepthPeeling(false);
  const auto slice_only = view.grab();

  const Field volume = ball_field(Grid::box({-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, {32, 32, 32}));
  scene.set_surface(Surface::Reach, render::extract_surface(volume, surface_request(Surface::Reach, 3.0)));
  const auto outer = view.grab();
  EXPECT_FALSE(renderer->GetLastRenderingUsedDepthPeeling());
  EXPECT_GE(distance(View::at(outer, 0.2, 0.1), View::at(slice_only, 0.2, 0.1)), 6);  // tinted
  EXPECT_LE(distance(View::at(outer, 1.4, 1.0), View::at(slice_only, 1.4, 1.0)), 1);  // outside the sphere
  // Both spheres over the opaque slice: the inner one shows through the outer.
  scene.set_surface(Surface::WellConditioned,
                    render::extract_surface(volume, surface_request(Surface::WellConditioned, 3.0)));
  const auto both = view.grab();
  EXPECT_GE(distance(View::at(both, 0.1, 0.1), View::at(outer, 0.1, 0.1)), 6);
  EXPECT_LE(distance(View::at(both, 0.8, 0.1), View::at(outer, 0.8, 0.1)), 1);

  renderer->SetUseDepthPeeling(true);
  const auto peeled = view.grab();
  EXPECT_TRUE(renderer->GetLastRenderingUsedDepthPeeling());
  EXPECT_GE(distance(View::at(peeled, 0.2, 0.1), View::at(slice_only, 0.2, 0.1)), 6);
}

TEST(FieldScene, UpdatesAtInteractiveRates) {
  if (!have_display()) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  FieldScene scene;
  View view(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY());
  scene.add_to(view.renderer);
  const int props = view_prop_count(view.renderer);
  std::vector<Field> slices;
  for (int n = 0; n < 4; ++n) slices.push_back(ball_field(Grid::slice(Axis::Z, 0.1 * n, -1.6, 1.6, -1.2, 1.2, 256, 256)));
  scene.set_slice(slices[0], SliceStyle{});
  view.window->Render();
  constexpr int kFrames = 20;
  const auto start = std::chrono::steady_clock::now();
  for (int n = 0; n < kFrames; ++n) {
    scene.set_slice(slices[n % slices.size()], SliceStyle{});
    view.window->Render();
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() /
                    kFrames;
  RecordProperty("ms_per_256x256_update_and_render", std::to_string(ms));
  std::printf("set_slice(256x256) + render: %.1f ms per frame\n", ms);
  EXPECT_LT(ms, 100.0);  // 10 Hz, with a wide margin for a busy machine
  EXPECT_EQ(view_prop_count(view.renderer), props);
}

TEST(FieldScene, CombinedSceneScreenshot) {
  if (!have_display()) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  FieldScene scene;
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(800, 600);
  window->SetMultiSamples(0);
  window->SetAlphaBitPlanes(1);
  window->AddRenderer(renderer);
  scene.add_to(renderer);
  // An asymmetric slice at z = 0: the ball shifted to +x, +y so that the
  // orientation shows (the ball's outline is nearer the +x, +y corner).
  Grid g = Grid::slice(Axis::Z, 0.0, -1.6, 1.6, -1.2, 1.2, 64, 48);
  Field slice = ball_field(g);
  for (int j = 0; j < g.dims[1]; ++j)
    for (int i = 0; i < g.dims[0]; ++i) {
      const std::size_t s = g.index(i, j, 0);
      const double r = (g.point(i, j, 0) - Eigen::Vector3d(0.4, 0.3, 0)).norm();
      const bool inside = r < 1;
      slice.reach_margin[s] = float(1 - r);
      slice.cond[s] = inside ? float(1 + 4 * r) : kInf;
      slice.reachable[s] = inside;
    }
  SliceStyle style;
  style.scale = 4;
  style.contour_levels = {2.0, 3.0};
  scene.set_slice(slice, style);
  const Field volume = ball_field(Grid::box({-1.2, -1.2, -1.2}, {1.2, 1.2, 1.2}, {32, 32, 32}));
  scene.set_surface(Surface::Reach, render::extract_surface(volume, surface_request(Surface::Reach, 3.0)));
  scene.set_surface(Surface::WellConditioned, render::extract_surface(volume, surface_request(Surface::WellConditioned, 3.0)));
  EXPECT_TRUE(scene.surface_visible(Surface::Reach));
  EXPECT_TRUE(scene.surface_visible(Surface::WellConditioned));
  EXPECT_TRUE(scene.colour_bar_visible());
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(2.5, -4.5, 3.5);
  camera->SetViewUp(0, 0, 1);
  renderer->ResetCamera();
  const std::filesystem::path png = "/tmp/field_scene.png";
  render::save_png(window, png);
  EXPECT_TRUE(renderer->GetLastRenderingUsedDepthPeeling());
  EXPECT_GT(std::filesystem::file_size(png), 10000u);
  // Only the two surfaces go through the translucent (peeling) pass: the
  // RGBA slice texture is fully opaque, so the slice is drawn as opaque.
  int translucent = 0;
  vtkPropCollection* props = renderer->GetViewProps();
  props->InitTraversal();
  while (vtkProp* p = props->GetNextProp()) translucent += p->GetVisibility() && p->HasTranslucentPolygonalGeometry();
  EXPECT_EQ(translucent, 2);
}

namespace {

// The spread of the distance to the origin over a mesh's points, relative
// to the mean: 0 for a perfect sphere.
double radial_roughness(vtkPolyData* mesh) {
  double sum = 0, sum2 = 0;
  const vtkIdType n = mesh->GetNumberOfPoints();
  for (vtkIdType i = 0; i < n; ++i) {
    double p[3];
    mesh->GetPoint(i, p);
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    sum += r;
    sum2 += r * r;
  }
  const double mean = sum / double(n);
  return std::sqrt(std::max(0.0, sum2 / double(n) - mean * mean)) / mean;
}

}  // namespace

TEST(FieldScene, SmoothingTakesTheGridsStaircaseOffTheSurface) {
  // A ball of radius 1 whose margin only says in or out (as a margin that
  // is not a distance does): the extracted surface follows the grid's cells.
  const Grid g = Grid::box({-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}, {24, 24, 24});
  Field f = ball_field(g);
  const float half = float(0.5 * g.spacing.x());
  for (std::size_t s = 0; s < g.size(); ++s) f.reach_margin[s] = f.reach_margin[s] > 0 ? half : -half;
  vtkSmartPointer<vtkPolyData> stairs = render::extract_surface(f, {});
  FieldScene scene;
  scene.set_surface(Surface::Reach, stairs);
  auto shown = [&] { return vtkPolyData::SafeDownCast(scene.surface_actor(Surface::Reach)->GetMapper()->GetInput()); };
  const double rough = radial_roughness(shown());
  scene.set_surface_smoothing(20);
  scene.set_surface(Surface::Reach, stairs);
  const double smooth = radial_roughness(shown());
  std::printf("radial roughness %.4f as extracted, %.4f smoothed\n", rough, smooth);
  EXPECT_LT(smooth, 0.5 * rough);
  EXPECT_EQ(shown()->GetNumberOfCells(), stairs->GetNumberOfCells());  // the same triangles, moved
  EXPECT_THROW(scene.set_surface_smoothing(-1), std::invalid_argument);
}
