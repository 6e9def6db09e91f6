// Where a sweep's designs are evaluated: in this process, or over the ranks
// of an MPI job (gui/cli/sweep_mpi.cpp, built with LINKSCAPE_MPI). Rank 0 hands
// out chunks of design indices as ranks ask for them (guided: about the
// remaining designs over twice the ranks, at least one design per thread and
// at most `max_chunk` or one per thread if more), evaluates designs itself on a
// second thread, and receives every row; the other ranks only evaluate.
// Within a process, designs run in parallel, one per OpenMP thread (a
// design's own loops then run on its thread alone); on one process and on
// rank 0 each thread takes the next design as it finishes one, on the other
// ranks the threads share a chunk. Rows are delivered one batch at a time:
// under MPI on rank 0's main thread, which alone writes the checkpoint and
// the table.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace linkscape::gui::sweep_ranks {

using Rows = std::vector<std::pair<std::size_t, std::string>>;

struct Job {
  std::vector<std::size_t> todo;                     // rank 0: the designs left, in table order
  std::function<std::string(std::size_t)> evaluate;  // one design's row (every rank)
  std::function<void(const Rows&)> finished;         // rank 0, one call at a time, as rows arrive
  std::size_t max_chunk = 16;
  int threads = 1;                                   // designs evaluated at once in each process
};

// The rows of `chunk`, its designs spread over job.threads OpenMP threads, in
// the chunk's order.
Rows evaluate_chunk(const Job& job, const std::vector<std::size_t>& chunk);
// How many designs to hand out next with `left` not yet handed out.
std::size_t chunk_size(const Job& job, std::size_t left, int ranks);

struct Place {
  int rank = 0, ranks = 1;
};

// The ranks of the MPI job that started this process, from its launcher's
// environment (Open MPI's mpirun, Slurm's srun with PMI or PMIx); 0 where
// none did. The single-process path never touches MPI.
int launched_ranks();
// This process's rank in that job (0 where none started it).
int launched_rank();

// Whether this binary can join an MPI job.
bool mpi_built();

// In this process: every design of job.todo.
void run_here(const Job& job);

// Over the MPI job (MPI_Init to MPI_Finalize); returns this process's place.
// Only where mpi_built().
Place run_over_ranks(const Job& job);

}  // namespace linkscape::gui::sweep_ranks
