// The parallel sampling loop shared by every mechanism's field: cell-centre
// points, grid rows in chunks over OpenMP, progress and cancellation. Internal to
// core (included by the mechanism field sources, not by users).
#pragma once

#include <omp.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/field.h"
#include "core/simd.h"

namespace linkscape::detail {

// Throws std::invalid_argument for an empty or non-finite grid, or one whose
// arrays (bytes_per_sample each) would exceed memory_limit_bytes.
inline void check_grid(const Grid& g, std::size_t bytes_per_sample, std::size_t memory_limit_bytes) {
  for (int k = 0; k < 3; ++k)
    if (g.dims[k] < 1 || !(g.spacing(k) > 0) || !std::isfinite(g.origin(k)))
      throw std::invalid_argument("the sampling grid needs positive sizes and spacings and a finite origin");
  const double bytes = double(g.size()) * double(bytes_per_sample);
  if (bytes > double(memory_limit_bytes)) {
    std::ostringstream msg;
    msg << "a grid of " << g.dims[0] << "x" << g.dims[1] << "x" << g.dims[2] << " samples needs "
        << bytes / (1 << 20) << " MiB, over the limit of " << memory_limit_bytes / (1 << 20)
        << " MiB; lower the resolution";
    throw std::invalid_argument(msg.str());
  }
}

// A run of consecutive samples along the grid's row axis: the first axis
// with more than one sample (x, or y for an x-slice), so a row is contiguous
// in the Field's arrays. Sample t (0 <= t < count) is
// g.point(start + t * unit(axis)), stored at index + t.
struct GridRow {
  int axis = 0;
  std::array<int, 3> start{0, 0, 0};
  int count = 0;
  std::size_t index = 0;

  // The coordinates of sample t, computed as Grid::point does (bit for bit).
  Eigen::Vector3d point(const Grid& g, int t) const {
    std::array<int, 3> ijk = start;
    ijk[axis] += t;
    return g.point(ijk[0], ijk[1], ijk[2]);
  }
};

// Where a row's samples go: each of the Field's arrays from the row's first
// index. cond_orientation is null for a field without the second measure.
struct FieldRowOut {
  float* cond;
  float* reach_margin;
  float* residual;
  std::uint8_t* reachable;
  std::uint8_t* status;
  std::uint16_t* iterations;
  std::uint8_t* method_used;
  float* cond_orientation;

  void store(int t, const FieldSample& s) const {
    cond[t] = s.cond;
    reach_margin[t] = s.reach_margin;
    residual[t] = s.residual;
    reachable[t] = s.reachable;
    status[t] = s.status;
    iterations[t] = s.iterations;
    method_used[t] = s.method_used;
    if (cond_orientation) cond_orientation[t] = s.cond_orientation;
  }

  // The same arrays `by` samples further on (another row of the Field).
  FieldRowOut shifted(std::ptrdiff_t by) const {
    return {cond + by,   reach_margin + by, residual + by,    reachable + by,
            status + by, iterations + by,   method_used + by, cond_orientation ? cond_orientation + by : nullptr};
  }
};

// Samples in a chunk of rows (below): the per-point kernels' chunks keep
// cancelling and progress prompt at up to tens of microseconds a sample; the
// vector kernels' (nanoseconds a sample) amortise each chunk's fixed cost,
// above all the fence after their streaming stores (docs/performance.md).
inline constexpr std::int64_t kChunkSamples = 512, kVectorChunkSamples = 4096;

// Sizes f's arrays to f.grid (cond_orientation only if with_orientation) and
// calls sample_row(const GridRow&, const FieldRowOut&) once for every grid
// row, which must fill all the row's samples. Rows go to the threads in
// chunks of about chunk_samples samples (at least one row); the cancel flag
// is checked before each chunk. Returns false if cancelled.
template <class SampleRow>
bool fill_field_rows(Field& f, bool with_orientation, int threads, const FieldProgress& progress,
                     SampleRow&& sample_row, std::int64_t chunk_samples = kChunkSamples) {
  const Grid& g = f.grid;
  const std::size_t n = g.size();
  f.cond.resize(n);
  f.reach_margin.resize(n);
  f.residual.resize(n);
  f.reachable.resize(n);
  f.status.resize(n);
  f.iterations.resize(n);
  f.method_used.resize(n);
  if (with_orientation) f.cond_orientation.resize(n);

  const int axis = g.dims[0] > 1 ? 0 : g.dims[1] > 1 ? 1 : 2;
  const std::int64_t row_length = g.dims[axis];
  const std::int64_t rows = std::int64_t(n) / row_length;
  const std::int64_t rows_per_chunk = std::max<std::int64_t>(1, chunk_samples / row_length);
  const std::int64_t chunks = (rows + rows_per_chunk - 1) / rows_per_chunk;
  const std::int64_t report_every = std::max<std::int64_t>(1, chunks / 200);
  std::atomic<std::int64_t> chunks_done{0};
  const int team = threads > 0 ? threads : omp_get_max_threads();
  const std::int64_t nx = g.dims[0], ny = g.dims[1];

#pragma omp parallel for schedule(dynamic, 4) num_threads(team)
  for (std::int64_t c = 0; c < chunks; ++c) {
    if (progress.cancel && progress.cancel->load(std::memory_order_relaxed)) continue;
    simd::clear_upper_registers();
    const std::int64_t last = std::min(rows, (c + 1) * rows_per_chunk);
    for (std::int64_t r = c * rows_per_chunk; r < last; ++r) {
      // The axes before `axis` have one sample, so the row starts at index r * row_length.
      const std::int64_t index = r * row_length;
      GridRow row;
      row.axis = axis;
      row.start = {int(index % nx), int(index / nx % ny), int(index / (nx * ny))};
      row.count = int(row_length);
      row.index = std::size_t(index);
      const FieldRowOut out{f.cond.data() + index,       f.reach_margin.data() + index, f.residual.data() + index,
                            f.reachable.data() + index,  f.status.data() + index,       f.iterations.data() + index,
                            f.method_used.data() + index,
                            with_orientation ? f.cond_orientation.data() + index : nullptr};
      sample_row(std::as_const(row), out);
    }
    // Kernels may write with streaming stores (weakly ordered): they are
    // done, for every thread, before the chunk counts as done.
    std::atomic_thread_fence(std::memory_order_seq_cst);
    const std::int64_t done = chunks_done.fetch_add(1, std::memory_order_relaxed) + 1;
    if (progress.report && done % report_every == 0) progress.report(double(done) / double(chunks));
  }
  if (progress.cancel && progress.cancel->load()) return false;
  if (progress.report) progress.report(1.0);
  return true;
}

// The same for a kernel of one point: fills sample i with sample_at(point i).
template <class SampleAt>
bool fill_field(Field& f, bool with_orientation, int threads, const FieldProgress& progress, SampleAt&& sample_at) {
  return fill_field_rows(f, with_orientation, threads, progress, [&](const GridRow& row, const FieldRowOut& out) {
    for (int t = 0; t < row.count; ++t) out.store(t, sample_at(row.point(f.grid, t)));
  });
}

}  // namespace linkscape::detail
