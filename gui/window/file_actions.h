// The File menu's session actions, usable without a window: read a session
// and its device's preset, save one, ask for their files, and the list of
// recent sessions. Failures are shown in a message box.
#pragma once

#include <QString>
#include <functional>

#include "core/preset.h"
#include "gui/window/session.h"

class QMainWindow;
class QMenu;
class QObject;
class QWidget;

namespace linkscape::gui {

// Reads the session at `path` and its device's preset (off the GUI thread)
// and hands both to `open`, which applies them (it may throw
// std::invalid_argument: nothing opened). True when it was opened; the
// status bar of `window` says so.
bool open_session_file(QMainWindow* window, const QString& path,
                       const std::function<void(const Session&, const Preset&)>& open);
bool save_session_file(QMainWindow* window, const Session& session, const QString& path);

// The session file the user picks to open, or to save as (`suggested`
// first); empty when cancelled.
QString ask_session_to_open(QWidget* parent);
QString ask_session_to_save(QWidget* parent, const QString& suggested);

// The recent sessions (kept in the settings, newest first, at most 8).
void add_recent_session(const QString& path);
// `menu` lists them; picking one calls `open` with its path.
void fill_recent_menu(QMenu* menu, QObject* context, const std::function<void(const QString&)>& open);

}  // namespace linkscape::gui
