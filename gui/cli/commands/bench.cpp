// linkscape bench: speed and accuracy of the field engine, measured the same
// way every time so docs/performance.md can quote it.
#include <sys/resource.h>
#include <omp.h>

#include <algorithm>
#include <tuple>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <iomanip>
#include <numbers>
#include <ostream>
#include <sstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/field.h"
#include "core/method_harness.h"
#include "core/mechanism.h"
#include "core/preset.h"
#include "core/simd.h"
#include "core/stability.h"
#include "gui/cli/command.h"
#include "gui/cli/sampling.h"
#include "gui/figures/method_chart.h"
#include <vtkPolyData.h>

#include "render/workspace_mesh.h"

namespace linkscape::gui {
namespace {

double peak_memory_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}

// The device's default box sampled with n samples per axis.
Grid cube(const Mechanism& m, int n) {
  const Eigen::AlignedBox3d box = m.default_box();
  return Grid::box(box.min(), box.max(), {n, n, n});
}

struct BenchOptions {
  PresetChoice mechanism;
  bool quick = false;   // smaller grids, fewer repeats (for a smoke test)
  std::string csv;      // also write the figures as CSV (plus <stem>.methods.csv, <stem>.sweeps.csv)
  std::string chart;    // error-against-time chart of every method (.png, .svg, .pdf)
  std::string sweeps;   // error-against-eps chart of the stability sweeps (.png, .svg, .pdf)
  // Methods and sweeps of the chosen device and these presets only (side by
  // side); empty: the chosen device and every registered one.
  std::vector<std::string> compare;
};
// Measures field throughput, slice and volume times, isosurfaces, peak
// memory and accuracy against resolution, then every numerical method's time
// per evaluation and error (core/method_harness.h) and the stability sweeps
// (core/stability.h); prints a report to `out`. Charts need a QGuiApplication.
struct Row {
  std::string what;
  double value;
  std::string unit;
};

// "name = value unit", in the parameter's own unit (an angle is not a length).
std::string with_unit(const Quantity& q, double value) {
  return q.name + " = " + format_number(value) + (q.unit.empty() ? "" : " " + q.unit);
}

// The bench's tables (docs/file-formats.md): a unit suffix where a column
// has one unit; unit columns where it varies by row; no value empty.
std::string measurements_csv(const std::vector<Row>& rows) {
  std::string csv = "measurement,value,unit\n";
  for (const Row& r : rows) csv += csv_text(r.what) + "," + csv_number(r.value) + "," + csv_text(r.unit) + "\n";
  return csv;
}

std::string methods_csv(const std::vector<methods::MethodRow>& table) {
  std::string csv = "family,method,parameter,samples,not_ok," + csv_column("time_per_evaluation", "s") +
                    ",error_median,error_p99,error_max,error_unit,mechanism\n";
  for (const auto& r : table)
    csv += csv_text(r.family) + ',' + csv_text(r.method) + ',' + csv_text(r.parameter) + ',' +
           std::to_string(r.samples) + ',' + std::to_string(r.failures) + ',' + csv_number(r.seconds_per_evaluation) +
           ',' + csv_number(r.error_median) + ',' + csv_number(r.error_p99) + ',' + csv_number(r.error_max) + ',' +
           csv_text(r.error_unit) + ',' + csv_text(r.mechanism) + "\n";
  return csv;
}

// distance, sigma_min (per rad) and residual are in the row's device's
// length unit; error in rad for ik, relative otherwise (core/stability.h).
std::string sweeps_csv(const std::vector<stability::SweepRow>& sweeps,
                       const std::map<std::string, std::string>& length_unit) {
  std::string csv = "path,base_point,eps,distance,cond,sigma_min,predicted,family,method,status,error,residual,"
                    "iterations,mechanism,length_unit,error_unit\n";
  for (const auto& r : sweeps) {
    const auto unit = length_unit.find(r.mechanism);
    csv += csv_text(stability::path_label(r)) + ',' + std::to_string(r.base_point) + ',' + csv_number(r.eps) + ',' +
           csv_number(r.distance) + ',' + csv_number(r.cond) + ',' + csv_number(r.sigma_min) + ',' +
           csv_number(r.predicted) + ',' + csv_text(r.family) + ',' + csv_text(r.method) + ',' +
           std::string(to_string(r.status)) + ',' + csv_number(r.error) + ',' + csv_number(r.residual) + ',' +
           std::to_string(r.iterations) + ',' + csv_text(r.mechanism) + ',' +
           csv_text(unit == length_unit.end() ? std::string() : unit->second) + ',' +
           (r.family == "ik" ? r.ik_error_unit : "relative") + "\n";
  }
  return csv;
}

void run_bench(const BenchOptions& o, std::ostream& out) {
  for (const std::string* chart : {&o.chart, &o.sweeps}) {
    const std::string ext = std::filesystem::path(*chart).extension().string();
    if (!chart->empty() && ext != ".png" && ext != ".svg" && ext != ".pdf")
      throw std::invalid_argument("bench: --chart and --sweeps must end in .png, .svg or .pdf, got '" + *chart + "'");
  }
  // Fields are measured for the chosen device; methods and sweeps for it and
  // every registered device (its shipped preset; --mechanism/--param set the
  // parameters of the one they name), or for it and the --compare presets.
  if (!o.csv.empty() && std::filesystem::path(o.csv).extension() != ".csv")
    throw std::invalid_argument("bench: --csv must end in .csv (its two companions are STEM.methods.csv and "
                                "STEM.sweeps.csv), got '" + o.csv + "'");
  Preset chosen = load_preset(o.mechanism.name_or_path);
  apply_overrides(chosen, o.mechanism.params);
  const std::shared_ptr<const Mechanism> m = make_mechanism(chosen);
  // Every device compared and every output checked before the minutes of measuring.
  std::vector<std::shared_ptr<const Mechanism>> compared;
  for (const std::string& name : o.compare) {
    auto device = make_mechanism(load_preset(name));
    const auto same = [&](const auto& d) { return d->info().name == device->info().name; };
    if (device->info().name != m->info().name && std::none_of(compared.begin(), compared.end(), same))
      compared.push_back(std::move(device));  // each device once
  }
  for (const std::string* file : {&o.csv, &o.chart, &o.sweeps}) check_output(*file);
  const MechanismInfo& info = m->info();
  const std::string unit = info.length_unit;
  const int repeats = o.quick ? 1 : 5;
  const int threads = omp_get_max_threads();
  const Eigen::VectorXd home = m->home_task();
  std::vector<Row> rows;
  auto report = [&](const std::string& what, double value, const std::string& u) {
    rows.push_back({what, value, u});
    out << std::left << std::setw(58) << what << std::right << std::setw(14) << std::setprecision(4) << value << " " << u
        << "\n"
        << std::flush;
  };
  auto field = [&](const Grid& grid, int t) { return m->compute_field(grid, home, {}, t, {}); };
  std::string design;
  for (const Quantity& q : info.parameters)
    if (q.in_panel) design += (design.empty() ? "" : ", ") + with_unit(q, m->parameters().at(q.name));
  simd::apply_environment();
  out << "linkscape bench: " << info.name << " (" << design << "), " << threads
      << " threads available, SIMD target " << simd::current_target() << "\n\n";

  // Throughput of the main measure's field over the device's default box.
  const std::string method = info.ik_methods.front().name;
  const int n_tp = o.quick ? 64 : 160;
  for (int t : {1, threads}) {
    const Grid grid = cube(*m, n_tp);
    const double s = methods::median_pass_seconds(repeats, [&] { field(grid, t); });
    report("cond field, " + method + ", " + std::to_string(n_tp) + "^3 cube, " + std::to_string(t) + " thread(s)",
           grid.size() / s / 1e6, "M points/s");
  }

  // A 512 x 512 slice on the device's first plane.
  {
    const auto [normal, position] = m->default_slice_plane(home);
    const auto [u, v] = Grid::slice_axes(normal);
    const Eigen::AlignedBox3d box = m->default_box();
    const int n = o.quick ? 128 : 512;
    const Grid grid = Grid::slice(normal, position, box.min()(int(u)), box.max()(int(u)), box.min()(int(v)),
                                  box.max()(int(v)), n, n);
    const double s = methods::median_pass_seconds(repeats, [&] { field(grid, 0); });
    report("slice " + std::to_string(n) + "x" + std::to_string(n) + " at " + std::string(1, "xyz"[int(normal)]) +
               " = " + format_number(position),
           s * 1e3, "ms");
  }

  // Volumes and their isosurfaces.
  const std::optional<double> analytic = m->analytic_reach_volume();
  for (int n : o.quick ? std::vector<int>{32, 64} : std::vector<int>{32, 64, 128, 256}) {
    const Grid grid = cube(*m, n);
    std::optional<Field> f;
    const double t_field = methods::median_pass_seconds(n >= 256 ? 1 : repeats, [&] { f = field(grid, 0); });
    vtkSmartPointer<vtkPolyData> reach, cond;
    render::SurfaceRequest reach_request, cond_request;
    cond_request.surface = render::Surface::WellConditioned;
    const double t_reach = methods::median_pass_seconds(n >= 256 ? 1 : repeats, [&] { reach = render::extract_surface(*f, reach_request); });
    const double t_cond = methods::median_pass_seconds(n >= 256 ? 1 : repeats, [&] { cond = render::extract_surface(*f, cond_request); });
    const render::MeshStats rs = render::mesh_stats(reach), cs = render::mesh_stats(cond);
    const std::string tag = std::to_string(n) + "^3";
    report("volume " + tag + ": field", t_field * 1e3, "ms");
    report("volume " + tag + ": reach isosurface (" + std::to_string(rs.faces) + " triangles)", t_reach * 1e3, "ms");
    report("volume " + tag + ": c<3 isosurface (" + std::to_string(cs.faces) + " triangles)", t_cond * 1e3, "ms");
    if (analytic)
      report("volume " + tag + ": reach mesh volume error vs analytic", 100.0 * (rs.volume - *analytic) / *analytic, "%");
    else
      report("volume " + tag + ": reach mesh volume", rs.volume, unit + "^3");
    report("volume " + tag + ": reach mesh boundary edges (0 = watertight)", double(rs.boundary_edges), "");
    report("volume " + tag + ": c<3 region x-span", cs.max.x() - cs.min.x(), unit);
    report("volume " + tag + ": c<3 region z-span", cs.max.z() - cs.min.z(), unit);
    report("volume " + tag + ": c<3 region y-extent (y > 0 half)", cs.max.y() - 0.0, unit);
    report("volume " + tag + ": c<3 region volume", cs.volume, unit + "^3");
  }
  report("peak resident memory", peak_memory_mib(), "MiB");

  // Every device's numerical methods, time per evaluation against error,
  // and its sweeps towards each singular set.
  std::vector<std::shared_ptr<const Mechanism>> devices;
  if (!o.compare.empty()) {
    devices.push_back(m);
    devices.insert(devices.end(), compared.begin(), compared.end());
  } else {
    const std::vector<std::string> registered = registered_mechanisms();
    if (std::find(registered.begin(), registered.end(), info.name) == registered.end()) devices.push_back(m);
    for (const std::string& name : registered)
      devices.push_back(name == info.name ? m : make_mechanism(load_preset(name)));
  }
  methods::HarnessOptions h;
  h.samples = o.quick ? 2000 : 20000;
  h.repeats = repeats;
  h.field_resolutions = o.quick ? std::vector<int>{16, 32} : std::vector<int>{16, 32, 64, 128};
  h.field_reference_resolution = o.quick ? 64 : 256;
  std::vector<methods::MethodRow> table;
  std::vector<stability::SweepRow> sweeps;
  for (const auto& device : devices) {
    methods::HarnessOptions hd = h;
    if (device->info().actuators.size() > 3) hd.samples = o.quick ? 300 : 20000;  // six-leg devices: slower references
    const auto device_rows = device->measure_methods(hd);
    table.insert(table.end(), device_rows.begin(), device_rows.end());
    const auto device_sweeps = device->stability_sweeps({});
    sweeps.insert(sweeps.end(), device_sweeps.begin(), device_sweeps.end());
  }
  out << "\nmethods: median time per evaluation (one thread; per field on " << threads
      << " threads) and error against each device's reference (the 12R's and PATHOS-II's in long double; the others' "
         "drawn actuator values, docs/methods.md) over " << h.samples << " workspace targets\n";
  out << std::left << std::setw(14) << "family" << std::setw(20) << "method" << std::setw(11) << "parameter"
      << std::right << std::setw(12) << "time (s)" << std::setw(12) << "median" << std::setw(12) << "p99"
      << std::setw(12) << "max" << std::setw(9) << "not ok" << "  unit\n";
  for (const methods::MethodRow& r : table) {
    if (&r == &table.front() || (&r - 1)->mechanism != r.mechanism) out << r.mechanism << ":\n";
    out << std::left << std::setw(14) << r.family << std::setw(20) << r.method << std::setw(11) << r.parameter
        << std::right << std::setprecision(3) << std::setw(12) << r.seconds_per_evaluation << std::setw(12)
        << r.error_median << std::setw(12) << r.error_p99 << std::setw(12) << r.error_max << std::setw(9)
        << r.failures << "  " << r.error_unit << "\n";
    const std::string name = "method " + (r.mechanism == devices.front()->info().name ? std::string() : r.mechanism + " ") + r.family +
                             "/" + r.method + (r.parameter.empty() ? "" : " " + r.parameter);
    rows.push_back({name + ": time per evaluation", r.seconds_per_evaluation, "s"});
    rows.push_back({name + ": median error", r.error_median, r.error_unit});
    rows.push_back({name + ": 99th percentile error", r.error_p99, r.error_unit});
    rows.push_back({name + ": max error", r.error_max, r.error_unit});
    rows.push_back({name + ": not ok", double(r.failures), "evaluations"});
  }

  out << "\nstability sweeps (IK, worst of " << stability::SweepOptions{}.base_points
      << " base points): smallest eps with an ok result, and the worst error / ((residual + u B) / sigma_min)\n";
  // Per device, singular set and method: the smallest eps with an ok
  // result, and the worst error against its first-order bound where the
  // device's sweeps predict one.
  std::vector<std::tuple<std::string, std::string, std::string>> keys;
  for (const auto& r : sweeps) {
    if (r.family != "ik" && r.family != "fk") continue;
    const auto key = std::make_tuple(r.mechanism, stability::path_label(r), r.method);
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
  }
  // Columns as wide as their longest entry (device and path names are the files').
  std::size_t path_width = 0, method_width = 0;
  for (const auto& [mechanism, path, method] : keys) {
    const std::string prefix = mechanism == devices.front()->info().name ? "" : mechanism + " ";
    path_width = std::max(path_width, prefix.size() + path.size() + 1);
    method_width = std::max(method_width, method.size() + 1);
  }
  for (const auto& [mechanism, path, method] : keys) {
    double smallest = std::numeric_limits<double>::quiet_NaN(), ratio = 0;  // NaN: no ok result
    bool bounded = false;  // a first-order bound predicted for some ok sample
    std::map<Status, int> statuses;  // of the samples, where none is ok: what they were
    for (const auto& r : sweeps) {
      if (r.mechanism != mechanism || stability::path_label(r) != path || r.method != method) continue;
      if (r.family != "ik" && r.family != "fk") continue;
      ++statuses[r.status];
      if (r.status == Status::Ok && std::isfinite(r.error)) {
        if (!(r.eps >= smallest)) smallest = r.eps;
        if (std::isfinite(r.predicted)) {
          bounded = true;
          ratio = std::max(ratio, r.error / (r.predicted + r.residual / r.sigma_min));
        }
      }
    }
    const std::string prefix = mechanism == devices.front()->info().name ? "" : mechanism + " ";
    out << "  " << std::left << std::setw(int(path_width)) << prefix + path << std::setw(int(method_width)) << method
        << "ok down to eps "
        << std::setw(10) << std::setprecision(2);
    if (std::isnan(smallest)) {
      // Nothing measured: say what the samples were instead of a bound of 0.
      out << "none (no sample ok:";
      for (const auto& [status, count] : statuses) out << " " << count << " " << to_string(status);
      out << ")\n";
    } else {
      out << smallest;
      if (bounded) out << " error/bound <= " << ratio << "\n";
      else out << " (no first-order bound: the residual is the measure)\n";
    }
    rows.push_back({"sweep " + prefix + path + "/" + method + ": smallest eps with an ok result", smallest, ""});
  }

  QString title;
  for (const auto& device : devices) {
    std::string design;
    for (const Quantity& q : device->info().parameters)
      if (q.in_panel) design += (design.empty() ? "" : ", ") + with_unit(q, device->parameters().at(q.name));
    title += QString(title.isEmpty() ? "" : "; ") + QString::fromStdString(device->info().name + " (" + design + ")");
  }
  if (!o.chart.empty()) {
    write_method_chart(table, "Speed against accuracy: " + title, o.chart);
    out << "wrote " << o.chart << "\n";
  }
  if (!o.sweeps.empty()) {
    write_sweep_chart(sweeps, "Stability towards the singular sets: " + title, o.sweeps);
    out << "wrote " << o.sweeps << "\n";
  }

  if (!o.csv.empty()) {
    // The three tables replace the old ones together or not at all.
    const std::filesystem::path base(o.csv);
    const std::string stem = (base.parent_path() / base.stem()).string();
    std::map<std::string, std::string> length_unit;  // of each device's rows
    for (const auto& device : devices) length_unit[device->info().name] = device->info().length_unit;
    write_texts_atomically({{o.csv, measurements_csv(rows)},
                            {stem + ".methods.csv", methods_csv(table)},
                            {stem + ".sweeps.csv", sweeps_csv(sweeps, length_unit)}});
    out << "wrote " << o.csv << ", " << stem << ".methods.csv, " << stem << ".sweeps.csv\n";
  }
}

Command add_bench(CLI::App& program, const DeviceHelp&) {
  auto o = std::make_shared<BenchOptions>();
  CLI::App* cmd = program.add_subcommand(
      "bench",
      "Measure field throughput, slice/volume/isosurface times, peak memory, accuracy vs resolution, and every "
      "numerical method's time per evaluation against its error, with stability sweeps towards the singular sets");
  add_mechanism_options(*cmd, o->mechanism);
  cmd->add_flag("--quick", o->quick, "Small grids and single runs (a smoke test, not a measurement)");
  cmd->add_option("--csv", o->csv,
                  "Also write the figures to this CSV file (measurement,value,unit, every method included), "
                  "the method table to <stem>.methods.csv and the sweeps to <stem>.sweeps.csv");
  cmd->add_option("--chart", o->chart,
                  "Write the error-against-time chart of every method with its Pareto front (.png, .svg, .pdf)");
  cmd->add_option("--sweeps", o->sweeps,
                  "Write the error-against-distance chart of the sweeps towards each singular set "
                  "(.png, .svg, .pdf)");
  cmd->add_option("--compare", o->compare,
                  "Measure the methods and sweeps of these presets beside the chosen device (side by side in "
                  "--chart and --sweeps), e.g. -m delta-described --compare delta; default: every registered "
                  "device")
      ->delimiter(',');
  cmd->footer(
      "parallel-12r (planar IK), delta (closed IK) and pathos2 fields use SIMD kernels with the best instruction set\n"
      "of the CPU. Environment, for every command:\n"
      "  LINKSCAPE_SIMD_TARGET=AVX2|SSE4|...|baseline   use at most this instruction set\n"
      "  LINKSCAPE_FIELD_KERNEL=scalar|vector|vector-mirrored   those kernels: scalar = the reference, one sample at\n"
      "    a time; vector = without the mirror symmetries (12R in x, Delta in y); default vector-mirrored");

  return {cmd, Runs::Painting,  // the charts draw text with QPainter
          "linkscape bench --chart m.png --sweeps s.png --csv b.csv   speed and accuracy of every method",
          [o](std::istream&, std::ostream& out) {
            run_bench(*o, out);
            return 0;
          }};
}

const RegisterCommand registered{80, add_bench};

}  // namespace
}  // namespace linkscape::gui
