#include "render/field_vtk.h"

#include "core/field_names.h"
#include "core/status.h"

#include <vtkErrorCode.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnsignedShortArray.h>
#include <vtkXMLImageDataWriter.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <limits>
#include <functional>
#include <type_traits>
#include <vector>
#include <stdexcept>
#include <string>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/haptics.h"

namespace linkscape::render {
namespace {

// A VTK array with the values of `values`: a copy, or a view of them (VTK
// neither writes nor frees them; they must outlive the array).
template <class Array, class Values>
vtkSmartPointer<Array> vtk_array(const char* name, const Values& values, bool copy) {
  auto array = vtkSmartPointer<Array>::New();
  array->SetName(name);
  array->SetNumberOfComponents(1);
  if (copy) {
    array->SetNumberOfTuples(vtkIdType(values.size()));
    std::copy(values.begin(), values.end(), array->GetPointer(0));
  } else {
    using Value = typename Values::value_type;
    array->SetArray(const_cast<Value*>(values.data()), vtkIdType(values.size()), /*save=*/1);
  }
  return array;
}

void add_string(vtkFieldData* out, const char* name, const std::string& value) {
  vtkNew<vtkStringArray> array;
  array->SetName(name);
  array->InsertNextValue(value);
  out->AddArray(array);
}

void add_numbers(vtkFieldData* out, const std::string& name, std::initializer_list<double> values) {
  vtkNew<vtkDoubleArray> array;
  array->SetName(name.c_str());
  for (double v : values) array->InsertNextValue(v);
  out->AddArray(array);
}

// A VTK array of the sample type of `values`, named `name` (a copy or a view, as vtk_array).
template <class T>
vtkSmartPointer<vtkDataArray> typed_vtk_array(const char* name, const SampleArray<T>& values, bool copy) {
  if constexpr (std::is_same_v<T, float>) return vtk_array<vtkFloatArray>(name, values, copy);
  else if constexpr (std::is_same_v<T, std::uint16_t>) return vtk_array<vtkUnsignedShortArray>(name, values, copy);
  else return vtk_array<vtkUnsignedCharArray>(name, values, copy);
}

// The kinematic arrays `field` holds (core/field_names.h).
std::vector<const FieldArrayInfo*> held_arrays(const Field& field) {
  std::vector<const FieldArrayInfo*> held;
  for (const FieldArrayInfo& a : kFieldArrays)
    if (!a.may_be_empty || !visit_field_array(field, a, [](const auto& v) { return v.empty(); })) held.push_back(&a);
  return held;
}

}  // namespace

void check_field(const Field& field) {
  const auto& d = field.grid.dims;
  if (d[0] <= 0 || d[1] <= 0 || d[2] <= 0)
    throw std::invalid_argument("field: expected positive grid dims, got " + std::to_string(d[0]) + "x" +
                                std::to_string(d[1]) + "x" + std::to_string(d[2]));
  const std::size_t n = field.grid.size();
  auto check = [&](const char* name, std::size_t size) {
    if (size != n)
      throw std::invalid_argument(std::string("field: expected ") + std::to_string(n) + " values of '" + name +
                                  "' (grid " + std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" +
                                  std::to_string(d[2]) + "), got " + std::to_string(size));
  };
  for (const FieldArrayInfo* a : held_arrays(field))  // method_used empty: not recorded; cond_orientation: six-DOF only
    check(a->file_name.data(), visit_field_array(field, *a, [](const auto& v) { return v.size(); }));
  for (const Field::NamedArray& a : field.extras) check(a.name.c_str(), a.values.size());
  if (!(field.grid.spacing.array() > 0).all() || !field.grid.spacing.allFinite() || !field.grid.origin.allFinite())
    throw std::invalid_argument("field: expected finite origin and positive finite spacing");
}

void add_metadata(vtkFieldData* out, const Field& field) {
  add_string(out, "mechanism", field.mechanism);
  add_string(out, "length_unit", field.length_unit);
  add_string(out, "method", field.method);
  add_numbers(out, "branch", {double(field.branch)});
  for (const auto& [name, value] : field.parameters) add_numbers(out, "param_" + name, {value});
  const auto& d = field.grid.dims;
  // Not "resolution", the haptic array's name: one name, one meaning.
  add_numbers(out, "grid_samples", {double(d[0]), double(d[1]), double(d[2])});
  // The coded arrays' legends, so a reader needs no manual to name a code.
  add_string(out, "status_codes", status_codes());
  if (!field.method_names.empty()) {
    std::string codes;
    for (std::size_t k = 0; k < field.method_names.size(); ++k)
      codes += (k ? ", " : "") + std::to_string(k) + " " + field.method_names[k];
    add_string(out, "method_used_codes", codes);
  }
  for (const Field::NamedArray& a : field.extras) {
    add_string(out, (a.name + "_unit").c_str(), a.unit);
    add_string(out, (a.name + "_title").c_str(), a.title);
    if (!a.description.empty()) add_string(out, (a.name + "_description").c_str(), a.description);
  }
}

namespace {

vtkSmartPointer<vtkImageData> image_data(const Field& field, bool copy) {
  check_field(field);
  const Grid& g = field.grid;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(g.dims[0], g.dims[1], g.dims[2]);
  image->SetSpacing(g.spacing.x(), g.spacing.y(), g.spacing.z());
  const Eigen::Vector3d first = g.origin + 0.5 * g.spacing;
  image->SetOrigin(first.x(), first.y(), first.z());
  vtkPointData* pd = image->GetPointData();
  // A value that exists only where the device reaches the sample (c(J), the
  // residual, the haptic measures) is NaN elsewhere, so that no reader takes
  // it for a value (c(J) would read +inf, a force 0: weak, not unreachable);
  // `reachable` beside them says where. Such arrays are copied; the others
  // are read in place where `copy` is off.
  const auto with_nan = [&](const char* name, const SampleArray<float>& values) {
    SampleArray<float> masked = values;
    for (std::size_t s = 0; s < masked.size(); ++s)
      if (!field.reachable[s]) masked[s] = std::numeric_limits<float>::quiet_NaN();
    return vtk_array<vtkFloatArray>(name, masked, true);
  };
  for (const FieldArrayInfo* a : held_arrays(field))
    pd->AddArray(visit_field_array(field, *a, [&](const auto& v) -> vtkSmartPointer<vtkDataArray> {
      if constexpr (std::is_same_v<std::decay_t<decltype(v)>, SampleArray<float>>)
        if (a->needs_solution) return with_nan(a->file_name.data(), v);
      return typed_vtk_array(a->file_name.data(), v, copy);
    }));
  for (const Field::NamedArray& a : field.extras) {
    pd->AddArray(haptics::is_haptic_field(a.name) ? with_nan(a.name.c_str(), a.values)
                                                  : vtk_array<vtkFloatArray>(a.name.c_str(), a.values, copy));
    // The unit also as the component name, which ParaView shows beside the array.
    pd->GetArray(a.name.c_str())->SetComponentName(0, a.unit.c_str());
  }
  pd->SetActiveScalars(field_array_info(FieldArray::Cond).file_name.data());
  add_metadata(image->GetFieldData(), field);
  return image;
}

}  // namespace

vtkSmartPointer<vtkImageData> to_image_data(const Field& field) { return image_data(field, true); }

void write_vti(const Field& field, const std::filesystem::path& path, const VtiCompression& compression) {
  // `field` outlives the writer, so its arrays are read in place.
  write_image_data(image_data(field, false), path, compression);
}

void write_image_data(vtkImageData* image, const std::filesystem::path& path, const VtiCompression& compression) {
  if (compression.level < 1 || compression.level > 9)
    throw std::invalid_argument("write_vti: compression level must be 1..9, got " + std::to_string(compression.level));
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    vtkNew<vtkXMLImageDataWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(image);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();  // raw binary
    switch (compression.type) {
      case VtiCompression::Type::None: writer->SetCompressorTypeToNone(); break;
      case VtiCompression::Type::ZLib: writer->SetCompressorTypeToZLib(); break;
      case VtiCompression::Type::LZ4: writer->SetCompressorTypeToLZ4(); break;
      case VtiCompression::Type::LZMA: writer->SetCompressorTypeToLZMA(); break;
    }
    writer->SetCompressionLevel(compression.level);
    if (writer->Write() != 1 || writer->GetErrorCode() != 0)
      throw std::runtime_error("cannot write VTK image data '" + path.string() + "': " +
                               vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode()));
  });
}

namespace {

// One CSV column of a field: its header, and its cell of a sample.
struct CsvColumn {
  std::string header;
  std::function<void(std::string&, std::size_t)> cell;
};

// The columns after x, y, z: the kinematic arrays, then the named ones. A
// value that needs a solution is left empty where the device does not
// reach the sample, as is a code that means "no value".
std::vector<CsvColumn> csv_columns(const Field& field) {
  std::vector<CsvColumn> columns;
  const auto& reachable = field.reachable;
  for (const FieldArrayInfo* a : held_arrays(field))
    visit_field_array(field, *a, [&](const auto& values) {
      columns.push_back({csv_column(a->file_name, a->length ? field.length_unit : ""),
                         [&values, &reachable, a](std::string& out, std::size_t s) {
                           if ((a->needs_solution && !reachable[s]) || double(values[s]) == a->no_value) return;
                           append_csv_number(out, values[s]);
                         }});
    });
  for (const Field::NamedArray& n : field.extras)
    columns.push_back({csv_column(n.name, n.unit), [&n, &reachable](std::string& out, std::size_t s) {
                         if (reachable[s]) append_csv_number(out, n.values[s]);
                       }});
  return columns;
}

}  // namespace

void write_field_csv(const Field& field, const std::filesystem::path& path) {
  check_field(field);
  const Grid& g = field.grid;
  const std::vector<CsvColumn> columns = csv_columns(field);
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw std::runtime_error("cannot open '" + tmp.string() + "' for writing");
    std::string chunk;
    for (const char* axis : {"x", "y", "z"}) chunk += csv_column(axis, field.length_unit) + ",";
    for (const CsvColumn& c : columns) chunk += c.header + ",";
    chunk.back() = '\n';
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i) {
          const std::size_t s = g.index(i, j, k);
          const Eigen::Vector3d p = g.point(i, j, k);
          for (int axis = 0; axis < 3; ++axis) {
            append_csv_number(chunk, p(axis));
            chunk += ',';
          }
          for (const CsvColumn& c : columns) {
            c.cell(chunk, s);
            chunk += ',';
          }
          chunk.back() = '\n';
          if (chunk.size() > (1u << 20)) {
            out.write(chunk.data(), std::streamsize(chunk.size()));
            chunk.clear();
          }
        }
    out.write(chunk.data(), std::streamsize(chunk.size()));
    out.close();
    if (!out) throw std::runtime_error("cannot write CSV '" + path.string() + "'");
  });
}

}  // namespace linkscape::render
