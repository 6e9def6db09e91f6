// Field export (.vti, .csv) and the writers' refusals, on the synthetic
// fields of field_render_fixture.h (no kinematics). The slice images are in
// test_field_render_slices.cpp, the workspace meshes in
// test_field_render_meshes.cpp. Needs no display: ctest runs them with
// DISPLAY unset.
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
