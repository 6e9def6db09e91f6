// Work off the GUI thread while the window keeps drawing: a blocking call
// that keeps the event loop turning, and the Run/Cancel worker of the
// panels that search or measure.
#pragma once

#include <QObject>
#include <QPointer>
#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "core/preset.h"

namespace linkscape::gui {

// Runs `work` on a worker thread and rethrows what it throws; the GUI thread
// meanwhile keeps drawing and running its timers (user input waits).
void run_off_gui_thread(const std::function<void()>& work);

// Reads a preset file and checks its model (load_preset, make_mechanism)
// through run_off_gui_thread: a large or hostile description never freezes
// the window. Throws what they throw.
Preset load_checked_preset(const std::string& name_or_path);

// One run at a time of long work on a worker thread, with Cancel (the
// panels' Run buttons). The work posts to the GUI thread through `post`:
// progress while the run is the current one, and its end, which finishes
// the run (`finished` is called first, and the worker joined). Posts from a
// run that is no longer current (or whose context is gone) are dropped.
// The destructor cancels and joins a run in flight.
class BackgroundTask {
 public:
  // What the work is handed: the cancel flag to poll, and the posts.
  struct Run {
    const std::atomic<bool>& cancelled;
    std::function<void(std::function<void()>)> progress;  // dropped once the run has ended
    std::function<void(std::function<void()>)> finish;    // the last post: the run ends
  };
  // `context` receives the posts (its thread is the GUI's); `finished`
  // runs on it when a run ends, before the work's own finishing post.
  BackgroundTask(QObject* context, std::function<void()> finished = {});
  ~BackgroundTask();
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;

  bool running() const { return running_; }
  // Starts `work` on a worker thread; false (nothing started) while a run is under way.
  bool start(std::function<void(const Run&)> work);
  // Asks the run to stop (the work polls `cancelled`); false when none runs.
  bool cancel();

 private:
  void join();

  QObject* context_;
  std::function<void()> finished_;
  bool running_ = false;
  unsigned generation_ = 0;
  std::shared_ptr<std::atomic<bool>> cancel_;
  std::thread worker_;
};

}  // namespace linkscape::gui
