// File > Open mechanism and Reload mechanism: a preset file opens its device
// in the window's place; a file that does not load leaves the window and its
// device as they were and shows why in the error panel (with the file's
// path); fixing the file and reloading brings the file's device and hides
// the panel; a reload keeps the camera and the pose and takes the file's
// design; a change of the file on disk reloads by itself, also when an
// editor writes a new file over the old one. The presets are copies of the
// shipped Delta preset in a temporary folder, changed as a user would.
#include <QAction>
#include <QApplication>
#include <QDir>
#include <QElapsedTimer>
#include <QLabel>
#include <QPointer>
#include <QProgressDialog>
#include <QPushButton>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QUndoStack>
#include <QtTest>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>

#include <filesystem>
#include <functional>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/preset.h"
#include "gui/window/error_panel.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/session_history.h"
#include "gui/window/vtk_widget.h"
#include "gui/window/background.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

std::string shipped(const std::string& preset) {
  std::ifstream in(load_preset(preset).source);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The Delta preset with its "La": 8.0 replaced by `la` (any text, to break it).
std::string delta_with_la(const std::string& la) {
  std::string text = shipped("delta");
  const std::string key = "\"La\": 8.0";
  const auto at = text.find(key);
  if (at == std::string::npos) throw std::runtime_error("the shipped delta.json has no \"La\": 8.0");
  return text.replace(at, key.size(), "\"La\": " + la);
}

void write_file(const QString& path, const std::string& text) {
  std::ofstream out(path.toStdString(), std::ios::trunc);
  out << text;
}

// How editors save: a new file renamed over the old one.
void replace_file(const QString& path, const std::string& text) {
  write_file(path + ".new", text);
  std::filesystem::rename((path + ".new").toStdString(), path.toStdString());
}

// A window of `preset` as the program makes one: deleted when it closes.
MechanismWindow* open_window(const std::string& preset) {
  auto* w = new MechanismWindow(load_preset(preset));
  w->setAttribute(Qt::WA_DeleteOnClose);
  w->resize(1280, 800);
  w->show();
  return w;
}

bool settled(MechanismWindow* w) {
  return w && QTest::qWaitForWindowExposed(w) && QTest::qWaitFor([&] { return w->fieldsSettled(); }, 30000);
}

int visible_windows() {
  int n = 0;
  for (QWidget* t : QApplication::topLevelWidgets())
    if (qobject_cast<MechanismWindow*>(t) && t->isVisible()) ++n;
  return n;
}

void close_all() {
  for (QWidget* t : QApplication::topLevelWidgets())
    if (auto* w = qobject_cast<MechanismWindow*>(t); w && w->isVisible()) w->close();
  QCoreApplication::sendPostedEvents(nullptr, QEvent::DeferredDelete);
}

vtkCamera* camera(MechanismWindow* w) {
  return w->view()->renderWindow()->GetRenderers()->GetFirstRenderer()->GetActiveCamera();
}

Eigen::Vector3d camera_position(MechanismWindow* w) {
  double p[3];
  camera(w)->GetPosition(p);
  return {p[0], p[1], p[2]};
}

QAction* action(MechanismWindow* w, const QString& name) { return w->findChild<QAction*>(name); }

// The Delta preset at `path` (La = 8.0), opened from a 12R window through
// File > Open mechanism, shown and settled; nullptr if any of that failed.
MechanismWindow* delta_window(const QString& path) {
  write_file(path, delta_with_la("8.0"));
  MechanismWindow* first = open_window("parallel-12r");
  if (!settled(first)) return nullptr;
  MechanismWindow* w = first->openMechanismFile(path);
  return settled(w) ? w : nullptr;
}

}  // namespace

class WindowOpenTest : public QObject {
  Q_OBJECT

 private slots:
  void cleanup() { close_all(); }

  void openingAPresetFileSwitchesTheDevice() {
    QTemporaryDir dir;
    const QString path = dir.filePath("my-delta.json");
    write_file(path, delta_with_la("9.0"));
    QPointer<MechanismWindow> w = open_window("parallel-12r");
    QVERIFY(settled(w));
    QAction* open = action(w, "openMechanismAction");
    QVERIFY(open);
    QCOMPARE(open->shortcut(), QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_O));
    QVERIFY(!open->statusTip().isEmpty());

    MechanismWindow* next = w->openMechanismFile(path);
    QVERIFY(next && next != w);
    QVERIFY(settled(next));
    QCOMPARE(next->preset().mechanism, std::string("delta"));
    QCOMPARE(QString::fromStdString(next->preset().source.string()), path);
    QCOMPARE(next->mechanism().parameters().at("La"), 9.0);  // the file's design
    QVERIFY(!next->errorPanel()->isVisible());
    // A new document, as with any change of device.
    QVERIFY(next->history()->path().isEmpty());
    QVERIFY(!next->isWindowModified());
    QCOMPARE(next->history()->stack()->count(), 0);
    QVERIFY(w.isNull() || !w->isVisible());  // it made way
    QCOMPARE(visible_windows(), 1);
    // The title names the file and the device, not "Untitled"; a session saved takes its place.
    const QString title = next->windowTitle();
    QVERIFY2(title.startsWith("my-delta.json[*]"), qPrintable(title));
    QVERIFY2(title.contains(QString::fromStdString(next->preset().title)), qPrintable(title));
    QVERIFY2(!title.contains("Untitled"), qPrintable(title));
    QVERIFY(next->saveSession(dir.filePath("study.json")));
    QVERIFY2(next->windowTitle().startsWith("study.json[*]"), qPrintable(next->windowTitle()));
  }

  void aMalformedPresetLeavesTheDeviceAndSaysWhy_data() {
    QTest::addColumn<QString>("text");
    QTest::addColumn<QString>("named");  // what the message must name
    QTest::newRow("bad value") << QString::fromStdString(delta_with_la("-3.0")) << "La";
    QTest::newRow("unknown key") << QString::fromStdString(delta_with_la("8.0, \"Lc\": 2.0")) << "Lc";
    QTest::newRow("not JSON") << QString::fromStdString(delta_with_la("8.0,,")) << "parse";
  }

  void aMalformedPresetLeavesTheDeviceAndSaysWhy() {
    QFETCH(QString, text);
    QFETCH(QString, named);
    QTemporaryDir dir;
    const QString path = dir.filePath("broken.json");
    write_file(path, text.toStdString());
    QPointer<MechanismWindow> w = open_window("parallel-12r");
    QVERIFY(settled(w));
    QVERIFY(!w->errorPanel()->isVisible());
    Eigen::VectorXd moved = w->task();
    moved(0) += 1.0;
    QVERIFY(w->setTask(moved));
    w->history()->flush();
    const auto parameters = w->mechanism().parameters();
    const int steps = w->history()->stack()->count();
    const QString title = w->windowTitle();

    QCOMPARE(w->openMechanismFile(path), nullptr);
    QVERIFY(!w.isNull() && w->isVisible());
    QCOMPARE(visible_windows(), 1);
    // Nothing else changed: device, design, pose, history, title.
    QCOMPARE(w->preset().mechanism, std::string("parallel-12r"));
    QVERIFY(w->mechanism().parameters() == parameters);
    QVERIFY((w->task() - moved).norm() < 1e-12);
    QCOMPARE(w->history()->stack()->count(), steps);
    QCOMPARE(w->windowTitle(), title);
    // The panel is shown above the view, names the file and says what is wrong.
    QTest::qWait(50);  // its layout
    gui::ErrorPanel* panel = w->errorPanel();
    QVERIFY(panel->isVisible());
    QVERIFY(!panel->visibleRegion().isEmpty());
    QVERIFY(panel->mapTo(w, QPoint(0, 0)).y() < w->view()->mapTo(w, QPoint(0, 0)).y());
    QCOMPARE(panel->path(), path);
    const QString message = panel->findChild<QLabel*>("errorMessageLabel")->text();
    QVERIFY2(message.contains(path), qPrintable(message));  // load_preset's message names the file
    QVERIFY2(message.contains(named), qPrintable(message));
    QVERIFY(panel->text().contains(path));
    QVERIFY(panel->findChild<QLabel*>("errorMessageLabel")->textInteractionFlags() & Qt::TextSelectableByMouse);
    QVERIFY(w->statusBar()->currentMessage().contains(message));
    // Dismiss hides it; the window still has its device.
    QTest::mouseClick(panel->findChild<QPushButton*>("errorDismissButton"), Qt::LeftButton);
    QVERIFY(!panel->isVisible());
    QCOMPARE(w->preset().mechanism, std::string("parallel-12r"));
  }

  void fixingTheFileAndReloadingHidesThePanel() {
    QTemporaryDir dir;
    const QString path = dir.filePath("delta.json");
    QPointer<MechanismWindow> w = delta_window(path);
    QVERIFY(w);
    QAction* reload = action(w, "reloadMechanismAction");
    QVERIFY(reload);
    QCOMPARE(reload->shortcut(), QKeySequence(Qt::Key_F5));

    write_file(path, delta_with_la("8.0,"));  // a comma too many, as typed in an editor
    QCOMPARE(w->reloadMechanism(), nullptr);
    QVERIFY(w->isVisible());
    QCOMPARE(w->mechanism().parameters().at("La"), 8.0);  // the device in force stays
    QVERIFY(w->errorPanel()->isVisible());
    QCOMPARE(w->errorPanel()->path(), path);
    QVERIFY(w->errorPanel()->text().contains("Cannot reload"));
    // LINKSCAPE_SCREENSHOTS=<folder> keeps a picture of it (docs/images/window-mechanism-error.png).
    if (const QByteArray folder = qgetenv("LINKSCAPE_SCREENSHOTS"); !folder.isEmpty()) {
      if (const QByteArray size = qgetenv("LINKSCAPE_SCREENSHOT_WIDTH"); !size.isEmpty()) w->resize(size.toInt(), 700);
      QTest::qWait(200);  // the panel laid out, a frame drawn
      QVERIFY(gui::VtkWidget::grabWindow(w).save(QDir(QString::fromLocal8Bit(folder)).filePath("window-mechanism-error.png")));
    }

    // Fixed: the panel's Reload button reads it again.
    write_file(path, delta_with_la("9.5"));
    QPointer<MechanismWindow> next;
    connect(w, &MechanismWindow::replacedBy, this, [&](MechanismWindow* n) { next = n; });
    QTest::mouseClick(w->errorPanel()->findChild<QPushButton*>("errorReloadButton"), Qt::LeftButton);
    QVERIFY(next);
    QVERIFY(settled(next));
    QCOMPARE(next->mechanism().parameters().at("La"), 9.5);
    QVERIFY(!next->errorPanel()->isVisible());
    QCOMPARE(visible_windows(), 1);
  }

  void aReloadKeepsTheCameraAndThePose() {
    QTemporaryDir dir;
    const QString path = dir.filePath("delta.json");
    QPointer<MechanismWindow> w = delta_window(path);
    QVERIFY(w);
    camera(w)->Azimuth(25);  // the user turns the view
    camera(w)->Elevation(10);
    const Eigen::Vector3d seen_from = camera_position(w);
    Eigen::VectorXd moved = w->task();
    moved(0) += 0.8;
    moved(1) -= 0.5;
    QVERIFY(w->setTask(moved));
    const Eigen::VectorXd actuators = w->actuators();

    // The same file again: the same document, not modified.
    MechanismWindow* same = w->reloadMechanism();
    QVERIFY(same);
    QVERIFY(settled(same));
    QVERIFY((camera_position(same) - seen_from).norm() < 1e-9);
    QVERIFY((same->task() - moved).norm() < 1e-9);
    QVERIFY((same->actuators() - actuators).norm() < 1e-9);

    // A longer upper arm in the file: the file's design, the same view and task pose.
    write_file(path, delta_with_la("8.5"));
    MechanismWindow* next = same->reloadMechanism();
    QVERIFY(next);
    QVERIFY(settled(next));
    QCOMPARE(next->mechanism().parameters().at("La"), 8.5);
    QVERIFY2((camera_position(next) - seen_from).norm() < 1e-9, "the camera was refitted");
    QVERIFY((next->task() - moved).norm() < 1e-9);
    QVERIFY((next->actuators() - actuators).norm() > 1e-6);  // the same point, reached by another design
    QVERIFY(next->isWindowModified());                      // the design changed
    QVERIFY(next->history()->stack()->count() > 0);          // undo reaches back across the reload
    QVERIFY(next->history()->stack()->canUndo());
    QVERIFY(!next->errorPanel()->isVisible());
  }

  void anotherDeviceInTheFileStartsAtItsHome() {
    QTemporaryDir dir;
    const QString path = dir.filePath("delta.json");
    QPointer<MechanismWindow> w = delta_window(path);
    QVERIFY(w);
    Eigen::VectorXd moved = w->task();
    moved(2) += 1.0;
    QVERIFY(w->setTask(moved));
    const Eigen::Vector3d seen_from = camera_position(w);
    write_file(path, shipped("pathos2"));  // other task coordinates (a pose with a grip)
    MechanismWindow* next = w->reloadMechanism();
    QVERIFY(settled(next));
    QCOMPARE(next->preset().mechanism, std::string("pathos2"));
    QVERIFY((next->task() - next->mechanism().home_task()).norm() < 1e-9);
    QVERIFY((camera_position(next) - seen_from).norm() < 1e-9);  // the view stays, as with any reload
    QVERIFY(!next->errorPanel()->isVisible());
  }

  void anUnchangedReloadKeepsTheDocumentClean() {
    QTemporaryDir dir;
    const QString path = dir.filePath("delta.json");
    const QString session = dir.filePath("s.json");
    QPointer<MechanismWindow> w = delta_window(path);
    QVERIFY(w);
    QVERIFY(w->saveSession(session));
    QVERIFY(!w->isWindowModified());
    MechanismWindow* next = w->reloadMechanism();
    QVERIFY(settled(next));
    QCOMPARE(next->history()->path(), session);  // the document keeps its file
    QVERIFY(!next->isWindowModified());
  }

  void aChangeOnDiskReloadsByItself() {
    QTemporaryDir dir;
    const QString path = dir.filePath("delta.json");
    QPointer<MechanismWindow> w = delta_window(path);
    QVERIFY(w);
    // `change` writes the file; the window in `w`'s place once settled, or
    // nullptr when none came.
    auto reloaded_by_itself = [&](const std::function<void()>& change) -> MechanismWindow* {
      QPointer<MechanismWindow> next;
      connect(w, &MechanismWindow::replacedBy, this, [&](MechanismWindow* n) { next = n; });
      change();
      return QTest::qWaitFor([&] { return !next.isNull(); }, 5000) && settled(next) ? next.data() : nullptr;
    };

    w = reloaded_by_itself([&] { write_file(path, delta_with_la("9.0")); });  // written in place
    QVERIFY(w);
    QCOMPARE(w->mechanism().parameters().at("La"), 9.0);
    // Replaced as an editor saves: the new window still follows the file,
    w = reloaded_by_itself([&] { replace_file(path, delta_with_la("9.5")); });
    QVERIFY(w);
    QCOMPARE(w->mechanism().parameters().at("La"), 9.5);
    // and after that too: the watch was taken up on the new file.
    replace_file(path, delta_with_la("-2.0"));
    QVERIFY(QTest::qWaitFor([&] { return w->errorPanel()->isVisible(); }, 5000));  // a broken file: it says why
    QVERIFY(w->isVisible());                                                       // and stays
    QCOMPARE(w->mechanism().parameters().at("La"), 9.5);
    w = reloaded_by_itself([&] { replace_file(path, delta_with_la("10.0")); });
    QVERIFY(w);
    QCOMPARE(w->mechanism().parameters().at("La"), 10.0);
    QVERIFY(!w->errorPanel()->isVisible());
  }

  // Files are read and checked on a worker thread (a hostile description
  // once held the GUI thread for minutes): the window's timers keep running.
  void slowWorkRunsOffTheGuiThreadWhileTheWindowKeepsGoing() {
    int ticks = 0;
    QTimer tick;
    connect(&tick, &QTimer::timeout, [&] { ++ticks; });
    tick.start(10);
    std::thread::id worker;
    gui::run_off_gui_thread([&] {
      worker = std::this_thread::get_id();
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
    });
    QVERIFY(worker != std::this_thread::get_id());
    QVERIFY2(ticks >= 5, qPrintable(QString("the GUI thread ran %1 timer ticks in 300 ms").arg(ticks)));
    // Errors come back to the caller, as from the work itself.
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument,
                             gui::run_off_gui_thread([] { throw std::invalid_argument("a bad file"); }));
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, gui::load_checked_preset("/no/such/preset.json"));
    QCOMPARE(gui::load_checked_preset("delta").mechanism, std::string("delta"));
  }

  // Work that outlasts a moment shows a dialog whose Cancel hands the window
  // back at once, even when the work itself never looks at the flag.
  void cancellingASlowReadReturnsAtOnce() {
    auto stopped = std::make_shared<std::atomic<bool>>(false);
    QTimer clicker;  // presses Cancel as soon as the dialog is up
    connect(&clicker, &QTimer::timeout, [] {
      for (QWidget* w : QApplication::topLevelWidgets())
        if (auto* dialog = qobject_cast<QProgressDialog*>(w); dialog && dialog->isVisible())
          dialog->findChild<QPushButton*>()->click();
    });
    clicker.start(20);
    QElapsedTimer clock;
    clock.start();
    QVERIFY_THROWS_EXCEPTION(gui::Cancelled, gui::run_off_gui_thread(
                                                 [stopped] {
                                                   std::this_thread::sleep_for(std::chrono::seconds(3));
                                                   *stopped = true;
                                                 },
                                                 "Reading a slow file"));
    const qint64 waited = clock.elapsed();
    QVERIFY2(waited >= gui::kDialogAfterMs && waited < 2000, qPrintable(QString("returned after %1 ms").arg(waited)));
    QVERIFY(!*stopped);  // the work runs on, unwaited, and ends by itself
    QVERIFY(QTest::qWaitFor([&] { return stopped->load(); }, 10000));
    // Work that polls the flag sees the Cancel.
    auto saw = std::make_shared<std::atomic<bool>>(false);
    QVERIFY_THROWS_EXCEPTION(gui::Cancelled, gui::wait_off_gui_thread([saw](const std::atomic<bool>& cancelled) {
      while (!cancelled) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      *saw = true;
    }));
    QVERIFY(QTest::qWaitFor([&] { return saw->load(); }, 5000));
  }
};

QTEST_MAIN(WindowOpenTest)
#include "test_window_open.moc"
