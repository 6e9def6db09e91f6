// Work off the GUI thread while the window keeps drawing: the Run/Cancel
// worker of everything that computes or reads for the window (the panels'
// searches, the field jobs, the reading of preset files), and a call that
// waits on it with a Cancel for the user.
#pragma once

#include <QObject>
#include <QString>
#include <atomic>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include "core/preset.h"

namespace linkscape::gui {

// One run at a time of long work on a worker thread, with Cancel. The work
// posts to the GUI thread through `progress` (delivered while the run is the
// current one and not cancelled) and `finish` (its last post). A run ends
// when its work returns, whether or not it posted `finish`: on the GUI
// thread the worker is joined, `finished` is called, then the work's
// finishing post. Posts after `finish`, and posts reaching a destroyed task
// or context, are dropped. The destructor cancels and joins a run in flight.
class BackgroundTask {
 public:
  // What the work is handed: the cancel flag to poll, and the posts.
  struct Run {
    const std::atomic<bool>& cancelled;
    std::function<void(std::function<void()>)> progress;
    std::function<void(std::function<void()>)> finish;  // runs when the run has ended
  };
  // `context` receives the posts (its thread is the GUI's); `finished`
  // runs on it when a run ends, before the work's own finishing post. It
  // may start the next run.
  BackgroundTask(QObject* context, std::function<void()> finished = {});
  ~BackgroundTask();
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;

  bool running() const { return running_; }
  // Starts `work` on a worker thread; false (nothing started) while a run is under way.
  bool start(std::function<void(const Run&)> work);
  // Asks the run to stop (the work polls `cancelled`; its progress is
  // dropped from now on); false when none runs.
  bool cancel();

 private:
  void join();

  QObject* context_;
  std::function<void()> finished_;
  bool running_ = false;
  unsigned generation_ = 0;
  std::shared_ptr<std::atomic<bool>> cancel_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
  std::thread worker_;
};

// The user's Cancel of a wait_off_gui_thread.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

// Runs `work` on a BackgroundTask and waits for it while the window keeps
// drawing and running its timers; user input waits. Work that lasts longer
// than kDialogAfterMs shows a modal dialog saying `what` with a Cancel
// button (under a QApplication): Cancel throws Cancelled at once, the work
// is asked to stop and runs on unwaited, so it must own what it touches.
// Rethrows what `work` throws.
inline constexpr int kDialogAfterMs = 400;
void wait_off_gui_thread(const std::function<void(const std::atomic<bool>& cancelled)>& work,
                         const QString& what = {});
// The same for work that does not poll the cancel flag.
void run_off_gui_thread(const std::function<void()>& work, const QString& what = {});

// Reads a preset file and checks its model (load_preset, make_mechanism)
// through wait_off_gui_thread: a large or hostile description never freezes
// the window, and the user may cancel it (Cancelled). Throws what they throw.
Preset load_checked_preset(const std::string& name_or_path);

}  // namespace linkscape::gui
