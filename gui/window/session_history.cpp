#include "gui/window/session_history.h"

#include <QStringList>
#include <QUndoCommand>

namespace linkscape::gui {

namespace {

bool same_vector(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return a.size() == b.size() && a == b; }

}  // namespace

// One step: the state before and after. The first redo is the change the
// user already made, so it does nothing.
class SnapshotCommand : public QUndoCommand {
 public:
  SnapshotCommand(SessionHistory* history, Session before, Session after)
      : QUndoCommand(change_text(before, after)), history_(history), before_(std::move(before)), after_(std::move(after)) {}
  const Session& before() const { return before_; }
  const Session& after() const { return after_; }
  void undo() override { history_->restore(before_); }
  void redo() override {
    if (done_) history_->restore(after_);
    done_ = true;
  }

 private:
  SessionHistory* history_;
  Session before_, after_;
  bool done_ = false;
};

bool same_document(const Session& a, const Session& b) {
  return a.mechanism == b.mechanism && a.parameters == b.parameters && a.actuator_limits_deg == b.actuator_limits_deg &&
         a.checks == b.checks &&
         same_vector(a.pose, b.pose) && same_vector(a.task, b.task) && a.field == b.field &&
         a.task_volume == b.task_volume && a.fit == b.fit;
}

QString change_text(const Session& before, const Session& after) {
  QStringList parts;
  for (const auto& [name, value] : after.parameters) {
    const auto it = before.parameters.find(name);
    if (it == before.parameters.end() || it->second != value) parts << QString::fromStdString(name);
  }
  if (before.actuator_limits_deg != after.actuator_limits_deg) parts << QObject::tr("actuator travel");
  if (before.checks != after.checks) parts << QObject::tr("stops");
  if (parts.isEmpty() && (!same_vector(before.pose, after.pose) || !same_vector(before.task, after.task)))
    parts << QObject::tr("pose");
  // The slice keeps its place relative to the sampling box, so a new
  // design moves its absolute position: that is the design's doing.
  FieldSettings field_before = before.field;
  if (!parts.isEmpty()) field_before.position = after.field.position;
  if (!(field_before == after.field)) parts << QObject::tr("field settings");
  if (!(before.task_volume == after.task_volume)) parts << QObject::tr("task volume");
  if (!(before.fit == after.fit)) parts << QObject::tr("fit settings");
  return parts.isEmpty() ? QObject::tr("change") : parts.join(", ");
}

SessionHistory::SessionHistory(std::function<Session()> capture, std::function<void(const Session&)> restore,
                               QObject* parent)
    : QObject(parent), capture_(std::move(capture)), restore_(std::move(restore)) {
  settle_.setSingleShot(true);
  settle_.setInterval(kSettleMs);
  connect(&settle_, &QTimer::timeout, this, &SessionHistory::flush);
  connect(&stack_, &QUndoStack::cleanChanged, this, [this](bool clean) { emit modifiedChanged(!clean); });
}

void SessionHistory::noteChange() {
  if (restoring_) return;
  if (held_) changed_while_held_ = true;
  else settle_.start();
}

void SessionHistory::hold(bool held) {
  if (held == held_) return;
  held_ = held;
  if (held) {
    if (settle_.isActive()) flush();  // a change before the press is a step of its own
    changed_while_held_ = false;
  } else if (changed_while_held_) {
    changed_while_held_ = false;
    flush();
  }
}

void SessionHistory::flush() {
  settle_.stop();
  Session now = capture_();
  now.camera.reset();
  if (same_document(now, last_)) return;
  Session before = last_;
  last_ = now;
  stack_.push(new SnapshotCommand(this, std::move(before), std::move(now)));
}

void SessionHistory::reset(const QString& path) {
  settle_.stop();
  last_ = capture_();
  last_.camera.reset();
  stack_.clear();
  stack_.setClean();
  if (path != path_) {
    path_ = path;
    emit pathChanged(path_);
  }
  emit modifiedChanged(false);
}

void SessionHistory::markSaved(const QString& path) {
  flush();
  stack_.setClean();
  if (path != path_) {
    path_ = path;
    emit pathChanged(path_);
  }
}

void SessionHistory::markModified() {
  flush();
  stack_.resetClean();  // emits cleanChanged, hence modifiedChanged, if it was clean
}

void SessionHistory::adopt(const SessionHistory& previous, const QString& what) {
  settle_.stop();
  stack_.clear();
  const int clean = previous.stack_.cleanIndex(), steps = previous.stack_.index();
  if (clean < 0 || clean > steps) stack_.resetClean();  // the file's state is not among the steps kept
  for (int i = 0; i < steps; ++i) {
    if (i == clean) stack_.setClean();
    const auto* step = static_cast<const SnapshotCommand*>(previous.stack_.command(i));
    stack_.push(new SnapshotCommand(this, step->before(), step->after()));
  }
  if (steps == clean) stack_.setClean();
  Session now = capture_();
  now.camera.reset();
  if (!same_document(previous.last_, now)) {
    auto* reload = new SnapshotCommand(this, previous.last_, now);
    reload->setText(what);
    stack_.push(reload);
  }
  last_ = now;
  if (previous.path_ != path_) {
    path_ = previous.path_;
    emit pathChanged(path_);
  }
  emit modifiedChanged(modified());
}

void SessionHistory::restore(const Session& s) {
  settle_.stop();
  restoring_ = true;
  try {
    restore_(s);
  } catch (...) {
    restoring_ = false;
    throw;
  }
  restoring_ = false;
  // The state as restored (a pose solved again may differ in the last bits
  // from the saved one): the next step starts from it.
  last_ = capture_();
  last_.camera.reset();
}

}  // namespace linkscape::gui
