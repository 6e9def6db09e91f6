#include "gui/sweep_ranks.h"

#include <algorithm>
#include <cstdlib>
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

void run_here(const Job& job) {
  for (std::size_t i : job.todo) job.finished({{i, job.evaluate(i)}});
}

#ifndef LINKSCAPE_WITH_MPI
bool mpi_built() { return false; }
Place run_over_ranks(const Job&) {
  throw std::invalid_argument("sweep: this linkscape was built without MPI (LINKSCAPE_MPI=OFF); run it without mpirun");
}
#endif

}  // namespace linkscape::gui::sweep_ranks
