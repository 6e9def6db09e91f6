#include "render/field_vtk.h"

#include "core/field_names.h"

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
#include <stdexcept>
#include <string>

#include "core/atomic_file.h"

namespace linkscape::render {
namespace {

// The name a file stores an array under (core/field_names.h).
const char* file_name(FieldArray array) { return field_array_name(array).file_name.data(); }

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

// Appends the shortest round-trip text of `v` (std::to_chars; inf -> "inf").
template <class T>
void append_number(std::string& out, T v) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  if (ec != std::errc()) throw std::runtime_error("cannot format a number for CSV");
  out.append(buffer, end);
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
  check("cond", field.cond.size());
  check("reach_margin", field.reach_margin.size());
  check("residual", field.residual.size());
  check("reachable", field.reachable.size());
  check("status", field.status.size());
  check("iterations", field.iterations.size());
  if (!field.method_used.empty()) check("method_used", field.method_used.size());  // empty: not recorded
  if (!field.cond_orientation.empty()) check("cond_orientation", field.cond_orientation.size());  // six-DOF only
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
  add_numbers(out, "resolution", {double(d[0]), double(d[1]), double(d[2])});
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
  pd->AddArray(vtk_array<vtkFloatArray>(file_name(FieldArray::Cond), field.cond, copy));
  if (!field.cond_orientation.empty())
    pd->AddArray(vtk_array<vtkFloatArray>(file_name(FieldArray::CondOrientation), field.cond_orientation, copy));
  pd->AddArray(vtk_array<vtkFloatArray>(file_name(FieldArray::Reach), field.reach_margin, copy));
  pd->AddArray(vtk_array<vtkFloatArray>(file_name(FieldArray::Residual), field.residual, copy));
  pd->AddArray(vtk_array<vtkUnsignedCharArray>("reachable", field.reachable, copy));
  pd->AddArray(vtk_array<vtkUnsignedCharArray>(file_name(FieldArray::Status), field.status, copy));
  pd->AddArray(vtk_array<vtkUnsignedShortArray>(file_name(FieldArray::Iterations), field.iterations, copy));
  if (!field.method_used.empty())
    pd->AddArray(vtk_array<vtkUnsignedCharArray>(file_name(FieldArray::Method), field.method_used, copy));
  for (const Field::NamedArray& a : field.extras) {
    pd->AddArray(vtk_array<vtkFloatArray>(a.name.c_str(), a.values, copy));
    // The unit also as the component name, which ParaView shows beside the array.
    pd->GetArray(a.name.c_str())->SetComponentName(0, a.unit.c_str());
  }
  pd->SetActiveScalars(file_name(FieldArray::Cond));
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

void write_field_csv(const Field& field, const std::filesystem::path& path) {
  check_field(field);
  const Grid& g = field.grid;
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw std::runtime_error("cannot open '" + tmp.string() + "' for writing");
    const bool with_method = !field.method_used.empty(), with_orientation = !field.cond_orientation.empty();
    // The columns in the order the rows below write them.
    std::string chunk = std::string("x,y,z,") + file_name(FieldArray::Cond) + ",";
    if (with_orientation) chunk += std::string(file_name(FieldArray::CondOrientation)) + ",";
    chunk += std::string(file_name(FieldArray::Reach)) + "," + file_name(FieldArray::Residual) + ",reachable," +
             file_name(FieldArray::Status) + "," + file_name(FieldArray::Iterations);
    if (with_method) chunk += std::string(",") + file_name(FieldArray::Method);
    for (const Field::NamedArray& a : field.extras) chunk += "," + a.name;
    chunk += '\n';
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i) {
          const std::size_t s = g.index(i, j, k);
          const Eigen::Vector3d p = g.point(i, j, k);
          append_number(chunk, p.x());
          chunk += ',';
          append_number(chunk, p.y());
          chunk += ',';
          append_number(chunk, p.z());
          chunk += ',';
          append_number(chunk, field.cond[s]);
          chunk += ',';
          if (with_orientation) {
            append_number(chunk, field.cond_orientation[s]);
            chunk += ',';
          }
          append_number(chunk, field.reach_margin[s]);
          chunk += ',';
          append_number(chunk, field.residual[s]);
          chunk += ',';
          append_number(chunk, unsigned(field.reachable[s]));
          chunk += ',';
          append_number(chunk, unsigned(field.status[s]));
          chunk += ',';
          append_number(chunk, unsigned(field.iterations[s]));
          if (with_method) {
            chunk += ',';
            append_number(chunk, unsigned(field.method_used[s]));
          }
          for (const Field::NamedArray& a : field.extras) {
            chunk += ',';
            append_number(chunk, a.values[s]);
          }
          chunk += '\n';
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
