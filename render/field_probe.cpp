#include "render/field_probe.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/field_names.h"
#include "core/status.h"
#include "render/field_vtk.h"
#include "render/slice_image.h"

namespace linkscape::render {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One array of a field as the probe reads it.
struct Array {
  std::string name, unit;
  bool continuous = true;   // interpolated where its neighbours allow
  bool needs_reach = true;  // a value only where the sample is reachable
  std::function<double(std::size_t)> at;
  std::function<std::string(double)> label;  // codes' names
};

std::vector<Array> arrays(const Field& f) {
  std::vector<Array> out;
  const std::string length = f.length_unit;
  for (const FieldArrayInfo& a : kFieldArrays) {  // core/field_names.h: the member, unit and reach of each
    if (!field_has(f, a)) continue;
    const bool code = a.array == FieldArray::Status || a.array == FieldArray::Method || a.array == FieldArray::Reachable;
    std::function<std::string(double)> label;
    if (a.array == FieldArray::Status) label = [](double v) { return std::string(to_string(Status(int(v)))); };
    if (a.array == FieldArray::Method) label = [&f](double v) { return method_code_name(f, int(v)); };
    if (a.array == FieldArray::Reachable) label = [](double v) { return std::string(v != 0 ? "yes" : "no"); };
    out.push_back({std::string(a.name), a.length ? length : "", !code && a.array != FieldArray::Iterations,
                   a.needs_solution && !code, [&f, &a](std::size_t s) { return field_value(f, a, s); }, label});
  }
  for (const Field::NamedArray& e : f.extras)
    out.push_back({e.name, e.unit, true, true, [&e](std::size_t s) { return double(e.values[s]); }, {}});
  return out;
}

// The title without its " (unit)".
std::string bare_title(const Field& f, const std::string& name) {
  std::string t = name == "reachable" ? name : field_title(f, name);
  if (const auto p = t.rfind(" ("); p != std::string::npos && t.back() == ')') t.resize(p);
  return t;
}

// The samples around `p` with their trilinear weights (axes with one sample,
// or a point beyond the outer samples, clamp to the nearest).
struct Stencil {
  std::array<std::size_t, 8> index{};
  std::array<double, 8> weight{};
  int count = 0;
  std::array<int, 3> nearest{};
};

Stencil stencil(const Grid& g, const Eigen::Vector3d& p) {
  std::array<int, 3> lo{};
  std::array<double, 3> frac{};
  Stencil st;
  for (int a = 0; a < 3; ++a) {
    const double t = (p(a) - g.origin(a)) / g.spacing(a) - 0.5;  // fractional sample index
    st.nearest[a] = std::clamp(int(std::lround(t)), 0, g.dims[a] - 1);
    if (g.dims[a] == 1) {
      lo[a] = 0;
      frac[a] = 0;
      continue;
    }
    lo[a] = std::clamp(int(std::floor(t)), 0, g.dims[a] - 2);
    frac[a] = std::clamp(t - lo[a], 0.0, 1.0);
  }
  for (int c = 0; c < 8; ++c) {
    double w = 1;
    int ijk[3];
    for (int a = 0; a < 3; ++a) {
      const int up = (c >> a) & 1;
      w *= up ? frac[a] : 1 - frac[a];
      ijk[a] = lo[a] + up;
    }
    if (w <= 0) continue;  // a corner that does not contribute must not veto interpolation
    st.index[st.count] = g.index(ijk[0], ijk[1], ijk[2]);
    st.weight[st.count++] = w;
  }
  return st;
}

ProbeValue read(const Field& f, const Array& a, const Stencil& st) {
  ProbeValue v{a.name, bare_title(f, a.name), a.unit, kNaN, {}, Sampling::Nearest};
  const std::size_t near = f.grid.index(st.nearest[0], st.nearest[1], st.nearest[2]);
  bool all_valid = a.continuous;
  double sum = 0;
  for (int k = 0; k < st.count && all_valid; ++k) {
    const double x = a.at(st.index[k]);
    all_valid = std::isfinite(x) && (!a.needs_reach || f.reachable[st.index[k]]);
    sum += st.weight[k] * x;
  }
  if (all_valid) {
    v.value = sum;
    v.sampling = Sampling::Trilinear;
  } else if (!a.needs_reach || f.reachable[near]) {
    v.value = a.at(near);
  }
  if (a.label && !std::isnan(v.value)) v.label = a.label(v.value);
  return v;
}

}  // namespace

const char* to_string(Sampling sampling) { return sampling == Sampling::Trilinear ? "trilinear" : "nearest sample"; }

const ProbeValue* ProbeSample::find(const std::string& name) const {
  for (const ProbeValue& v : values)
    if (v.name == name) return &v;
  return nullptr;
}

bool inside_cells(const Grid& g, const Eigen::Vector3d& p) {
  for (int a = 0; a < 3; ++a) {
    const double t = (p(a) - g.origin(a)) / g.spacing(a);
    const double slack = 1e-9 * g.dims[a];
    if (!(t >= -slack && t <= g.dims[a] + slack)) return false;
  }
  return true;
}

std::vector<std::string> probed_fields(const Field& field) {
  std::vector<std::string> names;
  for (const Array& a : arrays(field)) names.push_back(a.name);
  return names;
}

std::optional<ProbeSample> probe_point(const Field& field, const Eigen::Vector3d& p) {
  check_field(field);
  if (!inside_cells(field.grid, p)) return std::nullopt;
  const Stencil st = stencil(field.grid, p);
  ProbeSample out;
  out.point = p;
  out.nearest = st.nearest;
  out.nearest_point = field.grid.point(st.nearest[0], st.nearest[1], st.nearest[2]);
  for (const Array& a : arrays(field)) out.values.push_back(read(field, a, st));
  return out;
}

LineProfile probe_line(const Field& field, const std::string& name, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       int samples) {
  check_field(field);
  if (samples < 2) throw std::invalid_argument("line probe: expected at least 2 samples, got " + std::to_string(samples));
  if (!a.allFinite() || !b.allFinite()) throw std::invalid_argument("line probe: expected finite end points");
  const std::vector<Array> all = arrays(field);
  const auto it = std::find_if(all.begin(), all.end(), [&](const Array& x) { return x.name == name; });
  if (it == all.end()) {
    std::string known;
    for (const Array& x : all) known += (known.empty() ? "" : ", ") + x.name;
    throw std::invalid_argument("line probe: unknown field '" + name + "' (this field has " + known + ")");
  }
  LineProfile out{name, bare_title(field, name), it->unit, field.length_unit, {}, {}, {}, {}};
  const double length = (b - a).norm();
  for (int k = 0; k < samples; ++k) {
    const double t = double(k) / (samples - 1);
    const Eigen::Vector3d p = a + t * (b - a);
    out.distance.push_back(t * length);
    out.points.push_back(p);
    if (inside_cells(field.grid, p)) {
      const ProbeValue v = read(field, *it, stencil(field.grid, p));
      out.values.push_back(v.value);
      out.sampling.push_back(v.sampling);
    } else {
      out.values.push_back(kNaN);
      out.sampling.push_back(Sampling::Nearest);
    }
  }
  return out;
}

void write_profile_csv(const LineProfile& profile, const std::filesystem::path& path) {
  const std::string lu = profile.length_unit.empty() ? "" : " (" + profile.length_unit + ")";
  std::ostringstream out;
  out << "# " << profile.title << " along a segment; trilinear = 1 where interpolated between the samples around "
      << "the point, 0 where the nearest sample's value\n";
  out << csv_text("distance" + lu) << ',' << csv_text("x" + lu) << ',' << csv_text("y" + lu) << ','
      << csv_text("z" + lu) << ',' << csv_text(profile.field + (profile.unit.empty() ? "" : " (" + profile.unit + ")"))
      << ",trilinear\n";
  for (std::size_t k = 0; k < profile.values.size(); ++k) {
    const Eigen::Vector3d& p = profile.points[k];
    out << csv_number(profile.distance[k]) << ',' << csv_number(p.x()) << ',' << csv_number(p.y()) << ','
        << csv_number(p.z()) << ',' << csv_number(profile.values[k]) << ','
        << (profile.sampling[k] == Sampling::Trilinear ? 1 : 0) << '\n';
  }
  write_text_atomically(path, out.str());
}

}  // namespace linkscape::render
