#include "gui/window/window_document.h"

#include <QFileInfo>
#include <QMainWindow>
#include <QMenu>
#include <QMessageBox>
#include <QSettings>
#include <cmath>

#include "gui/window/file_actions.h"
#include "gui/window/session_history.h"

namespace linkscape::gui {

namespace {

bool same_camera(const CameraState& a, const CameraState& b) {
  const double scale = std::max(1.0, (a.position - a.focal_point).norm());
  return (a.position - b.position).norm() <= 1e-9 * scale && (a.focal_point - b.focal_point).norm() <= 1e-9 * scale &&
         (a.view_up - b.view_up).norm() <= 1e-9 && std::abs(a.view_angle - b.view_angle) <= 1e-9;
}

}  // namespace

WindowDocument::WindowDocument(QMainWindow* window, Hooks hooks)
    : QObject(window),
      window_(window),
      hooks_(std::move(hooks)),
      history_(new SessionHistory(hooks_.capture, hooks_.restore, this)) {
  connect(history_, &SessionHistory::modifiedChanged, this, &WindowDocument::updateTitle);
  connect(history_, &SessionHistory::pathChanged, this, &WindowDocument::updateTitle);
}

bool WindowDocument::maybeSave() {
  history_->flush();
  if (!interactive_ || !history_->modified()) return true;
  const auto answer = QMessageBox::warning(
      window_, tr("Unsaved changes"), tr("The session has changes that are not saved. Save them first?"),
      QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
  if (answer == QMessageBox::Save) return save();
  return answer == QMessageBox::Discard;
}

bool WindowDocument::save() {
  if (history_->path().isEmpty()) return saveAs();
  return saveSession(history_->path());
}

bool WindowDocument::saveAs() {
  const QString path =
      ask_session_to_save(window_, history_->path().isEmpty() ? QStringLiteral("session.json") : history_->path());
  return !path.isEmpty() && saveSession(path);
}

bool WindowDocument::saveSession(const QString& path) {
  history_->flush();
  if (!save_session_file(window_, hooks_.capture(), path)) return false;
  history_->markSaved(path);
  addRecent(path);
  return true;
}

bool WindowDocument::openSession(const QString& path) {
  const bool opened = open_session_file(
      window_, path, [this, path](const Session& s, const Preset& preset) { hooks_.open(s, preset, path); });
  if (!opened) return false;
  addRecent(path);
  return true;
}

void WindowDocument::setRecentMenu(QMenu* menu) {
  recent_menu_ = menu;
  fill_recent_menu(recent_menu_, this, [this](const QString& path) { openSession(path); });
}

void WindowDocument::addRecent(const QString& path) {
  add_recent_session(path);
  if (recent_menu_) setRecentMenu(recent_menu_);
}

void WindowDocument::updateTitle() {
  const QString document = !history_->path().isEmpty() ? QFileInfo(history_->path()).fileName() : tr("Untitled");
  // [*] is where Qt shows the modified mark.
  window_->setWindowTitle(QString("%1[*] — %2 — Linkscape").arg(document, hooks_.device_title()));
  window_->setWindowModified(history_->modified());
}

void WindowDocument::closing() {
  if (!interactive_) return;
  QSettings settings;
  settings.setValue("windowGeometry", window_->saveGeometry());
  settings.setValue("windowState", window_->saveState());
}

bool WindowDocument::cameraUntouched(const CameraState& now) const {
  return fitted_camera_ && same_camera(*fitted_camera_, now);
}

}  // namespace linkscape::gui
