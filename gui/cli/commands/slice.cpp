// linkscape slice: a field sampled on a plane, as a colour-mapped image, a figure or CSV.
#include <algorithm>
#include <cmath>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "core/field.h"
#include "core/field_names.h"
#include "core/haptics.h"
#include "core/size_text.h"
#include "gui/cli/command.h"
#include "gui/cli/field_sampling.h"
#include "gui/cli/terminal.h"
#include "gui/figures/slice_figure.h"
#include "render/field_vtk.h"
#include "render/colour_scale.h"
#include "render/slice_image.h"

namespace linkscape::gui {
namespace {

struct SliceOptions {
  FieldOptions sampling;
  std::string plane;             // axis=position, length unit; default: the device's first plane
  std::vector<double> extent;    // u_min,u_max,v_min,v_max; default +-reach
  std::string size = "512x512";  // samples along u x v
  std::string field = "cond";    // cond, reach, residual, iterations, status, method, force_iso, force_max, resolution, inertia
  std::string colour_map = "viridis";  // render::colour_maps()
  std::vector<double> contours{3.0};
  std::vector<double> range;     // colour range min,max
  bool linear = false;           // linear colour scale for cond/residual
  bool figure = false;           // axes, colour bar and title (PNG, SVG, PDF)
  std::string output;            // .png, .csv (.svg, .pdf with --figure)
};

void run_slice(const SliceOptions& o) {
  if (o.output.empty()) throw std::invalid_argument("slice: --output is empty; give a file (.png, .csv; .svg or .pdf with --figure)");
  const std::string ext = extension_of(o.output);
  const bool ok_ext = o.figure ? (ext == ".png" || ext == ".svg" || ext == ".pdf") : (ext == ".png" || ext == ".csv");
  if (!ok_ext)
    throw std::invalid_argument("slice: --output must end in " + std::string(o.figure ? ".png, .svg or .pdf" : ".png or .csv") +
                                ", got '" + o.output + "'");
  Sampling sampling = make_sampling(o.sampling, "slice");
  const MechanismInfo& info = sampling.mechanism->info();
  const auto [default_normal, default_position] = sampling.mechanism->default_slice_plane(sampling.task);
  const std::string plane =
      !o.plane.empty() ? o.plane : std::string(1, "xyz"[int(default_normal)]) + "=" + format_number(default_position);
  const auto eq = plane.find('=');
  if (eq == std::string::npos) throw std::invalid_argument("--plane expects axis=position, e.g. x=0.25, got '" + plane + "'");
  const Axis normal = [&] {
    try {
      return parse_axis(plane.substr(0, eq));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--plane: ") + e.what());
    }
  }();
  const double position = parse_numbers(plane.substr(eq + 1), 1, "--plane expects axis=position, e.g. x=0.25")[0];
  std::vector<double> extent = o.extent;
  const auto [au, av] = Grid::slice_axes(normal);
  if (extent.empty())
    extent = {sampling.box_min()(int(au)), sampling.box_max()(int(au)), sampling.box_min()(int(av)),
              sampling.box_max()(int(av))};
  if (extent.size() != 4 || !(extent[0] < extent[1] && extent[2] < extent[3]) ||
      !std::all_of(extent.begin(), extent.end(), [](double v) { return std::abs(v) <= 1e300; }))
    throw std::invalid_argument("--extent expects u_min,u_max,v_min,v_max: finite, min < max on each axis");
  const auto size = parse_width_height(o.size, "--size");
  const Grid grid = Grid::slice(normal, position, extent[0], extent[1], extent[2], extent[3], size[0], size[1]);

  render::SliceStyle style;
  style.field = o.field;
  style.log_scale = !o.linear;
  style.colour_map = o.colour_map;
  style.contour_levels = o.contours;
  for (const double level : o.contours)
    if (!(std::isfinite(level) && level > 0))
      throw std::invalid_argument("--contour levels are condition numbers, finite and positive, got " +
                                  format_number(level));
  if (!o.range.empty()) {
    if (o.range.size() != 2 || !std::isfinite(o.range[0]) || !std::isfinite(o.range[1]) || !(o.range[0] < o.range[1]))
      throw std::invalid_argument("--range expects min,max, finite, min below max");
    style.min = o.range[0];
    style.max = o.range[1];
  }
  // The fields a device has (core/field_names.h), then the haptic ones.
  std::vector<std::string> fields = device_fields(info);
  for (const haptics::FieldInfo& f : haptics::all_field_infos()) fields.push_back(f.name);
  if (std::find(fields.begin(), fields.end(), style.field) == fields.end()) {
    std::string known;
    for (const auto& f : fields) known += (known.empty() ? "" : ", ") + f;
    throw std::invalid_argument("--field for " + info.name + " must be one of " + known + ", got '" + style.field + "'");
  }
  if (info.measures.size() > 1 && style.field == info.measures[1].name)
    style.field = field_array_info(FieldArray::CondOrientation).name;  // the renderer's name for the second measure
  // The figure's colour bar is continuous; the categorical method colours
  // are written as a plain image or CSV (column method_used).
  if (style.field == "method" && o.figure)
    throw std::invalid_argument("--field method is written without --figure (.png image or .csv)");
  if (style.field == "method") style.log_scale = false;
  // A field of categories (status, method) has no scale to make linear or range to give.
  if (render::is_categorical(style.field))
    for (const auto& [given, option] : {std::pair{o.linear, "--linear"}, {!o.range.empty(), "--range"}})
      if (given)
        throw std::invalid_argument(std::string(option) + " sets a colour scale; --field " + style.field +
                                    " is drawn in a colour for each of its categories");
  // A joint margin or clearance is signed (< 0 past the stop): linear.
  for (const NamedItem& extra : info.extra_fields)
    if (style.field == extra.name) style.log_scale = false;
  if (haptics::is_haptic_field(style.field)) {
    sampling.with_haptics();
    if (style.field == "inertia" && !sampling.device_data().has_inertia())
      throw std::invalid_argument("--field inertia: the preset gives no rotor_inertia_kgm2 for every actuator");
  }

  const auto start = std::chrono::steady_clock::now();
  ProgressLine line(o.sampling.quiet);
  const Field field = sample(sampling, grid, line);
  line.step("writing " + o.output);
  if (ext == ".csv") render::write_field_csv(field, o.output);
  else if (o.figure) write_slice_figure(field, style, o.output);
  else render::write_slice_png(field, style, o.output);
  line.clear();
  summary(o.sampling.quiet, "slice: wrote " + o.output + " (" + o.field + " of " + info.name + " on " + plane + ", " +
                                dimensions_text(grid) + " samples) in " + seconds_since(start));
}

Command add_slice(CLI::App& program, const DeviceHelp& help) {
  auto o = std::make_shared<SliceOptions>();
  CLI::App* cmd = program.add_subcommand(
      "slice", "Sample a field on a plane and write a colour-mapped image or CSV (no display needed)");
  add_field_options(*cmd, o->sampling, help);
  cmd->add_option("--plane", o->plane,
                  "Plane as axis=position in the length unit, e.g. x=0.25 (default: the device's first slice "
                  "plane for the pose)");
  cmd->add_option("--extent", o->extent,
                  "u_min,u_max,v_min,v_max of the plane's axes (x: y,z; y: x,z; z: x,y); default the "
                  "device's sampling box")
      ->delimiter(',')
      ->expected(4);
  cmd->add_option("--size", o->size, "Samples along u and v, WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option(
          "--field", o->field,
          "Field to colour: cond (the device's main measure: " +
              help.per_device([](const MechanismInfo& i) { return i.measures.front().title; }) +
              "), the second measure by its name where the device has one (" +
              help.per_device([](const MechanismInfo& i) {
                      return i.measures.size() > 1 ? i.measures[1].name + " = " + i.measures[1].title : "";
                    }) +
                    "), reach, residual, iterations, status, method (IK method used per sample, where the device "
                    "has several), or a haptic measure: force_iso (N, in every direction), force_max (N, in some "
                    "direction), resolution (mm per encoder count), inertia (kg, reflected rotor inertia)")
      ->capture_default_str();
  cmd->add_option("--contour", o->contours,
                  "Condition-number levels drawn as contour lines (comma list; of cond_jo when that is shown)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--range", o->range, "Colour range min,max (default: 1,10 for cond; data range otherwise)")
      ->delimiter(',')
      ->expected(2);
  cmd->add_flag("--linear", o->linear, "Linear colour scale for cond and residual (default: log)");
  cmd->add_option("--colour-map", o->colour_map,
                  "viridis, cividis (also for colour vision deficiency) or diverging (blue-grey-red; a signed "
                  "field's automatic range is symmetric about 0, e.g. --field reach)")
      ->capture_default_str();
  cmd->add_flag("--figure", o->figure, "Add axes with units, colour bar, legend and title (PNG, SVG or PDF)");
  cmd->add_option("-o,--output", o->output, "Output: .png or .csv; with --figure .png, .svg or .pdf")
      ->required();
  cmd->footer(field_csv_legend());

  return {cmd, Runs::Painting,  // figures draw text with QPainter
          "linkscape slice --plane x=0.25 --output slice.png    condition-number slice image",
          [o](std::istream&, std::ostream&) {
            run_slice(*o);
            return 0;
          }};
}

const RegisterCommand registered{20, add_slice};

}  // namespace
}  // namespace linkscape::gui
