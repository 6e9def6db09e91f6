// The window's shared Run/Cancel worker: one run at a time, progress and the
// end delivered on the GUI thread, Cancel seen by the work, and a task
// destroyed mid-run cancelling and joining it; the field jobs on it.
#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QObject>
#include <QThread>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#ifdef __linux__
#include <sys/resource.h>
#include <unistd.h>
#endif

#include "gui/window/background.h"
#include "gui/window/field_job.h"

namespace linkscape::gui {
namespace {

// Turns the event loop until `done` or 10 s.
template <class F>
bool wait_for(F done) {
  QElapsedTimer clock;
  clock.start();
  while (!done() && clock.elapsed() < 10000) {
    QCoreApplication::processEvents();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return done();
}

TEST(BackgroundTask, RunsOneAtATimeAndPostsOnTheGuiThread) {
  QObject context;
  int finished_calls = 0;
  BackgroundTask task(&context, [&] { ++finished_calls; });
  std::atomic<bool> release{false};
  int progress = 0, ended = 0;
  QThread* progress_thread = nullptr;
  ASSERT_TRUE(task.start([&](const BackgroundTask::Run& run) {
    run.progress([&] {
      ++progress;
      progress_thread = QThread::currentThread();
    });
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    run.finish([&] { ++ended; });
  }));
  EXPECT_TRUE(task.running());
  EXPECT_FALSE(task.start([](const BackgroundTask::Run&) {}));  // one at a time
  ASSERT_TRUE(wait_for([&] { return progress == 1; }));
  EXPECT_EQ(progress_thread, QThread::currentThread());
  release = true;
  ASSERT_TRUE(wait_for([&] { return ended == 1; }));
  EXPECT_FALSE(task.running());
  EXPECT_EQ(finished_calls, 1);
  // A second run after the first.
  ASSERT_TRUE(task.start([&](const BackgroundTask::Run& run) { run.finish([&] { ++ended; }); }));
  ASSERT_TRUE(wait_for([&] { return ended == 2; }));
  EXPECT_EQ(finished_calls, 2);
}

#ifdef __linux__
// The work yields the cores to the window's threads: it runs ten nice levels
// below the thread that started it (at most 19), and threads it starts (as
// OpenMP's) inherit that.
TEST(BackgroundTask, WorkRunsBelowTheWindowsPriority) {
  const auto nice_of_this_thread = [] { return getpriority(PRIO_PROCESS, id_t(gettid())); };
  const int gui = nice_of_this_thread();
  QObject context;
  BackgroundTask task(&context);
  std::atomic<int> work = -100, started = -100;
  std::atomic<bool> done{false};
  ASSERT_TRUE(task.start([&](const BackgroundTask::Run&) {
    work = nice_of_this_thread();
    std::thread([&] { started = nice_of_this_thread(); }).join();
    done = true;
  }));
  ASSERT_TRUE(wait_for([&] { return done.load() && !task.running(); }));
  EXPECT_EQ(work.load(), std::min(gui + 10, 19));
  EXPECT_EQ(started.load(), work.load());
  EXPECT_EQ(nice_of_this_thread(), gui);  // the GUI thread's own is untouched
}
#endif

TEST(BackgroundTask, CancelIsSeenByTheWorkAndLaterProgressIsDropped) {
  QObject context;
  BackgroundTask task(&context);
  EXPECT_FALSE(task.cancel());  // nothing runs
  std::atomic<bool> saw_cancel{false};
  int progress_after_end = 0;
  bool ended = false;
  ASSERT_TRUE(task.start([&](const BackgroundTask::Run& run) {
    while (!run.cancelled) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    saw_cancel = true;
    run.finish([&] { ended = true; });
    run.progress([&] { ++progress_after_end; });  // after the end: dropped
  }));
  EXPECT_TRUE(task.cancel());
  ASSERT_TRUE(wait_for([&] { return ended; }));
  EXPECT_TRUE(saw_cancel);
  for (int i = 0; i < 20; ++i) QCoreApplication::processEvents();
  EXPECT_EQ(progress_after_end, 0);
}

TEST(BackgroundTask, DestroyedMidRunCancelsAndJoins) {
  std::atomic<bool> stopped{false};
  {
    QObject context;
    BackgroundTask task(&context);
    ASSERT_TRUE(task.start([&](const BackgroundTask::Run& run) {
      while (!run.cancelled) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      stopped = true;
    }));
  }
  EXPECT_TRUE(stopped);  // joined before the task went
}

TEST(BackgroundTask, ARunEndsWhenItsWorkReturnsWithoutFinishing) {
  QObject context;
  int finished_calls = 0;
  BackgroundTask task(&context, [&] { ++finished_calls; });
  ASSERT_TRUE(task.start([](const BackgroundTask::Run&) {}));
  ASSERT_TRUE(wait_for([&] { return !task.running(); }));
  EXPECT_EQ(finished_calls, 1);
  EXPECT_TRUE(task.start([](const BackgroundTask::Run&) {}));  // free for the next
  ASSERT_TRUE(wait_for([&] { return !task.running(); }));
}

TEST(BackgroundTask, ProgressOfACancelledRunIsDroppedItsEndIsNot) {
  QObject context;
  BackgroundTask task(&context);
  std::atomic<bool> posted{false};
  int progress = 0;
  bool ended = false;
  ASSERT_TRUE(task.start([&](const BackgroundTask::Run& run) {
    while (!run.cancelled) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    run.progress([&] { ++progress; });
    posted = true;
    run.finish([&] { ended = true; });
  }));
  EXPECT_TRUE(task.cancel());
  ASSERT_TRUE(wait_for([&] { return ended; }));
  EXPECT_TRUE(posted);
  EXPECT_EQ(progress, 0);
}

// A field of `grid` whose first cond sample says which job made it.
Field marked_field(const Grid& grid, double mark) {
  Field f;
  f.grid = grid;
  f.cond.assign(grid.size(), mark);
  return f;
}

TEST(FieldJobRunner, ANewJobCancelsTheOneInFlightAndOnlyItsResultsArrive) {
  FieldJobRunner runner;
  std::vector<double> marks;  // of the slices that arrived
  QObject::connect(&runner, &FieldJobRunner::sliceReady, &runner,
                   [&](const SliceResult& r) { marks.push_back(r.field->cond.front()); });
  std::atomic<bool> first_started{false}, first_saw_cancel{false};
  FieldJob first;
  first.slice = Grid::slice(Axis::Z, 0.0, -1, 1, -1, 1, 32, 32);
  first.sampler = [&](const Grid& grid, const FieldProgress& p) -> std::optional<Field> {
    first_started = true;
    // A long computation that stops when asked to, as compute_field does.
    for (int i = 0; i < 10000 && !p.cancel->load(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    first_saw_cancel = p.cancel->load();
    return marked_field(grid, 1.0);  // a result the cancel must drop
  };
  runner.submit(first);
  ASSERT_TRUE(wait_for([&] { return first_started.load(); }));
  EXPECT_TRUE(runner.busy());
  FieldJob second = first;
  second.sampler = [](const Grid& grid, const FieldProgress&) -> std::optional<Field> {
    return marked_field(grid, 2.0);
  };
  runner.submit(second);
  ASSERT_TRUE(wait_for([&] { return !runner.busy(); }));
  EXPECT_TRUE(first_saw_cancel);
  ASSERT_FALSE(marks.empty());
  for (double m : marks) EXPECT_EQ(m, 2.0);  // nothing of the first job
}

TEST(FieldJobRunner, CancelStopsTheJobAndNothingArrives) {
  FieldJobRunner runner;
  int slices = 0;
  QObject::connect(&runner, &FieldJobRunner::sliceReady, &runner, [&](const SliceResult&) { ++slices; });
  std::atomic<bool> started{false};
  FieldJob job;
  job.slice = Grid::slice(Axis::Z, 0.0, -1, 1, -1, 1, 32, 32);
  job.sampler = [&](const Grid& grid, const FieldProgress& p) -> std::optional<Field> {
    started = true;
    while (!p.cancel->load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return marked_field(grid, 1.0);
  };
  runner.submit(job);
  ASSERT_TRUE(wait_for([&] { return started.load(); }));
  runner.cancel();
  ASSERT_TRUE(wait_for([&] { return !runner.busy(); }));
  for (int i = 0; i < 20; ++i) QCoreApplication::processEvents();
  EXPECT_EQ(slices, 0);
}

}  // namespace
}  // namespace linkscape::gui

int main(int argc, char** argv) {
  QCoreApplication app(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
