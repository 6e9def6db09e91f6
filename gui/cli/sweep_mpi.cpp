// The MPI side of a sweep (gui/cli/sweep_ranks.h). Messages: a worker sends its
// finished rows (tag kRows; empty at first, so a message is also a request
// for work); rank 0 answers with a chunk of design indices (tag kWork; empty:
// stop). All of rank 0's MPI calls are on its main thread, which polls for
// rows while a second thread's OpenMP team evaluates rank 0's own designs.
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <iostream>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "gui/cli/sweep_ranks.h"

namespace linkscape::gui::sweep_ranks {
namespace {

constexpr int kRows = 1, kWork = 2;

void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("sweep: MPI ") + what + " failed");
}

// The rows of a worker's message: one line each (rows hold no line breaks).
Rows unpack(const std::string& text, const std::vector<std::size_t>& indices) {
  Rows rows;
  std::size_t start = 0, k = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    rows.emplace_back(indices.at(k++), text.substr(start, end - start));
  if (k != indices.size()) throw std::runtime_error("sweep: a rank sent " + std::to_string(k) + " rows for " +
                                                    std::to_string(indices.size()) + " designs");
  return rows;
}

// The designs not yet handed out, shared by rank 0's two threads.
class Queue {
 public:
  Queue(const Job& job, int ranks) : job_(job), left_(job.todo.begin(), job.todo.end()), ranks_(ranks) {}
  // A chunk for another rank.
  std::vector<std::size_t> take() { return take(chunk_size(job_, left_.size(), ranks_)); }
  std::vector<std::size_t> take(std::size_t most) {
    std::lock_guard lock(mutex_);
    const std::size_t n = std::min(left_.size(), most);
    std::vector<std::size_t> chunk(left_.begin(), left_.begin() + std::ptrdiff_t(n));
    left_.erase(left_.begin(), left_.begin() + std::ptrdiff_t(n));
    return chunk;
  }
  void clear() {
    std::lock_guard lock(mutex_);
    left_.clear();
  }

 private:
  const Job& job_;
  std::mutex mutex_;
  std::deque<std::size_t> left_;
  int ranks_;
};

void work(const Job& job) {
  std::string rows;
  for (;;) {
    check(MPI_Send(rows.data(), int(rows.size()), MPI_CHAR, 0, kRows, MPI_COMM_WORLD), "send");
    MPI_Status status;
    check(MPI_Probe(0, kWork, MPI_COMM_WORLD, &status), "probe");
    int count = 0;
    MPI_Get_count(&status, MPI_UINT64_T, &count);
    std::vector<std::uint64_t> chunk(static_cast<std::size_t>(count));
    check(MPI_Recv(chunk.data(), count, MPI_UINT64_T, 0, kWork, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "receive");
    if (chunk.empty()) return;
    rows.clear();
    for (const auto& [index, row] : evaluate_chunk(job, std::vector<std::size_t>(chunk.begin(), chunk.end())))
      rows += row + "\n";
  }
}

void lead(const Job& job, int ranks) {
  Queue queue(job, ranks);
  std::mutex mutex;
  Rows local;                 // finished by this rank's own thread
  bool local_done = false;
  std::string local_error;
  // Rank 0's own threads take one design at a time: none waits for another.
  std::thread own([&] {
#pragma omp parallel num_threads(std::max(1, job.threads))
    for (std::vector<std::size_t> one; !(one = queue.take(1)).empty();) {
      std::string row;
      try {
        row = job.evaluate(one.front());
      } catch (const std::exception& e) {
        std::lock_guard lock(mutex);
        local_error = e.what();
        continue;
      }
      std::lock_guard lock(mutex);
      local.emplace_back(one.front(), std::move(row));
    }
    std::lock_guard lock(mutex);
    local_done = true;
  });
  std::vector<std::vector<std::size_t>> given(static_cast<std::size_t>(ranks));  // the chunk each rank works on
  int working = ranks - 1;
  bool done = false;
  try {
    while (!done) {
      int waiting = 0;
      MPI_Status status;
      check(MPI_Iprobe(MPI_ANY_SOURCE, kRows, MPI_COMM_WORLD, &waiting, &status), "probe");
      if (waiting) {
        int count = 0;
        MPI_Get_count(&status, MPI_CHAR, &count);
        std::string text(std::size_t(count), '\0');
        const int from = status.MPI_SOURCE;
        check(MPI_Recv(text.data(), count, MPI_CHAR, from, kRows, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "receive");
        const Rows rows = unpack(text, given[std::size_t(from)]);
        if (!rows.empty()) job.finished(rows);
        given[std::size_t(from)] = queue.take();
        const std::vector<std::uint64_t> chunk(given[std::size_t(from)].begin(), given[std::size_t(from)].end());
        check(MPI_Send(chunk.data(), int(chunk.size()), MPI_UINT64_T, from, kWork, MPI_COMM_WORLD), "send");
        if (chunk.empty()) --working;
        continue;
      }
      Rows rows;
      {
        std::lock_guard lock(mutex);
        rows.swap(local);
        done = local_done && working == 0;
      }
      if (!rows.empty()) job.finished(rows);
      if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  } catch (...) {
    queue.clear();  // rank 0's own threads stop after their current design
    own.join();
    throw;
  }
  own.join();
  if (!local_error.empty()) throw std::runtime_error(local_error);
}

}  // namespace

bool mpi_built() { return true; }

Place run_over_ranks(const Job& job) {
  int provided = 0;
  check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "initialisation");
  Place place;
  MPI_Comm_rank(MPI_COMM_WORLD, &place.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &place.ranks);
  try {
    if (place.rank == 0) lead(job, place.ranks);
    else work(job);
  } catch (const std::exception& e) {
    // A broken exchange: no rank can go on.
    std::cerr << "linkscape: rank " << place.rank << ": " << e.what() << std::endl;
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  MPI_Finalize();
  return place;
}

}  // namespace linkscape::gui::sweep_ranks
