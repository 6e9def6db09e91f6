// Compiled devices' fields with their stated stops on and off
// (docs/mechanisms/pathos2.md "Stops", docs/mechanisms/delta.md "Ball-joint
// cones"): the 128^3 field over the device's default box at its home pose,
// two threads. Run with --benchmark_enable_random_interleaving=true
// --benchmark_repetitions=N to interleave the two.
#include <benchmark/benchmark.h>

#include "core/mechanism.h"
#include "core/preset.h"

namespace {

using namespace linkscape;

void field_with_stops(benchmark::State& state, const char* preset_name, bool stops) {
  Preset preset = load_preset(preset_name);
  preset.checks = {stops, stops};
  const auto m = make_mechanism(preset);
  const Eigen::AlignedBox3d box = m->default_box();
  const Grid grid = Grid::box(box.min(), box.max(), {128, 128, 128});
  std::size_t ok = 0;
  for (auto _ : state) {
    const std::optional<Field> f = m->compute_field(grid, m->home_task(), {}, 2, {});
    ok = 0;
    for (std::uint8_t r : f->reachable) ok += r;
    benchmark::DoNotOptimize(ok);
  }
  state.counters["ok_samples"] = double(ok);
  state.counters["samples_per_s"] = benchmark::Counter(double(grid.size()), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK_CAPTURE(field_with_stops, pathos2_on, "pathos2", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(field_with_stops, pathos2_off, "pathos2", false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(field_with_stops, delta_on, "delta", true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(field_with_stops, delta_off, "delta", false)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
