// linkscape bench: speed and accuracy of the field engine, measured the same
// way every time so docs/performance.md can quote it.
#include <sys/resource.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <functional>
#include <iomanip>
#include <numbers>
#include <ostream>
#include <sstream>
#include <vector>

#include "core/atomic_file.h"
#include "core/field.h"
#include "core/method_harness.h"
#include "core/pathos2_methods.h"
#include "core/preset.h"
#include "core/stability.h"
#include "gui/headless.h"
#include "gui/method_chart.h"
#include <vtkPolyData.h>

#include "render/workspace_mesh.h"

namespace linkscape::gui {
namespace {

double peak_memory_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
}

FieldRequest cube(const parallel12r::Model& m, int n, int threads = 0) {
  FieldRequest r;
  const double R = m.reach();
  r.grid = Grid::box({-R, -R, -R}, {R, R, R}, {n, n, n});
  r.threads = threads;
  return r;
}

struct Row {
  std::string what;
  double value;
  std::string unit;
};

}  // namespace

void run_bench(const BenchOptions& o, std::ostream& out) {
  // Both mechanisms are always measured: --mechanism/--param set the
  // parameters of the one they name, the other keeps its default preset.
  Preset chosen = load_preset(o.mechanism.mechanism);
  apply_overrides(chosen, o.mechanism.params);
  const bool chose_pathos2 = chosen.mechanism == pathos2::kMechanismName;
  const Preset preset = chose_pathos2 ? load_preset("parallel-12r") : chosen;
  const Preset preset_p2 = chose_pathos2 ? chosen : load_preset(std::string(pathos2::kMechanismName));
  const parallel12r::Model m = make_parallel12r(preset);
  const pathos2::Model m_p2 = make_pathos2(preset_p2);
  const std::string unit = m.length_unit;
  const int repeats = o.quick ? 1 : 5;
  const int threads = omp_get_max_threads();
  std::vector<Row> rows;
  auto report = [&](const std::string& what, double value, const std::string& u) {
    rows.push_back({what, value, u});
    out << std::left << std::setw(58) << what << std::right << std::setw(14) << std::setprecision(4) << value << " " << u
        << "\n"
        << std::flush;
  };

  out << "linkscape bench: " << preset.mechanism << " (L1 = " << m.L1 << ", L2 = " << m.L2 << " " << unit << "), "
      << threads << " threads available\n\n";

  // Throughput of the planar cond field over the cube +-(L1 + L2); about
  // 52 % of its samples are inside the reach sphere and need the full solve.
  const int n_tp = o.quick ? 64 : 160;
  for (int t : {1, threads}) {
    const FieldRequest r = cube(m, n_tp, t);
    const double s = methods::median_pass_seconds(repeats, [&] { compute_field(m, r); });
    report("cond field, planar, " + std::to_string(n_tp) + "^3 cube, " + std::to_string(t) + " thread(s)",
           r.grid.size() / s / 1e6, "M points/s");
  }

  // A 512 x 512 slice through x = L/4 (the Fig. 5 panel x = 0.25 for L = 1).
  {
    FieldRequest r;
    const double R = m.reach();
    const int n = o.quick ? 128 : 512;
    r.grid = Grid::slice(Axis::X, 0.125 * R, -R, R, -R, R, n, n);
    const double s = methods::median_pass_seconds(repeats, [&] { compute_field(m, r); });
    report("slice " + std::to_string(n) + "x" + std::to_string(n) + " at x = (L1+L2)/8", s * 1e3, "ms");
  }

  // Volumes and their isosurfaces.
  const double analytic = 4.0 / 3.0 * std::numbers::pi * (std::pow(m.reach(), 3) - std::pow(m.inner_reach(), 3));
  for (int n : o.quick ? std::vector<int>{32, 64} : std::vector<int>{32, 64, 128, 256}) {
    const FieldRequest r = cube(m, n);
    std::optional<Field> field;
    const double t_field = methods::median_pass_seconds(n >= 256 ? 1 : repeats, [&] { field = compute_field(m, r); });
    vtkSmartPointer<vtkPolyData> reach, cond;
    render::SurfaceRequest reach_request, cond_request;
    cond_request.surface = render::Surface::WellConditioned;
    const double t_reach = methods::median_pass_seconds(n >= 256 ? 1 : repeats, [&] { reach = render::extract_surface(*field, reach_request); });
    const double t_cond = methods::median_pass_seconds(n >= 256 ? 1 : repeats, [&] { cond = render::extract_surface(*field, cond_request); });
    const render::MeshStats rs = render::mesh_stats(reach), cs = render::mesh_stats(cond);
    const std::string tag = std::to_string(n) + "^3";
    report("volume " + tag + ": field", t_field * 1e3, "ms");
    report("volume " + tag + ": reach isosurface (" + std::to_string(rs.faces) + " triangles)", t_reach * 1e3, "ms");
    report("volume " + tag + ": c<3 isosurface (" + std::to_string(cs.faces) + " triangles)", t_cond * 1e3, "ms");
    report("volume " + tag + ": reach mesh volume error vs analytic", 100.0 * (rs.volume - analytic) / analytic, "%");
    report("volume " + tag + ": reach mesh boundary edges (0 = watertight)", double(rs.boundary_edges), "");
    report("volume " + tag + ": c<3 region x-span", cs.max.x() - cs.min.x(), unit);
    report("volume " + tag + ": c<3 region z-span", cs.max.z() - cs.min.z(), unit);
    report("volume " + tag + ": c<3 region y-extent (y > 0 half)", cs.max.y() - 0.0, unit);
    report("volume " + tag + ": c<3 region volume", cs.volume, unit + "^3");
  }
  report("peak resident memory", peak_memory_mib(), "MiB");

  // Every numerical method: time per evaluation against error.
  methods::HarnessOptions h;
  h.samples = o.quick ? 2000 : 20000;
  h.repeats = repeats;
  h.field_resolutions = o.quick ? std::vector<int>{16, 32} : std::vector<int>{16, 32, 64, 128};
  h.field_reference_resolution = o.quick ? 64 : 256;
  std::vector<methods::MethodRow> table = methods::run_method_harness(m, h);
  pathos2_methods::HarnessOptions h_p2;
  h_p2.samples = o.quick ? 300 : 20000;
  h_p2.repeats = repeats;
  {
    const auto rows_p2 = pathos2_methods::run_pathos2_harness(m_p2, h_p2);
    table.insert(table.end(), rows_p2.begin(), rows_p2.end());
  }
  out << "\nmethods: median time per evaluation (one thread; per field on " << threads
      << " threads) and error against a long-double reference over " << h.samples << " workspace targets\n";
  out << std::left << std::setw(14) << "family" << std::setw(20) << "method" << std::setw(11) << "parameter"
      << std::right << std::setw(12) << "time (s)" << std::setw(12) << "median" << std::setw(12) << "p99"
      << std::setw(12) << "max" << std::setw(9) << "not ok" << "  unit\n";
  for (const methods::MethodRow& r : table) {
    if (r.mechanism != "parallel-12r" && &r != &table.front() && (&r - 1)->mechanism != r.mechanism)
      out << "PATHOS-II (" << r.mechanism << " preset, " << h_p2.samples
          << " poses around the home pose; leg-ik: 6 legs each; fk error: max(|dp| / (l2 + l3), angle))\n";
    out << std::left << std::setw(14) << r.family << std::setw(20) << r.method << std::setw(11) << r.parameter
        << std::right << std::setprecision(3) << std::setw(12) << r.seconds_per_evaluation << std::setw(12)
        << r.error_median << std::setw(12) << r.error_p99 << std::setw(12) << r.error_max << std::setw(9)
        << r.failures << "  " << r.error_unit << "\n";
    const std::string name = "method " + (r.mechanism == "parallel-12r" ? std::string() : r.mechanism + " ") + r.family +
                             "/" + r.method + (r.parameter.empty() ? "" : " " + r.parameter);
    rows.push_back({name + ": time per evaluation", r.seconds_per_evaluation, "s"});
    rows.push_back({name + ": median error", r.error_median, r.error_unit});
    rows.push_back({name + ": 99th percentile error", r.error_p99, r.error_unit});
    rows.push_back({name + ": max error", r.error_max, r.error_unit});
    rows.push_back({name + ": not ok", double(r.failures), "evaluations"});
  }

  // Stability towards each singular set.
  std::vector<stability::SweepRow> sweeps = stability::run_stability_sweeps(m, {});
  {
    const auto rows_p2 = stability::run_pathos2_sweeps(m_p2, {});
    sweeps.insert(sweeps.end(), rows_p2.begin(), rows_p2.end());
  }
  out << "\nstability sweeps (IK, worst of " << stability::SweepOptions{}.base_points
      << " base points): smallest eps with an ok result, and the worst error / ((residual + u B) / sigma_min)\n";
  for (stability::SweepPath path : stability::kAllPaths)
    for (const char* method : {"paper", "planar", "newton", "dls", "fallback", "newton-near"}) {
      double smallest = 0, ratio = 0;
      for (const auto& r : sweeps)
        if (r.path == path && r.family == "ik" && r.method == method && r.status == Status::Ok && std::isfinite(r.error)) {
          if (smallest == 0 || r.eps < smallest) smallest = r.eps;
          if (std::isfinite(r.predicted)) ratio = std::max(ratio, r.error / (r.predicted + r.residual / r.sigma_min));
        }
      out << "  " << std::left << std::setw(15) << stability::to_string(path) << std::setw(13) << method
          << "ok down to eps " << std::setw(10) << std::setprecision(2) << smallest << " error/bound <= "
          << ratio << "\n";
      rows.push_back({std::string("sweep ") + std::string(stability::to_string(path)) + "/" + method +
                          ": smallest eps with an ok result",
                      smallest, ""});
    }
  for (stability::SweepPath path : stability::kPathos2Paths)
    for (const char* method : {"closed-form", "newton", "newton-near", "nine-sensor", "numeric", "numeric-near"}) {
      double smallest = 0, ratio = 0;
      bool present = false;
      for (const auto& r : sweeps) {
        if (r.mechanism != "pathos2" || r.path != path || (r.family != "ik" && r.family != "fk") || r.method != method)
          continue;
        present = true;
        if (r.status == Status::Ok && std::isfinite(r.error)) {
          if (smallest == 0 || r.eps < smallest) smallest = r.eps;
          if (std::isfinite(r.predicted)) ratio = std::max(ratio, r.error / (r.predicted + r.residual / r.sigma_min));
        }
      }
      if (!present) continue;
      out << "  pathos2 " << std::left << std::setw(15) << stability::to_string(path) << std::setw(13) << method
          << "ok down to eps " << std::setw(10) << std::setprecision(2) << smallest << " error/bound <= " << ratio
          << "\n";
      rows.push_back({std::string("sweep pathos2 ") + std::string(stability::to_string(path)) + "/" + method +
                          ": smallest eps with an ok result",
                      smallest, ""});
    }

  const QString title = QString("%1 (L1 = %2, L2 = %3 %4) and PATHOS-II (l2 = %5, l3 = %6, lp = %7 cm)")
                            .arg(QString::fromStdString(preset.mechanism))
                            .arg(m.L1)
                            .arg(m.L2)
                            .arg(QString::fromStdString(unit))
                            .arg(m_p2.l2)
                            .arg(m_p2.l3)
                            .arg(m_p2.lp);
  if (!o.chart.empty()) {
    write_method_chart(table, "Speed against accuracy: " + title, o.chart);
    out << "wrote " << o.chart << "\n";
  }
  if (!o.sweeps.empty()) {
    write_sweep_chart(sweeps, "Stability towards the singular sets: " + title, o.sweeps);
    out << "wrote " << o.sweeps << "\n";
  }

  if (!o.csv.empty()) {
    const std::filesystem::path base(o.csv);
    const std::filesystem::path stem = base.parent_path() / base.stem();
    auto write_text = [](const std::filesystem::path& path, const std::string& text) {
      write_atomically(path, [&](const std::filesystem::path& tmp) {
        std::ofstream f(tmp);
        f << text;
        if (!f) throw std::runtime_error("cannot write '" + path.string() + "'");
      });
    };
    std::ostringstream table_csv;
    table_csv << "family,method,parameter,samples,not_ok,seconds_per_evaluation,error_median,error_p99,error_max,"
                 "error_unit,mechanism\n"
              << std::setprecision(6);
    for (const auto& r : table)
      table_csv << r.family << ',' << '"' << r.method << '"' << ',' << r.parameter << ',' << r.samples << ','
                << r.failures << ',' << r.seconds_per_evaluation << ',' << r.error_median << ',' << r.error_p99 << ','
                << r.error_max << ',' << r.error_unit << ',' << r.mechanism << "\n";
    write_text(stem.string() + ".methods.csv", table_csv.str());
    std::ostringstream sweep_csv;
    sweep_csv << "path,base_point,eps,distance,cond,sigma_min,predicted,family,method,status,error,residual,iterations,mechanism\n"
              << std::setprecision(6);
    for (const auto& r : sweeps)
      sweep_csv << stability::path_label(r) << ',' << r.base_point << ',' << r.eps << ',' << r.distance << ','
                << r.cond << ',' << r.sigma_min << ',' << r.predicted << ',' << r.family << ',' << r.method << ','
                << to_string(r.status) << ',' << r.error << ',' << r.residual << ',' << r.iterations << ',' << r.mechanism << "\n";
    write_text(stem.string() + ".sweeps.csv", sweep_csv.str());
    out << "wrote " << o.csv << ", " << stem.string() << ".methods.csv, " << stem.string() << ".sweeps.csv\n";
  }

  if (!o.csv.empty()) {
    std::ostringstream csv;
    csv << "measurement,value,unit\n";
    for (const Row& r : rows) csv << '"' << r.what << "\"," << std::setprecision(10) << r.value << "," << r.unit << "\n";
    write_atomically(o.csv, [&](const std::filesystem::path& tmp) {
      std::ofstream f(tmp);
      f << csv.str();
      if (!f) throw std::runtime_error("cannot write '" + o.csv + "'");
    });
  }
}

}  // namespace linkscape::gui
