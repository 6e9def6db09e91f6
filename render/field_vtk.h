// A core Field as VTK image data, and its export as .vti and .csv.
//
// Samples sit at cell centres, so the image's points are the samples: its
// origin is grid.origin + spacing/2 (length unit) and its dimensions are
// grid.dims. Point order is the Field's (x fastest), so no reordering.
#pragma once

#include <vtkSmartPointer.h>

#include <filesystem>

#include "core/field.h"

class vtkFieldData;
class vtkImageData;

namespace linkscape::render {

// Checks that `field` has samples and that every per-sample array holds
// grid.size() values. Throws std::invalid_argument otherwise.
void check_field(const Field& field);

// The field as image data with a point array per kinematic array it holds
// (core/field_names.h, under its file name: "cond", "cond_orientation",
// "reach_margin", "residual", "reachable", "iterations", "status",
// "method_used", of the Field's sample types; method_used is the device's
// method code, 255 = none), each named array of Field::extras (float, its
// unit as the component name), active scalars "cond", and the metadata of
// add_metadata(). A real value that needs a solution (cond, the residual,
// the haptic measures) is NaN where `reachable` is 0, never +inf or 0. The
// arrays are COPIED (about 2x the field's memory for a moment), so the image
// is independent of the Field's lifetime.
// Throws std::invalid_argument as check_field.
vtkSmartPointer<vtkImageData> to_image_data(const Field& field);

// Adds the field's provenance to `out`: "mechanism", "length_unit",
// "method" (string arrays), "branch", "param_<name>" for every parameter
// (one-value double arrays), "grid_samples" (three doubles: grid.dims), and
// per named array "<name>_unit", "<name>_title", "<name>_description".
void add_metadata(vtkFieldData* out, const Field& field);

// How a .vti's appended arrays are compressed: VTK's XML compressors, level
// 1 (fastest) .. 9 (smallest). The default comes from the size and time
// table in docs/performance.md (LZ4 at level 1: at 192^3 about 5x faster to
// write than zlib at its default level, the file about a quarter larger).
struct VtiCompression {
  enum class Type { None, ZLib, LZ4, LZMA };
  Type type = Type::LZ4;
  int level = 1;
};

// Writes the image of to_image_data(field) as binary, compressed VTK XML
// image data, atomically, reading the Field's arrays in place (no copy).
// Throws std::invalid_argument as check_field or for a level outside 1..9,
// std::runtime_error if the file cannot be written (the target is then
// untouched).
void write_vti(const Field& field, const std::filesystem::path& path, const VtiCompression& compression = {});
// Writes any image data the same way (binary, compressed, atomically).
void write_image_data(vtkImageData* image, const std::filesystem::path& path, const VtiCompression& compression = {});

// Writes one CSV row per sample, x fastest:
//   x_U,y_U,z_U,cond[,cond_orientation],reach_margin_U,residual_U,reachable,iterations,status[,method_used][,<name>_<unit>...]
// where U is the field's length unit (core/csv.h's csv_column: a unit
// suffix; no suffix: a ratio, count or code), method_used when the field
// records it (every field from compute_field) and the named arrays of
// Field::extras (e.g. force_iso_N). x, y, z are the sample's cell centre.
// A value with no meaning is an empty cell: cond, cond_orientation,
// residual, method_used and the named arrays where the sample is not
// reachable, method_used where no method served. Numbers use the shortest
// text that reads back to the same value (floats as floats); cond is "inf"
// at a reachable singular sample. Atomic; throws as write_vti.
void write_field_csv(const Field& field, const std::filesystem::path& path);

}  // namespace linkscape::render
