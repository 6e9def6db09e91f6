// Haptic measures and their fields (core/haptics.h) for every registered
// device: the measures of one J, and the generic field pass (IK per sample
// through the interface, then J) beside the device's own kernel.
// Run: build/tests/bench/bench_haptics
#include <benchmark/benchmark.h>

#include <random>

#include "core/haptics.h"
#include "core/preset.h"

namespace {

using namespace linkscape;

struct Device {
  std::shared_ptr<const Mechanism> mechanism;
  haptics::DeviceData data;
};

Device device(int index) {
  const Preset preset = load_preset(registered_mechanisms().at(std::size_t(index)));
  Device d{make_mechanism(preset), {}};
  d.data = haptics::device_data(preset, d.mechanism->info());
  return d;
}

void BM_MeasuresOfOneJacobian(benchmark::State& state) {
  const Device d = device(int(state.range(0)));
  state.SetLabel(d.mechanism->info().name);
  const Eigen::MatrixXd J = d.mechanism->jacobian(d.mechanism->home_actuators(), d.mechanism->home_task());
  for (auto _ : state) {
    const haptics::Measures m = haptics::measures(J, d.data, haptics::TorqueRating::Continuous);
    benchmark::DoNotOptimize(m.force_max_N);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MeasuresOfOneJacobian)->DenseRange(0, 2);

// A 48^3 volume over the device's default box: items are samples per second.
// Arguments: device index, threads, 0 = the device's kernel alone, 1 = with
// the haptic pass.
void BM_Field48(benchmark::State& state) {
  const Device d = device(int(state.range(0)));
  const int threads = int(state.range(1));
  const bool haptic = state.range(2) != 0;
  const Eigen::AlignedBox3d box = d.mechanism->default_box();
  const Grid grid = Grid::box(box.min(), box.max(), {48, 48, 48});
  std::size_t reachable = 0;
  for (auto _ : state) {
    const auto field = haptics::sample_field(*d.mechanism, grid, d.mechanism->home_task(), {}, threads, {},
                                             haptic ? &d.data : nullptr);
    reachable = std::count(field->reachable.begin(), field->reachable.end(), 1);
    benchmark::DoNotOptimize(field->cond.data());
  }
  state.SetLabel(d.mechanism->info().name + (haptic ? " kernel + haptic pass" : " kernel") + ", " +
                 std::to_string(100 * reachable / grid.size()) + " % reachable");
  state.SetItemsProcessed(state.iterations() * std::int64_t(grid.size()));
}
BENCHMARK(BM_Field48)
    ->ArgsProduct({{0, 1, 2}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
