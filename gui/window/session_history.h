// The window's document: the session file it was opened from or saved to,
// whether it changed since, and undo/redo of every change to the design,
// the pose, the actuator travel and the field settings. The camera is a
// view of the document, not part of it. Each step is a pair of session
// snapshots: what changed while a mouse button was held (a slider or handle
// dragged from press to release) is one step, taken at the release; other
// changes (keys, typed values) become a step once nothing changed for a
// moment.
#pragma once

#include <QObject>
#include <QString>
#include <QTimer>
#include <QUndoStack>
#include <functional>

#include "gui/window/session.h"

namespace linkscape::gui {

class SessionHistory : public QObject {
  Q_OBJECT

 public:
  // `capture` reads the window's state; `restore` puts a state back.
  SessionHistory(std::function<Session()> capture, std::function<void(const Session&)> restore,
                 QObject* parent = nullptr);

  QUndoStack* stack() { return &stack_; }
  // Something may have changed: a snapshot follows when things are still.
  // Ignored while a snapshot is being restored.
  void noteChange();
  // Takes a pending snapshot now (before saving, or in tests).
  void flush();
  // A mouse button went down (true) or up (false) in the window: while it is
  // held changes wait, and its release takes them as one step.
  void hold(bool held);
  // The state as it is now is the document's: opened from `path` (empty: a
  // new, unsaved document). Clears the history.
  void reset(const QString& path);
  // The state as it is now was saved to `path`.
  void markSaved(const QString& path);
  // The state as it is now differs from the document's file, though no step
  // led here (a reloaded preset changed the design).
  void markModified();
  // The history of `previous` carried over to the device made again from
  // its reloaded file: its steps up to its current one, then the step from
  // its state to this one's, named `what` (none where nothing changed).
  // The path, and the clean mark where it still applies, come along.
  void adopt(const SessionHistory& previous, const QString& what);
  const QString& path() const { return path_; }
  bool modified() const { return !stack_.isClean(); }
  static constexpr int kSettleMs = 350;  // a change (not a drag) is a step once nothing moved this long

 signals:
  void modifiedChanged(bool modified);
  void pathChanged(const QString& path);

 private:
  friend class SnapshotCommand;
  void restore(const Session& s);

  std::function<Session()> capture_;
  std::function<void(const Session&)> restore_;
  QUndoStack stack_;
  QTimer settle_;
  Session last_;  // the state the top of the stack ends in
  QString path_;
  bool restoring_ = false;
  bool held_ = false, changed_while_held_ = false;
};

// Whether two sessions hold the same document (the camera is ignored).
bool same_document(const Session& a, const Session& b);
// What changed between two states, for the Edit menu: "L1", "pose",
// "field settings", ...
QString change_text(const Session& before, const Session& after);

}  // namespace linkscape::gui
