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

}  // namespace linkscape::gui
