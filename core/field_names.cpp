#include "core/field_names.h"

#include <stdexcept>

namespace linkscape {

std::optional<FieldArray> field_array(std::string_view name) {
  for (const FieldArrayInfo& a : kFieldArrays)
    if (a.name == name && a.shown != FieldShown::Never) return a.array;
  return std::nullopt;
}

const FieldArrayInfo& field_array_info(FieldArray array) {
  for (const FieldArrayInfo& a : kFieldArrays)
    if (a.array == array) return a;
  throw std::logic_error("field_array_info: an array without a row");
}

std::string field_array_names() {
  std::string out;
  for (const FieldArrayInfo& a : kFieldArrays)
    if (a.shown != FieldShown::Never) out += (out.empty() ? "" : ", ") + std::string(a.name);
  return out;
}

bool field_has(const Field& field, const FieldArrayInfo& array) {
  return visit_field_array(field, array, [&](const auto& values) { return values.size() == field.grid.size(); });
}

double field_value(const Field& field, const FieldArrayInfo& array, std::size_t s) {
  return visit_field_array(field, array, [s](const auto& values) { return double(values[s]); });
}

std::string method_code_name(const Field& field, int code) {
  if (code == Field::kNoMethod) return "none";
  if (code >= 0 && std::size_t(code) < field.method_names.size() && !field.method_names[std::size_t(code)].empty())
    return field.method_names[std::size_t(code)];
  return "method code " + std::to_string(code);
}

std::vector<std::string> device_fields(const MechanismInfo& info, bool diagnostics) {
  std::vector<std::string> out;
  for (const FieldArrayInfo& a : kFieldArrays) {
    switch (a.shown) {
      case FieldShown::Always: out.emplace_back(a.name); break;
      case FieldShown::WithSecondMeasure:
        if (info.measures.size() > 1) out.push_back(info.measures[1].name);
        break;
      case FieldShown::WithDiagnostics:
        if (diagnostics) out.emplace_back(a.name);
        break;
      case FieldShown::WithSeveralMethods:
        if (info.ik_methods.size() > 1) out.emplace_back(a.name);
        break;
      case FieldShown::Never: break;
    }
  }
  for (const NamedItem& extra : info.extra_fields) out.push_back(extra.name);  // joint_margin, clearance
  return out;
}

}  // namespace linkscape
