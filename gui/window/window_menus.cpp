#include "gui/window/window_menus.h"

#include <QAction>
#include <QApplication>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QKeyEvent>
#include <QLabel>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QUndoStack>
#include <algorithm>
#include <cstdlib>
#include <functional>
#include <vector>
#include <iostream>
#include <memory>

#include "gui/window/documentation.h"
#include "gui/window/help_actions.h"
#include "gui/window/view_tools.h"

namespace linkscape::gui {

namespace {

// A spin box keeps Undo and Redo for its text even once the text is
// entered: then the window's Undo and Redo (of the value entered) take the
// keys; while a value is being typed, the box keeps them.
class EditKeysToWindow : public QObject {
 public:
  using QObject::QObject;

 protected:
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (event->type() != QEvent::ShortcutOverride) return false;
    auto* box = qobject_cast<QDoubleSpinBox*>(watched);
    if (!box && watched->parent()) box = qobject_cast<QDoubleSpinBox*>(watched->parent());
    if (!box || box->cleanText() != box->textFromValue(box->value())) return false;
    const auto* key = static_cast<QKeyEvent*>(event);
    // Left unaccepted, the override lets the window's shortcut have the key.
    return key->matches(QKeySequence::Undo) || key->matches(QKeySequence::Redo) ||
           key->keyCombination() == QKeyCombination(Qt::CTRL, Qt::Key_Y);
  }
};

// The View menu's checkable actions, its submenus' too, without the docks' toggles.
std::vector<QAction*> toggles_of(const QMainWindow* window) {
  std::vector<QAction*> out;
  const QMenu* view = window->findChild<QMenu*>("viewMenu");
  if (!view) return out;
  std::vector<const QAction*> docks;
  for (const QDockWidget* dock : window->findChildren<QDockWidget*>()) docks.push_back(dock->toggleViewAction());
  std::function<void(const QMenu*)> walk = [&](const QMenu* menu) {
    for (QAction* a : menu->actions()) {
      if (a->menu()) walk(a->menu());
      else if (a->isCheckable() && std::find(docks.begin(), docks.end(), a) == docks.end()) out.push_back(a);
    }
  };
  walk(view);
  return out;
}

QAction* add(QMenu* menu, const QString& text, const QKeySequence& key, QObject* context,
             const std::function<void()>& run) {
  QAction* a = menu->addAction(text, context, run);
  if (!key.isEmpty()) a->setShortcut(key);
  return a;
}

}  // namespace

void add_menus(QMainWindow* window, const MenuActions& actions) {
  QMenu* file = window->menuBar()->addMenu(QObject::tr("&File"));
  add(file, QObject::tr("&Open session…"), QKeySequence::Open, window, actions.open_session);
  add(file, QObject::tr("&Save session"), QKeySequence::Save, window, actions.save);
  // Explicit: QKeySequence::SaveAs is empty on plain X11.
  add(file, QObject::tr("Save session &as…"), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_S), window, actions.save_as);
  actions.recent_sessions(file->addMenu(QObject::tr("Recent sessions")));
  file->addSeparator();
  QAction* open_mechanism = add(file, QObject::tr("Open &mechanism…"), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_O),
                                window, actions.open_mechanism);
  open_mechanism->setObjectName("openMechanismAction");
  open_mechanism->setStatusTip(
      QObject::tr("Open a device from its preset file (.json), a shipped one or a described mechanism"));
  QAction* reload =
      add(file, QObject::tr("&Reload mechanism"), QKeySequence(Qt::Key_F5), window, actions.reload_mechanism);
  reload->setObjectName("reloadMechanismAction");
  reload->setStatusTip(QObject::tr("Read the preset file again (done by itself when the file changes): the design "
                                   "is the file's; the camera, the pose, the field and task settings stay"));
  file->addSeparator();
  add(file, QObject::tr("Export slice &image…"), {}, window, actions.export_slice);
  add(file, QObject::tr("Export workspace &mesh…"), {}, window, actions.export_mesh);
  add(file, QObject::tr("Export &field (VTI)…"), {}, window, actions.export_field);
  QAction* model = add(file, QObject::tr("Export m&odel (MuJoCo MJCF)…"), {}, window, actions.export_model);
  model->setObjectName("exportModelAction");
  model->setStatusTip(QObject::tr("The design as a MuJoCo model: legs as body chains welded to the platform, "
                                  "motors on the actuators (docs/model-export.md)"));
  add(file, QObject::tr("Export s&cene (glTF)…"), {}, window, actions.export_scene)
      ->setStatusTip(QObject::tr("The 3-D view's meshes with their colours, for presentation tools"));
  add(file, QObject::tr("Save screens&hot…"), {}, window, actions.save_screenshot);
  add(file, QObject::tr("Save &view image…"), {}, window, actions.save_view_image);
  file->addSeparator();
  // Explicit keys where Qt's standard ones depend on the desktop (empty on plain X11).
  add(file, QObject::tr("&Quit"), QKeySequence(Qt::CTRL | Qt::Key_Q), window, [window] { window->close(); });

  QMenu* edit = window->menuBar()->addMenu(QObject::tr("&Edit"));
  QAction* undo = actions.undo_stack->createUndoAction(window, QObject::tr("&Undo"));
  undo->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_Z));
  qApp->installEventFilter(new EditKeysToWindow(window));  // removed with the window
  QAction* redo = actions.undo_stack->createRedoAction(window, QObject::tr("&Redo"));
  // Both common keys: Qt's standard one on X11 is Ctrl+Shift+Z only.
  redo->setShortcuts({QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_Z), QKeySequence(Qt::CTRL | Qt::Key_Y)});
  edit->addAction(undo);
  edit->addAction(redo);

  QMenu* view = window->menuBar()->addMenu(QObject::tr("&View"));
  view->setObjectName("viewMenu");  // sessions find its toggles here (view_toggles)
  add(view, QObject::tr("&Reset camera"), {}, window, actions.reset_camera);
  add(view, QObject::tr("Reset &layout"), {}, window, actions.reset_layout);
  view->addSeparator();
  if (actions.view_tools) actions.view_tools(view);
  view->addSeparator();
  for (QDockWidget* dock : window->findChildren<QDockWidget*>()) {
    view->addAction(dock->toggleViewAction());
    // A panel brought back comes to the front of its tabs.
    QObject::connect(dock->toggleViewAction(), &QAction::triggered, dock, [dock](bool on) {
      if (on) dock->raise();
    });
  }
  view->addSeparator();
  // Depth peeling composites the translucent surfaces exactly but costs
  // several full-screen passes per frame (docs/performance.md), so
  // interaction uses plain alpha blending unless the user asks.
  QAction* exact = view->addAction(QObject::tr("&Exact transparency (slower)"));
  exact->setObjectName("exactTransparencyAction");
  exact->setCheckable(true);
  QObject::connect(exact, &QAction::toggled, window, actions.exact_transparency);
  // The status bar's compute and frame times (gui/window/docks.h), hidden by default.
  QAction* timings = view->addAction(QObject::tr("Show &timings"));
  timings->setObjectName("showTimingsAction");
  timings->setCheckable(true);
  QObject::connect(timings, &QAction::toggled, window, [window](bool on) {
    for (const char* name : {"computeLabel", "frameLabel"})
      if (auto* label = window->findChild<QLabel*>(name)) label->setVisible(on);
  });

  QMenu* help = window->menuBar()->addMenu(QObject::tr("&Help"));
  add(help, QObject::tr("&Documentation"), QKeySequence(Qt::Key_F1), window, [window] { show_documentation(window); })
      ->setObjectName("documentationAction");
  add(help, QObject::tr("&Keyboard shortcuts"), {}, window,
      [window] { show_shortcuts(window, window->menuBar()); })
      ->setObjectName("shortcutsAction");
  help->addAction(QObject::tr("About this &mechanism…"), window, actions.about_mechanism)
      ->setObjectName("aboutMechanismAction");
  help->addAction(QObject::tr("&About Linkscape"), window, [window] { show_about(window); });
}

std::map<std::string, bool> view_toggles(const QMainWindow* window) {
  std::map<std::string, bool> out;
  for (const QAction* a : toggles_of(window))
    if (!a->objectName().isEmpty()) out[a->objectName().toStdString()] = a->isChecked();
  return out;
}

QStringList apply_view_toggles(QMainWindow* window, const std::map<std::string, bool>& toggles) {
  const std::vector<QAction*> actions = toggles_of(window);
  QStringList unknown;
  for (const auto& [name, on] : toggles) {
    const auto it = std::find_if(actions.begin(), actions.end(),
                                 [&name = name](const QAction* a) { return a->objectName().toStdString() == name; });
    if (it == actions.end()) unknown << QString::fromStdString(name);
    else (*it)->setChecked(on);  // toggled runs its effect
  }
  return unknown;
}

std::unique_ptr<QMainWindow> window_with_menus() {
  auto window = std::make_unique<QMainWindow>();
  MenuActions none;
  none.undo_stack = new QUndoStack(window.get());
  none.recent_sessions = [](QMenu*) {};
  none.view_tools = [](QMenu* menu) { ViewTools::addViewMenu(menu); };
  add_menus(window.get(), none);
  return window;
}

int print_shortcuts(int argc, char** argv) {
  // Off-screen: the table needs no display, only the menus.
  setenv("QT_QPA_PLATFORM", "offscreen", 1);
  QApplication app(argc, argv);
  std::cout << shortcut_table(window_with_menus()->menuBar()).toStdString();
  return 0;
}

}  // namespace linkscape::gui
