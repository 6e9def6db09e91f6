// The window's menu bar: File (sessions; the mechanism; exports; Quit),
// Edit (undo, redo), View (camera, layout, the docks, transparency) and
// Help. Each entry runs the action the window hands it: the window's own
// or one of the actions of file_actions.h, mechanism_actions.h,
// export_actions.h and help_actions.h.
#pragma once

#include <QStringList>
#include <functional>
#include <map>
#include <memory>
#include <string>

class QMainWindow;
class QMenu;
class QUndoStack;

namespace linkscape::gui {

struct MenuActions {
  std::function<void()> open_session, save, save_as;
  std::function<void(QMenu*)> recent_sessions;  // fills the submenu
  std::function<void()> open_mechanism, reload_mechanism;
  std::function<void()> export_slice, export_mesh, export_field, export_model, export_scene, save_screenshot,
      save_view_image;
  QUndoStack* undo_stack = nullptr;
  std::function<void()> reset_camera, reset_layout;
  std::function<void(QMenu*)> view_tools;  // the standard views, projection, framing
  std::function<void(bool)> exact_transparency;
  std::function<void()> about_mechanism;
};

// The menus of `window` (its docks' toggles from the docks it has now).
void add_menus(QMainWindow* window, const MenuActions& actions);

// The View menu's checkable toggles (labels in front, smoothing, parallel
// projection, timings, ...) by their actions' object names, and back: what
// sessions keep, so a toggle added to the menu with an object name is kept
// without more code. The docks' toggles are the layout's and left out.
// apply_view_toggles sets the toggles the window has (each runs as if
// clicked) and returns the names it has no toggle for.
std::map<std::string, bool> view_toggles(const QMainWindow* window);
QStringList apply_view_toggles(QMainWindow* window, const std::map<std::string, bool>& toggles);

// A window with the menus alone, their entries doing nothing.
std::unique_ptr<QMainWindow> window_with_menus();

// linkscape --shortcuts: the window's menus built off-screen and their table
// printed (the manual page's WINDOW section is made from it).
int print_shortcuts(int argc, char** argv);

}  // namespace linkscape::gui
