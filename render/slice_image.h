// Colour-mapped images of a one-sample-thick field slice, drawn without any
// display: pixels are computed on the CPU and written with vtkPNGWriter.
//
// Viridis for the value, light grey (0.85) for unreachable samples, white
// contour lines of cond and a dark grey line on the reachable boundary
// (reach_margin = 0), both found by marching squares on the sample grid.
// The first slice axis (Grid::slice_axes) points right, the second up.
#pragma once

#include <vtkSmartPointer.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/field.h"

class vtkImageData;
class vtkLookupTable;

namespace linkscape::render {

struct SliceStyle {
  // Which per-sample value is colour-mapped: "cond", "reach" (reach_margin),
  // "residual", "iterations", "status" or "method" (method_used, drawn in
  // categorical colours, method_colour(); min/max and log_scale are ignored),
  // or the name of one of the field's named arrays (Field::extras: force_iso,
  // force_max, resolution, inertia).
  std::string field = "cond";
  // Logarithmic colour scale; applies to cond, residual and named arrays.
  bool log_scale = true;
  // One of colour_maps(): "viridis" (default), "cividis" (also for colour
  // vision deficiency), "diverging" (blue-grey-red around the middle of the
  // range; for signed quantities such as the reach margin its automatic
  // range is symmetric about 0).
  std::string colour_map = "viridis";
  // Colour range in the value's own unit. Defaults: cond 1..10; otherwise
  // the range of the finite values over reachable samples.
  std::optional<double> min, max;
  // cond values outlined by contour lines (whatever `field` is shown).
  std::vector<double> contour_levels = {3.0};
  bool draw_reach_boundary = true;
  // Pixels per sample along each axis (nearest-neighbour upscaling), >= 1.
  int scale = 1;
  // Opacity (0..255) of samples outside the workspace: opaque in images; the
  // 3-D view lowers it so the slice's square corners do not hide the scene.
  unsigned char unreachable_alpha = 255;
};

// Display name of a slice field: the device's measure titles for "cond" and
// "cond_jo" (Field::measure_titles), "reach margin (cm)", "residual (cm)",
// a named array's title and unit ("isotropic force (N)"), else the name.
std::string field_title(const Field& field, const std::string& name);
// The quantity whose contours style.contour_levels draws: "cond_jo" when
// that is shown, else "cond".
std::string contour_field(const std::string& name);
// Whether style.field is drawn on a log10 scale (cond, cond_jo, residual,
// named arrays) rather than linearly.
bool uses_log_scale(const SliceStyle& style);

// The colour maps a slice can use (SliceStyle::colour_map).
const std::vector<std::string>& colour_maps();
// The colour of `map` at value01 in [0, 1] (clamped; NaN gives the value at
// 1), RGB 0..1. Throws std::invalid_argument for an unknown map.
std::array<double, 3> colour_of(double value01, const std::string& map = "viridis");
// Categorical colour of the IK method index stored per sample (Field::
// method_used) in the "method" slice, RGB 0..1: indices 0..4 purple, blue,
// orange, green, grey; anything else (no method) the unreachable grey.
std::array<double, 3> method_colour(std::uint8_t method);
// `map` as an n-entry lookup table over [0, 1], for colour bars.
vtkSmartPointer<vtkLookupTable> colour_lookup_table(const std::string& map = "viridis", int entries = 256);
// Round tick values for a colour bar over [lo, hi]: 1, 2, 3, 5 times the
// powers of ten on a log scale, steps of 1, 2 or 5 times a power of ten
// otherwise (about `count`; also on a log scale too narrow for three of the
// former). The window's bar and the figures use these.
std::vector<double> colour_bar_ticks(double lo, double hi, bool log, int count = 5);
// Round steps of 1, 2 or 5 times a power of ten over [lo, hi], about `count` of them.
std::vector<double> nice_ticks(double lo, double hi, int count);

// The colour range used for `field`: style.min/max where given, else the
// defaults described in SliceStyle. Throws std::invalid_argument for an
// unknown style.field, an empty field, min >= max, or a non-positive bound
// on a logarithmic scale.
std::pair<double, double> colour_range(const Field& field, const SliceStyle& style);
// Whether a diverging map's automatic range is symmetric about 0 for
// `field` over the data range [lo, hi]: for a margin (reach, joint_margin,
// clearance; negative past its limit) and for data of both signs, not for
// a field of one sign (a force), which would be drawn in one half of the map.
bool centres_zero(const std::string& field, double lo, double hi);
// A diverging map's automatic range: [lo, hi] made symmetric about 0 where
// centres_zero says so, else as it is.
void centre_diverging_range(const std::string& field, double& lo, double& hi);
// `style` with min and max filled in from colour_range().
SliceStyle resolved_style(const Field& field, const SliceStyle& style);
// Where `v` falls in the colour range of `style` (0..1, clamped; log10 on a
// logarithmic scale; +inf and NaN give 1). The range is style.min/max, or
// for cond the default 1..10; otherwise use resolved_style() first.
// Throws std::invalid_argument if the range is unknown or empty.
double normalised_value(double v, const SliceStyle& style);

// The slice's normal: the axis with dims == 1 (Z first, then Y, then X if
// several). Throws std::invalid_argument if no axis has one sample.
Axis slice_normal(const Grid& grid);

// The slice as an RGBA unsigned char image of (nu*scale) x (nv*scale)
// pixels, where nu, nv are the sample counts along the slice axes; x to the
// right, y up (row 0 at the bottom, as VTK images are). Throws
// std::invalid_argument for a bad field or style (see colour_range, scale < 1).
vtkSmartPointer<vtkImageData> render_slice_rgba(const Field& field, const SliceStyle& style);

// A line segment in sample coordinates: fractional sample indices along the
// slice's u and v axes (sample (i, j) sits at (i, j)).
struct SliceSegment {
  double u0, v0, u1, v1;
};
// The lines a slice image draws, by marching squares over the samples: each
// of style.contour_levels' segments (of contour_field(style.field), in
// log10) and the reach boundary's (reach margin 0) where
// style.draw_reach_boundary. Figures draw them as vector paths.
struct SliceLines {
  std::vector<std::pair<double, std::vector<SliceSegment>>> contours;  // level, segments
  std::vector<SliceSegment> boundary;
};
SliceLines slice_lines(const Field& field, const SliceStyle& style);

// render_slice_rgba() written as a PNG (top row = max v), atomically.
// Throws as render_slice_rgba and std::runtime_error on I/O failure.
void write_slice_png(const Field& field, const SliceStyle& style, const std::filesystem::path& path);

}  // namespace linkscape::render
