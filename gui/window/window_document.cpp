#include "gui/window/window_document.h"

#include <QAction>
#include <QApplication>
#include <QFileInfo>
#include <QShortcut>
#include <QStatusBar>
#include <QTimer>
#include <QMainWindow>
#include <QMenu>
#include <QMessageBox>
#include <QSettings>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "gui/window/file_actions.h"
#include "gui/window/fit_panel.h"
#include "gui/window/session_history.h"
#include "gui/window/window_menus.h"

namespace linkscape::gui {

namespace {

bool same_camera(const CameraState& a, const CameraState& b) {
  const double scale = std::max(1.0, (a.position - a.focal_point).norm());
  return (a.position - b.position).norm() <= 1e-9 * scale && (a.focal_point - b.focal_point).norm() <= 1e-9 * scale &&
         (a.view_up - b.view_up).norm() <= 1e-9 && std::abs(a.view_angle - b.view_angle) <= 1e-9;
}

void apply_fit_setting(QMainWindow* window, const Session& s) {
  FitPanel* fit = window->findChild<FitPanel*>();
  if (!fit || !s.fit) return;
  try {
    fit->applySetting(*s.fit);
  } catch (const std::invalid_argument& e) {  // e.g. a parameter this device does not have
    window->statusBar()->showMessage(
        QObject::tr("The session's fit settings were not applied: %1").arg(QString::fromStdString(e.what())), 8000);
  }
}

// The window's hooks with what the document keeps of its panels: the last
// valid task setting in place of one the Task tab rejected, the Fit tab's
// settings and last result, and the View menu's toggles. Undo and redo
// restore the settings; the result and the toggles come with an opened
// session (apply_window_session; neither makes an undo step).
WindowDocument::Hooks with_panels(WindowDocument::Hooks hooks, QMainWindow* window) {
  auto last_valid = std::make_shared<std::optional<TaskSetting>>();
  hooks.capture = [capture = hooks.capture, window, last_valid] {
    Session s = capture();
    if (s.task_volume && !valid_task_setting(*s.task_volume)) s.task_volume = *last_valid;
    else *last_valid = s.task_volume;
    if (const FitPanel* fit = window->findChild<FitPanel*>()) {
      s.fit = fit->setting();
      s.fit_result = fit->outcome();
    }
    s.view = view_toggles(window);
    return s;
  };
  hooks.restore = [restore = hooks.restore, window](const Session& s) {
    restore(s);
    apply_fit_setting(window, s);
  };
  return hooks;
}

}  // namespace

void apply_window_session(QMainWindow* window, const Session& s) {
  apply_fit_setting(window, s);
  FitPanel* fit = window->findChild<FitPanel*>();
  if (fit && s.fit_result) fit->applyOutcome(*s.fit_result);
  const QStringList unknown = apply_view_toggles(window, s.view);
  if (!unknown.isEmpty())
    window->statusBar()->showMessage(
        QObject::tr("The session's view toggles %1 are not in this window's View menu").arg(unknown.join(", ")), 8000);
}

WindowDocument::WindowDocument(QMainWindow* window, Hooks hooks)
    : QObject(window),
      window_(window),
      hooks_(with_panels(std::move(hooks), window)),
      history_(new SessionHistory(hooks_.capture, hooks_.restore, this)) {
  connect(history_, &SessionHistory::modifiedChanged, this, &WindowDocument::updateTitle);
  connect(history_, &SessionHistory::pathChanged, this, &WindowDocument::updateTitle);
  // Save As on Ctrl+Shift+S (QKeySequence::SaveAs is empty on plain X11),
  // once the menus are built, unless an action has the key already.
  QTimer::singleShot(0, this, [this] {
    const QKeySequence save_as(Qt::CTRL | Qt::SHIFT | Qt::Key_S);
    for (const QAction* a : window_->findChildren<QAction*>())
      if (a->shortcuts().contains(save_as)) return;
    auto* shortcut = new QShortcut(save_as, window_);
    shortcut->setObjectName("saveAsShortcut");
    connect(shortcut, &QShortcut::activated, this, [this] { saveAs(); });
  });
  qApp->installEventFilter(this);  // the window's mouse buttons: one undo step per drag
}

bool WindowDocument::eventFilter(QObject* watched, QEvent* event) {
  const QEvent::Type type = event->type();
  if (type != QEvent::MouseButtonPress && type != QEvent::MouseButtonRelease) return false;
  if (type == QEvent::MouseButtonPress) {
    const auto* widget = qobject_cast<QWidget*>(watched);
    if (widget && widget->window() == window_) history_->hold(true);
  } else {  // anywhere: a press may open a popup that takes the release
    // After the widget has taken the release (a slider's last value comes with it).
    QTimer::singleShot(0, this, [this] {
      if (QGuiApplication::mouseButtons() == Qt::NoButton) history_->hold(false);
    });
  }
  return false;
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

bool WindowDocument::mayReload() {
  history_->flush();
  if (!interactive_ || !history_->modified()) return true;
  return QMessageBox::question(window_, tr("Reload mechanism"),
                               tr("The design in the window has changes the file does not have. Reload the file? "
                                  "The changes stay in Edit > Undo."),
                               QMessageBox::Yes | QMessageBox::Cancel, QMessageBox::Cancel) == QMessageBox::Yes;
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
  const QString file = !history_->path().isEmpty() ? history_->path() : hooks_.device_file ? hooks_.device_file() : QString();
  const QString document = !file.isEmpty() ? QFileInfo(file).fileName() : tr("Untitled");
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
