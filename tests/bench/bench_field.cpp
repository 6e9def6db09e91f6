// Field engine throughput: the 12R c(J) field over its default box
// (+-(L1 + L2) on every axis) at 256^3, on 1 and 2 threads.
// Run: build/tests/bench/bench_field --benchmark_repetitions=5
#include <benchmark/benchmark.h>

#include "core/mechanisms/parallel12r/field.h"

namespace {

using linkscape::FieldRequest;
using linkscape::Grid;

void BM_Parallel12rField256(benchmark::State& state) {
  linkscape::parallel12r::Model model;
  model.L1 = model.L2 = 15.0;
  FieldRequest r;
  const double reach = model.reach();
  r.grid = Grid::box({-reach, -reach, -reach}, {reach, reach, reach}, {256, 256, 256});
  r.threads = int(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(linkscape::compute_field(model, r));
  state.SetItemsProcessed(state.iterations() * std::int64_t(r.grid.size()));
}
BENCHMARK(BM_Parallel12rField256)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
