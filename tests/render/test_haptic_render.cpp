// The haptic fields (core/haptics.h) in every export: .vti arrays with their
// units, CSV columns, slice colours and titles, threshold surfaces. No
// display needed.
#include <gtest/gtest.h>

#include <cmath>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkXMLImageDataReader.h>

#include <filesystem>
#include <fstream>

#include "core/haptics.h"
#include "core/preset.h"
#include "render/field_vtk.h"
#include "render/slice_image.h"
#include "render/workspace_mesh.h"

using namespace linkscape;

namespace {

struct Sampled {
  std::shared_ptr<const Mechanism> mechanism;
  haptics::DeviceData data;
  Field field;
};

Sampled sampled_12r(const Grid& grid) {
  const Preset preset = load_preset("parallel-12r");
  Sampled s{make_mechanism(preset), {}, {}};
  s.data = haptics::device_data(preset, s.mechanism->info());
  s.field = *haptics::sample_field(*s.mechanism, grid, s.mechanism->home_task(), {}, 2, {}, &s.data);
  return s;
}

std::filesystem::path temp(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "linkscape_haptic_render";
  std::filesystem::create_directories(dir);
  return dir / name;
}

}  // namespace

TEST(HapticExport, VtiCarriesEveryArrayWithItsUnit) {
  const Sampled s = sampled_12r(Grid::box({-30, -30, -30}, {30, 30, 30}, {12, 12, 12}));
  const auto path = temp("haptic.vti");
  render::write_vti(s.field, path);
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  for (const auto& [name, unit] : {std::pair{"force_iso", "N"}, {"force_max", "N"}, {"resolution", "mm"}, {"inertia", "kg"}}) {
    vtkDataArray* array = image->GetPointData()->GetArray(name);
    ASSERT_NE(array, nullptr) << name;
    EXPECT_STREQ(array->GetComponentName(0), unit) << name;
    auto* unit_array = vtkStringArray::SafeDownCast(image->GetFieldData()->GetAbstractArray((std::string(name) + "_unit").c_str()));
    ASSERT_NE(unit_array, nullptr) << name;
    EXPECT_EQ(unit_array->GetValue(0), unit);
    const Field::NamedArray* original = s.field.extra(name);
    // The measure where the device reaches the sample, NaN elsewhere (not 0: weak).
    for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i) {
      if (s.field.reachable[std::size_t(i)])
        ASSERT_EQ(float(array->GetTuple1(i)), original->values[std::size_t(i)]) << name << " sample " << i;
      else
        ASSERT_TRUE(std::isnan(array->GetTuple1(i))) << name << " sample " << i;
    }
  }
  auto* description = vtkStringArray::SafeDownCast(image->GetFieldData()->GetAbstractArray("force_iso_description"));
  ASSERT_NE(description, nullptr);
  EXPECT_NE(description->GetValue(0).find("continuous torque"), std::string::npos);
}

TEST(HapticExport, CsvHasTheArraysAsColumns) {
  const Sampled s = sampled_12r(Grid::box({-30, -30, -30}, {30, 30, 30}, {4, 4, 4}));
  const auto path = temp("haptic.csv");
  render::write_field_csv(s.field, path);
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  EXPECT_NE(header.find(",force_iso_N,force_max_N,resolution_mm,inertia_kg"), std::string::npos) << header;
}

TEST(HapticExport, SliceColoursTheArrayWithItsTitleAndLogScale) {
  const Sampled s = sampled_12r(Grid::slice(Axis::X, 3.75, -30, 30, -30, 30, 48, 48));
  render::SliceStyle style;
  style.field = "force_iso";
  EXPECT_EQ(render::field_title(s.field, "force_iso"), "isotropic force (N)");
  EXPECT_TRUE(render::uses_log_scale(style));
  // The default range spans the reachable samples' values.
  const auto [lo, hi] = render::colour_range(s.field, style);
  float smallest = INFINITY, largest = 0;
  const auto& values = s.field.extra("force_iso")->values;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (s.field.reachable[i]) smallest = std::min(smallest, values[i]), largest = std::max(largest, values[i]);
  EXPECT_FLOAT_EQ(float(lo), smallest);
  EXPECT_FLOAT_EQ(float(hi), largest);
  EXPECT_NO_THROW(render::render_slice_rgba(s.field, style));
  style.field = "torque";
  try {
    render::colour_range(s.field, style);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("force_iso"), std::string::npos) << e.what();
  }
}

// The surface force_iso = F encloses samples meeting it: every vertex lies
// where the sampled force, interpolated, is F (between a sample above and
// one below), and inside the reachable set.
TEST(HapticExport, ThresholdSurfaceBoundsTheRegionMeetingIt) {
  const Sampled s = sampled_12r(Grid::box({-30, -30, -30}, {30, 30, 30}, {40, 40, 40}));
  render::SurfaceRequest request;
  request.surface = render::Surface::Threshold;
  request.field = "force_iso";
  request.above = true;
  request.threshold = 1.0;
  const auto mesh = render::extract_surface(s.field, request);
  const render::MeshStats stats = render::mesh_stats(mesh);
  ASSERT_GT(stats.faces, 100u);
  EXPECT_EQ(stats.boundary_edges, 0u);
  EXPECT_GT(stats.volume, 0);
  // Inside the sampled reach surface, as the well-conditioned surface is.
  request.surface = render::Surface::Reach;
  const render::MeshStats reach = render::mesh_stats(render::extract_surface(s.field, request));
  EXPECT_LT(stats.volume, reach.volume);
  EXPECT_LE(stats.max.maxCoeff(), reach.max.maxCoeff() + 1e-6);
  EXPECT_GE(stats.min.minCoeff(), reach.min.minCoeff() - 1e-6);
  // Most vertices lie where force_iso (evaluated exactly) is near the
  // threshold; the others where the region meets the reach boundary.
  int near = 0;
  const vtkIdType n = mesh->GetNumberOfPoints();
  for (vtkIdType i = 0; i < n; i += 7) {
    Eigen::Vector3d p;
    mesh->GetPoint(i, p.data());
    const IkResult ik = s.mechanism->inverse(p, {});
    if (ik.status != Status::Ok) continue;
    const double f = haptics::measures(s.mechanism->jacobian(ik.solutions.front().q, p), s.data, {}).force_iso_N;
    near += std::abs(f - 1.0) < 0.1;
  }
  EXPECT_GT(near, n / 7 * 0.5);
  request.surface = render::Surface::Threshold;
  request.field = "torque";
  EXPECT_THROW(render::extract_surface(s.field, request), std::invalid_argument);
  request.field = "force_iso";
  request.threshold = 0;
  EXPECT_THROW(render::extract_surface(s.field, request), std::invalid_argument);
}
