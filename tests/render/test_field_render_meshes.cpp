// Workspace meshes (reach and well-conditioned surfaces, decimation, the
// light surface, export and length units), on the synthetic fields of
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
