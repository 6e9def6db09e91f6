#include "core/field_names.h"

#include <stdexcept>

namespace linkscape {

std::optional<FieldArray> field_array(std::string_view name) {
  for (const FieldArrayName& a : kFieldArrays)
    if (a.name == name) return a.array;
  return std::nullopt;
}

const FieldArrayName& field_array_name(FieldArray array) {
  for (const FieldArrayName& a : kFieldArrays)
    if (a.array == array) return a;
  throw std::logic_error("field_array_name: an array without a name");
}

std::string field_array_names() {
  std::string out;
  for (const FieldArrayName& a : kFieldArrays) out += (out.empty() ? "" : ", ") + std::string(a.name);
  return out;
}

std::vector<std::string> device_fields(const MechanismInfo& info, bool diagnostics) {
  std::vector<std::string> out;
  for (const FieldArrayName& a : kFieldArrays) {
    switch (a.array) {
      case FieldArray::CondOrientation:
        if (info.measures.size() > 1) out.push_back(info.measures[1].name);
        break;
      case FieldArray::Residual:
      case FieldArray::Iterations:
        if (diagnostics) out.emplace_back(a.name);
        break;
      case FieldArray::Method:
        if (info.ik_methods.size() > 1) out.emplace_back(a.name);
        break;
      default: out.emplace_back(a.name);
    }
  }
  return out;
}

}  // namespace linkscape
