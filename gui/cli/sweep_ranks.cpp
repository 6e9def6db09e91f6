#include "gui/cli/sweep_ranks.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <stdexcept>

namespace linkscape::gui::sweep_ranks {

int launched_ranks() {
  auto number = [](const char* name) {
    const char* value = std::getenv(name);
    return value && *value ? std::max(1, std::atoi(value)) : 0;
  };
  if (const int n = number("OMPI_COMM_WORLD_SIZE")) return n;  // Open MPI's mpirun
  if (const int n = number("PMI_SIZE")) return n;              // PMI launchers (srun --mpi=pmi2, MPICH's hydra)
  if (std::getenv("PMIX_RANK")) return std::max(1, number("SLURM_STEP_NUM_TASKS"));  // srun --mpi=pmix
  return 0;
}

int launched_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (const char* value = std::getenv(name); value && *value) return std::atoi(value);
  return 0;
}

Rows evaluate_chunk(const Job& job, const std::vector<std::size_t>& chunk) {
  Rows rows(chunk.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, job.threads))
  for (std::int64_t k = 0; k < std::int64_t(chunk.size()); ++k)
    rows[std::size_t(k)] = {chunk[std::size_t(k)], job.evaluate(chunk[std::size_t(k)])};
  return rows;
}

std::size_t chunk_size(const Job& job, std::size_t left, int ranks) {
  const std::size_t threads = std::size_t(std::max(1, job.threads));
  const std::size_t most = std::max(job.max_chunk, threads), fewest = std::min(threads, most);
  return std::clamp(left / (2 * std::size_t(std::max(1, ranks))), fewest, most);
}

void run_here(const Job& job) {
  // One design at a time per thread, rows handed over as they finish: no
  // thread waits for another. An exception cannot leave an OpenMP loop: the
  // first one (a checkpoint that cannot be written) stops the others and is
  // thrown after it.
  std::mutex handing_over;
  std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, job.threads))
  for (std::int64_t k = 0; k < std::int64_t(job.todo.size()); ++k) {
    {
      std::lock_guard lock(handing_over);
      if (failure) continue;
    }
    const std::size_t i = job.todo[std::size_t(k)];
    try {
      Rows row{{i, job.evaluate(i)}};
      std::lock_guard lock(handing_over);
      if (!failure) job.finished(row);
    } catch (...) {
      std::lock_guard lock(handing_over);
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
}

#ifndef LINKSCAPE_WITH_MPI
bool mpi_built() { return false; }
Place run_over_ranks(const Job&) {
  throw std::invalid_argument("sweep: this linkscape was built without MPI (LINKSCAPE_MPI=OFF); run it without mpirun");
}
#endif

}  // namespace linkscape::gui::sweep_ranks
