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
#include "core/preset.h"
#include "gui/headless.h"
#include <vtkPolyData.h>

#include "render/workspace_mesh.h"

namespace linkscape::gui {
namespace {

using Clock = std::chrono::steady_clock;

// Median wall time in seconds of `repeats` runs (after one warm-up run).
double median_seconds(int repeats, const std::function<void()>& work) {
  work();
  std::vector<double> t;
  for (int i = 0; i < repeats; ++i) {
    const auto start = Clock::now();
    work();
    t.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

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
  Preset preset = load_preset(o.mechanism.mechanism);
  apply_overrides(preset, o.mechanism.params);
  const parallel12r::Model m = make_parallel12r(preset);
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
    const double s = median_seconds(repeats, [&] { compute_field(m, r); });
    report("cond field, planar, " + std::to_string(n_tp) + "^3 cube, " + std::to_string(t) + " thread(s)",
           r.grid.size() / s / 1e6, "M points/s");
  }

  // A 512 x 512 slice through x = L/4 (the Fig. 5 panel x = 0.25 for L = 1).
  {
    FieldRequest r;
    const double R = m.reach();
    const int n = o.quick ? 128 : 512;
    r.grid = Grid::slice(Axis::X, 0.125 * R, -R, R, -R, R, n, n);
    const double s = median_seconds(repeats, [&] { compute_field(m, r); });
    report("slice " + std::to_string(n) + "x" + std::to_string(n) + " at x = (L1+L2)/8", s * 1e3, "ms");
  }

  // Volumes and their isosurfaces.
  const double analytic = 4.0 / 3.0 * std::numbers::pi * (std::pow(m.reach(), 3) - std::pow(m.inner_reach(), 3));
  for (int n : o.quick ? std::vector<int>{32, 64} : std::vector<int>{32, 64, 128, 256}) {
    const FieldRequest r = cube(m, n);
    std::optional<Field> field;
    const double t_field = median_seconds(n >= 256 ? 1 : repeats, [&] { field = compute_field(m, r); });
    vtkSmartPointer<vtkPolyData> reach, cond;
    render::SurfaceRequest reach_request, cond_request;
    cond_request.surface = render::Surface::WellConditioned;
    const double t_reach = median_seconds(n >= 256 ? 1 : repeats, [&] { reach = render::extract_surface(*field, reach_request); });
    const double t_cond = median_seconds(n >= 256 ? 1 : repeats, [&] { cond = render::extract_surface(*field, cond_request); });
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
