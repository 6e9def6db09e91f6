// The names of a Field's per-sample arrays, in one place for every layer:
// the name a user types (slice --field, the window's field list, the
// renderer's styles) and the name files store it under (.vti arrays, CSV
// columns). The haptic arrays are named in core/haptics.h (FieldInfo) and
// travel as Field::extras under those names.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/mechanism.h"

namespace linkscape {

enum class FieldArray { Cond, CondOrientation, Reach, Residual, Iterations, Status, Method };

struct FieldArrayName {
  FieldArray array;
  std::string_view name;       // as users and styles name it
  std::string_view file_name;  // as .vti and CSV files store it
};

// Every kinematic array, in the order lists show them.
inline constexpr std::array<FieldArrayName, 7> kFieldArrays{{
    {FieldArray::Cond, "cond", "cond"},
    {FieldArray::CondOrientation, "cond_jo", "cond_orientation"},  // the second measure (six-DOF devices)
    {FieldArray::Reach, "reach", "reach_margin"},
    {FieldArray::Residual, "residual", "residual"},
    {FieldArray::Iterations, "iterations", "iterations"},
    {FieldArray::Status, "status", "status"},
    {FieldArray::Method, "method", "method_used"},
}};

// The array of a user's name; none for another name (a haptic array, or a typo).
std::optional<FieldArray> field_array(std::string_view name);

const FieldArrayName& field_array_name(FieldArray array);

// "cond, cond_jo, reach, residual, iterations, status, method".
std::string field_array_names();

// The fields a device's fields have, as a user names them: cond (its first
// measure), its second measure under that measure's own name, reach, residual
// and iterations (where `diagnostics`), status, and method where it has
// several IK methods. The haptic fields follow in core/haptics.h.
std::vector<std::string> device_fields(const MechanismInfo& info, bool diagnostics = true);

}  // namespace linkscape
