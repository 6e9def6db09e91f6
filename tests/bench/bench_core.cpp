// Core timings: PATHOS-II pose IK + Jacobian + conditioning per pose, and the
// Table 2 design search. Run: build/tests/bench/bench_core
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "core/mechanisms/pathos2/pathos2.h"
#include "core/mechanisms/pathos2/design.h"
#include "core/mechanisms/pathos2/field.h"

namespace {

using namespace linkscape::pathos2;

std::vector<Pose> sample_poses(const Geometry& g, int count) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Pose> poses;
  const Pose home = home_pose(g.model);
  while (static_cast<int>(poses.size()) < count) {
    const Pose p = Pose::from_xyz_rpy(3 * u(rng), 3 * u(rng), home.p_world_E.z() + 3 * u(rng), 0.15 * u(rng),
                                      0.15 * u(rng), 0.5236 + 0.15 * u(rng), g.model.h0);
    if (inverse(g, p).status == linkscape::Status::Ok) poses.push_back(p);
  }
  return poses;
}

void BM_Pathos2PoseIk(benchmark::State& state) {
  const Geometry g = make_geometry(Model{});
  const auto poses = sample_poses(g, 1024);
  std::size_t i = 0;
  for (auto _ : state) {
    const PoseIkResult ik = inverse(g, poses[i++ & 1023]);
    benchmark::DoNotOptimize(ik);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pathos2PoseIk);

// The hot path of a condition-number map: full pose IK (active and passive
// angles, limits) + 6x6 Jacobian + cond(Jp) + cond(Jo).
void BM_Pathos2IkJacobianCond(benchmark::State& state) {
  const Geometry g = make_geometry(Model{});
  const auto poses = sample_poses(g, 1024);
  std::size_t i = 0;
  for (auto _ : state) {
    const Pose& p = poses[i++ & 1023];
    const JacobianResult jr = jacobian(g, p, inverse(g, p));
    benchmark::DoNotOptimize(jr.cond_p);
    benchmark::DoNotOptimize(jr.cond_o);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pathos2IkJacobianCond);

// Same with IkDetail::ActiveOnly (passive angles skipped, limits still checked).
void BM_Pathos2ActiveIkJacobianCond(benchmark::State& state) {
  const Geometry g = make_geometry(Model{});
  const auto poses = sample_poses(g, 1024);
  std::size_t i = 0;
  for (auto _ : state) {
    const Pose& p = poses[i++ & 1023];
    const JacobianResult jr = jacobian(g, p, inverse(g, p, IkDetail::ActiveOnly));
    benchmark::DoNotOptimize(jr.cond_p);
    benchmark::DoNotOptimize(jr.cond_o);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pathos2ActiveIkJacobianCond);

void BM_Pathos2NineSensorFk(benchmark::State& state) {
  const Geometry g = make_geometry(Model{});
  const auto poses = sample_poses(g, 256);
  std::vector<NineSensors> sensors;
  for (const Pose& p : poses) sensors.push_back(sensors_of(inverse(g, p)));
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(forward_nine_sensors(g, sensors[i++ & 255]));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pathos2NineSensorFk);

void BM_Pathos2NumericFk(benchmark::State& state) {
  const Geometry g = make_geometry(Model{});
  const auto poses = sample_poses(g, 256);
  std::vector<Vector6d> q;
  for (const Pose& p : poses) q.push_back(inverse(g, p).q_active);
  const Pose seed = home_pose(g.model);
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ & 255;
    benchmark::DoNotOptimize(forward_numeric(g, q[k], poses[k].h0, seed));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Pathos2NumericFk);

// Table 2: 83,349 designs, all threads OpenMP gives (OMP_NUM_THREADS).
void BM_Pathos2Table2Search(benchmark::State& state) {
  const Model base = table1_model();
  for (auto _ : state) {
    const DesignSearchResult r = design_search(base);
    benchmark::DoNotOptimize(r.best);
    state.counters["designs"] = static_cast<double>(r.rows.size());
    state.counters["evaluated"] = static_cast<double>(r.evaluated);
  }
}
BENCHMARK(BM_Pathos2Table2Search)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

// PATHOS-II field: 96^3 positions over +-12 cm around the Table 3 pose, full
// IK + closure residual + Jacobian + both condition numbers per sample.
void BM_Pathos2Field96(benchmark::State& state) {
  const linkscape::pathos2::Model model;
  linkscape::pathos2::FieldRequest r;
  r.grid = linkscape::Grid::box({-12, -12, 10.5}, {12, 12, 34.5}, {96, 96, 96});
  r.rpy = {0, 0, 0.5235987755982988};
  r.h0 = model.h0;
  r.threads = int(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(linkscape::pathos2::compute_field(model, r));
  state.SetItemsProcessed(state.iterations() * std::int64_t(r.grid.size()));
}
BENCHMARK(BM_Pathos2Field96)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
