#include "gui/window/background.h"

#include <QEventLoop>
#include <QTimer>
#include <chrono>
#include <future>

#include "core/mechanism.h"

namespace linkscape::gui {

void run_off_gui_thread(const std::function<void()>& work) {
  auto job = std::async(std::launch::async, work);
  const auto ready = [&job] { return job.wait_for(std::chrono::seconds(0)) == std::future_status::ready; };
  if (!ready()) {
    QEventLoop loop;
    QTimer poll;
    QObject::connect(&poll, &QTimer::timeout, &loop, [&] {
      if (ready()) loop.quit();
    });
    poll.start(10);
    loop.exec(QEventLoop::ExcludeUserInputEvents);
  }
  job.get();
}

Preset load_checked_preset(const std::string& name_or_path) {
  Preset preset;
  run_off_gui_thread([&] {
    preset = load_preset(name_or_path);
    make_mechanism(preset);
  });
  return preset;
}

BackgroundTask::BackgroundTask(QObject* context, std::function<void()> finished)
    : context_(context), finished_(std::move(finished)) {}

BackgroundTask::~BackgroundTask() {
  if (cancel_) cancel_->store(true);
  join();
}

void BackgroundTask::join() {
  if (worker_.joinable()) worker_.join();
}

bool BackgroundTask::start(std::function<void(const Run&)> work) {
  if (running_) return false;
  join();  // a finished worker may still be unwinding
  running_ = true;
  const unsigned generation = ++generation_;
  cancel_ = std::make_shared<std::atomic<bool>>(false);
  // Posts are queued calls with the context as receiver: Qt drops them if
  // it is gone, and the destructor joins the thread before it goes.
  QObject* context = context_;
  auto progress = [this, context, generation](std::function<void()> f) {
    QMetaObject::invokeMethod(
        context,
        [this, generation, f = std::move(f)] {
          if (generation == generation_ && running_) f();
        },
        Qt::QueuedConnection);
  };
  auto finish = [this, context, generation](std::function<void()> f) {
    QMetaObject::invokeMethod(
        context,
        [this, generation, f = std::move(f)] {
          if (generation != generation_) return;
          running_ = false;
          join();
          if (finished_) finished_();
          f();
        },
        Qt::QueuedConnection);
  };
  worker_ = std::thread([work = std::move(work), cancel = cancel_, progress, finish] {
    work(Run{*cancel, progress, finish});
  });
  return true;
}

bool BackgroundTask::cancel() {
  if (!running_ || !cancel_) return false;
  cancel_->store(true);
  return true;
}

}  // namespace linkscape::gui
