// The window's mechanism actions, usable without a window: the preset
// chooser, File > Open mechanism's dialog, what a reloaded preset keeps of
// the session, and the watch on the preset file that reloads it.
#pragma once

#include <QObject>
#include <QString>
#include <functional>
#include <optional>

#include "core/mechanism.h"
#include "core/preset.h"
#include "gui/window/session.h"

class QComboBox;
class QFileSystemWatcher;
class QTimer;
class QWidget;

namespace linkscape::gui {

// The preset's file as the watcher and the error panel name it; empty for a
// preset not read from a file.
QString preset_file(const Preset& preset);

// A combo box of every preset on the search path, showing `current`.
// Picking another one asks `may_discard` (false: the user keeps the
// document) and hands the preset, read off the GUI thread, to `open`; a
// preset that fails to load (or that `open` refuses with
// std::invalid_argument) leaves everything as it was and says why.
QComboBox* make_preset_chooser(QWidget* window, const Preset& current, const std::function<bool()>& may_discard,
                               const std::function<void(const Preset&)>& open);

// The preset file the user picks (starting in the folder of `current`'s
// file, else the documents folder); empty when cancelled.
QString ask_mechanism_file(QWidget* parent, const Preset& current);

// What a device made again from its reloaded preset `next` keeps of the
// session `before` of the device `old` (pose q, x): the camera, the field
// and task volume settings, and the pose where the device has the same task
// coordinates (clamped into the new ranges; the actuators seed the solve
// where they are the same too), else its home. Design parameters and travel
// are left out: the file's stand.
Session reload_session(const Session& before, const Preset& next, const Mechanism& next_device,
                       const Mechanism& old, const Eigen::VectorXd& q, const Eigen::VectorXd& x);
// Whether reload_session kept the task coordinates' names (else it went home).
bool same_task_coordinates(const Mechanism& a, const Mechanism& b);

// Reads and checks preset files (load_checked_preset, off the GUI thread)
// for `owner`, one at a time: while one is read another gets nothing (the
// watcher tries again), and so does a read whose owner closed meanwhile.
class PresetReader {
 public:
  explicit PresetReader(QObject* owner) : owner_(owner) {}
  // The preset in `file`, or nothing: then `error` says why (empty when
  // busy, cancelled by the user or the owner went; then touch nothing of
  // the owner).
  std::optional<Preset> read(const QString& file, QString& error);

 private:
  QObject* owner_;
  bool busy_ = false;
};

// Watches a preset file, and its folder (editors save by writing a new file
// over the old one, which ends the watch on it); `changed` runs once for a
// burst of changes, and not under an open dialog.
class PresetWatcher : public QObject {
 public:
  PresetWatcher(QObject* parent, std::function<void()> changed);
  void watch(const QString& file);  // empty: nothing is watched
  void stop();

 private:
  QString file_;
  QFileSystemWatcher* watcher_;
  QTimer* timer_;
};

}  // namespace linkscape::gui
