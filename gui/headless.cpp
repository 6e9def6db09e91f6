#include "gui/headless.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <numbers>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/field.h"
#include "core/parallel12r.h"
#include "core/preset.h"
#include "gui/slice_figure.h"
#include "render/field_vtk.h"
#include "render/slice_image.h"
#include <vtkPolyData.h>

#include "render/workspace_mesh.h"

namespace linkscape::gui {
namespace {

using parallel12r::IkResult;
using parallel12r::IkSolution;

Table read_input(const std::string& file, std::istream& stdin_stream) {
  if (file == "-") return read_csv(stdin_stream, "<stdin>");
  std::ifstream in(file);
  if (!in) throw std::invalid_argument("cannot open input file '" + file + "'");
  return read_csv(in, file);
}

// CSV cells; missing values are empty cells, never NaN.
std::string cell(double v) { return std::isfinite(v) ? format_number(v) : (std::isinf(v) ? "inf" : ""); }

void write_ik(const parallel12r::Model& model, const Table& table, const EvalOptions& o, std::ostream& out) {
  const std::size_t cx = table.column("x"), cy = table.column("y"), cz = table.column("z");
  parallel12r::IkOptions ik;
  ik.seed = o.seed;
  ik.tolerance = o.tolerance;
  ik.max_iterations = o.max_iterations;
  const auto method = parallel12r::parse_ik_method(o.method);
  out << "x,y,z,branch,status,alpha,beta,gamma,cond,det,residual,iterations\n";
  for (const auto& row : table.rows) {
    const Eigen::Vector3d p(row[cx], row[cy], row[cz]);
    const std::string where = cell(p.x()) + "," + cell(p.y()) + "," + cell(p.z()) + ",";
    const IkResult r = parallel12r::inverse(model, p, method, ik);
    bool written = false;
    for (const IkSolution& s : r.solutions) {
      if (o.branch && s.branch != *o.branch) continue;
      const auto c = parallel12r::conditioning(model, s.q_actuated);
      out << where << s.branch << "," << to_string(s.status) << "," << cell(s.q_actuated.x()) << ","
          << cell(s.q_actuated.y()) << "," << cell(s.q_actuated.z()) << "," << cell(c.cond) << ","
          << cell(c.det) << "," << cell(s.residual) << "," << s.iterations << "\n";
      written = true;
    }
    if (!written) {
      // No solution (in the requested branch): one row that says why.
      const Status status = r.status == Status::Ok ? Status::NotConverged : r.status;
      out << where << (o.branch ? std::to_string(*o.branch) : "") << "," << to_string(status)
          << ",,,,,,,\n";
    }
  }
}

void write_fk(const parallel12r::Model& model, const Table& table, std::ostream& out) {
  const std::size_t ca = table.column("alpha"), cb = table.column("beta"), cg = table.column("gamma");
  out << "alpha,beta,gamma,x,y,z,cond,det\n";
  for (const auto& row : table.rows) {
    const Eigen::Vector3d q(row[ca], row[cb], row[cg]);
    const Eigen::Vector3d p = parallel12r::forward(model, q);
    const auto c = parallel12r::conditioning(model, q);
    out << cell(q.x()) << "," << cell(q.y()) << "," << cell(q.z()) << "," << cell(p.x()) << ","
        << cell(p.y()) << "," << cell(p.z()) << "," << cell(c.cond) << "," << cell(c.det) << "\n";
  }
}

}  // namespace

void run_eval(const EvalOptions& o, std::istream& stdin_stream, std::ostream& stdout_stream) {
  if (o.ik_file.empty() == o.fk_file.empty())
    throw std::invalid_argument("eval: give exactly one of --ik FILE or --fk FILE");
  if (o.branch && (*o.branch < 0 || *o.branch > 1))
    throw std::invalid_argument("eval: --branch must be 0 or 1, got " + std::to_string(*o.branch));
  if (!(o.tolerance > 0)) throw std::invalid_argument("eval: --tolerance must be positive");
  Preset preset = load_preset(o.mechanism.mechanism);
  apply_overrides(preset, o.mechanism.params);
  const parallel12r::Model model = make_parallel12r(preset);
  parallel12r::parse_ik_method(o.method);  // reject a bad name before reading input
  const Table table = read_input(o.ik_file.empty() ? o.fk_file : o.ik_file, stdin_stream);

  std::ostringstream result;
  if (!o.ik_file.empty()) write_ik(model, table, o, result);
  else write_fk(model, table, result);

  if (o.output == "-") {
    stdout_stream << result.str();
  } else {
    write_atomically(o.output, [&](const std::filesystem::path& tmp) {
      std::ofstream out(tmp);
      out << result.str();
      if (!out) throw std::runtime_error("cannot write '" + o.output + "'");
    });
  }
}

// ---- Commands that sample a field -------------------------------------------

namespace {

parallel12r::Model load_model(const MechanismChoice& choice) {
  Preset preset = load_preset(choice.mechanism);
  apply_overrides(preset, choice.params);
  return make_parallel12r(preset);
}

std::string extension_of(const std::string& path) { return std::filesystem::path(path).extension().string(); }

std::array<int, 2> parse_size(const std::string& text, const char* option) {
  int a = 0, b = 0;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> a >> x >> b) || x != 'x' || !in.eof() || a < 1 || b < 1)
    throw std::invalid_argument(std::string(option) + " expects WIDTHxHEIGHT, got '" + text + "'");
  return {a, b};
}

std::array<int, 3> parse_resolution(const std::string& text) {
  std::array<int, 3> dims{};
  std::istringstream in(text);
  int n = 0;
  char x = 0;
  if ((in >> n) && in.eof() && n >= 2) return {n, n, n};
  in.clear();
  in.str(text);
  if ((in >> dims[0] >> x >> dims[1]) && x == 'x' && (in >> x >> dims[2]) && x == 'x' && in.eof() &&
      dims[0] >= 2 && dims[1] >= 2 && dims[2] >= 2)
    return dims;
  throw std::invalid_argument("--resolution expects N or NXxNYxNZ (each >= 2), got '" + text + "'");
}

FieldRequest make_request(const SamplingOptions& s, const Grid& grid) {
  FieldRequest r;
  r.grid = grid;
  r.method = parallel12r::parse_ik_method(s.method);
  if (s.branch != 0 && s.branch != 1) throw std::invalid_argument("--branch must be 0 or 1");
  r.branch = s.branch;
  return r;
}

// Samples the field, with a progress line on an interactive stderr.
Field sample(const parallel12r::Model& model, const FieldRequest& request, bool quiet) {
  FieldProgress progress;
  const bool show = !quiet && ::isatty(STDERR_FILENO);
  std::atomic<int> shown{-1};
  if (show)
    progress.report = [&](double f) {
      const int percent = int(f * 100);
      if (percent != shown.exchange(percent)) std::cerr << "\rsampling " << percent << " %" << std::flush;
    };
  std::optional<Field> field = compute_field(model, request, progress);
  if (show) std::cerr << "\r               \r";
  return std::move(*field);
}

}  // namespace

void run_slice(const SliceOptions& o) {
  if (o.output.empty()) throw std::invalid_argument("slice: --output FILE is required (.png, .csv; .svg or .pdf with --figure)");
  const std::string ext = extension_of(o.output);
  const bool ok_ext = o.figure ? (ext == ".png" || ext == ".svg" || ext == ".pdf") : (ext == ".png" || ext == ".csv");
  if (!ok_ext)
    throw std::invalid_argument("slice: --output must end in " + std::string(o.figure ? ".png, .svg or .pdf" : ".png or .csv") +
                                ", got '" + o.output + "'");
  const parallel12r::Model model = load_model(o.sampling.mechanism);
  const auto eq = o.plane.find('=');
  if (eq == std::string::npos) throw std::invalid_argument("--plane expects axis=position, e.g. x=0.25, got '" + o.plane + "'");
  const Axis normal = parse_axis(o.plane.substr(0, eq));
  double position = 0;
  try {
    std::size_t used = 0;
    position = std::stod(o.plane.substr(eq + 1), &used);
    if (used != o.plane.size() - eq - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw std::invalid_argument("--plane expects axis=position, e.g. x=0.25, got '" + o.plane + "'");
  }
  std::vector<double> extent = o.extent;
  const double r = model.reach();
  if (extent.empty()) extent = {-r, r, -r, r};
  if (extent.size() != 4) throw std::invalid_argument("--extent expects u_min,u_max,v_min,v_max");
  const auto size = parse_size(o.size, "--size");
  const Grid grid = Grid::slice(normal, position, extent[0], extent[1], extent[2], extent[3], size[0], size[1]);
  const FieldRequest request = make_request(o.sampling, grid);

  render::SliceStyle style;
  style.field = o.field;
  style.log_scale = !o.linear;
  style.contour_levels = o.contours;
  if (!o.range.empty()) {
    if (o.range.size() != 2) throw std::invalid_argument("--range expects min,max");
    style.min = o.range[0];
    style.max = o.range[1];
  }
  // Reject a bad style before sampling: check it on a tiny field of the same kind.
  if (style.field != "cond" && style.field != "reach" && style.field != "residual" && style.field != "iterations" &&
      style.field != "status" && style.field != "method")
    throw std::invalid_argument("--field must be cond, reach, residual, iterations, status or method, got '" + style.field +
                                "'");
  // The figure's colour bar is continuous; the categorical method colours
  // are written as a plain image or CSV (column method_used).
  if (style.field == "method" && o.figure)
    throw std::invalid_argument("--field method is written without --figure (.png image or .csv)");
  if (style.field == "method") style.log_scale = false;

  const Field field = sample(model, request, o.sampling.quiet);
  if (ext == ".csv") render::write_field_csv(field, o.output);
  else if (o.figure) write_slice_figure(field, style, o.output);
  else render::write_slice_png(field, style, o.output);
}

void run_field(const FieldCommandOptions& o) {
  if (o.output.empty()) throw std::invalid_argument("field: --output FILE is required (.vti or .csv)");
  const std::string ext = extension_of(o.output);
  if (ext != ".vti" && ext != ".csv")
    throw std::invalid_argument("field: --output must end in .vti or .csv, got '" + o.output + "'");
  const parallel12r::Model model = load_model(o.sampling.mechanism);
  std::vector<double> box = o.box;
  const double r = model.reach();
  if (box.empty()) box = {-r, r, -r, r, -r, r};
  if (box.size() != 6) throw std::invalid_argument("--box expects x_min,x_max,y_min,y_max,z_min,z_max");
  const Grid grid = Grid::box({box[0], box[2], box[4]}, {box[1], box[3], box[5]}, parse_resolution(o.resolution));
  const Field field = sample(model, make_request(o.sampling, grid), o.sampling.quiet);
  if (ext == ".vti") render::write_vti(field, o.output);
  else render::write_field_csv(field, o.output);
}

// ---- mesh ---------------------------------------------------------------------

namespace {

render::SurfaceRequest parse_surface(const std::string& text) {
  render::SurfaceRequest r;
  if (text == "reach") return r;
  if (text.rfind("cond<", 0) == 0) {
    r.surface = render::Surface::WellConditioned;
    try {
      std::size_t used = 0;
      r.cond_threshold = std::stod(text.substr(5), &used);
      if (used == text.size() - 5 && r.cond_threshold > 1) return r;
    } catch (const std::exception&) {
    }
  }
  throw std::invalid_argument("--surface expects reach or cond<T with T > 1 (e.g. cond<3), got '" + text + "'");
}

// Volume of the reachable set when the actuator ranges do not cut it: the
// shell between the spheres |L1 - L2| and L1 + L2.
std::optional<double> analytic_reach_volume(const parallel12r::Model& m) {
  const parallel12r::Model full;
  const bool full_ranges = m.alpha_limits.lo <= full.alpha_limits.lo && m.alpha_limits.hi >= full.alpha_limits.hi &&
                           m.beta_limits.lo <= full.beta_limits.lo && m.beta_limits.hi >= full.beta_limits.hi &&
                           m.gamma_limits.lo <= full.gamma_limits.lo && m.gamma_limits.hi >= full.gamma_limits.hi;
  if (!full_ranges) return std::nullopt;
  const double R = m.reach(), r = m.inner_reach();
  return 4.0 / 3.0 * std::numbers::pi * (R * R * R - r * r * r);
}

}  // namespace

void run_mesh(const MeshOptions& o, std::ostream& out) {
  if (o.output.empty()) throw std::invalid_argument("mesh: --output FILE is required (.stl, .obj, .ply, .off, .vtp)");
  const std::string ext = extension_of(o.output);
  if (ext != ".stl" && ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".vtp")
    throw std::invalid_argument("mesh: --output must end in .stl, .obj, .ply, .off or .vtp, got '" + o.output + "'");
  render::SurfaceRequest request = parse_surface(o.surface);
  if (!(o.decimate >= 0)) throw std::invalid_argument("--decimate must be >= 0");
  request.decimate_error = o.decimate;
  const parallel12r::Model model = load_model(o.sampling.mechanism);
  std::vector<double> box = o.box;
  const double r = model.reach();
  if (box.empty()) box = {-r, r, -r, r, -r, r};
  if (box.size() != 6) throw std::invalid_argument("--box expects x_min,x_max,y_min,y_max,z_min,z_max");
  const Grid grid = Grid::box({box[0], box[2], box[4]}, {box[1], box[3], box[5]}, parse_resolution(o.resolution));
  const Field field = sample(model, make_request(o.sampling, grid), o.sampling.quiet);
  const vtkSmartPointer<vtkPolyData> mesh = render::extract_surface(field, request);
  const render::MeshStats s = render::mesh_stats(mesh);
  if (s.faces == 0) throw std::invalid_argument("mesh: the surface does not occur in the box (nothing written)");
  render::write_mesh(mesh, o.output, field, request);
  out << "wrote " << o.output << ": " << s.vertices << " vertices, " << s.faces << " triangles, "
      << (s.boundary_edges == 0 && s.non_manifold_edges == 0 ? "watertight" : "NOT watertight")
      << ", Euler characteristic " << s.euler_characteristic << "\n"
      << "volume " << s.volume << " " << model.length_unit << "^3, area " << s.area << " " << model.length_unit
      << "^2, bounds x [" << s.min.x() << ", " << s.max.x() << "] y [" << s.min.y() << ", " << s.max.y() << "] z ["
      << s.min.z() << ", " << s.max.z() << "]\n";
  if (request.surface == render::Surface::Reach)
    if (const auto v = analytic_reach_volume(model))
      out << "analytic volume " << *v << " " << model.length_unit << "^3 (error " << 100.0 * (s.volume - *v) / *v
          << " %)\n";
}

}  // namespace linkscape::gui
