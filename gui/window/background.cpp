#include "gui/window/background.h"

#include <QApplication>
#include <QEventLoop>
#include <QProgressDialog>
#include <QTimer>
#include <algorithm>
#include <cerrno>

#include "core/mechanism.h"

#ifdef __linux__
#include <sys/resource.h>
#include <unistd.h>
#endif

namespace linkscape::gui {
namespace {

// Background work yields the cores to the window's own threads (the GUI's
// and the software rasteriser's) when both want them: a frame under way
// then costs what it costs on an idle machine, and the work takes whatever
// the frames leave. Threads the work starts (OpenMP's) inherit it.
void yield_to_the_window() {
#ifdef __linux__
  const id_t self = id_t(gettid());
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, self);
  if (errno == 0) setpriority(PRIO_PROCESS, self, std::min(nice + 10, 19));
#endif
}

}  // namespace

BackgroundTask::BackgroundTask(QObject* context, std::function<void()> finished)
    : context_(context), finished_(std::move(finished)) {}

BackgroundTask::~BackgroundTask() {
  alive_.reset();  // posts still queued find the task gone
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
  auto cancel = cancel_ = std::make_shared<std::atomic<bool>>(false);
  auto ended = std::make_shared<std::atomic<bool>>(false);  // the work posted `finish`
  auto last = std::make_shared<std::function<void()>>();    // what it posted (read after the join)
  // Posts are queued calls with the context as receiver: Qt drops them if
  // it is gone, and they check that the task is still there.
  QObject* context = context_;
  const std::weak_ptr<bool> alive = alive_;
  auto current = [this, alive, generation] { return !alive.expired() && generation == generation_; };
  auto progress = [context, current, cancel, ended, this](std::function<void()> f) {
    if (ended->load()) return;
    QMetaObject::invokeMethod(
        context,
        [this, current, cancel, f = std::move(f)] {
          if (current() && running_ && !cancel->load()) f();
        },
        Qt::QueuedConnection);
  };
  auto finish = [ended, last](std::function<void()> f) {
    if (!ended->exchange(true)) *last = std::move(f);
  };
  worker_ = std::thread([this, work = std::move(work), cancel, progress, finish, last, context, current] {
    yield_to_the_window();
    work(Run{*cancel, progress, finish});
    QMetaObject::invokeMethod(
        context,
        [this, current, last] {
          if (!current()) return;
          running_ = false;
          join();
          if (finished_) finished_();
          if (*last) (*last)();
        },
        Qt::QueuedConnection);
  });
  return true;
}

bool BackgroundTask::cancel() {
  if (!running_ || !cancel_) return false;
  cancel_->store(true);
  return true;
}

namespace {

// One waited-for run. A run the caller stopped waiting for (Cancel) keeps
// it until its work returns, then deletes it.
class WaitedRun : public QObject {
 public:
  WaitedRun()
      : task(this, [this] {
          done = true;
          if (abandoned) deleteLater();
          else if (on_done) on_done();
        }) {}
  BackgroundTask task;
  bool done = false, abandoned = false;
  std::function<void()> on_done;
  std::exception_ptr error;  // written by the worker, read after its join
};

}  // namespace

void wait_off_gui_thread(const std::function<void(const std::atomic<bool>& cancelled)>& work, const QString& what) {
  auto* run = new WaitedRun;
  run->task.start([run, work](const BackgroundTask::Run& r) {
    try {
      work(r.cancelled);
    } catch (...) {
      run->error = std::current_exception();
    }
  });
  QEventLoop loop;
  run->on_done = [&loop] { loop.quit(); };
  // First without a dialog: most reads end before one would be seen.
  QTimer::singleShot(kDialogAfterMs, &loop, &QEventLoop::quit);
  loop.exec(QEventLoop::ExcludeUserInputEvents);
  if (!run->done && qobject_cast<QApplication*>(QCoreApplication::instance())) {
    QProgressDialog dialog(what.isEmpty() ? QObject::tr("Working…") : what, QObject::tr("Cancel"), 0, 0,
                           QApplication::activeWindow());
    dialog.setObjectName("waitDialog");
    dialog.setWindowModality(Qt::ApplicationModal);
    dialog.setMinimumDuration(0);
    QObject::connect(&dialog, &QProgressDialog::canceled, &loop, &QEventLoop::quit);
    dialog.show();
    if (!run->done) loop.exec();  // the modal dialog takes the user's input
    if (!run->done) {
      run->abandoned = true;
      run->task.cancel();
      throw Cancelled();
    }
  }
  while (!run->done) loop.exec(QEventLoop::ExcludeUserInputEvents);
  const std::exception_ptr error = run->error;
  delete run;
  if (error) std::rethrow_exception(error);
}

void run_off_gui_thread(const std::function<void()>& work, const QString& what) {
  wait_off_gui_thread([work](const std::atomic<bool>&) { work(); }, what);
}

Preset load_checked_preset(const std::string& name_or_path) {
  auto read = std::make_shared<Preset>();  // the work may outlive this call (Cancel)
  wait_off_gui_thread(
      [name_or_path, read](const std::atomic<bool>& cancelled) {
        Preset preset = load_preset(name_or_path);
        if (cancelled) return;
        make_mechanism(preset);
        *read = std::move(preset);
      },
      QObject::tr("Reading %1…").arg(QString::fromStdString(name_or_path)));
  return std::move(*read);
}

}  // namespace linkscape::gui
