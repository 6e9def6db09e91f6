#include "render/workspace_mesh.h"

#include <vtkErrorCode.h>
#include <vtkCellArray.h>
#include <vtkCellArrayIterator.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFlyingEdges3D.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLWriter.h>
#include <vtkStringArray.h>
#include <vtkXMLPolyDataWriter.h>

#include <Eigen/Geometry>

// MeshIO first: it registers OpenMesh's readers and writers.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModHausdorffT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "core/atomic_file.h"
#include "core/haptics.h"
#include "render/field_vtk.h"

namespace linkscape::render {
namespace {

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

constexpr double kCondCap = 1e6;  // cond above this (and +inf, NaN) counts as this
constexpr double kDecadesCap = 6;  // a named array's log10 distance to its threshold is clamped to this

// The scalar whose zero level set is the requested surface, > 0 inside:
// fills out[0 .. count) with the values of samples first, first + step, ...
using SurfaceScalar = std::function<void(std::size_t first, int count, int step, float* out)>;
SurfaceScalar surface_scalar(const Field& field, const SurfaceRequest& request) {
  const double h = field.grid.spacing.minCoeff();
  if (request.surface == Surface::Reach)
    return [&field, h](std::size_t first, int count, int step, float* out) {
      const float* margin = field.reach_margin.data() + first;
      for (int t = 0; t < count; ++t) {
        const float m = margin[std::size_t(t) * std::size_t(step)];
        out[t] = std::isnan(m) ? float(-h) : m;
      }
    };
  // s = log10(threshold) - log10(cond) in decades, combined by min() with
  // the reach margin in cells (k*m). On every grid edge where the reach
  // surface crosses (m_a > 0 > m_b), s_a <= k*m_a and s_b <= k*m_b give
  // s_a/(s_a - s_b) <= m_a/(m_a - m_b): the interpolated crossing of s is no
  // farther out than the reach surface's, so the well-conditioned surface
  // stays inside the reachable set, whatever cond does outside it.
  // Unreachable samples (also those with m > 0, e.g. at joint limits) get
  // at most -1, one decade worse than the threshold.
  const double k = 1.0 / h;
  // Decades by which sample i meets the criterion (> 0 inside).
  std::function<double(std::size_t)> decades;
  if (request.surface == Surface::WellConditioned) {
    const double top = std::log10(request.cond_threshold);
    if (request.measure == 1 && field.cond_orientation.size() != field.grid.size())
      throw std::invalid_argument("surface: the field has no second measure (cond_orientation)");
    decades = [&field, top, measure = request.measure](std::size_t i) {
      // Six-DOF mechanisms: by default well conditioned in position and orientation.
      const double c = measure == 0 || field.cond_orientation.empty() ? field.cond[i]
                       : measure == 1                                ? field.cond_orientation[i]
                                                                     : std::max(field.cond[i], field.cond_orientation[i]);
      return top - std::log10(std::isnan(c) ? kCondCap : std::clamp(c, 1.0, kCondCap));
    };
  } else {
    const Field::NamedArray* array = field.extra(request.field);
    if (!array) throw std::invalid_argument("surface: the field has no array '" + request.field + "'");
    const double level = std::log10(request.threshold), sign = request.above ? 1.0 : -1.0;
    decades = [array, level, sign](std::size_t i) {
      const double v = array->values[i];
      const double d = v > 0 ? std::log10(v) - level : -kDecadesCap;  // 0 and NaN: nothing
      return sign * std::clamp(std::isnan(d) ? -kDecadesCap : d, -kDecadesCap, kDecadesCap);
    };
  }
  return [&field, h, k, decades](std::size_t first, int count, int step, float* out) {
    for (int t = 0; t < count; ++t) {
      const std::size_t i = first + std::size_t(t) * std::size_t(step);
      const double m = std::isnan(field.reach_margin[i]) ? -h : double(field.reach_margin[i]);
      out[t] = float(field.reachable[i] ? std::min(decades(i), k * m) : std::min(k * m, -1.0));
    }
  };
}

// The surface scalar at every `stride`-th sample of the grid along each axis
// (the first included), padded by one sample on every side, each row written
// straight into the image's array: only the samples kept are evaluated. A pad
// sample takes minus its nearest real sample's value (or a small negative
// value), so a surface leaving the box crosses exactly half-way to the pad
// (for stride 1 on the box face) and is closed. Values of exactly 0 are
// nudged outside so that no triangle degenerates.
vtkSmartPointer<vtkImageData> padded_image(const Grid& g, const SurfaceScalar& scalar, float eps, int stride) {
  const int nx = (g.dims[0] + stride - 1) / stride + 2, ny = (g.dims[1] + stride - 1) / stride + 2,
            nz = (g.dims[2] + stride - 1) / stride + 2;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(nx, ny, nz);
  const Eigen::Vector3d step = stride * g.spacing;
  image->SetSpacing(step.x(), step.y(), step.z());
  const Eigen::Vector3d first = g.origin + (0.5 - stride) * g.spacing;  // one step before the first sample
  image->SetOrigin(first.x(), first.y(), first.z());
  vtkNew<vtkFloatArray> scalars;
  scalars->SetName("surface_scalar");
  scalars->SetNumberOfTuples(vtkIdType(nx) * ny * nz);
  float* out = scalars->GetPointer(0);
  const auto at = [&](int i, int j, int k) -> float& { return out[i + std::size_t(nx) * (j + std::size_t(ny) * k)]; };
  for (int k = 1; k < nz - 1; ++k)
    for (int j = 1; j < ny - 1; ++j) {
      float* row = &at(1, j, k);
      scalar(g.index(0, stride * (j - 1), stride * (k - 1)), nx - 2, stride, row);
      for (int i = 0; i < nx - 2; ++i)
        if (std::abs(row[i]) < eps) row[i] = -eps;
    }
  const auto pad = [&](int i, int j, int k) {
    at(i, j, k) = std::min(-eps, -at(std::clamp(i, 1, nx - 2), std::clamp(j, 1, ny - 2), std::clamp(k, 1, nz - 2)));
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      if (k == 0 || j == 0 || k == nz - 1 || j == ny - 1) {
        for (int i = 0; i < nx; ++i) pad(i, j, k);
      } else {
        pad(0, j, k);
        pad(nx - 1, j, k);
      }
  image->GetPointData()->SetScalars(scalars);
  return image;
}

// Triangles of a poly data (polygons fan-triangulated), as point ids.
std::vector<std::array<vtkIdType, 3>> triangles_of(vtkPolyData* mesh) {
  std::vector<std::array<vtkIdType, 3>> out;
  vtkCellArray* polys = mesh->GetPolys();
  if (!polys) return out;
  auto it = vtk::TakeSmartPointer(polys->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell()) {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    for (vtkIdType k = 1; k + 1 < n; ++k) out.push_back({ids[0], ids[k], ids[k + 1]});
  }
  return out;
}

struct EdgeCounts {
  std::size_t edges = 0, boundary = 0, non_manifold = 0;  // all, of one triangle, of three or more
};

// The edges of `triangles` (point ids below `points`) and how many triangles
// share each: the edges are bucketed by their smaller end (a counting sort),
// so each bucket holds the few larger ends of one point's edges.
EdgeCounts count_edges(const std::vector<std::array<vtkIdType, 3>>& triangles, std::size_t points) {
  std::vector<std::size_t> start(points + 1, 0);
  const auto for_each_edge = [&](auto&& visit) {
    for (const auto& t : triangles)
      for (int k = 0; k < 3; ++k) visit(std::minmax(t[k], t[(k + 1) % 3]));
  };
  for_each_edge([&](auto e) { ++start[std::size_t(e.first) + 1]; });
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<vtkIdType> larger_end(start.back());
  std::vector<std::size_t> next(start.begin(), start.end() - 1);
  for_each_edge([&](auto e) { larger_end[next[std::size_t(e.first)]++] = e.second; });
  EdgeCounts counts;
  for (std::size_t v = 0; v < points; ++v) {
    const auto first = larger_end.begin() + std::ptrdiff_t(start[v]), last = larger_end.begin() + std::ptrdiff_t(start[v + 1]);
    std::sort(first, last);
    for (auto run = first; run != last;) {
      const auto end = std::find_if(run, last, [&](vtkIdType w) { return w != *run; });
      ++counts.edges;
      counts.boundary += end - run == 1;
      counts.non_manifold += end - run > 2;
      run = end;
    }
  }
  return counts;
}

struct FloatKey {
  std::array<float, 3> p;
  bool operator==(const FloatKey& o) const { return p == o.p; }
};
struct FloatKeyHash {
  std::size_t operator()(const FloatKey& k) const {
    std::uint32_t b[3];
    std::memcpy(b, k.p.data(), sizeof b);
    return (std::size_t(b[0]) * 73856093u) ^ (std::size_t(b[1]) * 19349663u) ^ (std::size_t(b[2]) * 83492791u);
  }
};

// An OpenMesh mesh from the triangles of `poly`, points merged by exact
// coordinates, degenerate triangles dropped, every face reversed if `flip`.
Mesh to_openmesh(vtkPolyData* poly, bool flip) {
  Mesh mesh;
  const std::size_t points = std::size_t(poly->GetNumberOfPoints()), faces = std::size_t(poly->GetNumberOfPolys());
  mesh.reserve(points, 3 * faces / 2, faces);  // a closed triangle mesh: E = 3F/2
  std::unordered_map<FloatKey, Mesh::VertexHandle, FloatKeyHash> merged;
  merged.reserve(points);
  std::vector<Mesh::VertexHandle> handle(points);
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    double p[3];
    poly->GetPoint(i, p);
    const FloatKey key{{float(p[0]), float(p[1]), float(p[2])}};
    auto [it, added] = merged.try_emplace(key);
    if (added) it->second = mesh.add_vertex(Mesh::Point(key.p[0], key.p[1], key.p[2]));
    handle[std::size_t(i)] = it->second;
  }
  for (const auto& t : triangles_of(poly)) {
    Mesh::VertexHandle a = handle[std::size_t(t[0])], b = handle[std::size_t(t[1])], c = handle[std::size_t(t[2])];
    if (a == b || b == c || a == c) continue;
    if (flip) std::swap(b, c);
    mesh.add_face(a, b, c);  // an invalid handle (complex edge) leaves a hole, visible in mesh_stats
  }
  // Vertices left isolated (only in degenerate triangles) are dropped.
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_face_status();
  bool isolated = false;
  for (auto v : mesh.vertices())
    if (mesh.is_isolated(v)) {
      mesh.delete_vertex(v, false);
      isolated = true;
    }
  if (isolated) mesh.garbage_collection();
  return mesh;
}

vtkSmartPointer<vtkPolyData> to_polydata(Mesh& mesh) {
  mesh.request_face_normals();
  mesh.request_vertex_normals();
  mesh.update_normals();
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToFloat();
  points->SetNumberOfPoints(vtkIdType(mesh.n_vertices()));
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(vtkIdType(mesh.n_vertices()));
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    const auto& nrm = mesh.normal(v);
    points->SetPoint(v.idx(), p[0], p[1], p[2]);
    normals->SetTuple3(v.idx(), nrm[0], nrm[1], nrm[2]);
  }
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(vtkIdType(mesh.n_faces()), 3 * vtkIdType(mesh.n_faces()));
  for (auto f : mesh.faces()) {
    vtkIdType ids[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) ids[k++] = v.idx();
    polys->InsertNextCell(3, ids);
  }
  poly->SetPoints(points);
  poly->SetPolys(polys);
  poly->GetPointData()->SetNormals(normals);
  return poly;
}

double signed_volume(vtkPolyData* poly) {
  double volume = 0;
  for (const auto& t : triangles_of(poly)) {
    double a[3], b[3], c[3];
    poly->GetPoint(t[0], a);
    poly->GetPoint(t[1], b);
    poly->GetPoint(t[2], c);
    volume += Eigen::Vector3d(a).dot(Eigen::Vector3d(b).cross(Eigen::Vector3d(c))) / 6;
  }
  return volume;
}

void decimate(Mesh& mesh, double max_error) {
  namespace D = OpenMesh::Decimater;
  mesh.request_face_normals();  // for the normal-flipping module
  mesh.update_face_normals();
  D::DecimaterT<Mesh> decimater(mesh);
  // Quadrics order the collapses; in OpenMesh 9 they are area weighted, so
  // their value is not a distance: the length bound comes from the
  // Hausdorff module. Normal flipping forbids fold-overs.
  D::ModQuadricT<Mesh>::Handle quadric;
  D::ModHausdorffT<Mesh>::Handle hausdorff;
  D::ModNormalFlippingT<Mesh>::Handle normal_flipping;
  decimater.add(quadric);
  decimater.module(quadric).unset_max_err();
  decimater.add(hausdorff);
  decimater.module(hausdorff).set_tolerance(float(max_error));
  decimater.add(normal_flipping);
  decimater.module(normal_flipping).set_max_normal_deviation(60.0);
  if (!decimater.initialize()) throw std::runtime_error("OpenMesh decimater failed to initialise");
  decimater.decimate();
  mesh.garbage_collection();
}

void add_surface_metadata(vtkFieldData* out, const SurfaceRequest& request) {
  vtkNew<vtkStringArray> surface;
  surface->SetName("surface");
  surface->InsertNextValue(request.surface == Surface::Threshold
                               ? request.field + (request.above ? ">" : "<") + std::to_string(request.threshold)
                               : to_string(request.surface));
  out->AddArray(surface);
  for (auto [name, value] : {std::pair<const char*, double>{"cond_threshold", request.cond_threshold},
                             std::pair<const char*, double>{"decimate_error", request.decimate_error}}) {
    vtkNew<vtkDoubleArray> number;
    number->SetName(name);
    number->InsertNextValue(value);
    out->AddArray(number);
  }
}

// Runs a VTK writer; throws std::runtime_error naming `path` if it fails.
template <class Writer>
void check_written(Writer* writer, const std::filesystem::path& path, const std::string& what) {
  if (writer->Write() != 1 || writer->GetErrorCode() != 0)
    throw std::runtime_error("cannot write " + what + " '" + path.string() + "': " +
                             vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode()));
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

}  // namespace

std::string openmesh_version() {
  return std::to_string(OM_GET_VER) + "." + std::to_string(OM_GET_MAJ) + "." + std::to_string(OM_GET_MIN);
}

std::string to_string(Surface surface) {
  switch (surface) {
    case Surface::Reach: return "reach";
    case Surface::WellConditioned: return "well_conditioned";
    case Surface::Threshold: return "threshold";
  }
  return "?";
}

namespace {

vtkSmartPointer<vtkPolyData> extract(const Field& field, const SurfaceRequest& request, int stride,
                                     MeshStats* before_decimation) {
  check_field(field);
  const auto& d = field.grid.dims;
  if (d[0] < 2 || d[1] < 2 || d[2] < 2)
    throw std::invalid_argument("surface: expected a volume with at least 2 samples per axis, got " +
                                std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]));
  if (request.surface == Surface::Threshold && !(request.threshold > 0 && std::isfinite(request.threshold)))
    throw std::invalid_argument("surface: expected a positive finite threshold for '" + request.field + "', got " +
                                std::to_string(request.threshold));
  if (request.surface == Surface::WellConditioned && !(request.cond_threshold > 1 && std::isfinite(request.cond_threshold)))
    throw std::invalid_argument("surface: expected a finite cond_threshold > 1, got " +
                                std::to_string(request.cond_threshold));
  if (!(request.decimate_error >= 0) || !std::isfinite(request.decimate_error))
    throw std::invalid_argument("surface: expected decimate_error >= 0, got " + std::to_string(request.decimate_error));

  const float eps = request.surface == Surface::Reach ? float(1e-6 * field.grid.spacing.minCoeff()) : 1e-6f;
  vtkSmartPointer<vtkImageData> image = padded_image(field.grid, surface_scalar(field, request), eps, stride);
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(image);
  contour->SetValue(0, 0.0);
  contour->ComputeNormalsOff();
  contour->ComputeGradientsOff();
  contour->ComputeScalarsOff();
  contour->Update();
  vtkPolyData* raw = contour->GetOutput();

  // Flying edges orients all triangles consistently with the gradient, so a
  // single global flip makes them outward; per-component flips would be
  // wrong for cavities, whose surfaces must face inward (negative volume).
  Mesh mesh = to_openmesh(raw, signed_volume(raw) < 0);
  if (request.decimate_error > 0 && mesh.n_faces() > 0) {
    if (before_decimation) *before_decimation = mesh_stats(to_polydata(mesh));
    decimate(mesh, request.decimate_error);
  }
  vtkSmartPointer<vtkPolyData> out = to_polydata(mesh);
  add_metadata(out->GetFieldData(), field);
  add_surface_metadata(out->GetFieldData(), request);
  return out;
}

}  // namespace

vtkSmartPointer<vtkPolyData> extract_surface(const Field& field, const SurfaceRequest& request,
                                             MeshStats* before_decimation) {
  return extract(field, request, 1, before_decimation);
}

vtkSmartPointer<vtkPolyData> extract_light_surface(const Field& field, const SurfaceRequest& request, int stride) {
  if (stride < 1) throw std::invalid_argument("surface: expected a stride >= 1, got " + std::to_string(stride));
  SurfaceRequest undecimated = request;
  undecimated.decimate_error = 0;
  return extract(field, undecimated, stride, nullptr);
}

MeshStats mesh_stats(vtkPolyData* mesh) {
  if (!mesh) throw std::invalid_argument("mesh_stats: expected a mesh, got null");
  MeshStats stats;
  const auto triangles = triangles_of(mesh);
  const EdgeCounts edges = count_edges(triangles, std::size_t(mesh->GetNumberOfPoints()));
  std::vector<char> used(std::size_t(mesh->GetNumberOfPoints()), 0);
  stats.min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  stats.max = -stats.min;
  for (const auto& t : triangles) {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) {
      mesh->GetPoint(t[k], p[k].data());
      if (!used[std::size_t(t[k])]) {
        used[std::size_t(t[k])] = 1;
        ++stats.vertices;
        stats.min = stats.min.cwiseMin(p[k]);
        stats.max = stats.max.cwiseMax(p[k]);
      }
    }
    stats.volume += p[0].dot(p[1].cross(p[2])) / 6;
    stats.area += (p[1] - p[0]).cross(p[2] - p[0]).norm() / 2;
  }
  stats.faces = triangles.size();
  stats.boundary_edges = edges.boundary;
  stats.non_manifold_edges = edges.non_manifold;
  if (stats.vertices == 0) stats.min = stats.max = Eigen::Vector3d::Zero();
  stats.euler_characteristic = int(stats.vertices) - int(edges.edges) + int(stats.faces);
  return stats;
}

namespace {

// `mesh` with its points in `unit` instead of `field_unit` (itself when the
// two are the same).
vtkSmartPointer<vtkPolyData> in_unit(vtkPolyData* mesh, const std::string& field_unit, const std::string& unit) {
  vtkSmartPointer<vtkPolyData> out = mesh;
  if (unit == field_unit) return out;
  if (!haptics::is_length_unit(unit)) throw std::invalid_argument("mesh unit: expected mm, cm, m or in, got '" + unit + "'");
  if (!haptics::is_length_unit(field_unit))
    throw std::invalid_argument("mesh unit: the device's length unit '" + field_unit + "' has no conversion to " + unit);
  const double scale = haptics::metres_per(field_unit) / haptics::metres_per(unit);
  out = vtkSmartPointer<vtkPolyData>::New();
  out->ShallowCopy(mesh);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(mesh->GetNumberOfPoints());
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i) {
    double p[3];
    mesh->GetPoint(i, p);
    points->SetPoint(i, scale * p[0], scale * p[1], scale * p[2]);
  }
  out->SetPoints(points);
  return out;
}

// The file's text with its unit as a comment where readers skip it: OBJ's
// first line; in a PLY header after "ply" and the format line.
std::string with_unit_comment(const std::string& file, const std::string& ext, const std::string& unit) {
  if (ext == ".obj") return "# length unit: " + unit + "\n" + file;
  const std::size_t format_end = file.find('\n', file.find('\n') + 1);
  return file.substr(0, format_end + 1) + "comment length unit: " + unit + "\n" + file.substr(format_end + 1);
}

}  // namespace

void write_mesh(vtkPolyData* mesh_in_field_unit, const std::filesystem::path& path, const Field& for_metadata,
                const SurfaceRequest& request, const std::string& unit_asked) {
  if (!mesh_in_field_unit) throw std::invalid_argument("write_mesh: expected a mesh, got null");
  const std::string ext = lower(path.extension().string());
  if (ext != ".stl" && ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".vtp")
    throw std::invalid_argument("write_mesh: expected a path ending in .stl, .obj, .ply, .off or .vtp, got '" +
                                path.string() + "'");
  const std::string unit = unit_asked.empty() ? for_metadata.length_unit : unit_asked;
  const vtkSmartPointer<vtkPolyData> mesh = in_unit(mesh_in_field_unit, for_metadata.length_unit, unit);
  if (ext == ".stl") {
    // An STL file holds bare triangles: VTK writes them straight from `mesh`,
    // without building OpenMesh's connectivity first.
    write_atomically(path, [&](const std::filesystem::path& tmp) {
      vtkNew<vtkSTLWriter> writer;
      writer->SetFileName(tmp.c_str());
      writer->SetInputData(mesh);
      writer->SetFileTypeToBinary();
      // The 80-byte header, which readers skip: where the unit can be said.
      writer->SetHeader(("Linkscape workspace mesh, length unit: " + unit).c_str());
      check_written(writer.Get(), path, "STL");
    });
    return;
  }
  if (ext == ".vtp") {
    vtkNew<vtkPolyData> copy;
    copy->ShallowCopy(mesh);
    vtkNew<vtkFieldData> metadata;
    add_metadata(metadata, for_metadata);
    add_surface_metadata(metadata, request);
    metadata->RemoveArray("length_unit");  // the points' unit, which may differ from the field's
    vtkNew<vtkStringArray> unit_array;
    unit_array->SetName("length_unit");
    unit_array->InsertNextValue(unit);
    metadata->AddArray(unit_array);
    copy->SetFieldData(metadata);
    write_atomically(path, [&](const std::filesystem::path& tmp) {
      vtkNew<vtkXMLPolyDataWriter> writer;
      writer->SetFileName(tmp.c_str());
      writer->SetInputData(copy);
      writer->SetDataModeToAppended();
      writer->EncodeAppendedDataOff();
      writer->SetCompressorTypeToZLib();
      check_written(writer.Get(), path, "VTK poly data");
    });
    return;
  }

  // Same vertex order as `mesh` (no merging, no flipping) so that readers
  // see the same points and triangles.
  Mesh om;
  for (vtkIdType i = 0; i < mesh->GetNumberOfPoints(); ++i) {
    double p[3];
    mesh->GetPoint(i, p);
    om.add_vertex(Mesh::Point(float(p[0]), float(p[1]), float(p[2])));
  }
  const auto triangles = triangles_of(mesh);
  for (const auto& t : triangles)
    om.add_face(om.vertex_handle(int(t[0])), om.vertex_handle(int(t[1])), om.vertex_handle(int(t[2])));
  if (om.n_faces() != triangles.size())
    throw std::invalid_argument("write_mesh: expected a manifold triangle mesh, got " +
                                std::to_string(triangles.size() - om.n_faces()) + " triangles OpenMesh cannot connect");
  OpenMesh::IO::Options options;
  if (ext == ".stl" || ext == ".ply") options += OpenMesh::IO::Options::Binary;
  if (ext == ".ply" || ext == ".obj") {
    vtkDataArray* normals = mesh->GetPointData()->GetNormals();
    if (normals && normals->GetNumberOfComponents() == 3) {
      om.request_vertex_normals();
      for (auto v : om.vertices()) {
        const double* n = normals->GetTuple3(v.idx());
        om.set_normal(v, Mesh::Normal(float(n[0]), float(n[1]), float(n[2])));
      }
      options += OpenMesh::IO::Options::VertexNormal;
    }
  }
  // OpenMesh's writers log every file to omlog (stdout); keep quiet.
  struct QuietLog {
    bool was = ::omlog().is_enabled();
    QuietLog() { ::omlog().disable(); }
    ~QuietLog() {
      if (was) ::omlog().enable();
    }
  } quiet;
  // The format from the target's extension, not tmp's; the unit as a
  // comment where the format has them (PLY, OBJ; OFF has none every reader takes).
  std::ostringstream text;
  if (!OpenMesh::IO::write_mesh(om, text, ext, options, 9))
    throw std::runtime_error("cannot write mesh '" + path.string() + "'");
  const std::string file = ext == ".off" ? text.str() : with_unit_comment(text.str(), ext, unit);
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out.write(file.data(), std::streamsize(file.size())) || !out.flush())
      throw std::runtime_error("cannot write mesh '" + path.string() + "'");
  });
}

}  // namespace linkscape::render
