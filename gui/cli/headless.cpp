#include "gui/cli/headless.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
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
#include "core/haptics.h"
#include "core/mechanism.h"
#include "core/task.h"
#include "core/preset.h"
#include "gui/figures/slice_figure.h"
#include "gui/cli/terminal.h"
#include "render/field_vtk.h"
#include "render/slice_image.h"
#include <vtkPolyData.h>

#include "render/workspace_mesh.h"

namespace linkscape::gui {
namespace {

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


std::string joined_names(const std::vector<Quantity>& items, const std::string& prefix = "") {
  std::string out;
  for (const Quantity& q : items) out += (out.empty() ? "" : ",") + prefix + q.name;
  return out;
}
std::string empties(std::size_t n) { return std::string(n, ','); }

// Inverse kinematics of each row of task coordinates: one output row per
// solution (branch), or one row that says why there is none. Columns as
// MechanismInfo::EvalColumns describes.
void write_ik(const Mechanism& m, const Table& table, const IkOptions& ik, std::ostream& out) {
  const MechanismInfo& info = m.info();
  const auto& c = info.eval_columns;
  std::vector<std::size_t> col;
  for (const Quantity& q : info.task) col.push_back(table.column(q.name));
  require_finite(table, col);
  out << joined_names(info.task) << (c.ik_branch ? ",branch" : "") << ",status"
      << (c.ik_failing_part.empty() ? "" : "," + c.ik_failing_part) << "," << joined_names(info.actuators);
  for (const NamedItem& measure : info.measures) out << "," << measure.name;
  out << (c.ik_det ? ",det" : "") << (c.ik_diagnostics ? ",residual,iterations" : "") << "\n";
  const std::size_t after_status = info.actuators.size() + info.measures.size() + (c.ik_det ? 1 : 0) +
                                   (c.ik_diagnostics ? 2 : 0) + (c.ik_failing_part.empty() ? 0 : 1);
  for_each_row(table, [&](const std::vector<double>& row) {
    Eigen::VectorXd x(Eigen::Index(col.size()));
    std::string where;
    for (std::size_t k = 0; k < col.size(); ++k) {
      x(Eigen::Index(k)) = row[col[k]];
      where += csv_number(row[col[k]]) + ",";
    }
    const IkResult r = m.inverse(x, ik);
    for (const IkSolution& s : r.solutions) {
      out << where;
      if (c.ik_branch) out << s.branch << ",";
      out << to_string(s.status);
      if (!c.ik_failing_part.empty()) out << "," << csv_text(s.failing_part);
      for (Eigen::Index k = 0; k < s.q.size(); ++k) out << "," << csv_number(s.q(k));
      const Measures meas = m.measures(s.q, x);
      for (double v : meas.values) out << "," << csv_number(v);
      if (c.ik_det) out << "," << csv_number(meas.det);
      if (c.ik_diagnostics) out << "," << csv_number(s.residual) << "," << s.iterations;
      out << "\n";
    }
    if (r.solutions.empty()) {
      const Status status = r.status == Status::Ok ? Status::NotConverged : r.status;
      out << where;
      if (c.ik_branch) out << (ik.branch ? std::to_string(*ik.branch) : "") << ",";
      out << csv_text(r.status_text.empty() ? std::string(to_string(status)) : r.status_text);
      if (!c.ik_failing_part.empty()) out << "," << csv_text(r.failing_part) << empties(after_status - 1) << "\n";
      else out << empties(after_status) << "\n";
    }
  });
}

// Forward kinematics of each row of actuator values (and the task
// coordinates the device reads as inputs), from the home pose or the row's
// seed_<coordinate> columns: a row's answer depends on that row alone.
void write_fk(const Mechanism& m, const Table& table, std::ostream& out) {
  const MechanismInfo& info = m.info();
  const auto& c = info.eval_columns;
  std::vector<std::size_t> q_col, input_col, used;
  for (const Quantity& q : info.actuators) used.push_back(q_col.emplace_back(table.column(q.name)));
  std::vector<int> input_index, result_index;  // into info.task
  for (std::size_t k = 0; k < info.task.size(); ++k) {
    const bool input = std::count(info.fk_inputs.begin(), info.fk_inputs.end(), info.task[k].name) > 0;
    (input ? input_index : result_index).push_back(int(k));
    if (input) used.push_back(input_col.emplace_back(table.column(info.task[k].name)));
  }
  // Seeds: all of seed_<result coordinate> or none.
  std::vector<std::size_t> seed_col;
  std::string seed_names;
  for (int k : result_index) {
    const std::string name = "seed_" + info.task[std::size_t(k)].name;
    seed_names += (seed_names.empty() ? "" : ",") + name;
    if (std::count(table.columns.begin(), table.columns.end(), name)) seed_col.push_back(table.column(name));
  }
  if (!seed_col.empty() && seed_col.size() != result_index.size())
    throw std::invalid_argument(table.origin + ": give all of the seed columns (" + seed_names + ") or none");
  used.insert(used.end(), seed_col.begin(), seed_col.end());
  require_finite(table, used);

  out << joined_names(info.actuators);
  for (int k : input_index) out << "," << info.task[std::size_t(k)].name;
  if (c.fk_status) out << ",status";
  for (int k : result_index) out << "," << info.task[std::size_t(k)].name;
  if (c.fk_measures) {
    for (const NamedItem& measure : info.measures) out << "," << measure.name;
    out << ",det";
  }
  out << (c.fk_diagnostics ? ",iterations,residual" : "") << "\n";
  const Eigen::VectorXd home = m.home_task();
  for_each_row(table, [&](const std::vector<double>& row) {
    Eigen::VectorXd q(Eigen::Index(q_col.size()));
    for (std::size_t k = 0; k < q_col.size(); ++k) q(Eigen::Index(k)) = row[q_col[k]];
    FkOptions fo;
    fo.seed = home;
    for (std::size_t k = 0; k < input_index.size(); ++k) (*fo.seed)(input_index[k]) = row[input_col[k]];
    for (std::size_t k = 0; k < seed_col.size(); ++k) (*fo.seed)(result_index[k]) = row[seed_col[k]];
    for (std::size_t k = 0; k < q_col.size(); ++k) out << (k ? "," : "") << csv_number(row[q_col[k]]);
    for (std::size_t k = 0; k < input_col.size(); ++k) out << "," << csv_number(row[input_col[k]]);
    const FkResult r = m.forward(q, fo);
    const bool ok = r.status == Status::Ok;
    if (c.fk_status) out << "," << (r.status_text.empty() ? std::string(to_string(r.status)) : r.status_text);
    for (int k : result_index) out << "," << (ok ? csv_number(r.x(k)) : "");
    if (c.fk_measures) {
      const Measures meas = ok ? m.measures(q, r.x) : Measures{};
      for (std::size_t k = 0; k < info.measures.size(); ++k)
        out << "," << (ok && k < meas.values.size() ? csv_number(meas.values[k]) : "");
      out << "," << (ok ? csv_number(meas.det) : "");
    }
    if (c.fk_diagnostics) {
      if (r.status_text.empty()) out << "," << r.iterations << "," << csv_number(r.residual);
      else out << ",,";
    }
    out << "\n";
  });
}

std::shared_ptr<const Mechanism> chosen_mechanism(const PresetChoice& choice) {
  return make_mechanism(chosen_preset(choice));
}

}  // namespace

void run_eval(const EvalOptions& o, std::istream& stdin_stream, std::ostream& stdout_stream) {
  if (o.ik_file.empty() == o.fk_file.empty())
    throw std::invalid_argument("eval: give exactly one of --ik FILE or --fk FILE");
  if (!(o.tolerance > 0) || !std::isfinite(o.tolerance))
    throw std::invalid_argument("eval: --tolerance must be a positive finite number, got " + format_number(o.tolerance));
  if (o.max_iterations < 1)
    throw std::invalid_argument("eval: --max-iterations must be at least 1, got " + std::to_string(o.max_iterations));
  const std::shared_ptr<const Mechanism> m = chosen_mechanism(o.mechanism);
  const MechanismInfo& info = m->info();
  IkOptions ik;
  if (!o.method.empty()) index_of(info.ik_methods, o.method, "IK method for " + info.name);  // before reading input
  ik.method = o.method;
  if (o.branch && (*o.branch < 0 || *o.branch >= int(info.branches.size())))
    throw std::invalid_argument("eval: --branch must be 0.." + std::to_string(info.branches.size() - 1) + " for " +
                                info.name + ", got " + std::to_string(*o.branch));
  ik.branch = o.branch;
  if (o.seed) {
    if (o.seed->size() != Eigen::Index(info.actuators.size()))
      throw std::invalid_argument("eval: --seed expects " + joined_names(info.actuators) + " (" +
                                  std::to_string(info.actuators.size()) + " values) for " + info.name);
    ik.seed = *o.seed;
  }
  ik.tolerance = o.tolerance;
  ik.max_iterations = o.max_iterations;
  const auto start = std::chrono::steady_clock::now();
  const Table table = read_input(o.ik_file.empty() ? o.fk_file : o.ik_file, stdin_stream);
  std::ostringstream result;
  if (!o.ik_file.empty()) write_ik(*m, table, ik, result);
  else write_fk(*m, table, result);

  if (o.output == "-") {
    stdout_stream << result.str();
  } else {
    write_text_atomically(o.output, result.str());
  }
  // Written to stdout, the rows themselves say it worked; a summary there would only get in a pipe's way.
  if (o.output != "-")
    summary(o.quiet, std::string("eval: ") + (o.ik_file.empty() ? "forward" : "inverse") + " kinematics of " +
                       std::to_string(table.rows.size()) + (table.rows.size() == 1 ? " row (" : " rows (") + info.name + ") written to " +
                       o.output + " in " + seconds_since(start));
}

// ---- Commands that sample a field -------------------------------------------

namespace {

// What the sampling commands need of the chosen mechanism.
struct Sampling {
  Preset preset;
  std::shared_ptr<const Mechanism> mechanism;
  Eigen::VectorXd task;  // fields hold its non-position coordinates; the default slice passes through it
  IkOptions ik;
  haptics::TorqueRating torque = haptics::TorqueRating::Continuous;
  bool haptic = false;  // also the haptic fields (core/haptics.h)
  std::size_t bytes_per_sample = Field::bytes_per_sample();  // the field arrays
  std::string length_unit() const { return mechanism->info().length_unit; }
  Eigen::Vector3d box_min() const { return mechanism->default_box().min(); }
  Eigen::Vector3d box_max() const { return mechanism->default_box().max(); }
  haptics::DeviceData device_data() const { return haptics::device_data(preset, mechanism->info()); }
  // Asks for the haptic fields; checks the preset's actuator data at once.
  void with_haptics() {
    device_data();
    haptic = true;
    bytes_per_sample += 4 * sizeof(float);
  }
  std::optional<Field> sample(const Grid& grid, const FieldProgress& progress) const {
    if (!haptic) return mechanism->compute_field(grid, task, ik, 0, progress);
    const haptics::DeviceData data = device_data();
    return haptics::sample_field(*mechanism, grid, task, ik, 0, progress, &data, torque);
  }
};

// Peak memory of a whole command as a multiple of its field arrays, measured
// with /usr/bin/time -v at 256^3 (parallel-12r, 285 MiB of arrays): a .vti
// export compresses the arrays in place (333 MiB, 1.17x), a mesh
// adds the isosurface and its OpenMesh copy (523 MiB, 1.8x), a CSV streams
// (323 MiB, 1.13x). Rounded up, plus the program itself.
constexpr double kPeakVti = 1.3, kPeakMesh = 2.0, kPeakCsv = 1.25;
constexpr double kProgramBytes = 96.0 * (1 << 20);

// Refuses a command whose estimated peak exceeds the memory limit of the
// field engine or the memory available now, whichever is smaller.
void check_peak_memory(const Grid& grid, std::size_t bytes_per_sample, double factor, const std::string& what) {
  const double arrays = double(grid.size()) * double(bytes_per_sample);
  const double peak = arrays * factor + kProgramBytes;
  double limit = double(kFieldMemoryLimitBytes);
  std::string limit_source = "the field engine's limit";
  if (const std::optional<double> available = available_memory_bytes(); available && *available < limit) {
    limit = *available;
    limit_source = "the memory available now";
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

Sampling make_sampling(const SamplingOptions& s) {
  Sampling out;
  out.preset = chosen_preset(s.mechanism);
  out.mechanism = make_mechanism(out.preset);
  out.torque = haptics::parse_torque_rating(s.torque);
  const MechanismInfo& info = out.mechanism->info();
  out.task = out.mechanism->home_task();
  if (!s.pose.empty()) {
    const auto v = parse_numbers(s.pose, info.task.size(),
                                 "--pose expects " + joined_names(info.task) + " for " + info.name);
    out.task = Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
  }
  if (!s.method.empty()) index_of(info.ik_methods, s.method, "IK method for " + info.name);
  out.ik.method = s.method;
  if (s.branch < 0 || s.branch >= int(info.branches.size()))
    throw std::invalid_argument("--branch must be 0.." + std::to_string(info.branches.size() - 1) + " for " +
                                info.name + ", got " + std::to_string(s.branch));
  if (s.branch != 0) out.ik.branch = s.branch;
  if (!(s.tolerance > 0) || !std::isfinite(s.tolerance))
    throw std::invalid_argument("--tolerance must be positive, got " + format_number(s.tolerance));
  out.ik.tolerance = s.tolerance;
  // Field arrays: a second condition array where the device has a second
  // measure, the method used per sample where it has several methods.
  if (info.measures.size() > 1) out.bytes_per_sample += sizeof(float);
  if (info.ik_methods.size() > 1) out.bytes_per_sample += 1;
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

// Samples the field, showing its progress on the terminal.
Field sample(const Sampling& sampling, const Grid& grid, ProgressLine& line) {
  FieldProgress progress;
  line.step("sampling");
  if (line.shown()) progress.report = [&](double f) { line.report(f); };
  std::optional<Field> field = sampling.sample(grid, progress);
  line.clear();
  return std::move(*field);
}

std::string megabytes(std::uintmax_t bytes) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << double(bytes) / 1e6 << " MB";
  return out.str();
}

// "192x192x192" or "512x512".
std::string dimensions_text(const Grid& grid) {
  std::string out;
  for (int n : grid.dims)
    if (n > 1) out += (out.empty() ? "" : "x") + std::to_string(n);
  return out.empty() ? "1" : out;
}

Grid box_grid(const Sampling& sampling, const std::vector<double>& box_option, const std::string& resolution) {
  std::vector<double> box = box_option;
  if (box.empty())
    box = {sampling.box_min().x(), sampling.box_max().x(), sampling.box_min().y(),
           sampling.box_max().y(), sampling.box_min().z(), sampling.box_max().z()};
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
  Sampling sampling = make_sampling(o.sampling);
  const MechanismInfo& info = sampling.mechanism->info();
  const auto [default_normal, default_position] = sampling.mechanism->default_slice_plane(sampling.task);
  const std::string plane =
      !o.plane.empty() ? o.plane : std::string(1, "xyz"[int(default_normal)]) + "=" + format_number(default_position);
  const auto eq = plane.find('=');
  if (eq == std::string::npos) throw std::invalid_argument("--plane expects axis=position, e.g. x=0.25, got '" + plane + "'");
  const Axis normal = parse_axis(plane.substr(0, eq));
  const double position = parse_numbers(plane.substr(eq + 1), 1, "--plane expects axis=position, e.g. x=0.25")[0];
  std::vector<double> extent = o.extent;
  const auto [au, av] = Grid::slice_axes(normal);
  if (extent.empty())
    extent = {sampling.box_min()(int(au)), sampling.box_max()(int(au)), sampling.box_min()(int(av)),
              sampling.box_max()(int(av))};
  if (extent.size() != 4) throw std::invalid_argument("--extent expects u_min,u_max,v_min,v_max");
  const auto size = parse_size(o.size, "--size");
  const Grid grid = Grid::slice(normal, position, extent[0], extent[1], extent[2], extent[3], size[0], size[1]);

  render::SliceStyle style;
  style.field = o.field;
  style.log_scale = !o.linear;
  style.colour_map = o.colour_map;
  style.contour_levels = o.contours;
  if (!o.range.empty()) {
    if (o.range.size() != 2) throw std::invalid_argument("--range expects min,max");
    style.min = o.range[0];
    style.max = o.range[1];
  }
  // The fields a device has: its main measure as "cond", a second measure
  // under its own name (the field's second condition array, "cond_jo" to
  // the renderer), the reach margin and the solver diagnostics; "method"
  // where it has several IK methods.
  std::vector<std::string> fields = {"cond"};
  if (info.measures.size() > 1) fields.push_back(info.measures[1].name);
  for (const char* f : {"reach", "residual", "iterations", "status"}) fields.push_back(f);
  if (info.ik_methods.size() > 1) fields.push_back("method");
  for (const haptics::FieldInfo& f : haptics::all_field_infos()) fields.push_back(f.name);
  if (std::find(fields.begin(), fields.end(), style.field) == fields.end()) {
    std::string known;
    for (const auto& f : fields) known += (known.empty() ? "" : ", ") + f;
    throw std::invalid_argument("--field for " + info.name + " must be one of " + known + ", got '" + style.field + "'");
  }
  if (info.measures.size() > 1 && style.field == info.measures[1].name) style.field = "cond_jo";
  // The figure's colour bar is continuous; the categorical method colours
  // are written as a plain image or CSV (column method_used).
  if (style.field == "method" && o.figure)
    throw std::invalid_argument("--field method is written without --figure (.png image or .csv)");
  if (style.field == "method") style.log_scale = false;
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

void run_field(const FieldCommandOptions& o) {
  if (o.output.empty()) throw std::invalid_argument("field: --output is empty; give a file (.vti or .csv)");
  const std::string ext = extension_of(o.output);
  if (ext != ".vti" && ext != ".csv")
    throw std::invalid_argument("field: --output must end in .vti or .csv, got '" + o.output + "'");
  Sampling sampling = make_sampling(o.sampling);
  for (const std::string& name : o.fields)
    if (!haptics::is_haptic_field(name))
      throw std::invalid_argument("field: --field adds force_iso, force_max, resolution or inertia (the other arrays "
                                  "are always written), got '" + name + "'");
  if (!o.fields.empty()) sampling.with_haptics();
  if (std::count(o.fields.begin(), o.fields.end(), "inertia") && !sampling.device_data().has_inertia())
    throw std::invalid_argument("--field inertia: the preset gives no rotor_inertia_kgm2 for every actuator");
  const Grid grid = box_grid(sampling, o.box, o.resolution);
  check_peak_memory(grid, sampling.bytes_per_sample, ext == ".vti" ? kPeakVti : kPeakCsv, "field");
  const auto start = std::chrono::steady_clock::now();
  ProgressLine line(o.sampling.quiet);
  Field field = sample(sampling, grid, line);
  std::erase_if(field.extras, [&](const Field::NamedArray& a) {
    return std::find(o.fields.begin(), o.fields.end(), a.name) == o.fields.end();
  });
  line.step("writing " + o.output);
  if (ext == ".vti") render::write_vti(field, o.output);
  else render::write_field_csv(field, o.output);
  line.clear();
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(o.output, ec);
  summary(o.sampling.quiet, "field: wrote " + o.output + " (" + sampling.mechanism->info().name + ", " +
                                dimensions_text(grid) + " samples" +
                                (ec ? std::string() : ", " + megabytes(bytes)) + ") in " +
                                seconds_since(start));
}

// ---- mesh ---------------------------------------------------------------------

namespace {

// reach, cond<T (the device's first measure; both measures for six-DOF
// devices), or a haptic criterion such as force_iso>2 (core/task.h).
render::SurfaceRequest parse_surface(const std::string& text, const MechanismInfo& info) {
  render::SurfaceRequest r;
  task::Criterion c;
  try {
    c = task::parse_criterion(text);
    if (c.measure != "reach" && c.measure != "cond" && !c.haptic()) throw std::invalid_argument("not a surface");
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument("--surface expects reach, cond<T with T > 1 (e.g. cond<3) or a haptic criterion "
                                "(force_iso>F, force_max>F in N, resolution<R in mm, inertia<M in kg) for " +
                                info.name + ", got '" + text + "'" + task::quoting_hint(text));
  }
  if (c.measure == "cond") {
    r.surface = render::Surface::WellConditioned;
    r.cond_threshold = c.threshold;
  } else if (c.haptic()) {
    r.surface = render::Surface::Threshold;
    r.field = c.measure;
    r.above = c.above;
    r.threshold = c.threshold;
  }
  return r;
}

}  // namespace

void run_mesh(const MeshOptions& o, std::ostream& out) {
  if (o.output.empty()) throw std::invalid_argument("mesh: --output is empty; give a file (.stl, .obj, .ply, .off, .vtp)");
  const std::string ext = extension_of(o.output);
  if (ext != ".stl" && ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".vtp")
    throw std::invalid_argument("mesh: --output must end in .stl, .obj, .ply, .off or .vtp, got '" + o.output + "'");
  if (!(o.decimate >= 0) || !std::isfinite(o.decimate))
    throw std::invalid_argument("--decimate must be a finite number >= 0, got " + format_number(o.decimate));
  Sampling sampling = make_sampling(o.sampling);
  render::SurfaceRequest request = parse_surface(o.surface, sampling.mechanism->info());
  request.decimate_error = o.decimate;
  if (request.surface == render::Surface::Threshold) {
    sampling.with_haptics();
    if (request.field == "inertia" && !sampling.device_data().has_inertia())
      throw std::invalid_argument("--surface inertia<M: the preset gives no rotor_inertia_kgm2 for every actuator");
  }
  const Grid grid = box_grid(sampling, o.box, o.resolution);
  check_peak_memory(grid, sampling.bytes_per_sample, kPeakMesh, "mesh");
  ProgressLine line(o.sampling.quiet);
  const Field field = sample(sampling, grid, line);
  line.step("extracting the surface");
  const vtkSmartPointer<vtkPolyData> mesh = render::extract_surface(field, request);
  const render::MeshStats s = render::mesh_stats(mesh);
  if (s.faces == 0) throw std::invalid_argument("mesh: the surface does not occur in the box (nothing written)");
  line.step("writing " + o.output);
  render::write_mesh(mesh, o.output, field, request);
  line.clear();
  out << "wrote " << o.output << ": " << s.vertices << " vertices, " << s.faces << " triangles, "
      << (s.boundary_edges == 0 && s.non_manifold_edges == 0 ? "watertight" : "NOT watertight")
      << ", Euler characteristic " << s.euler_characteristic << "\n"
      << "volume " << s.volume << " " << sampling.length_unit() << "^3, area " << s.area << " " << sampling.length_unit()
      << "^2, bounds x [" << s.min.x() << ", " << s.max.x() << "] y [" << s.min.y() << ", " << s.max.y() << "] z ["
      << s.min.z() << ", " << s.max.z() << "]\n";
  if (request.surface == render::Surface::Reach)
    if (const auto v = sampling.mechanism->analytic_reach_volume())
      out << "analytic volume " << *v << " " << sampling.length_unit() << "^3 (error " << 100.0 * (s.volume - *v) / *v
          << " %)\n";
}

}  // namespace linkscape::gui
