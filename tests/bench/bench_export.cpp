// .vti export: time and size of the parallel-12r field at 192^3 over its
// default box (what `linkscape field --resolution 192 -o f.vti` writes) per
// VTK compressor and level, for the table in docs/performance.md from which
// render::VtiCompression's default is chosen. The file goes to the system's
// temporary folder; "MiB" is its size, "ratio" the arrays' bytes over it.
// Run: build/tests/bench/bench_export --benchmark_repetitions=3
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "core/mechanism.h"
#include "core/preset.h"
#include "render/field_vtk.h"

namespace {

using linkscape::render::VtiCompression;

const linkscape::Field& field_192() {
  static const linkscape::Field field = [] {
    const auto mechanism = linkscape::make_mechanism(linkscape::load_preset("parallel-12r"));
    const Eigen::AlignedBox3d box = mechanism->default_box();
    const auto grid = linkscape::Grid::box(box.min(), box.max(), {192, 192, 192});
    return *mechanism->compute_field(grid, mechanism->home_task(), {}, 0, {});
  }();
  return field;
}

void write_192(benchmark::State& state, VtiCompression compression) {
  const linkscape::Field& field = field_192();
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "linkscape_bench_export.vti";
  for (auto _ : state) linkscape::render::write_vti(field, path, compression);
  const double bytes = double(std::filesystem::file_size(path));
  std::filesystem::remove(path);
  state.counters["MiB"] = bytes / (1 << 20);
  state.counters["ratio"] = double(field.grid.size() * linkscape::Field::bytes_per_sample()) / bytes;
}

void add(const std::string& name, VtiCompression::Type type, int level) {
  benchmark::RegisterBenchmark(("BM_WriteVti192/" + name + "/level:" + std::to_string(level)).c_str(), write_192,
                               VtiCompression{type, level})
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
}

}  // namespace

int main(int argc, char** argv) {
  using Type = VtiCompression::Type;
  add("none", Type::None, 1);
  for (int level : {1, 3, 5, 9}) add("lz4", Type::LZ4, level);
  for (int level : {1, 2, 3, 5, 9}) add("zlib", Type::ZLib, level);
  for (int level : {1, 5}) add("lzma", Type::LZMA, level);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
