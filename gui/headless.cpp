#include "gui/headless.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <iomanip>
#include <fstream>
#include <numbers>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/field.h"
#include "core/parallel12r.h"
#include "core/pathos2.h"
#include "core/pathos2_field.h"
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

// Every value a command reads must be finite: the first that is not is an
// error naming its file, line and column.
void require_finite(const Table& table, const std::vector<std::size_t>& columns) {
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    for (std::size_t c : columns)
      if (!std::isfinite(table.rows[r][c]))
        throw std::invalid_argument(table.where(r) + ": column '" + table.columns[c] + "': " +
                                    format_number(table.rows[r][c]) + " is not a finite number");
}

// Runs `body` for each row; an invalid_argument thrown for a row is reported
// with the row's file and line.
template <typename Body>
void for_each_row(const Table& table, Body body) {
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    try {
      body(table.rows[r]);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(table.where(r) + ": " + e.what());
    }
  }
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
  require_finite(table, {cx, cy, cz});
  out << "x,y,z,branch,status,alpha,beta,gamma,cond,det,residual,iterations\n";
  for_each_row(table, [&](const std::vector<double>& row) {
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
  });
}

void write_fk(const parallel12r::Model& model, const Table& table, std::ostream& out) {
  const std::size_t ca = table.column("alpha"), cb = table.column("beta"), cg = table.column("gamma");
  require_finite(table, {ca, cb, cg});
  out << "alpha,beta,gamma,x,y,z,cond,det\n";
  for_each_row(table, [&](const std::vector<double>& row) {
    const Eigen::Vector3d q(row[ca], row[cb], row[cg]);
    const Eigen::Vector3d p = parallel12r::forward(model, q);
    const auto c = parallel12r::conditioning(model, q);
    out << cell(q.x()) << "," << cell(q.y()) << "," << cell(q.z()) << "," << cell(p.x()) << ","
        << cell(p.y()) << "," << cell(p.z()) << "," << cell(c.cond) << "," << cell(c.det) << "\n";
  });
}

// PATHOS-II pose IK: one row per pose, the active angles and both condition
// numbers, or the status and the first failing leg (1-based).
void write_pathos2_ik(const pathos2::Geometry& g, const Table& table, std::ostream& out) {
  const char* names[] = {"x", "y", "z", "rx", "ry", "rz", "h0"};
  std::array<std::size_t, 7> col{};
  for (int k = 0; k < 7; ++k) col[k] = table.column(names[k]);
  require_finite(table, {col.begin(), col.end()});
  out << "x,y,z,rx,ry,rz,h0,status,failing_leg,q1,q2,q3,q4,q5,q6,cond_jp,cond_jo\n";
  for_each_row(table, [&](const std::vector<double>& row) {
    std::string line;
    for (int k = 0; k < 7; ++k) line += cell(row[col[k]]) + ",";
    if (!(row[col[6]] > 0)) {
      out << line << "invalid-grip,,,,,,,,,\n";
      return;
    }
    const pathos2::Pose pose =
        pathos2::Pose::from_xyz_rpy(row[col[0]], row[col[1]], row[col[2]], row[col[3]], row[col[4]], row[col[5]], row[col[6]]);
    const pathos2::PoseIkResult ik = pathos2::inverse(g, pose);
    out << line << to_string(ik.status) << "," << (ik.failing_leg >= 0 ? std::to_string(ik.failing_leg + 1) : "");
    if (ik.status == Status::Ok) {
      const pathos2::JacobianResult J = pathos2::jacobian(g, pose, ik);
      for (int i = 0; i < 6; ++i) out << "," << cell(ik.q_active(i));
      out << "," << cell(J.cond_p) << "," << cell(J.cond_o) << "\n";
    } else {
      out << ",,,,,,,,\n";
    }
  });
}

// PATHOS-II numerical FK: damped Newton from a seed pose that depends on the
// row alone, so a row's answer never depends on the rows before it: the
// row's seed_x,seed_y,seed_z,seed_rx,seed_ry,seed_rz columns when the file
// has them, else the home pose.
void write_pathos2_fk(const pathos2::Geometry& g, const Table& table, std::ostream& out) {
  const char* names[] = {"q1", "q2", "q3", "q4", "q5", "q6", "h0"};
  std::array<std::size_t, 7> col{};
  for (int k = 0; k < 7; ++k) col[k] = table.column(names[k]);
  std::vector<std::size_t> used(col.begin(), col.end());
  const char* seed_names[] = {"seed_x", "seed_y", "seed_z", "seed_rx", "seed_ry", "seed_rz"};
  int seed_columns_found = 0;
  for (const char* n : seed_names)
    seed_columns_found += std::count(table.columns.begin(), table.columns.end(), n) ? 1 : 0;
  if (seed_columns_found != 0 && seed_columns_found != 6)
    throw std::invalid_argument(table.origin + ": give all six seed columns (seed_x,seed_y,seed_z,seed_rx,seed_ry,"
                                "seed_rz: cm, rad) or none");
  std::array<std::size_t, 6> seed_col{};
  if (seed_columns_found == 6)
    for (int k = 0; k < 6; ++k) used.push_back(seed_col[k] = table.column(seed_names[k]));
  require_finite(table, used);
  out << "q1,q2,q3,q4,q5,q6,h0,status,x,y,z,rx,ry,rz,iterations,residual\n";
  const pathos2::Pose home = pathos2::home_pose(g.model);
  for_each_row(table, [&](const std::vector<double>& row) {
    pathos2::Vector6d q;
    for (int i = 0; i < 6; ++i) q(i) = row[col[i]];
    const double h0 = row[col[6]];
    for (int k = 0; k < 7; ++k) out << cell(row[col[k]]) << ",";
    if (!(h0 > 0)) {
      out << "invalid-input,,,,,,,,\n";
      return;
    }
    pathos2::Pose seed = home;
    if (seed_columns_found == 6)
      seed = pathos2::Pose::from_xyz_rpy(row[seed_col[0]], row[seed_col[1]], row[seed_col[2]], row[seed_col[3]],
                                         row[seed_col[4]], row[seed_col[5]], h0);
    seed.h0 = h0;
    const pathos2::FkResult fk = pathos2::forward_numeric(g, q, h0, seed);
    out << to_string(fk.status);
    if (fk.status == Status::Ok) {
      const Eigen::Vector3d p = fk.pose.p_world_E, rpy = fk.pose.rpy();
      for (double v : {p.x(), p.y(), p.z(), rpy.x(), rpy.y(), rpy.z()}) out << "," << cell(v);
    } else {
      out << ",,,,,,";
    }
    out << "," << fk.iterations << "," << cell(fk.residual) << "\n";
  });
}

}  // namespace

void run_eval(const EvalOptions& o, std::istream& stdin_stream, std::ostream& stdout_stream) {
  if (o.ik_file.empty() == o.fk_file.empty())
    throw std::invalid_argument("eval: give exactly one of --ik FILE or --fk FILE");
  if (o.branch && (*o.branch < 0 || *o.branch > 1))
    throw std::invalid_argument("eval: --branch must be 0 or 1, got " + std::to_string(*o.branch));
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance))
    throw std::invalid_argument("eval: --tolerance must be a positive finite number, got " + format_number(o.tolerance));
  if (o.max_iterations < 1)
    throw std::invalid_argument("eval: --max-iterations must be at least 1, got " + std::to_string(o.max_iterations));
  Preset preset = load_preset(o.mechanism.mechanism);
  apply_overrides(preset, o.mechanism.params);
  std::ostringstream result;
  if (preset.mechanism == pathos2::kMechanismName) {
    if (o.method != "planar" || o.branch || o.seed)
      throw std::invalid_argument("eval: --method, --branch and --seed apply to parallel-12r; pathos2 uses its "
                                  "closed-form IK with the preset's branch_1..branch_6");
    const pathos2::Geometry geometry = pathos2::make_geometry(make_pathos2(preset));
    const Table table = read_input(o.ik_file.empty() ? o.fk_file : o.ik_file, stdin_stream);
    if (!o.ik_file.empty()) write_pathos2_ik(geometry, table, result);
    else write_pathos2_fk(geometry, table, result);
  } else {
    const parallel12r::Model model = make_parallel12r(preset);
    parallel12r::parse_ik_method(o.method);  // reject a bad name before reading input
    const Table table = read_input(o.ik_file.empty() ? o.fk_file : o.ik_file, stdin_stream);
    if (!o.ik_file.empty()) write_ik(model, table, o, result);
    else write_fk(model, table, result);
  }

  if (o.output == "-") {
    stdout_stream << result.str();
  } else {
    write_atomically(o.output, [&](const std::filesystem::path& tmp) {
      std::ofstream out(tmp);
      out << result.str();
      out.close();
      if (!out) throw std::runtime_error("cannot write '" + o.output + "'");
    });
  }
}

// ---- Commands that sample a field -------------------------------------------

namespace {

// What the sampling commands need of the chosen mechanism.
struct Sampling {
  std::string mechanism, length_unit;
  Eigen::Vector3d box_min, box_max;  // default sampling box
  Eigen::Vector3d focus;             // the default slice plane passes through it
  std::function<std::optional<Field>(const Grid&, const FieldProgress&)> sample;
  std::optional<double> analytic_reach_volume;  // of the reach mesh, where known
  std::size_t bytes_per_sample = Field::bytes_per_sample();  // the field arrays
};

// Peak memory of a whole command as a multiple of its field arrays, measured
// with /usr/bin/time -v at 256^3 (parallel-12r, 285 MiB of arrays): a .vti
// export copies the arrays into VTK and compresses (603 MiB, 2.1x), a mesh
// adds the isosurface and its OpenMesh copy (523 MiB, 1.8x), a CSV streams
// (323 MiB, 1.13x). Rounded up, plus the program itself.
constexpr double kPeakVti = 2.3, kPeakMesh = 2.0, kPeakCsv = 1.25;
constexpr double kProgramBytes = 96.0 * (1 << 20);

// Refuses a command whose estimated peak exceeds the memory limit of the
// field engine or the memory available now, whichever is smaller.
void check_peak_memory(const Grid& grid, std::size_t bytes_per_sample, double factor, const std::string& what) {
  const double arrays = double(grid.size()) * double(bytes_per_sample);
  const double peak = arrays * factor + kProgramBytes;
  double limit = double(FieldRequest{}.memory_limit_bytes);
  std::string limit_source = "the field engine's limit";
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0;
  while (meminfo >> key >> kib) {
    if (key == "MemAvailable:" && kib * 1024 < limit) {
      limit = kib * 1024;
      limit_source = "the memory available now";
    }
    meminfo.ignore(64, '\n');
  }
  if (peak <= limit) return;
  std::ostringstream msg;
  msg << std::fixed << std::setprecision(2) << what << ": " << grid.dims[0] << "x" << grid.dims[1] << "x" << grid.dims[2] << " samples need about "
      << peak / (1 << 30) << " GiB at peak (field arrays " << arrays / (1 << 30) << " GiB x " << factor
      << " for the output), over " << limit / (1 << 30) << " GiB (" << limit_source << "); lower the resolution";
  throw std::invalid_argument(msg.str());
}

std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) {
    const std::optional<double> x = parse_number(part);
    if (!x || !std::isfinite(*x)) throw std::invalid_argument(what + ", got '" + text + "'");
    v.push_back(*x);
  }
  if (v.size() != count || (!text.empty() && text.back() == ','))
    throw std::invalid_argument(what + ", got '" + text + "'");
  return v;
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

Sampling make_sampling(const SamplingOptions& s) {
  Preset preset = load_preset(s.mechanism.mechanism);
  apply_overrides(preset, s.mechanism.params);
  Sampling out;
  out.mechanism = preset.mechanism;
  if (preset.mechanism == pathos2::kMechanismName) {
    if (s.method != "planar" || s.branch != 0 || s.tolerance != SamplingOptions{}.tolerance)
      throw std::invalid_argument("--method, --branch and --tolerance apply to parallel-12r; pathos2 uses its "
                                  "closed-form IK with the preset's branch_1..branch_6");
    const pathos2::Model model = make_pathos2(preset);
    pathos2::Pose pose = pathos2::home_pose(model);
    if (!s.pose.empty()) {
      const auto v = parse_numbers(s.pose, 7, "--pose expects x,y,z,rx,ry,rz,h0 (cm, rad, cm)");
      if (!(v[6] > 0)) throw std::invalid_argument("--pose: the grip h0 must be > 0, got " + std::to_string(v[6]));
      pose = pathos2::Pose::from_xyz_rpy(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
    }
    pathos2::FieldRequest request;
    request.rpy = pose.rpy();
    request.h0 = pose.h0;
    out.length_unit = "cm";
    // The workspace spans about half the leg reach l2 + l3 each way (13.8 cm
    // along x for Table 1); 0.6 (l2 + l3) leaves room, and mesh reports a
    // surface cut by the box as not watertight.
    const double half = 0.6 * (model.l2 + model.l3);
    const Eigen::Vector3d centre(0, 0, model.l0 / 2);
    out.box_min = centre - Eigen::Vector3d::Constant(half);
    out.box_max = centre + Eigen::Vector3d::Constant(half);
    out.focus = pose.p_world_E;
    out.bytes_per_sample = Field::bytes_per_sample() + sizeof(float);  // cond_orientation
    out.sample = [model, request](const Grid& grid, const FieldProgress& progress) {
      pathos2::FieldRequest r = request;
      r.grid = grid;
      return pathos2::compute_field(model, r, progress);
    };
    return out;
  }
  if (!s.pose.empty()) throw std::invalid_argument("--pose applies to pathos2");
  if (s.branch != 0 && s.branch != 1) throw std::invalid_argument("--branch must be 0 or 1");
  const parallel12r::Model model = make_parallel12r(preset);
  FieldRequest request;
  request.method = parallel12r::parse_ik_method(s.method);
  request.branch = s.branch;
  if (!(s.tolerance > 0) || !std::isfinite(s.tolerance))
    throw std::invalid_argument("--tolerance must be positive, got " + format_number(s.tolerance));
  request.ik.tolerance = s.tolerance;
  const double r = model.reach();
  out.length_unit = model.length_unit;
  out.box_min = Eigen::Vector3d::Constant(-r);
  out.box_max = Eigen::Vector3d::Constant(r);
  out.focus = Eigen::Vector3d(0.125 * r, 0, 0);  // x = 0.25 for L1 = L2 = 1, as in the paper's Fig. 5
  out.analytic_reach_volume = analytic_reach_volume(model);
  if (request.method == parallel12r::IkMethod::Fallback) out.bytes_per_sample += 1;  // method_used
  out.sample = [model, request](const Grid& grid, const FieldProgress& progress) {
    FieldRequest q = request;
    q.grid = grid;
    return compute_field(model, q, progress);
  };
  return out;
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

// Samples the field, with a progress line on an interactive stderr.
Field sample(const Sampling& sampling, const Grid& grid, bool quiet) {
  FieldProgress progress;
  const bool show = !quiet && ::isatty(STDERR_FILENO);
  std::atomic<int> shown{-1};
  if (show)
    progress.report = [&](double f) {
      const int percent = int(f * 100);
      if (percent != shown.exchange(percent)) std::cerr << "\rsampling " << percent << " %" << std::flush;
    };
  std::optional<Field> field = sampling.sample(grid, progress);
  if (show) std::cerr << "\r               \r";
  return std::move(*field);
}

Grid box_grid(const Sampling& sampling, const std::vector<double>& box_option, const std::string& resolution) {
  std::vector<double> box = box_option;
  if (box.empty())
    box = {sampling.box_min.x(), sampling.box_max.x(), sampling.box_min.y(),
           sampling.box_max.y(), sampling.box_min.z(), sampling.box_max.z()};
  if (box.size() != 6) throw std::invalid_argument("--box expects x_min,x_max,y_min,y_max,z_min,z_max");
  return Grid::box({box[0], box[2], box[4]}, {box[1], box[3], box[5]}, parse_resolution(resolution));
}

}  // namespace

void run_slice(const SliceOptions& o) {
  if (o.output.empty()) throw std::invalid_argument("slice: --output is empty; give a file (.png, .csv; .svg or .pdf with --figure)");
  const std::string ext = extension_of(o.output);
  const bool ok_ext = o.figure ? (ext == ".png" || ext == ".svg" || ext == ".pdf") : (ext == ".png" || ext == ".csv");
  if (!ok_ext)
    throw std::invalid_argument("slice: --output must end in " + std::string(o.figure ? ".png, .svg or .pdf" : ".png or .csv") +
                                ", got '" + o.output + "'");
  const Sampling sampling = make_sampling(o.sampling);
  // Default plane: x = 0.25 (L1 = L2 = 1 scale) for 12R, the x-y plane through the pose for pathos2.
  const bool six_dof = sampling.mechanism == pathos2::kMechanismName;
  const std::string plane =
      !o.plane.empty() ? o.plane
                       : (six_dof ? "z=" + format_number(sampling.focus.z()) : "x=" + format_number(sampling.focus.x()));
  const auto eq = plane.find('=');
  if (eq == std::string::npos) throw std::invalid_argument("--plane expects axis=position, e.g. x=0.25, got '" + plane + "'");
  const Axis normal = parse_axis(plane.substr(0, eq));
  const double position = parse_numbers(plane.substr(eq + 1), 1, "--plane expects axis=position, e.g. x=0.25")[0];
  std::vector<double> extent = o.extent;
  const auto [au, av] = Grid::slice_axes(normal);
  if (extent.empty())
    extent = {sampling.box_min(int(au)), sampling.box_max(int(au)), sampling.box_min(int(av)), sampling.box_max(int(av))};
  if (extent.size() != 4) throw std::invalid_argument("--extent expects u_min,u_max,v_min,v_max");
  const auto size = parse_size(o.size, "--size");
  const Grid grid = Grid::slice(normal, position, extent[0], extent[1], extent[2], extent[3], size[0], size[1]);

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
      style.field != "status" && style.field != "method" && style.field != "cond_jo")
    throw std::invalid_argument("--field must be cond, cond_jo, reach, residual, iterations, status or method, got '" +
                                style.field + "'");
  if (style.field == "cond_jo" && !six_dof)
    throw std::invalid_argument("--field cond_jo (orientation conditioning) applies to pathos2");
  // The figure's colour bar is continuous; the categorical method colours
  // are written as a plain image or CSV (column method_used).
  if (style.field == "method" && o.figure)
    throw std::invalid_argument("--field method is written without --figure (.png image or .csv)");
  if (style.field == "method") style.log_scale = false;

  const Field field = sample(sampling, grid, o.sampling.quiet);
  if (ext == ".csv") render::write_field_csv(field, o.output);
  else if (o.figure) write_slice_figure(field, style, o.output);
  else render::write_slice_png(field, style, o.output);
}

void run_field(const FieldCommandOptions& o) {
  if (o.output.empty()) throw std::invalid_argument("field: --output is empty; give a file (.vti or .csv)");
  const std::string ext = extension_of(o.output);
  if (ext != ".vti" && ext != ".csv")
    throw std::invalid_argument("field: --output must end in .vti or .csv, got '" + o.output + "'");
  const Sampling sampling = make_sampling(o.sampling);
  const Grid grid = box_grid(sampling, o.box, o.resolution);
  check_peak_memory(grid, sampling.bytes_per_sample, ext == ".vti" ? kPeakVti : kPeakCsv, "field");
  const Field field = sample(sampling, grid, o.sampling.quiet);
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
    const std::optional<double> t = parse_number(text.substr(5));
    if (t && std::isfinite(*t) && *t > 1) {
      r.cond_threshold = *t;
      return r;
    }
  }
  throw std::invalid_argument("--surface expects reach or cond<T with T > 1 (e.g. cond<3), got '" + text + "'");
}

}  // namespace

void run_mesh(const MeshOptions& o, std::ostream& out) {
  if (o.output.empty()) throw std::invalid_argument("mesh: --output is empty; give a file (.stl, .obj, .ply, .off, .vtp)");
  const std::string ext = extension_of(o.output);
  if (ext != ".stl" && ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".vtp")
    throw std::invalid_argument("mesh: --output must end in .stl, .obj, .ply, .off or .vtp, got '" + o.output + "'");
  render::SurfaceRequest request = parse_surface(o.surface);
  if (!(o.decimate >= 0) || !std::isfinite(o.decimate))
    throw std::invalid_argument("--decimate must be a finite number >= 0, got " + format_number(o.decimate));
  request.decimate_error = o.decimate;
  const Sampling sampling = make_sampling(o.sampling);
  const Grid grid = box_grid(sampling, o.box, o.resolution);
  check_peak_memory(grid, sampling.bytes_per_sample, kPeakMesh, "mesh");
  const Field field = sample(sampling, grid, o.sampling.quiet);
  const vtkSmartPointer<vtkPolyData> mesh = render::extract_surface(field, request);
  const render::MeshStats s = render::mesh_stats(mesh);
  if (s.faces == 0) throw std::invalid_argument("mesh: the surface does not occur in the box (nothing written)");
  render::write_mesh(mesh, o.output, field, request);
  out << "wrote " << o.output << ": " << s.vertices << " vertices, " << s.faces << " triangles, "
      << (s.boundary_edges == 0 && s.non_manifold_edges == 0 ? "watertight" : "NOT watertight")
      << ", Euler characteristic " << s.euler_characteristic << "\n"
      << "volume " << s.volume << " " << sampling.length_unit << "^3, area " << s.area << " " << sampling.length_unit
      << "^2, bounds x [" << s.min.x() << ", " << s.max.x() << "] y [" << s.min.y() << ", " << s.max.y() << "] z ["
      << s.min.z() << ", " << s.max.z() << "]\n";
  if (request.surface == render::Surface::Reach)
    if (const auto v = sampling.analytic_reach_volume)
      out << "analytic volume " << *v << " " << sampling.length_unit << "^3 (error " << 100.0 * (s.volume - *v) / *v
          << " %)\n";
}

}  // namespace linkscape::gui
