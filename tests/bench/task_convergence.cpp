// How the task-volume results converge with resolution (docs/task-volumes.md):
// the largest sphere and cube inside c(J) < 3 of the 12R (L1 = L2 = 1, and
// force_iso > 1 N at 15 cm) over grid resolutions and zoom refinements, and
// the coverage and worst c(J) of a sphere that leaves the good region, over
// task resolutions. Prints CSV tables with the time of each row.
// Run: build/tests/bench/task_convergence [--quick | --reference]
#include <chrono>
#include <cstring>
#include <iomanip>
#include <iostream>

#include "core/preset.h"
#include "core/task.h"

using namespace linkscape;
using namespace linkscape::task;

namespace {

Device device_of(const std::vector<std::string>& params) {
  Preset preset = load_preset("parallel-12r");
  apply_overrides(preset, params);
  Device d;
  d.mechanism = make_mechanism(preset);
  d.fixed_task = d.mechanism->home_task();
  d.data = haptics::device_data(preset, d.mechanism->info());
  return d;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void inscribed_table(const char* title, const Device& d, const std::vector<Criterion>& criteria, const TaskVolume& shape,
                     const std::vector<int>& resolutions) {
  std::cout << "# " << title << "\nresolution,refinements,size,cx,cy,cz,finest_spacing,seconds\n";
  for (int n : resolutions)
    for (int refinements : {0, 1, 2, 3}) {
      const auto t0 = std::chrono::steady_clock::now();
      const auto r = largest_inscribed(d, criteria, shape, d.mechanism->default_box(), {n, refinements});
      std::cout << n << "," << refinements << "," << std::setprecision(6) << r->size << "," << r->centre.x() << ","
                << r->centre.y() << "," << r->centre.z() << "," << r->spacing << "," << seconds_since(t0) << "\n";
    }
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const bool reference_only = argc > 1 && std::strcmp(argv[1], "--reference") == 0;
  const std::vector<int> resolutions = quick ? std::vector<int>{16, 32} : std::vector<int>{16, 24, 32, 48, 64, 96, 128};
  const Device unit = device_of({"L1=1", "L2=1"});
  const auto cond3 = resolve(unit, {parse_criterion("cond<3")});
  if (!reference_only) {
    inscribed_table("12R L1 = L2 = 1, cond<3: largest sphere (diameter)", unit, cond3, parse_task("sphere:diameter=1"),
                    resolutions);
    inscribed_table("12R L1 = L2 = 1, cond<3: largest cube (edge)", unit, cond3, parse_task("box:size=1"), resolutions);
    const Device cm = device_of({});
    inscribed_table("12R L1 = L2 = 15 cm, force_iso>1 N (continuous): largest sphere (diameter, cm)", cm,
                    resolve(cm, {parse_criterion("force_iso>1")}), parse_task("sphere:diameter=1"), resolutions);
  }

  // An independent reference for the first table: the clearance of a centre,
  // the distance along each of 2000 directions to the first point failing
  // c(J) < 3 (marching by 0.002, then bisection), maximised over the centre
  // by Nelder-Mead from the sampled answer.
  {
    const auto t0 = std::chrono::steady_clock::now();
    auto clearance = [&](const Eigen::Vector3d& c) {
      if (!evaluate_point(unit, cond3, c).meets) return 0.0;
      double r = INFINITY;
      for (int k = 0; k < 2000; ++k) {
        const double z = 1 - (2 * k + 1.0) / 2000, rho = std::sqrt(1 - z * z), phi = k * 2.399963229728653;
        const Eigen::Vector3d u(rho * std::cos(phi), rho * std::sin(phi), z);
        double lo = 0, hi = 0;
        for (double t = 0.002; t < r; t += 0.002) {
          if (!evaluate_point(unit, cond3, c + t * u).meets) {
            hi = t;
            break;
          }
          lo = t;
        }
        if (hi == 0) continue;  // beyond the current minimum
        for (int it = 0; it < 30; ++it) {
          const double mid = 0.5 * (lo + hi);
          (evaluate_point(unit, cond3, c + mid * u).meets ? lo : hi) = mid;
        }
        r = std::min(r, lo);
      }
      return r;
    };
    const auto start = largest_inscribed(unit, cond3, parse_task("sphere:diameter=1"), unit.mechanism->default_box(),
                                         {64, 2, 3});
    std::vector<Eigen::Vector3d> simplex = {start->centre};
    for (int k = 0; k < 3; ++k) simplex.push_back(start->centre + 0.02 * Eigen::Vector3d::Unit(k));
    std::vector<double> value;
    for (const auto& p : simplex) value.push_back(clearance(p));
    for (int it = 0; it < (quick ? 5 : 80); ++it) {
      std::vector<int> order = {0, 1, 2, 3};
      std::sort(order.begin(), order.end(), [&](int a, int b) { return value[a] > value[b]; });
      const int worst = order[3];
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) mean += simplex[order[k]] / 3;
      const Eigen::Vector3d reflected = mean + (mean - simplex[worst]);
      const double fr = clearance(reflected);
      if (fr > value[worst]) {
        simplex[worst] = reflected, value[worst] = fr;
      } else {  // shrink towards the best
        for (int k = 1; k < 4; ++k) {
          simplex[order[k]] = simplex[order[0]] + 0.5 * (simplex[order[k]] - simplex[order[0]]);
          value[order[k]] = clearance(simplex[order[k]]);
        }
      }
    }
    const int best = int(std::max_element(value.begin(), value.end()) - value.begin());
    std::cout << "# independent reference: largest c(J) < 3 sphere at L1 = L2 = 1 by ray clearance and Nelder-Mead\n"
                 "diameter,cx,cy,cz,seconds\n"
              << std::setprecision(6) << 2 * value[std::size_t(best)] << "," << simplex[std::size_t(best)].x() << ","
              << simplex[std::size_t(best)].y() << "," << simplex[std::size_t(best)].z() << "," << seconds_since(t0) << "\n";
  }

  if (reference_only) return 0;
  // A 15 cm sphere reaching across the region's edge: coverage and worst c(J).
  const Device cm = device_of({});
  const TaskVolume sphere = parse_task("sphere:diameter=15");
  const Eigen::Vector3d centre(0, 12, 10);
  const auto cond3_cm = resolve(cm, {parse_criterion("cond<3")});
  std::cout << "# 12R 15 cm, cond<3: a 15 cm sphere at (0, 12, 10): coverage and worst c(J)\n"
               "task_resolution,samples,fraction,worst_cond,seconds\n";
  for (int n : quick ? std::vector<int>{8, 16} : std::vector<int>{6, 8, 12, 16, 24, 32, 48, 64, 96}) {
    const auto t0 = std::chrono::steady_clock::now();
    const TaskReport r = evaluate(cm, cond3_cm, sphere, centre, n);
    std::cout << n << "," << r.samples << "," << std::setprecision(6) << r.fraction << "," << r.criteria[0].worst
              << "," << seconds_since(t0) << "\n";
  }
  return 0;
}
