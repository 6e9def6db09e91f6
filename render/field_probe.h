// Reading a sampled Field at any point: the value of every array there (the
// window's pick read-out), one array along a segment (its line probe), and
// that profile written as CSV.
//
// Samples sit at cell centres (core/field.h). Continuous arrays (the
// measures, the reach margin, the residual, the named haptic arrays) are
// interpolated trilinearly between the 8 samples around the point (4 on a
// slice, 2 on a line) when every one of them holds a value (reachable and
// finite; the reach margin needs only finite); otherwise, and always for the
// integer and categorical arrays (iterations, status, method, reachable),
// the nearest sample's value is given. Each value says which.
#pragma once

#include <Eigen/Core>

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/field.h"

namespace linkscape::render {

enum class Sampling { Nearest, Trilinear };
const char* to_string(Sampling sampling);

struct ProbeValue {
  std::string name;   // as users name the field: "cond", "reach", "force_iso", ...
  std::string title;  // as the colour bar titles it, without the unit
  std::string unit;   // empty: dimensionless or a code
  double value = 0;   // NaN where the sample holds none
  std::string label;  // a code's name ("unreachable"), else empty
  Sampling sampling = Sampling::Nearest;
};

struct ProbeSample {
  Eigen::Vector3d point;
  std::array<int, 3> nearest{};  // the nearest sample's grid index (i, j, k)
  Eigen::Vector3d nearest_point;  // and its position
  std::vector<ProbeValue> values;  // every array the field has, kinematic first, then the named ones
  const ProbeValue* find(const std::string& name) const;
};

// Whether `p` lies in the field's cells: within half a spacing of the
// outermost samples along every axis (a slice is one cell thick).
bool inside_cells(const Grid& grid, const Eigen::Vector3d& p);

// Every array of `field` at `p`, or nothing where `p` lies outside its cells.
// Throws std::invalid_argument for a field whose arrays do not cover its grid.
std::optional<ProbeSample> probe_point(const Field& field, const Eigen::Vector3d& p);

// The names probe_point reports for `field`, in its order.
std::vector<std::string> probed_fields(const Field& field);

// One array along the segment a -> b at `samples` evenly spaced points
// (both ends included); points outside the field's cells get NaN.
struct LineProfile {
  std::string field, title, unit, length_unit;
  std::vector<double> distance;  // from a, length unit
  std::vector<Eigen::Vector3d> points;
  std::vector<double> values;
  std::vector<Sampling> sampling;
};
// Throws std::invalid_argument for fewer than 2 samples, a field name the
// field does not have, non-finite ends, or a field as probe_point.
LineProfile probe_line(const Field& field, const std::string& name, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       int samples);

// The profile as CSV, atomically: a '#' line saying what it is, then
// columns distance, x, y, z (with the length unit), the field (with its
// unit) and trilinear (1 interpolated, 0 nearest sample); numbers as
// core/csv.h's csv_number writes them (NaN: an empty cell), so read_csv
// reads it back. Throws std::runtime_error
// when the file cannot be written (the target is then untouched).
void write_profile_csv(const LineProfile& profile, const std::filesystem::path& path);

}  // namespace linkscape::render
