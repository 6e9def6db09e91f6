// The kinematic arrays of a Field, in one table for every layer: the name a
// user types (slice --field, the window's field list, the renderer's
// styles), the name files store it under (.vti arrays, CSV columns), the
// member of Field that holds it, its unit and when it is offered. Adding a
// kinematic array is a Field member and a row here; the lists, the
// renderer's values and the .vti and CSV writers read it through the row.
// The haptic arrays are named in core/haptics.h (FieldInfo) and travel as
// Field::extras under those names.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/field.h"
#include "core/mechanism.h"

namespace linkscape {

enum class FieldArray { Cond, CondOrientation, Reach, Residual, Reachable, Iterations, Status, Method };

// Where a Field holds an array (the sample types it has).
using FieldMember = std::variant<SampleArray<float> Field::*, SampleArray<std::uint8_t> Field::*,
                                 SampleArray<std::uint16_t> Field::*>;

// When a device's lists offer an array.
enum class FieldShown {
  Always,
  WithSecondMeasure,   // devices with a second measure, under that measure's name
  WithDiagnostics,     // where the device's evaluation reports solver diagnostics
  WithSeveralMethods,  // devices with more than one IK method
  Never,               // written to files only
};

struct FieldArrayInfo {
  FieldArray array;
  std::string_view name;       // as users and styles name it
  std::string_view file_name;  // as .vti and CSV files store it
  FieldMember member;
  bool length = false;          // in the device's length unit (else without a unit: a ratio, count or code)
  bool needs_solution = false;  // a value only where the device reaches the sample; files leave it out elsewhere
  bool may_be_empty = false;    // a Field may not hold it (then files leave the column out)
  FieldShown shown = FieldShown::Always;
  double no_value = std::numeric_limits<double>::quiet_NaN();  // a code meaning "no value" (none: NaN)
};

// Every kinematic array, in the order lists and files show them.
inline constexpr std::array<FieldArrayInfo, 8> kFieldArrays{{
    {FieldArray::Cond, "cond", "cond", &Field::cond, false, true},
    // The second measure (six-DOF devices).
    {FieldArray::CondOrientation, "cond_jo", "cond_orientation", &Field::cond_orientation, false, true, true,
     FieldShown::WithSecondMeasure},
    {FieldArray::Reach, "reach", "reach_margin", &Field::reach_margin, true},
    {FieldArray::Residual, "residual", "residual", &Field::residual, true, true, false, FieldShown::WithDiagnostics},
    {FieldArray::Reachable, "reachable", "reachable", &Field::reachable, false, false, false, FieldShown::Never},
    {FieldArray::Iterations, "iterations", "iterations", &Field::iterations, false, false, false,
     FieldShown::WithDiagnostics},
    {FieldArray::Status, "status", "status", &Field::status},
    {FieldArray::Method, "method", "method_used", &Field::method_used, false, true, true,
     FieldShown::WithSeveralMethods, Field::kNoMethod},
}};

// The array of a user's name; none for another name (a haptic array, an
// array written to files only, or a typo).
std::optional<FieldArray> field_array(std::string_view name);

const FieldArrayInfo& field_array_info(FieldArray array);

// The names users may choose: "cond, cond_jo, reach, residual, iterations, status, method".
std::string field_array_names();

// Whether `field` holds the array (one value per sample).
bool field_has(const Field& field, const FieldArrayInfo& array);

// The array's value at sample `s` (field_has must hold).
double field_value(const Field& field, const FieldArrayInfo& array, std::size_t s);

// Calls `f` with the array itself (a SampleArray of its sample type).
template <class F>
decltype(auto) visit_field_array(const Field& field, const FieldArrayInfo& array, F&& f) {
  return std::visit([&](auto member) -> decltype(auto) { return f(field.*member); }, array.member);
}

// A method code's name (Field::method_used): the device's name for it
// (Field::method_names, as eval --method lists them), "none" for
// Field::kNoMethod, else "method code N" (a field that did not record names).
std::string method_code_name(const Field& field, int code);

// The fields a device's fields have, as a user names them: cond (its first
// measure), its second measure under that measure's own name, reach, residual
// and iterations (where `diagnostics`), status, method where it has
// several IK methods, and the device's own extra fields (joint_margin,
// clearance). The haptic fields follow in core/haptics.h.
std::vector<std::string> device_fields(const MechanismInfo& info, bool diagnostics = true);

}  // namespace linkscape
