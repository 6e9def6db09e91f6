// The window as a document: its session file and undo/redo history
// (SessionHistory, one step per drag: it watches the window's mouse
// buttons), the modified mark in the title, Save and Save As (Ctrl+Shift+S
// where no menu action has that key), asking before unsaved work is
// discarded, the recent sessions; and where the camera was last fitted to
// the device (a camera nobody moved since follows the device's size).
//
// Only valid input is kept: criteria the Task tab rejects stay in its box
// but the document keeps the last valid ones; the Fit tab's settings are
// part of the document (FitPanel::setting, which keeps the last valid Hold
// equal groups and centre region). Its last result and the View menu's
// toggles are saved with it and set again when a session opens
// (apply_window_session), but make no undo step.
#pragma once

#include <QObject>
#include <QString>
#include <functional>
#include <optional>

#include "core/preset.h"
#include "gui/window/session.h"

class QEvent;
class QMainWindow;
class QMenu;

namespace linkscape::gui {

class SessionHistory;

// What an opened session sets beyond the device, the pose and the panels
// the window restores itself: the Fit tab's settings and last result and the
// View menu's toggles (window_menus.h). A part the window cannot take is
// said in its status bar.
void apply_window_session(QMainWindow* window, const Session& session);

class WindowDocument : public QObject {
 public:
  struct Hooks {
    std::function<Session()> capture;             // the window's state as a session
    std::function<void(const Session&)> restore;  // undo and redo
    // A session read from `path` with its device's preset: applied, or
    // opened in a window of its own. May throw std::invalid_argument.
    std::function<void(const Session&, const Preset&, const QString& path)> open;
    std::function<QString()> device_title;  // for the window's title
    // The device's preset file (empty: none): the title names it while the
    // document has no session file.
    std::function<QString()> device_file;
  };
  WindowDocument(QMainWindow* window, Hooks hooks);

  SessionHistory* history() const { return history_; }
  // Interactive: asks before unsaved work is discarded. Off in tests,
  // screenshots and latency runs, which never wait for a dialog.
  void setInteractive(bool on) { interactive_ = on; }
  bool interactive() const { return interactive_; }
  // Asks to save unsaved changes (only when interactive); false: the user cancelled.
  bool maybeSave();
  // Before File > Reload mechanism replaces a design changed since the
  // document was opened or saved: asks whether to reload (only when
  // interactive); false: the user keeps the window as it is. The changes
  // stay in the undo history (SessionHistory::adopt) either way.
  bool mayReload();
  bool save();    // to the document's file, else as Save As
  bool saveAs();  // asks for the file
  bool saveSession(const QString& path);
  bool openSession(const QString& path);
  // `menu` lists the recent sessions (and again whenever they change).
  void setRecentMenu(QMenu* menu);
  void updateTitle();
  // The window closes: an interactive one remembers its size and panel layout.
  void closing();

  // The camera as fitted to the device; whether `now` is still there.
  void cameraFitted(const CameraState& fitted) { fitted_camera_ = fitted; }
  bool cameraUntouched(const CameraState& now) const;

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  void addRecent(const QString& path);

  QMainWindow* window_;
  Hooks hooks_;
  SessionHistory* history_;
  QMenu* recent_menu_ = nullptr;
  bool interactive_ = false;
  std::optional<CameraState> fitted_camera_;
};

}  // namespace linkscape::gui
