// Workspace isosurfaces of a 3-D field as closed, outward-oriented triangle
// meshes, their statistics, and export (STL, OBJ, PLY, OFF, VTP).
//
// Surfaces come from vtkFlyingEdges3D on the samples, padded by one sample of
// "outside" on every side so that surfaces cut by the sampled box are closed
// exactly on the box faces. OpenMesh then orients them outward (positive
// signed volume) and optionally decimates them.
#pragma once

#include <vtkSmartPointer.h>

#include <Eigen/Core>
#include <cstddef>
#include <filesystem>
#include <string>

#include "core/field.h"

class vtkPolyData;

namespace linkscape::render {

enum class Surface {
  Reach,            // reach_margin = 0: the boundary of the reachable set
  WellConditioned,  // cond = cond_threshold, kept inside the reachable set
  Threshold,        // a named array (Field::extras) = threshold, kept inside the reachable set
};
// "reach" / "well_conditioned" / "threshold".
std::string to_string(Surface surface);

// "9.0.0": the OpenMesh this program was built with (Help > About).
std::string openmesh_version();

struct SurfaceRequest {
  Surface surface = Surface::Reach;
  double cond_threshold = 3.0;  // for WellConditioned, > 1
  // For WellConditioned: -1 the worst of the device's measures (a six-DOF
  // device well conditioned in position and orientation), 0 its first
  // (Field::cond) alone, 1 its second (Field::cond_orientation) alone.
  int measure = -1;
  // 0 = no decimation; else the largest distance (length unit) a decimated
  // vertex may lie from the original surface (OpenMesh quadric decimation
  // bounded by a Hausdorff-distance module).
  double decimate_error = 0;
  // For Threshold: the region where the array `field` is above (or below)
  // `threshold` (> 0, in the array's unit), e.g. force_iso above 2 N.
  std::string field;
  bool above = true;
  double threshold = 1.0;
};

struct MeshStats {
  std::size_t vertices = 0;  // points used by triangles
  std::size_t faces = 0;     // triangles (larger polygons count as fans)
  std::size_t boundary_edges = 0;      // edges of one triangle: 0 if closed
  std::size_t non_manifold_edges = 0;  // edges of three or more triangles
  int euler_characteristic = 0;        // V - E + F: 2 per sphere-like component
  double volume = 0;                   // signed, by the divergence theorem, length unit^3
  double area = 0;                     // length unit^2
  Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();  // bounds of used points
};
// Throws std::invalid_argument for a null mesh.
MeshStats mesh_stats(vtkPolyData* mesh);

// The requested isosurface as triangles with point normals ("Normals"), the
// field's metadata (see add_metadata) plus "surface" and "cond_threshold" as
// field data. Empty (no points) if the surface does not occur. Throws
// std::invalid_argument for a bad field (fewer than 2 samples along an axis)
// or request (cond_threshold <= 1, a threshold <= 0 or an array the field
// lacks, negative decimate_error). With `before_decimation` and a
// decimation asked for, the statistics of the surface it simplified.
vtkSmartPointer<vtkPolyData> extract_surface(const Field& field, const SurfaceRequest& request,
                                             MeshStats* before_decimation = nullptr);

// The same surface from every `stride`-th sample along each axis (the first
// included), undecimated: about stride^2 fewer triangles, for drawing while
// the view changes every frame. Where it leaves the sampled box it is closed
// up to half a sample beyond the full surface's face. Throws as
// extract_surface, and for a stride below 1.
vtkSmartPointer<vtkPolyData> extract_light_surface(const Field& field, const SurfaceRequest& request, int stride = 2);

// Writes `mesh` by the extension of `path`: .stl (binary) through VTK,
// .ply (binary), .obj, .off through OpenMesh; .vtp (binary, compressed) through VTK with
// the field's metadata and the request's "surface" and "cond_threshold" as
// field data. Atomic. Throws std::invalid_argument for an unknown extension
// (the message lists the supported ones) or a null mesh, std::runtime_error
// if the file cannot be written (the target is then untouched).
// `unit` (mm, cm, m or in; empty: the field's length unit) scales the
// points and is written where the format has room: the STL header, a PLY
// comment, an OBJ comment, the VTP's length_unit (OFF has no place for it).
void write_mesh(vtkPolyData* mesh, const std::filesystem::path& path, const Field& for_metadata,
                const SurfaceRequest& request, const std::string& unit = {});

}  // namespace linkscape::render
