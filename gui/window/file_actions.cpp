#include "gui/window/file_actions.h"

#include <QFileDialog>
#include <QFileInfo>
#include <QMainWindow>
#include <QMenu>
#include <QMessageBox>
#include <QSettings>
#include <QStatusBar>
#include <QStringList>

#include "gui/window/background.h"

namespace linkscape::gui {

bool open_session_file(QMainWindow* window, const QString& path,
                       const std::function<void(const Session&, const Preset&)>& open) {
  try {
    const Session s = load_session(path.toStdString());
    open(s, load_checked_preset(s.mechanism));
  } catch (const Cancelled&) {
    window->statusBar()->showMessage(QObject::tr("Opening %1 cancelled").arg(path), 4000);
    return false;
  } catch (const std::exception& e) {
    QMessageBox::warning(window, QObject::tr("Cannot open session"), QString::fromStdString(e.what()));
    return false;
  }
  window->statusBar()->showMessage(QObject::tr("Opened %1").arg(path), 4000);
  return true;
}

bool save_session_file(QMainWindow* window, const Session& session, const QString& path) {
  try {
    save_session(session, path.toStdString());
  } catch (const std::exception& e) {
    QMessageBox::warning(window, QObject::tr("Cannot save session"), QString::fromStdString(e.what()));
    return false;
  }
  window->statusBar()->showMessage(QObject::tr("Saved %1").arg(path), 4000);
  return true;
}

QString ask_session_to_open(QWidget* parent) {
  return QFileDialog::getOpenFileName(parent, QObject::tr("Open session"), QString(),
                                      QObject::tr("Linkscape session (*.json)"));
}

QString ask_session_to_save(QWidget* parent, const QString& suggested) {
  return QFileDialog::getSaveFileName(parent, QObject::tr("Save session as"), suggested,
                                      QObject::tr("Linkscape session (*.json)"));
}

void add_recent_session(const QString& path) {
  QSettings settings;
  QStringList recent = settings.value("recentSessions").toStringList();
  const QString absolute = QFileInfo(path).absoluteFilePath();
  recent.removeAll(absolute);
  recent.prepend(absolute);
  while (recent.size() > 8) recent.removeLast();
  settings.setValue("recentSessions", recent);
}

void fill_recent_menu(QMenu* menu, QObject* context, const std::function<void(const QString&)>& open) {
  menu->clear();
  const QStringList recent = QSettings().value("recentSessions").toStringList();
  for (const QString& path : recent) menu->addAction(path, context, [open, path] { open(path); });
  menu->setEnabled(!recent.isEmpty());
}

}  // namespace linkscape::gui
