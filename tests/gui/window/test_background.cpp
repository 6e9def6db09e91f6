// The panels' shared Run/Cancel worker: one run at a time, progress and the
// end delivered on the GUI thread, Cancel seen by the work, and a task
// destroyed mid-run cancelling and joining it.
#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QObject>
#include <QThread>
#include <atomic>
#include <chrono>
#include <thread>

#include "gui/window/background.h"

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

}  // namespace
}  // namespace linkscape::gui

int main(int argc, char** argv) {
  QCoreApplication app(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
