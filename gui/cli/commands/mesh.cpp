// linkscape mesh: a workspace isosurface written as a mesh, with its statistics.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "core/field.h"
#include "core/haptics.h"
#include "core/size_text.h"
#include "gui/cli/command.h"
#include "gui/cli/field_sampling.h"
#include "gui/cli/terminal.h"
#include <vtkPolyData.h>

#include "core/task.h"
#include "render/workspace_mesh.h"

namespace linkscape::gui {
namespace {

struct MeshOptions {
  FieldOptions sampling;
  std::string surface = "reach";   // "reach", "cond<T" or a haptic criterion ("force_iso>2")
  std::string resolution = "128";
  std::vector<double> box;
  double decimate = 0;             // max decimation error, length unit; 0 = off
  std::string output;              // .stl .obj .ply .off .vtp
  std::string unit;                // of the written points; empty: the device's length unit
};

// reach, cond<T (the device's first measure; both measures for six-DOF
// devices, or one of them by name: cond_jp<T, cond_jo<T), a haptic criterion such as force_iso>2, or one on the device's
// stops such as clearance>2 (core/task.h).
render::SurfaceRequest parse_surface(const std::string& text, const MechanismInfo& info) {
  render::SurfaceRequest r;
  task::Criterion c;
  // A device's conditioning measure by name, where it has two (0, 1), else -1.
  const auto measure_of = [&info](const std::string& measure) {
    if (info.measures.size() < 2) return -1;
    for (int k = 0; k < 2; ++k)
      if (info.measures[std::size_t(k)].name == measure && measure != "cond") return k;
    return -1;
  };
  const auto on_a_stop = [&info](const std::string& measure) {
    return std::any_of(info.extra_fields.begin(), info.extra_fields.end(),
                       [&](const NamedItem& f) { return f.name == measure; });
  };
  try {
    const std::vector<std::string> parts = task::split_criteria(text);  // 'cond < 3' as cond<3
    if (parts.size() != 1) throw std::invalid_argument("one surface");
    c = task::parse_criterion(parts.front());
    if (c.measure != "reach" && c.measure != "cond" && !c.haptic() && !on_a_stop(c.measure) && measure_of(c.measure) < 0)
      throw std::invalid_argument("not a surface");
    if (measure_of(c.measure) >= 0) c = task::resolve(c, info, nullptr);  // its side and bound
  } catch (const std::invalid_argument&) {
    std::string stops, measures;
    for (const NamedItem& f : info.extra_fields) stops += ", " + f.name + ">M";
    if (info.measures.size() >= 2)
      measures = " (both measures; " + info.measures[0].name + "<T or " + info.measures[1].name + "<T for one)";
    throw std::invalid_argument("--surface expects reach, cond<T with T > 1 (e.g. cond<3)" + measures + ", a haptic criterion "
                                "(force_iso>F, force_max>F in N, resolution<R in mm, inertia<M in kg)" +
                                (stops.empty() ? "" : " or a margin to a stop (" + stops.substr(2) + ")") + " for " +
                                info.name + ", got '" + text + "'" + task::quoting_hint(text));
  }
  if (on_a_stop(c.measure)) c = task::resolve(c, info, nullptr);  // its side and a positive margin
  if (c.measure == "cond") {
    r.surface = render::Surface::WellConditioned;
    r.cond_threshold = c.threshold;
  } else if (measure_of(c.measure) >= 0) {  // one of a six-DOF device's two, by name (cond_jp, cond_jo)
    r.surface = render::Surface::WellConditioned;
    r.cond_threshold = c.threshold;
    r.measure = measure_of(c.measure);
  } else if (c.haptic() || c.extra) {
    r.surface = render::Surface::Threshold;
    r.field = c.measure;
    r.above = c.above;
    r.threshold = c.threshold;
  }
  return r;
}


void run_mesh(const MeshOptions& o, std::ostream& out) {
  if (o.output.empty()) throw std::invalid_argument("mesh: --output is empty; give a file (.stl, .obj, .ply, .off, .vtp)");
  const std::string ext = extension_of(o.output);
  if (ext != ".stl" && ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".vtp")
    throw std::invalid_argument("mesh: --output must end in .stl, .obj, .ply, .off or .vtp, got '" + o.output + "'");
  if (!(o.decimate >= 0) || !std::isfinite(o.decimate))
    throw std::invalid_argument("--decimate must be a finite number >= 0, got " + format_number(o.decimate));
  if (!o.unit.empty() && !haptics::is_length_unit(o.unit))
    throw std::invalid_argument("mesh: --unit expects mm, cm, m or in, got '" + o.unit + "'");
  Sampling sampling = make_sampling(o.sampling, "mesh");
  render::SurfaceRequest request = parse_surface(o.surface, sampling.mechanism->info());
  request.decimate_error = o.decimate;
  if (request.surface == render::Surface::Threshold && haptics::is_haptic_field(request.field)) {
    sampling.with_haptics();
    if (request.field == "inertia" && !sampling.device_data().has_inertia())
      throw std::invalid_argument("--surface inertia<M: the preset gives no rotor_inertia_kgm2 for every actuator");
  }
  const Grid grid = box_grid(sampling, o.box, o.resolution);
  check_peak_memory(grid, sampling.bytes_per_sample, kPeakMesh, "mesh");
  ProgressLine line(o.sampling.quiet);
  const Field field = sample(sampling, grid, line);
  line.step("extracting the surface");
  // What a decimation changed: against the surface it simplified.
  std::optional<render::MeshStats> full;
  if (o.decimate > 0) full.emplace();
  const vtkSmartPointer<vtkPolyData> mesh = render::extract_surface(field, request, full ? &*full : nullptr);
  const render::MeshStats s = render::mesh_stats(mesh);
  if (s.faces == 0) {
    // Cells wider than the device can step over its whole region.
    const double cell = grid.spacing.maxCoeff(), size = sampling.mechanism->size();
    throw std::invalid_argument("mesh: the surface does not occur on the grid (nothing written)" +
                                (cell > 0.25 * size ? "; its cells are " + format_number(cell) + " " +
                                                          sampling.mechanism->info().length_unit +
                                                          " wide against the device's size " + format_number(size) +
                                                          ": a smaller --box or a finer --resolution may find it"
                                                    : std::string()));
  }
  line.step("writing " + o.output);
  render::write_mesh(mesh, o.output, field, request, o.unit);
  line.clear();
  out << "wrote " << o.output << " (points in " << (o.unit.empty() ? sampling.length_unit() : o.unit)
      << "): " << s.vertices << " vertices, " << s.faces << " triangles, "
      << (s.boundary_edges == 0 && s.non_manifold_edges == 0 ? "watertight" : "NOT watertight")
      << ", Euler characteristic " << s.euler_characteristic << "\n"
      << "volume " << s.volume << " " << sampling.length_unit() << "^3, area " << s.area << " " << sampling.length_unit()
      << "^2, bounds x [" << s.min.x() << ", " << s.max.x() << "] y [" << s.min.y() << ", " << s.max.y() << "] z ["
      << s.min.z() << ", " << s.max.z() << "]\n";
  if (full) {
    const double change = full->volume != 0 ? 100.0 * (s.volume - full->volume) / std::abs(full->volume) : 0.0;
    out << "decimated from " << full->faces << " to " << s.faces << " triangles, volume change " << change << " %\n";
    if (std::abs(change) > 5)
      out << "note: the decimation changed the volume by more than 5 %: --decimate " << o.decimate << " "
          << sampling.length_unit() << " is coarse for a region of " << (full->max - full->min).maxCoeff() << " "
          << sampling.length_unit() << "; a smaller value keeps its shape\n";
  }
  // A region present at the box's outermost samples may go on past the box,
  // which closes the mesh there: say at which faces.
  std::string faces;
  const auto number = [](double v) {
    std::ostringstream text;
    text << v;
    return text.str();
  };
  const Eigen::Vector3d lo = grid.origin, hi = grid.origin + grid.spacing.cwiseProduct(
                                                  Eigen::Vector3d(grid.dims[0], grid.dims[1], grid.dims[2]));
  const std::optional<double> plane = sampling.mechanism->info().plane_z;
  const render::MeshStats& region = full ? *full : s;  // where the surface is, before any decimation
  for (int a = 0; a < (plane ? 2 : 3); ++a) {
    if (grid.dims[std::size_t(a)] < 2) continue;
    const double close = 0.5 * grid.spacing(a);
    const std::string axis(1, char('x' + a));
    if (region.min(a) <= lo(a) + close) faces += (faces.empty() ? "" : ", ") + axis + " = " + number(lo(a));
    if (region.max(a) >= hi(a) - close) faces += (faces.empty() ? "" : ", ") + axis + " = " + number(hi(a));
  }
  // A planar device's field is its plane's, extruded along z: the mesh is a
  // prism, and what it says of the plane is its area.
  if (plane && region.max.z() > region.min.z())
    out << "planar: the region of the plane z = " << *plane << " extruded over z from " << region.min.z() << " to "
        << region.max.z() << "; its area in the plane " << region.volume / (region.max.z() - region.min.z()) << " "
        << sampling.length_unit() << "^2\n";
  if (!faces.empty())
    out << "note: the region reaches the box's faces at " << faces << " and may go on past them; the mesh is closed "
        << "there and its volume is the part inside the box (widen --box to see)\n";
  if (request.surface == render::Surface::Reach)
    if (const auto v = sampling.mechanism->analytic_reach_volume())
      out << "analytic volume " << *v << " " << sampling.length_unit() << "^3 (error " << 100.0 * (s.volume - *v) / *v
          << " %)\n";
}

Command add_mesh(CLI::App& program, const DeviceHelp& help) {
  auto o = std::make_shared<MeshOptions>();
  CLI::App* cmd = program.add_subcommand(
      "mesh", "Extract a workspace isosurface and write a mesh (STL, OBJ, PLY, OFF, VTP); prints its statistics");
  add_field_options(*cmd, o->sampling, help);
  cmd->add_option("--surface", o->surface,
                  "reach (boundary of the reachable set), 'cond<T' (well-conditioned region, e.g. 'cond<3', "
                  "quoted for the shell; a six-DOF device's both measures, or one by name: 'cond_jp<T', "
                  "'cond_jo<T'), or the region meeting a haptic criterion: 'force_iso>F', 'force_max>F' "
                  "(N), 'resolution<R' (mm), 'inertia<M' (kg), or a margin to the device's stops: 'joint_margin>D' "
                  "(deg), 'clearance>C' (length unit)")
      ->capture_default_str()
      ->check(criteria_check());
  cmd->add_option("--resolution", o->resolution, "Samples per axis: N or NXxNYxNZ")->capture_default_str();
  cmd->add_option("--box", o->box, "x_min,x_max,y_min,y_max,z_min,z_max; default the device's sampling box")
      ->delimiter(',')
      ->expected(6);
  cmd->add_option("--decimate", o->decimate,
                  "Simplify the mesh; the largest allowed deviation in the length unit (0 = off)")
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output, "Output: .stl, .obj, .ply, .off or .vtp")->required();
  cmd->add_option("--unit", o->unit,
                  "Length unit of the written points: mm, cm, m or in (default: the device's); said in the STL "
                  "header, a PLY or OBJ comment and the VTP's length_unit. The statistics stay in the device's unit");

  return {cmd, Runs::Headless, "linkscape mesh --surface 'cond<3' --output ws.stl    workspace isosurface mesh",
          [o](std::istream&, std::ostream& out) {
            run_mesh(*o, out);
            return 0;
          }};
}

const RegisterCommand registered{40, add_mesh};

}  // namespace
}  // namespace linkscape::gui
