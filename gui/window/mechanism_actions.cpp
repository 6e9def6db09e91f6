#include "gui/window/mechanism_actions.h"

#include <QApplication>
#include <QComboBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFileSystemWatcher>
#include <QMessageBox>
#include <QPointer>
#include <QSignalBlocker>
#include <QStandardPaths>
#include <QTimer>
#include <algorithm>
#include <stdexcept>

#include "gui/window/background.h"

namespace linkscape::gui {

namespace {

std::vector<std::string> names_of(const std::vector<Quantity>& quantities) {
  std::vector<std::string> names;
  for (const Quantity& q : quantities) names.push_back(q.name);
  return names;
}

}  // namespace

QString preset_file(const Preset& preset) {
  return preset.source.empty() ? QString()
                               : QFileInfo(QString::fromStdString(preset.source.string())).absoluteFilePath();
}

QComboBox* make_preset_chooser(QWidget* window, const Preset& current, const std::function<bool()>& may_discard,
                               const std::function<void(const Preset&)>& open) {
  auto* box = new QComboBox;
  box->setObjectName("presetBox");
  for (const auto& name : available_presets()) box->addItem(QString::fromStdString(name));
  const QString current_name = QString::fromStdString(current.source.stem().string());
  box->setCurrentText(current_name.isEmpty() ? QString::fromStdString(current.mechanism) : current_name);
  box->setToolTip(QString::fromStdString(current.title));
  QObject::connect(box, &QComboBox::activated, window, [window, box, current_name, may_discard, open] {
    const QString chosen = box->currentText();
    if (chosen == current_name) return;
    if (!may_discard()) {
      const QSignalBlocker block(box);
      box->setCurrentText(current_name);
      return;
    }
    const auto keep_current = [box, current_name] {
      const QSignalBlocker block(box);
      box->setCurrentText(current_name);
    };
    try {
      open(load_checked_preset(chosen.toStdString()));
    } catch (const Cancelled&) {
      keep_current();
    } catch (const std::invalid_argument& e) {
      keep_current();
      QMessageBox::warning(window, QObject::tr("Cannot open preset"), QString::fromStdString(e.what()));
    }
  });
  return box;
}

QString ask_mechanism_file(QWidget* parent, const Preset& current) {
  const QString folder = current.source.empty() ? QStandardPaths::writableLocation(QStandardPaths::DocumentsLocation)
                                                : QFileInfo(preset_file(current)).absolutePath();
  return QFileDialog::getOpenFileName(parent, QObject::tr("Open mechanism"), folder,
                                      QObject::tr("Mechanism preset (*.json)"));
}

bool same_task_coordinates(const Mechanism& a, const Mechanism& b) {
  return names_of(a.info().task) == names_of(b.info().task);
}

Session reload_session(const Session& before, const Preset& next, const Mechanism& next_device,
                       const Mechanism& old, const Eigen::VectorXd& q, const Eigen::VectorXd& x) {
  const MechanismInfo& info = next_device.info();
  Session kept;
  kept.mechanism = preset_reference(next);
  kept.camera = before.camera;
  kept.field = before.field;
  kept.task_volume = before.task_volume;
  if (same_task_coordinates(next_device, old)) {
    kept.task = x;
    for (std::size_t k = 0; k < info.task.size(); ++k)
      kept.task(Eigen::Index(k)) = std::clamp(x(Eigen::Index(k)), info.task[k].range.lo, info.task[k].range.hi);
    // The actuators seed the solve, so the device stays in its assembly branch.
    if (names_of(info.actuators) == names_of(old.info().actuators)) kept.pose = q;
  } else {
    kept.task = next_device.home_task();
    kept.pose = next_device.home_actuators();
  }
  return kept;
}

std::optional<Preset> PresetReader::read(const QString& file, QString& error) {
  if (busy_) return std::nullopt;
  busy_ = true;
  const QPointer<QObject> alive(owner_);
  std::optional<Preset> next;
  QString why;
  try {
    next = load_checked_preset(file.toStdString());
  } catch (const Cancelled&) {
    // the user's choice: nothing to say
  } catch (const std::exception& e) {
    why = QString::fromStdString(e.what());
  }
  if (!alive) return std::nullopt;  // closed while the file was read: this reader is gone too
  busy_ = false;
  error = why;
  return next;
}

PresetWatcher::PresetWatcher(QObject* parent, std::function<void()> changed)
    : QObject(parent), watcher_(new QFileSystemWatcher(this)), timer_(new QTimer(this)) {
  timer_->setSingleShot(true);
  timer_->setInterval(200);  // an editor's save is several changes
  connect(watcher_, &QFileSystemWatcher::fileChanged, timer_, qOverload<>(&QTimer::start));
  connect(watcher_, &QFileSystemWatcher::directoryChanged, this, [this] {
    if (!watcher_->files().contains(file_) && QFileInfo::exists(file_)) timer_->start();
  });
  connect(timer_, &QTimer::timeout, this, [this, changed] {
    if (QApplication::activeModalWidget()) {  // not under an open dialog: later
      timer_->start();
      return;
    }
    changed();
  });
}

void PresetWatcher::watch(const QString& file) {
  file_ = file;
  if (file.isEmpty()) return;
  if (QFileInfo::exists(file) && !watcher_->files().contains(file)) watcher_->addPath(file);
  const QString folder = QFileInfo(file).absolutePath();
  if (!watcher_->directories().contains(folder)) watcher_->addPath(folder);
}

void PresetWatcher::stop() {
  timer_->stop();
  const QStringList watched = watcher_->files() + watcher_->directories();
  if (!watched.isEmpty()) watcher_->removePaths(watched);
}

}  // namespace linkscape::gui
