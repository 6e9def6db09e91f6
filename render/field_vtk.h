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

// The field as image data with point arrays "cond", "reach_margin",
// "residual" (float), "reachable", "status" (unsigned char) and "iterations"
// (unsigned short), "method_used" (unsigned char: the device's method code,
// 255 = none; only when the field records it), each named array of
// Field::extras (float, its unit as the component name), active scalars
// "cond", and the metadata of add_metadata(). The arrays are COPIED (about 2x the field's memory for a
// moment), so the image is independent of the Field's lifetime.
// Throws std::invalid_argument as check_field.
vtkSmartPointer<vtkImageData> to_image_data(const Field& field);

// Adds the field's provenance to `out`: "mechanism", "length_unit",
// "method" (string arrays), "branch", "param_<name>" for every parameter
// (one-value double arrays), "resolution" (three doubles: grid.dims), and
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
//   x,y,z,cond,reach_margin,residual,reachable,status,iterations[,method_used][,<named arrays>]
// (method_used when the field records it: every field from compute_field;
// the named arrays of Field::extras, e.g. force_iso, in their units).
// x, y, z are the sample's cell centre (length unit); numbers use the
// shortest text that reads back to the same value (floats as floats),
// infinities as "inf"/"-inf". Atomic; throws as write_vti.
void write_field_csv(const Field& field, const std::filesystem::path& path);

}  // namespace linkscape::render
