// Described devices against the compiled ones, side by side in one run: each
// case is registered as compiled (where the device exists in C++), described
// in SIMD lanes (IK method "closed", the default: lanes where the device's
// legs allow, counter in_lanes the samples they decided), described with the
// closed forms one pose at a time (IK method "closed-scalar") and described
// through the numerical reference (IK method "newton"), one after another,
// and the whole list three times over (rounds), so that a change of the
// machine's load shows in every column alike. Fields over the device's
// default box (n^3) and slices on its default plane (n x n), at the home
// task, 2 threads (compiled and lanes also on one). The newton cases run
// once a round, in the first two rounds (they take seconds), each slice
// and small box beside the same solver unaided (LINKSCAPE_NUMERIC_AIDS=off:
// no reach bounds, no row seeding; what a leg of no known pattern gains
// from them). The CPU column is every thread's time; the rate is per
// wall-clock second. OffsetElbowArm (the arm of test_travel_search.cpp,
// tests/core/mechanisms/described/offset-elbow-arm.json): legs of no known
// pattern, the numerical solver alone, aided and unaided.
// BM_Kinematics / BM_KinematicsSampled: a device's Kinematics built, without
// and with every leg's sampled reach.
// Run: build/tests/bench/bench_described (--benchmark_filter=Stewart etc.)
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "core/mechanism.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/model.h"
#include "core/preset.h"

namespace {

using linkscape::Grid;

Grid grid_of(const linkscape::Mechanism& m, int n, bool slice) {
  const Eigen::AlignedBox3d box = m.default_box();
  if (!slice) return Grid::box(box.min(), box.max(), {n, n, n});
  const auto [normal, position] = m.default_slice_plane(m.home_task());
  const auto [u, v] = Grid::slice_axes(normal);
  return Grid::slice(normal, position, box.min()(int(u)), box.max()(int(u)), box.min()(int(v)), box.max()(int(v)), n,
                     n);
}

void field(benchmark::State& state, const std::string& preset, const std::string& method, int n, bool slice,
           int threads, bool unaided) {
  // Unaided: the numerical solver without its reach bounds and row seeding
  // (read when the device is built).
  if (unaided) setenv("LINKSCAPE_NUMERIC_AIDS", "off", 1);
  const auto mechanism = linkscape::make_mechanism(linkscape::load_preset(preset));
  unsetenv("LINKSCAPE_NUMERIC_AIDS");
  // The compiled devices' grids are those of the described copies, so both sample the same points.
  const std::string grid_preset = preset == "delta" ? "delta-described" : preset == "pathos2" ? "pathos2-described" : preset;
  const Grid g = grid_of(*linkscape::make_mechanism(linkscape::load_preset(grid_preset)), n, slice);
  linkscape::IkOptions o;
  o.method = method;
  std::size_t reachable = 0, in_lanes = 0;
  for (auto _ : state) {
    const auto f = mechanism->compute_field(g, mechanism->home_task(), o, threads, {});
    reachable = in_lanes = 0;
    for (std::uint8_t r : f->reachable) reachable += r;
    if (f->method == "lanes")
      for (std::uint8_t m : f->method_used) in_lanes += m == 2;
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(g.size()));
  state.counters["reachable"] = double(reachable);
  state.counters["in_lanes"] = double(in_lanes);
}

// `numeric`: legs of no known pattern, the numerical solver's alone (no lanes, no closed forms).
void add(const std::string& name, const std::string& compiled, const std::string& described, int n, bool slice,
         int round, bool numeric) {
  const std::string shape = slice ? "Slice" + std::to_string(n) : "Box" + std::to_string(n);
  auto reg = [&](const std::string& label, const std::string& preset, const std::string& method, int threads = 2,
                 bool unaided = false) {
    auto* b = benchmark::RegisterBenchmark(
                  ("BM_" + name + shape + "/" + label + (threads == 1 ? "-1thread" : "") + "/round:" + std::to_string(round)).c_str(),
                  field, preset, method, n, slice, threads, unaided)
                  ->Unit(benchmark::kMillisecond)
                  ->MeasureProcessCPUTime()
                  ->UseRealTime();
    if (method == "newton") b->Iterations(1);
  };
  if (!numeric) {
    if (!compiled.empty()) reg("compiled", compiled, "");
    reg("described-lanes", described, "closed");
    // On one thread: the kernels' own cost, which a loaded machine's scheduling
    // of two threads (a sub-millisecond field waits for the second) does not blur.
    if (!compiled.empty()) reg("compiled", compiled, "", 1);
    reg("described-lanes", described, "closed", 1);
    reg("described-closed", described, "closed-scalar");
  }
  if (round < 2) {
    reg("described-newton", described, "newton");
    // (Unaided, a 64^3 box takes minutes.)
    if (slice || n <= 24) reg("described-newton-unaided", described, "newton", 2, true);
  }
}

// A device's Kinematics built from its model, alone, with every leg's
// sampled reach or with every leg's turned reach (sampled_reach.h,
// turned_reach.h): what the
// numerical solver pays once per design where it has searched a leg's
// travel often enough, and where a leg is of no known pattern.
enum class Reach { None, Sampled, Turned };
void kinematics(benchmark::State& state, const std::string& preset, Reach reach) {
  const linkscape::Preset p = linkscape::load_preset(preset);
  const linkscape::described::Model model =
      linkscape::described::build_model(p.description, p.parameters, p.limits_deg, p.length_unit);
  int built = 0;
  for (auto _ : state) {
    const linkscape::described::Kinematics k(model);
    built = 0;
    for (std::size_t leg = 0; reach != Reach::None && leg < model.legs.size(); ++leg)
      built += reach == Reach::Sampled ? k.sampled_reach(int(leg)).built : k.turned_reach(int(leg)).built;
  }
  state.counters["legs_sampled"] = double(built);
}

}  // namespace

int main(int argc, char** argv) {
  struct Case {
    const char *name, *compiled, *described;
    int n;
    bool slice, numeric = false;
  };
  const Case cases[] = {
      {"Delta", "delta", "delta-described", 96, true},      {"Delta", "delta", "delta-described", 64, false},
      {"Pathos2", "pathos2", "pathos2-described", 96, true}, {"Pathos2", "pathos2", "pathos2-described", 64, false},
      {"Stewart", "", "stewart", 192, true},                {"Stewart", "", "stewart", 64, false},
      {"HexapodRus", "", "hexapod-rus", 96, true},          {"LinearDelta", "", "linear-delta", 96, true},
      {"FiveBar", "", "five-bar", 192, true},               {"ThreeRrr", "", "three-rrr", 192, true},
      {"Falcon", "", "falcon", 96, true},                   {"Falcon", "", "falcon", 24, false},
      {"Falcon", "", "falcon", 48, false},                  {"Haply2diy", "", "haply-2diy", 192, true},
      {"OffsetElbowArm", "", LINKSCAPE_ARM_FILE, 128, true, true},
  };
  for (int round = 0; round < 3; ++round)
    for (const Case& c : cases) add(c.name, c.compiled, c.described, c.n, c.slice, round, c.numeric);
  for (const std::string preset : {"five-bar", "haply-2diy", "three-rrr", "pathos2-described", "hexapod-rus", "stewart",
                                   "delta-described", "linear-delta", "falcon", LINKSCAPE_ARM_FILE}) {
    const std::string name = preset == LINKSCAPE_ARM_FILE ? "offset-elbow-arm" : preset;
    for (const auto& [label, reach] : {std::pair{"BM_Kinematics/", Reach::None}, {"BM_KinematicsSampled/", Reach::Sampled},
                                       {"BM_KinematicsTurned/", Reach::Turned}})
      benchmark::RegisterBenchmark((label + name).c_str(), kinematics, preset, reach)->Unit(benchmark::kMillisecond);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
