#include "render/slice_image.h"

#include <vtkErrorCode.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/field_names.h"
#include "render/field_vtk.h"

namespace linkscape::render {
namespace {

// Viridis (matplotlib, CC0): entries 0, 16, ..., 255 of its 256-entry table,
// as (position, r, g, b); linear interpolation in between.
constexpr std::array<std::array<double, 4>, 17> kViridis = {{
    {0 / 255.0, 0.267004, 0.004874, 0.329415},   {16 / 255.0, 0.282327, 0.094955, 0.417331},
    {32 / 255.0, 0.278826, 0.175490, 0.483397},  {48 / 255.0, 0.258965, 0.251537, 0.524736},
    {64 / 255.0, 0.229739, 0.322361, 0.545706},  {80 / 255.0, 0.199430, 0.387607, 0.554642},
    {96 / 255.0, 0.172719, 0.448791, 0.557885},  {112 / 255.0, 0.149039, 0.508051, 0.557250},
    {128 / 255.0, 0.127568, 0.566949, 0.550556}, {143 / 255.0, 0.120081, 0.622161, 0.534946},
    {159 / 255.0, 0.153894, 0.680203, 0.504172}, {175 / 255.0, 0.239374, 0.735588, 0.455688},
    {191 / 255.0, 0.360741, 0.785964, 0.387814}, {207 / 255.0, 0.506271, 0.828786, 0.300362},
    {223 / 255.0, 0.668054, 0.861999, 0.196293}, {239 / 255.0, 0.835270, 0.886029, 0.102646},
    {255 / 255.0, 0.993248, 0.906157, 0.143936},
}};

// cividis (Nuñez, Anderton and Renslow 2018) and Moreland's cool-to-warm
// diverging map, at the same 17 points as viridis above, from matplotlib's tables.
constexpr std::array<std::array<double, 4>, 17> kCividis = {{
    {0 / 255.0, 0.000000, 0.135112, 0.304751},   {16 / 255.0, 0.000000, 0.178802, 0.414764},
    {32 / 255.0, 0.103401, 0.220406, 0.435790},  {48 / 255.0, 0.195057, 0.264372, 0.425924},
    {64 / 255.0, 0.263738, 0.307831, 0.422789},  {80 / 255.0, 0.324250, 0.351289, 0.426250},
    {96 / 255.0, 0.380830, 0.395164, 0.435653},  {112 / 255.0, 0.435168, 0.439763, 0.451134},
    {128 / 255.0, 0.488697, 0.485318, 0.471008}, {143 / 255.0, 0.544069, 0.528948, 0.471947},
    {159 / 255.0, 0.605211, 0.576777, 0.464441}, {175 / 255.0, 0.668008, 0.626171, 0.449270},
    {191 / 255.0, 0.732422, 0.677364, 0.425717}, {207 / 255.0, 0.798480, 0.730580, 0.392597},
    {223 / 255.0, 0.866421, 0.786028, 0.346571}, {239 / 255.0, 0.936660, 0.843841, 0.280876},
    {255 / 255.0, 0.995737, 0.909344, 0.217772},
}};
constexpr std::array<std::array<double, 4>, 17> kCoolWarm = {{
    {0 / 255.0, 0.229806, 0.298718, 0.753683},   {16 / 255.0, 0.304174, 0.406945, 0.845263},
    {32 / 255.0, 0.383662, 0.510183, 0.917831},  {48 / 255.0, 0.467678, 0.605591, 0.968546},
    {64 / 255.0, 0.554312, 0.690097, 0.995516},  {80 / 255.0, 0.640828, 0.760752, 0.997846},
    {96 / 255.0, 0.724041, 0.814910, 0.975651},  {112 / 255.0, 0.800601, 0.850358, 0.930008},
    {128 / 255.0, 0.867428, 0.864377, 0.862602}, {143 / 255.0, 0.922681, 0.828568, 0.777054},
    {159 / 255.0, 0.958176, 0.771234, 0.680301}, {175 / 255.0, 0.969851, 0.695830, 0.581312},
    {191 / 255.0, 0.958279, 0.604335, 0.483297}, {207 / 255.0, 0.924409, 0.498590, 0.389059},
    {223 / 255.0, 0.869655, 0.379274, 0.300941}, {239 / 255.0, 0.795938, 0.241845, 0.220830},
    {255 / 255.0, 0.705673, 0.015556, 0.150233},
}};

constexpr double kUnreachableGrey = 0.85;
constexpr std::array<unsigned char, 3> kContourColour = {255, 255, 255};
constexpr std::array<unsigned char, 3> kBoundaryColour = {64, 64, 64};
constexpr double kCondCap = 1e6;  // cond beyond this (and +inf) is treated as this for contours

// A kinematic array (core/field_names.h), or none for one of the field's
// named arrays (Field::extras, e.g. force_iso).
using Quantity = std::optional<FieldArray>;

Quantity parse_quantity(const std::string& name) {
  if (name.empty())
    throw std::invalid_argument("slice style: expected a field name (" + field_array_names() +
                                " or one of the field's named arrays), got none");
  return field_array(name);
}

// The named array a style shows. Throws std::invalid_argument listing the
// field's arrays when it has none of that name.
const Field::NamedArray& extra_array(const Field& field, const std::string& name) {
  if (const Field::NamedArray* a = field.extra(name)) return *a;
  std::string known = field_array_names();
  for (const auto& a : field.extras) known += ", " + a.name;
  throw std::invalid_argument("slice style: expected field " + known + ", got '" + name + "'");
}

bool is_cond(Quantity q) { return q == FieldArray::Cond || q == FieldArray::CondOrientation; }

// Condition numbers, residuals and the named arrays (forces, resolutions,
// inertias) spread over decades.
bool is_log(const SliceStyle& style, Quantity q) {
  return style.log_scale && (is_cond(q) || q == FieldArray::Residual || !q);
}

}  // namespace

std::string field_title(const Field& field, const std::string& name) {
  const std::string unit = field.length_unit.empty() ? "" : " (" + field.length_unit + ")";
  const auto& titles = field.measure_titles;
  switch (field_array(name).value_or(FieldArray::Method)) {
    case FieldArray::Cond: return titles.size() > 0 ? titles[0] : name;
    case FieldArray::CondOrientation: return titles.size() > 1 ? titles[1] : name;
    case FieldArray::Reach: return "reach margin" + unit;
    case FieldArray::Residual: return "residual" + unit;
    default: break;
  }
  if (const Field::NamedArray* a = field.extra(name)) return a->title + (a->unit.empty() ? "" : " (" + a->unit + ")");
  return name;  // iterations, status, method
}

std::string contour_field(const std::string& name) {
  const FieldArray shown = field_array(name) == FieldArray::CondOrientation ? FieldArray::CondOrientation : FieldArray::Cond;
  return std::string(field_array_info(shown).name);
}

bool uses_log_scale(const SliceStyle& style) { return is_log(style, parse_quantity(style.field)); }

namespace {

double value_at(const Field& f, Quantity q, std::size_t s, const Field::NamedArray* extra = nullptr) {
  if (!q) return extra->values[s];
  if (*q == FieldArray::Method && f.method_used.empty()) return Field::kNoMethod;  // not recorded
  return field_value(f, field_array_info(*q), s);
}

void check_range(double lo, double hi, bool log) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi))
    throw std::invalid_argument("slice style: expected a finite colour range with min < max, got [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "]");
  if (log && lo <= 0)
    throw std::invalid_argument("slice style: a logarithmic colour scale needs min > 0, got " + std::to_string(lo));
}

// The grid index of sample (iu, iv) of a slice with axes u, v.
std::size_t slice_index(const Grid& g, Axis u, Axis v, int iu, int iv) {
  int ijk[3] = {0, 0, 0};
  ijk[int(u)] = iu;
  ijk[int(v)] = iv;
  return g.index(ijk[0], ijk[1], ijk[2]);
}

// Marching squares: the segments where `f` (nu x nv, u fastest) crosses
// `level`; saddles are resolved by the cell-centre average.
std::vector<SliceSegment> contour(const std::vector<double>& f, int nu, int nv, double level) {
  std::vector<SliceSegment> out;
  static constexpr int kCorner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int j = 0; j + 1 < nv; ++j)
    for (int i = 0; i + 1 < nu; ++i) {
      double value[4];
      bool inside[4];
      int count = 0;
      for (int c = 0; c < 4; ++c) {
        value[c] = f[std::size_t(i + kCorner[c][0]) + std::size_t(nu) * (j + kCorner[c][1])];
        inside[c] = value[c] > level;
        count += inside[c];
      }
      if (count == 0 || count == 4) continue;
      // Crossing on edge e (corner e to corner e+1).
      double pu[4], pv[4];
      bool crossed[4];
      for (int e = 0; e < 4; ++e) {
        const int a = e, b = (e + 1) % 4;
        crossed[e] = inside[a] != inside[b];
        if (!crossed[e]) continue;
        const double t = (level - value[a]) / (value[b] - value[a]);
        pu[e] = i + kCorner[a][0] + t * (kCorner[b][0] - kCorner[a][0]);
        pv[e] = j + kCorner[a][1] + t * (kCorner[b][1] - kCorner[a][1]);
      }
      auto add = [&](int e0, int e1) { out.push_back({pu[e0], pv[e0], pu[e1], pv[e1]}); };
      if (crossed[0] && crossed[1] && crossed[2] && crossed[3]) {
        const bool centre = (value[0] + value[1] + value[2] + value[3]) / 4 > level;
        if (centre == inside[0]) {  // corners 0 and 2 joined: cut off 1 and 3
          add(0, 1);
          add(2, 3);
        } else {
          add(3, 0);
          add(1, 2);
        }
        continue;
      }
      int e[2], n = 0;
      for (int k = 0; k < 4; ++k)
        if (crossed[k]) e[n++] = k;
      add(e[0], e[1]);
    }
  return out;
}

// Draws `segments` into the RGBA buffer with a square brush `width` pixels wide.
void draw(unsigned char* rgba, int width_px, int height_px, int scale, const std::vector<SliceSegment>& segments,
          std::array<unsigned char, 3> colour, int width) {
  auto paint = [&](double x, double y) {
    const int x0 = int(std::floor(x - width / 2.0 + 0.5)), y0 = int(std::floor(y - width / 2.0 + 0.5));
    for (int py = y0; py < y0 + width; ++py)
      for (int px = x0; px < x0 + width; ++px) {
        if (px < 0 || py < 0 || px >= width_px || py >= height_px) continue;
        unsigned char* p = rgba + 4 * (std::size_t(px) + std::size_t(width_px) * py);
        p[0] = colour[0];
        p[1] = colour[1];
        p[2] = colour[2];
        p[3] = 255;
      }
  };
  for (const SliceSegment& s : segments) {
    const double x0 = (s.u0 + 0.5) * scale, y0 = (s.v0 + 0.5) * scale;
    const double x1 = (s.u1 + 0.5) * scale, y1 = (s.v1 + 0.5) * scale;
    const int steps = 1 + int(std::ceil(4 * std::max(std::abs(x1 - x0), std::abs(y1 - y0))));
    for (int k = 0; k <= steps; ++k) {
      const double t = double(k) / steps;
      paint(x0 + t * (x1 - x0), y0 + t * (y1 - y0));
    }
  }
}

unsigned char to_byte(double c) { return static_cast<unsigned char>(std::lround(std::clamp(c, 0.0, 1.0) * 255)); }

}  // namespace

std::array<double, 3> method_colour(std::uint8_t method) {
  switch (method) {
    case 0: return {0.58, 0.40, 0.74};  // purple
    case 1: return {0.12, 0.47, 0.71};  // blue
    case 2: return {1.00, 0.50, 0.05};  // orange
    case 3: return {0.17, 0.63, 0.17};  // green
    case 4: return {0.50, 0.50, 0.50};  // grey
    default: return {kUnreachableGrey, kUnreachableGrey, kUnreachableGrey};
  }
}

const std::vector<std::string>& colour_maps() {
  static const std::vector<std::string> maps = {"viridis", "cividis", "diverging"};
  return maps;
}

std::array<double, 3> colour_of(double value01, const std::string& map) {
  const auto& table = map == "viridis" ? kViridis : map == "cividis" ? kCividis : map == "diverging" ? kCoolWarm
      : throw std::invalid_argument("unknown colour map '" + map + "' (viridis, cividis or diverging)");
  const double t = std::isnan(value01) ? 1.0 : std::clamp(value01, 0.0, 1.0);
  std::size_t k = 1;
  while (k + 1 < table.size() && table[k][0] < t) ++k;
  const auto& a = table[k - 1];
  const auto& b = table[k];
  const double w = (t - a[0]) / (b[0] - a[0]);
  return {a[1] + w * (b[1] - a[1]), a[2] + w * (b[2] - a[2]), a[3] + w * (b[3] - a[3])};
}

std::vector<double> nice_ticks(double lo, double hi, int count) {
  const double raw = (hi - lo) / std::max(1, count);
  if (!(raw > 0) || !std::isfinite(raw)) return {lo};
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag < 1.5 ? mag : raw / mag < 3.5 ? 2 * mag : raw / mag < 7.5 ? 5 * mag : 10 * mag;
  std::vector<double> ticks;
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * step; t += step)
    ticks.push_back(std::abs(t) < 1e-12 * step ? 0.0 : t);
  return ticks;
}

std::vector<double> colour_bar_ticks(double lo, double hi, bool log, int count) {
  if (!log || !(lo > 0)) return nice_ticks(lo, hi, count);
  // 1-2-3-5 in each decade; fewer mantissas, then every n-th decade, while there are too many.
  const int first = int(std::floor(std::log10(lo))), last = int(std::ceil(std::log10(hi)));
  std::vector<double> ticks;
  for (const std::vector<int>& mantissas : {std::vector<int>{1, 2, 3, 5}, {1, 3}, {1}}) {
    for (int every = 1; every <= std::max(1, last - first); ++every) {
      ticks.clear();
      for (int e = first; e <= last; ++e) {
        if ((e - first) % every != 0) continue;
        for (int m : mantissas) {
          const double t = std::stod(std::to_string(m) + "e" + std::to_string(e));  // the double nearest 3e-2, not 3 * 1e-2
          if (t >= lo * (1 - 1e-9) && t <= hi * (1 + 1e-9)) ticks.push_back(t);
        }
      }
      // Under a decade wide, fewer than three of them: round linear steps,
      // at their places on the log scale (1.1, 1.15, 1.2, ... over 1.09-1.36).
      if (ticks.size() < 3) return nice_ticks(lo, hi, count);
      if (int(ticks.size()) <= 2 * count) return ticks;
      if (mantissas.size() > 1) break;  // try fewer mantissas before skipping decades
    }
  }
  return ticks;
}

vtkSmartPointer<vtkLookupTable> colour_lookup_table(const std::string& map, int entries) {
  if (entries < 2) throw std::invalid_argument("colour table: expected at least 2 entries, got " +
                                               std::to_string(entries));
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(entries);
  lut->SetTableRange(0, 1);
  for (int i = 0; i < entries; ++i) {
    const auto c = colour_of(double(i) / (entries - 1), map);
    lut->SetTableValue(i, c[0], c[1], c[2], 1.0);
  }
  lut->SetNanColor(kUnreachableGrey, kUnreachableGrey, kUnreachableGrey, 1.0);
  return lut;
}

bool centres_zero(const std::string& field, double lo, double hi) {
  return field == "reach" || field == "joint_margin" || field == "clearance" || (lo < 0 && hi > 0);
}

void centre_diverging_range(const std::string& field, double& lo, double& hi) {
  if (centres_zero(field, lo, hi)) hi = -(lo = -std::max(std::abs(lo), std::abs(hi)));
}

std::pair<double, double> colour_range(const Field& field, const SliceStyle& style) {
  const Quantity q = parse_quantity(style.field);
  check_field(field);
  colour_of(0, style.colour_map);  // an unknown map is a bad style
  const bool log = is_log(style, q);
  double lo = 1, hi = 10;
  if (q == FieldArray::CondOrientation && field.cond_orientation.size() != field.grid.size())
    throw std::invalid_argument("slice style: field 'cond_jo' needs a field with a second condition array");
  const Field::NamedArray* extra = !q ? &extra_array(field, style.field) : nullptr;
  if (extra && extra->values.size() != field.grid.size())
    throw std::invalid_argument("slice style: array '" + style.field + "' does not cover the grid");
  if (!is_cond(q) && !(style.min && style.max)) {
    lo = std::numeric_limits<double>::infinity();
    hi = -lo;
    for (std::size_t s = 0; s < field.grid.size(); ++s) {
      if (!field.reachable[s]) continue;
      const double v = value_at(field, q, s, extra);
      if (!std::isfinite(v) || (log && v <= 0)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    if (lo > hi) {  // nothing reachable: any valid range
      lo = log ? 1e-3 : 0;
      hi = log ? 1 : 1;
    } else if (lo == hi) {
      lo = log ? lo / 2 : lo - 0.5;
      hi = log ? hi * 2 : hi + 0.5;
    }
    if (style.colour_map == "diverging" && !log) centre_diverging_range(style.field, lo, hi);
  }
  if (style.min) lo = *style.min;
  if (style.max) hi = *style.max;
  check_range(lo, hi, log);
  return {lo, hi};
}

SliceStyle resolved_style(const Field& field, const SliceStyle& style) {
  SliceStyle out = style;
  const auto [lo, hi] = colour_range(field, style);
  out.min = lo;
  out.max = hi;
  return out;
}

double normalised_value(double v, const SliceStyle& style) {
  const Quantity q = parse_quantity(style.field);
  if (!is_cond(q) && !(style.min && style.max))
    throw std::invalid_argument("normalised_value: expected a style with min and max for field '" + style.field +
                                "' (use resolved_style), got none");
  const double lo = style.min.value_or(1.0), hi = style.max.value_or(10.0);
  const bool log = is_log(style, q);
  check_range(lo, hi, log);
  if (std::isnan(v) || v == std::numeric_limits<double>::infinity()) return 1.0;
  double t;
  if (log)
    t = v <= 0 ? 0.0 : (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo));
  else
    t = (v - lo) / (hi - lo);
  return std::clamp(t, 0.0, 1.0);
}

Axis slice_normal(const Grid& grid) {
  for (Axis a : {Axis::Z, Axis::Y, Axis::X})
    if (grid.dims[int(a)] == 1) return a;
  throw std::invalid_argument("slice: expected a grid with one sample along some axis, got " +
                              std::to_string(grid.dims[0]) + "x" + std::to_string(grid.dims[1]) + "x" +
                              std::to_string(grid.dims[2]));
}

vtkSmartPointer<vtkImageData> render_slice_rgba(const Field& field, const SliceStyle& style_in) {
  const SliceStyle style = resolved_style(field, style_in);  // validates field and style
  if (style.scale < 1 || style.scale > 64)
    throw std::invalid_argument("slice style: expected scale in 1..64, got " + std::to_string(style.scale));
  for (double level : style.contour_levels)
    if (!(level > 0) || !std::isfinite(level))
      throw std::invalid_argument("slice style: expected positive finite contour levels, got " +
                                  std::to_string(level));
  const Quantity q = parse_quantity(style.field);
  const Field::NamedArray* extra = !q ? &extra_array(field, style.field) : nullptr;
  const Grid& g = field.grid;
  const Axis normal = slice_normal(g);
  const std::array<Axis, 2> axes = Grid::slice_axes(normal);
  const Axis au = axes[0], av = axes[1];  // not a structured binding: clang 14 cannot capture those
  const int nu = g.dims[int(au)], nv = g.dims[int(av)];
  auto sample = [&](int iu, int iv) { return slice_index(g, au, av, iu, iv); };

  const int scale = style.scale;
  const int width = nu * scale, height = nv * scale;
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(width, height, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 4);
  image->GetPointData()->GetScalars()->SetName("rgba");
  auto* rgba = static_cast<unsigned char*>(image->GetScalarPointer());

  // Sample colours, upscaled by repetition.
  const unsigned char grey = to_byte(kUnreachableGrey);
  for (int iv = 0; iv < nv; ++iv)
    for (int iu = 0; iu < nu; ++iu) {
      const std::size_t s = sample(iu, iv);
      std::array<unsigned char, 4> c{grey, grey, grey, style.unreachable_alpha};
      if (field.reachable[s] && q == FieldArray::Method) {
        const auto rgb = method_colour(std::uint8_t(value_at(field, q, s)));
        c = {to_byte(rgb[0]), to_byte(rgb[1]), to_byte(rgb[2]), 255};
      } else if (field.reachable[s]) {
        const auto rgb = colour_of(normalised_value(value_at(field, q, s, extra), style), style.colour_map);
        c = {to_byte(rgb[0]), to_byte(rgb[1]), to_byte(rgb[2]), 255};
      }
      for (int y = iv * scale; y < (iv + 1) * scale; ++y)
        for (int x = iu * scale; x < (iu + 1) * scale; ++x) {
          unsigned char* p = rgba + 4 * (std::size_t(x) + std::size_t(width) * y);
          p[0] = c[0];
          p[1] = c[1];
          p[2] = c[2];
          p[3] = c[3];
        }
    }

  // Lines: cond contours, then the reachable boundary on top.
  const SliceLines lines = slice_lines(field, style);
  for (const auto& [level, segments] : lines.contours) draw(rgba, width, height, scale, segments, kContourColour, scale == 1 ? 1 : 2);
  draw(rgba, width, height, scale, lines.boundary, kBoundaryColour, 2);
  return image;
}

SliceLines slice_lines(const Field& field, const SliceStyle& style) {
  const Grid& g = field.grid;
  const std::array<Axis, 2> axes = Grid::slice_axes(slice_normal(g));
  const Axis au = axes[0], av = axes[1];  // not a structured binding: clang 14 cannot capture those
  const int nu = g.dims[int(au)], nv = g.dims[int(av)];
  auto sample = [&](int iu, int iv) { return slice_index(g, au, av, iu, iv); };
  SliceLines lines;
  std::vector<double> values(std::size_t(nu) * nv);
  // cond in log10: it is spread over decades.
  if (!style.contour_levels.empty()) {
    const Quantity q = parse_quantity(contour_field(style.field));
    for (int iv = 0; iv < nv; ++iv)
      for (int iu = 0; iu < nu; ++iu) {
        const double c = value_at(field, q, sample(iu, iv));
        values[iu + std::size_t(nu) * iv] = std::log10(std::isnan(c) ? kCondCap : std::clamp(c, 1e-30, kCondCap));
      }
    for (double level : style.contour_levels) lines.contours.emplace_back(level, contour(values, nu, nv, std::log10(level)));
  }
  if (style.draw_reach_boundary) {
    for (int iv = 0; iv < nv; ++iv)
      for (int iu = 0; iu < nu; ++iu) {
        const double m = field.reach_margin[sample(iu, iv)];
        values[iu + std::size_t(nu) * iv] = std::isnan(m) ? -1e30 : std::clamp(m, -1e30, 1e30);
      }
    lines.boundary = contour(values, nu, nv, 0.0);
  }
  return lines;
}

void write_slice_png(const Field& field, const SliceStyle& style, const std::filesystem::path& path) {
  vtkSmartPointer<vtkImageData> image = render_slice_rgba(field, style);
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(image);
    writer->Write();
    if (writer->GetErrorCode() != 0)
      throw std::runtime_error("cannot write PNG '" + path.string() + "': " +
                               vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode()));
  });
}

}  // namespace linkscape::render
