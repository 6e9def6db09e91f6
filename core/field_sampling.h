// The parallel sampling loop shared by every mechanism's field: cell-centre
// points, fixed chunks over OpenMP, progress and cancellation. Internal to
// core (included by the mechanism field sources, not by users).
#pragma once

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/field.h"

namespace linkscape::detail {

// Throws std::invalid_argument for an empty or non-finite grid, or one whose
// arrays (bytes_per_sample each) would exceed memory_limit_bytes.
inline void check_grid(const Grid& g, std::size_t bytes_per_sample, std::size_t memory_limit_bytes) {
  for (int k = 0; k < 3; ++k)
    if (g.dims[k] < 1 || !(g.spacing(k) > 0) || !std::isfinite(g.origin(k)))
      throw std::invalid_argument("field: grid needs positive sizes and spacings and a finite origin");
  const double bytes = double(g.size()) * double(bytes_per_sample);
  if (bytes > double(memory_limit_bytes)) {
    std::ostringstream msg;
    msg << "field: " << g.dims[0] << "x" << g.dims[1] << "x" << g.dims[2] << " samples need "
        << bytes / (1 << 20) << " MiB, over the limit of " << memory_limit_bytes / (1 << 20)
        << " MiB; lower the resolution";
    throw std::invalid_argument(msg.str());
  }
}

// Sizes f's arrays to f.grid (cond_orientation only if with_orientation) and
// fills sample i with sample_at(point i). Returns false if cancelled.
template <class SampleAt>
bool fill_field(Field& f, bool with_orientation, int threads, const FieldProgress& progress, SampleAt&& sample_at) {
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

  // Fixed chunks of consecutive samples: balanced whatever the slice
  // orientation, and the cancel flag is checked before each chunk (<0.1 ms).
  constexpr std::int64_t kChunk = 512;
  const std::int64_t chunks = (std::int64_t(n) + kChunk - 1) / kChunk;
  const std::int64_t report_every = std::max<std::int64_t>(1, chunks / 200);
  std::atomic<std::int64_t> chunks_done{0};
  const int team = threads > 0 ? threads : omp_get_max_threads();
  const std::int64_t nx = g.dims[0], nxy = nx * g.dims[1];

#pragma omp parallel for schedule(dynamic, 4) num_threads(team)
  for (std::int64_t c = 0; c < chunks; ++c) {
    if (progress.cancel && progress.cancel->load(std::memory_order_relaxed)) continue;
    const std::int64_t end = std::min<std::int64_t>(std::int64_t(n), (c + 1) * kChunk);
    for (std::int64_t idx = c * kChunk; idx < end; ++idx) {
      const int i = int(idx % nx), j = int((idx / nx) % g.dims[1]), k = int(idx / nxy);
      const FieldSample s = sample_at(g.point(i, j, k));
      f.cond[idx] = s.cond;
      f.reach_margin[idx] = s.reach_margin;
      f.residual[idx] = s.residual;
      f.reachable[idx] = s.reachable;
      f.status[idx] = s.status;
      f.iterations[idx] = s.iterations;
      f.method_used[idx] = s.method_used;
      if (with_orientation) f.cond_orientation[idx] = s.cond_orientation;
    }
    const std::int64_t done = chunks_done.fetch_add(1, std::memory_order_relaxed) + 1;
    if (progress.report && done % report_every == 0) progress.report(double(done) / double(chunks));
  }
  if (progress.cancel && progress.cancel->load()) return false;
  if (progress.report) progress.report(1.0);
  return true;
}

}  // namespace linkscape::detail
