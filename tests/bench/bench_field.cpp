// Field engine throughput: the 12R c(J) field over its default box
// (+-(L1 + L2) on every axis) at 256^3, per planar kernel (scalar reference,
// vector, vector with the x mirror), SIMD target (core/simd.h; "best" = what
// dispatch picks on this CPU) and thread count; the row kernel alone; and
// every device's field over its default box and its 512 x 512 default slice
// through the mechanism interface (what the window and the headless commands
// call), the Delta's and PATHOS-II's on every SIMD target.
// The CPU column is the process's CPU time (every thread, page faults
// included), the rate is per wall-clock second.
// Run: build/tests/bench/bench_field --benchmark_repetitions=5
//      (--benchmark_filter=AVX2 etc. for one target)
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "core/mechanism.h"
#include "core/mechanisms/parallel12r/field.h"
#include "core/mechanisms/parallel12r/planar_kernel.h"
#include "core/preset.h"
#include "core/simd.h"

namespace {

using linkscape::FieldRequest;
using linkscape::Grid;
using linkscape::PlanarKernel;

void field_256(benchmark::State& state, PlanarKernel kernel, const std::string& target, int threads) {
  linkscape::parallel12r::Model model;
  model.L1 = model.L2 = 15.0;
  FieldRequest r;
  const double reach = model.reach();
  r.grid = Grid::box({-reach, -reach, -reach}, {reach, reach, reach}, {256, 256, 256});
  r.threads = threads;
  r.kernel = kernel;
  linkscape::simd::limit_targets(target == "best" ? "" : target);
  for (auto _ : state) benchmark::DoNotOptimize(linkscape::compute_field(model, r));
  state.SetItemsProcessed(state.iterations() * std::int64_t(r.grid.size()));
  state.SetLabel(linkscape::simd::current_target());
  linkscape::simd::limit_targets("");
}

// The kernel alone, one thread: every row of the same 256^3 box written into
// one row-sized buffer, so no field memory is touched (what the field adds
// on top is first-touching its 285 MiB of fresh pages). Its rate is per
// second of the thread's CPU time.
void rows_256(benchmark::State& state, PlanarKernel kernel, const std::string& target) {
  namespace planar = linkscape::parallel12r::planar;
  linkscape::parallel12r::Model model;
  model.L1 = model.L2 = 15.0;
  const double reach = model.reach();
  const Grid g = Grid::box({-reach, -reach, -reach}, {reach, reach, reach}, {256, 256, 256});
  const planar::UnitModel unit = planar::unit_model(model);
  std::vector<float> cond(256), margin(256), residual(256);
  std::vector<std::uint8_t> reachable(256), status(256), method(256);
  std::vector<std::uint16_t> iterations(256);
  const linkscape::detail::FieldRowOut out{cond.data(),   margin.data(),     residual.data(), reachable.data(),
                                           status.data(), iterations.data(), method.data(),   nullptr};
  linkscape::simd::limit_targets(target == "best" ? "" : target);
  for (auto _ : state)
    for (int k = 0; k < 256; ++k)
      for (int j = 0; j < 256; ++j) {
        linkscape::detail::GridRow row;
        row.start = {0, j, k};
        row.count = 256;
        if (kernel == PlanarKernel::Scalar)
          for (int t = 0; t < 256; ++t)
            out.store(t, planar::to_field_sample(planar::sample(unit, row.point(g, t), 0, false)));
        else if (kernel == PlanarKernel::Vector)
          planar::sample_row_vector(unit, 0, false, g, row, 0, 256, false, out);
        else
          planar::sample_row_vector(unit, 0, false, g, row, 128, 128, true, out);
        benchmark::DoNotOptimize(cond.data());
      }
  state.SetItemsProcessed(state.iterations() * std::int64_t(g.size()));
  state.SetLabel(linkscape::simd::current_target());
  linkscape::simd::limit_targets("");
}

// A device's field (its preset's home task, default IK) over its default box
// at n^3, per thread count; LINKSCAPE_FIELD_KERNEL=scalar for the reference.
void device_field(benchmark::State& state, const std::string& preset, int n, const std::string& target,
                  int threads) {
  const auto mechanism = linkscape::make_mechanism(linkscape::load_preset(preset));
  const Eigen::AlignedBox3d box = mechanism->default_box();
  const Grid g = Grid::box(box.min(), box.max(), {n, n, n});
  const Eigen::VectorXd task = mechanism->home_task();
  linkscape::simd::limit_targets(target == "best" ? "" : target);
  for (auto _ : state) benchmark::DoNotOptimize(mechanism->compute_field(g, task, {}, threads, {}));
  state.SetItemsProcessed(state.iterations() * std::int64_t(g.size()));
  state.SetLabel(linkscape::simd::current_target());
  linkscape::simd::limit_targets("");
}

// The device's 512 x 512 slice on its first plane over its default box, as
// `linkscape bench` and the window take it, on every core.
void device_slice(benchmark::State& state, const std::string& preset, const std::string& target) {
  const auto mechanism = linkscape::make_mechanism(linkscape::load_preset(preset));
  const Eigen::VectorXd task = mechanism->home_task();
  const auto [normal, position] = mechanism->default_slice_plane(task);
  const auto [u, v] = Grid::slice_axes(normal);
  const Eigen::AlignedBox3d box = mechanism->default_box();
  const Grid g = Grid::slice(normal, position, box.min()(int(u)), box.max()(int(u)), box.min()(int(v)),
                             box.max()(int(v)), 512, 512);
  linkscape::simd::limit_targets(target == "best" ? "" : target);
  for (auto _ : state) benchmark::DoNotOptimize(mechanism->compute_field(g, task, {}, 0, {}));
  state.SetItemsProcessed(state.iterations() * std::int64_t(g.size()));
  state.SetLabel(linkscape::simd::current_target());
  linkscape::simd::limit_targets("");
}

void add_device(const std::string& name, const std::string& preset, int n, const std::string& target) {
  for (int threads : {1, 2})
    benchmark::RegisterBenchmark(("BM_" + name + "Field" + std::to_string(n) + "/" + target + "/threads:" +
                                  std::to_string(threads)).c_str(),
                                 device_field, preset, n, target, threads)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime()
        ->UseRealTime();
  benchmark::RegisterBenchmark(("BM_" + name + "Slice512/" + target).c_str(), device_slice, preset, target)
      ->Unit(benchmark::kMillisecond)
      ->MeasureProcessCPUTime()
      ->UseRealTime();
}

void add(const std::string& kernel_name, PlanarKernel kernel, const std::string& target) {
  for (int threads : {1, 2})
    benchmark::RegisterBenchmark(("BM_Parallel12rField256/" + kernel_name + "/" + target + "/threads:" +
                                  std::to_string(threads)).c_str(),
                                 field_256, kernel, target, threads)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime()  // CPU: all threads' time, the cost on a shared machine
        ->UseRealTime();           // items_per_second: samples per wall-clock second
  benchmark::RegisterBenchmark(("BM_Parallel12rRows256/" + kernel_name + "/" + target).c_str(), rows_256, kernel,
                               target)
      ->Unit(benchmark::kMillisecond);
}

}  // namespace

int main(int argc, char** argv) {
  add("scalar", PlanarKernel::Scalar, "best");
  for (const std::string& target : linkscape::simd::available_targets()) {
    add("vector", PlanarKernel::Vector, target);
    add("vector-mirrored", PlanarKernel::VectorMirrored, target);
  }
  add_device("Parallel12r", "parallel-12r", 160, "best");
  for (const std::string& target : linkscape::simd::available_targets()) add_device("Delta", "delta", 160, target);
  for (const std::string& target : linkscape::simd::available_targets()) add_device("Pathos2", "pathos2", 96, target);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
