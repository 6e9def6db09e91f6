// The window as a document and a view: undo/redo of every change, Save and
// Save As with the modified mark, the camera following the device's size,
// the colour range shown, the slice position kept relative, and the View
// menu's panels. Numbers come from the window's own state, not literals.
#include <QAction>
#include <QCheckBox>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QMenuBar>
#include <QRegularExpression>
#include <QSlider>
#include <QTemporaryDir>
#include <QUndoStack>
#include <QWindow>
#include <QStatusBar>
#include <QtTest>
#include <sstream>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>

#include "core/preset.h"
#include "gui/window/help_actions.h"
#include "gui/window/latency_probe.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/session.h"
#include "gui/window/session_history.h"
#include "settled.h"
#include "gui/window/task_panel.h"
#include "gui/window/view_handles.h"
#include "gui/window/vtk_widget.h"
#include "render/field_scene.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

using window_tests::show_settled;

QAction* action(MechanismWindow& w, const QString& text) {
  for (QAction* a : w.findChildren<QAction*>())
    if (a->text() == text) return a;
  return nullptr;
}

vtkRenderer* renderer_of(MechanismWindow& w) { return w.view()->renderWindow()->GetRenderers()->GetFirstRenderer(); }

Eigen::Vector3d camera_position(MechanismWindow& w) {
  double p[3];
  renderer_of(w)->GetActiveCamera()->GetPosition(p);
  return {p[0], p[1], p[2]};
}

// The "(NN %)" of the slice position label.
int position_percent(MechanismWindow& w) {
  const QString text = w.findChild<QLabel*>("positionLabel")->text();
  const auto m = QRegularExpression("\\((-?\\d+) %\\)").match(text);
  return m.hasMatch() ? m.captured(1).toInt() : -1000;
}

}  // namespace

class WindowDocumentTest : public QObject {
  Q_OBJECT

 private slots:
  // The view is a native window inside the main one: with it focused,
  // keys still reach the window's shortcuts (here Undo).
  void shortcutsWorkWithTheViewFocused() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    w.activateWindow();
    const double l1 = w.mechanism().parameters().at("L1");
    QVERIFY(w.setParameters({{"L1", l1 + 2}}));
    w.history()->flush();
    QCOMPARE(w.history()->stack()->count(), 1);
    QWindow* view = w.view()->nativeWindow();
    w.view()->setFocus();
    QTRY_VERIFY(QGuiApplication::focusWindow() == view || w.view()->hasFocus() ||
                (QApplication::focusWidget() && w.view()->isAncestorOf(QApplication::focusWidget())));
    QTest::keyClick(view, Qt::Key_Z, Qt::ControlModifier);
    QTRY_COMPARE(w.mechanism().parameters().at("L1"), l1);
  }

  // A value typed into a spin box and entered is undone by Ctrl+Z there and
  // then, and redone by Ctrl+Y or Ctrl+Shift+Z (the box had kept the keys for
  // its own text).
  void undoAndRedoKeysWorkInASpinBox() {
    MechanismWindow w(load_preset("delta"));
    QVERIFY(show_settled(w));
    w.activateWindow();
    auto* box = w.findChild<QDoubleSpinBox*>("xBox");
    QVERIFY(box && box->isVisible());
    const double x0 = w.task()(0);
    box->setFocus();
    QTRY_VERIFY(box->hasFocus());
    box->selectAll();
    QTest::keyClicks(box, "1.5");
    QTest::keyClick(box, Qt::Key_Return);
    QTRY_VERIFY(std::abs(w.task()(0) - 1.5) < 1e-9);
    w.history()->flush();
    QTest::keyClick(box, Qt::Key_Z, Qt::ControlModifier);
    QTRY_VERIFY(std::abs(w.task()(0) - x0) < 1e-9);
    QTest::keyClick(box, Qt::Key_Y, Qt::ControlModifier);
    QTRY_VERIFY(std::abs(w.task()(0) - 1.5) < 1e-9);
    QTest::keyClick(box, Qt::Key_Z, Qt::ControlModifier);
    QTRY_VERIFY(std::abs(w.task()(0) - x0) < 1e-9);
    QTest::keyClick(box, Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
    QTRY_VERIFY(std::abs(w.task()(0) - 1.5) < 1e-9);
  }

  void undoAndRedoEveryKindOfChange() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    QUndoStack* stack = w.history()->stack();
    QCOMPARE(stack->count(), 0);
    QVERIFY(!w.isWindowModified());
    const double l1 = w.mechanism().parameters().at("L1");
    const Eigen::VectorXd task = w.task();

    QVERIFY(w.setParameters({{"L1", l1 + 2}}));
    w.history()->flush();
    QCOMPARE(stack->count(), 1);
    QCOMPARE(stack->undoText(), QString("L1"));
    QVERIFY(w.isWindowModified());

    const Eigen::VectorXd after_l1 = w.task();
    Eigen::VectorXd moved = after_l1;
    moved(0) += 1.0;
    QVERIFY(w.setTask(moved));
    w.history()->flush();
    QCOMPARE(stack->count(), 2);
    QCOMPARE(stack->undoText(), QString("pose"));

    w.findChild<QComboBox*>("normalBox")->setCurrentText("y");
    w.history()->flush();
    QCOMPARE(stack->count(), 3);
    QCOMPARE(stack->undoText(), QString("field settings"));

    // A settle with nothing new adds no step.
    w.history()->flush();
    QCOMPARE(stack->count(), 3);

    stack->undo();
    QCOMPARE(w.fieldSettings().normal, std::string("x"));
    stack->undo();
    QVERIFY((w.task() - after_l1).norm() < 1e-9);
    stack->undo();
    QCOMPARE(w.mechanism().parameters().at("L1"), l1);
    QVERIFY((w.task() - task).norm() < 1e-9);
    QVERIFY(!w.isWindowModified());  // back where the document started

    stack->redo();
    QCOMPARE(w.mechanism().parameters().at("L1"), l1 + 2);
    stack->redo();
    stack->redo();
    QCOMPARE(w.fieldSettings().normal, std::string("y"));
    QVERIFY((w.task() - moved).norm() < 1e-9);
    // Field results arriving after a redo add no step and keep the redo-able state.
    QVERIFY(QTest::qWaitFor([&] { return w.fieldsSettled(); }, 30000));
    QTest::qWait(gui::SessionHistory::kSettleMs + 100);
    QCOMPARE(stack->count(), 3);
    QCOMPARE(stack->index(), 3);
  }

  void saveAndSaveAsMarkTheDocument() {
    QTemporaryDir dir;
    const QString path = dir.filePath("design.json");
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    QVERIFY2(w.windowTitle().startsWith("parallel-12r.json[*]"), qPrintable(w.windowTitle()));  // the preset's file
    QVERIFY(w.setParameters({{"L2", 17.0}}));
    w.history()->flush();
    QVERIFY(w.isWindowModified());
    QVERIFY(w.saveSession(path));  // what Save As does once the file is chosen
    QVERIFY(!w.isWindowModified());
    QCOMPARE(w.history()->path(), path);
    QVERIFY(w.windowTitle().startsWith("design.json[*]"));
    // Save writes to the same file without asking.
    QVERIFY(w.setParameters({{"L2", 18.0}}));
    QAction* save = action(w, "&Save session");
    QVERIFY(save);
    QCOMPARE(save->shortcut(), QKeySequence(QKeySequence::Save));
    save->trigger();
    QVERIFY(!w.isWindowModified());
    QCOMPARE(gui::load_session(path.toStdString()).parameters.at("L2"), 18.0);
    QVERIFY(action(w, "Save session &as…"));
  }

  // Motor ratings given as parameters are part of the design a session keeps.
  void motorRatingsAsParametersAreSaved() {
    QTemporaryDir dir;
    const QString path = dir.filePath("rated.json");
    Preset preset = load_preset("delta");
    apply_overrides(preset, {"continuous_torque_Nm=0.3", "gear_ratio=2"});
    MechanismWindow w(preset);
    QVERIFY(show_settled(w));
    QVERIFY(w.setParameters({{"La", 8.5}}));
    QVERIFY(w.saveSession(path));
    const gui::Session saved = gui::load_session(path.toStdString());
    QCOMPARE(saved.parameters.at("continuous_torque_Nm"), 0.3);
    QCOMPARE(saved.parameters.at("gear_ratio"), 2.0);
    QCOMPARE(saved.parameters.at("La"), 8.5);
  }

  // Help > About this mechanism: how the device in the window is solved.
  void aboutThisMechanismSaysHowTheDeviceIsSolved() {
    // The menu is there at once; the Falcon's fields (legs with stops and
    // links) need not be finished for it.
    MechanismWindow w(load_preset("falcon"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    QVERIFY(w.findChild<QAction*>("aboutMechanismAction"));
    const std::string falcon = gui::mechanism_summary(w.preset());
    QVERIFY(falcon.find("leg 1: crank-parallelogram") != std::string::npos);
    QVERIFY(falcon.find("travel -60 .. 105 deg") != std::string::npos);
    const std::string stewart = gui::mechanism_summary(load_preset("stewart"));
    QVERIFY(stewart.find("extensible") != std::string::npos);
    QVERIFY(gui::mechanism_summary(load_preset("delta")).find("compiled in C++") != std::string::npos);
  }

  void theCameraFollowsTheSizeUntilTheUserMovesIt() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    const Eigen::Vector3d before = camera_position(w);
    QVERIFY(w.setParameters({{"L1", 24.0}, {"L2", 24.0}}));
    const Eigen::Vector3d refit = camera_position(w);
    QVERIFY((refit - before).norm() > 1.0);  // a larger device, a camera further out
    w.fitCamera();
    QVERIFY((camera_position(w) - refit).norm() < 1e-9);  // it was the fitted camera
    renderer_of(w)->GetActiveCamera()->Azimuth(30);     // the user moves it
    const Eigen::Vector3d moved = camera_position(w);
    QVERIFY(w.setParameters({{"L1", 12.0}, {"L2", 12.0}}));
    QVERIFY((camera_position(w) - moved).norm() < 1e-9);
  }

  void theColourRangeBoxesShowTheRangeInUse() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    auto* lo = w.findChild<QDoubleSpinBox*>("rangeMinBox");
    auto* hi = w.findChild<QDoubleSpinBox*>("rangeMaxBox");
    const auto range = w.fieldScene().colour_bar_range();
    QVERIFY(range);
    QVERIFY(!lo->isEnabled() && !hi->isEnabled());
    QVERIFY(std::abs(lo->value() - (*range)[0]) <= 0.5e-3 + 1e-12);
    QVERIFY(std::abs(hi->value() - (*range)[1]) <= 0.5e-3 + 1e-12);
  }

  void theColourMapIsSavedAndUndone() {
    QTemporaryDir dir;
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    w.findChild<QComboBox*>("colourMapBox")->setCurrentText("cividis");
    w.findChild<QCheckBox*>("logScaleBox")->setChecked(false);
    QCOMPARE(w.fieldSettings().colour_map, std::string("cividis"));
    QVERIFY(w.saveSession(dir.filePath("s.json")));
    const gui::Session saved = gui::load_session(dir.filePath("s.json").toStdString());
    QCOMPARE(saved.field.colour_map, std::string("cividis"));
    QCOMPARE(saved.field.log_scale, false);
    w.history()->stack()->undo();
    QCOMPARE(w.fieldSettings().colour_map, std::string("viridis"));
    QCOMPARE(w.fieldSettings().log_scale, true);
  }

  void theTaskVolumeIsPartOfTheDocument() {
    QTemporaryDir dir;
    const QString path = dir.filePath("task.json");
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    w.taskPanel()->setTask("sphere:diameter=10,centre=0,15,15", {"cond<3"});
    w.history()->flush();
    QCOMPARE(w.history()->stack()->undoText(), QString("task volume"));
    QVERIFY(w.saveSession(path));
    const gui::Session saved = gui::load_session(path.toStdString());
    QVERIFY(saved.task_volume);
    QCOMPARE(saved.task_volume->volume, std::string("sphere:diameter=10,centre=0,15,15"));
    QCOMPARE(saved.task_volume->criteria, std::vector<std::string>{"cond<3"});
    MechanismWindow other(load_preset("parallel-12r"));
    QVERIFY(other.openSession(path));
    QCOMPARE(other.taskPanel()->setting(), *saved.task_volume);
    w.history()->stack()->undo();
    QVERIFY(!(w.taskPanel()->setting() == *saved.task_volume));
  }

  void theSlicePositionIsKeptRelative() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    const int percent = position_percent(w);
    QVERIFY(percent >= 0 && percent <= 100);
    QVERIFY(w.setParameters({{"L1", 22.0}}));
    QVERIFY(QTest::qWaitFor([&] { return w.fieldsSettled(); }, 30000));
    QCOMPARE(position_percent(w), percent);
  }

  void theViewMenuBringsBackEveryPanel() {
    MechanismWindow w(load_preset("delta"));
    QVERIFY(show_settled(w));
    const QList<QDockWidget*> docks = w.findChildren<QDockWidget*>();
    QVERIFY(docks.size() >= 5);
    for (QDockWidget* dock : docks) QVERIFY2(action(w, dock->windowTitle()), qPrintable(dock->windowTitle()));
    for (QDockWidget* dock : docks) dock->close();
    action(w, "Reset &layout")->trigger();
    for (QDockWidget* dock : docks) QVERIFY(dock->isVisible());
    // One panel closed and brought back from the menu comes to the front of its tabs.
    QDockWidget* field = w.findChild<QDockWidget*>("fieldDock");
    QVERIFY(field);
    field->close();
    field->toggleViewAction()->trigger();
    QTRY_VERIFY(field->isVisible() && !field->visibleRegion().isEmpty());
  }

  // A planar device's plane is not a freedom: the five-bar has x and y sliders, no z.
  void aPlanarDeviceHasNoOutOfPlaneSlider() {
    MechanismWindow w(load_preset("five-bar"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    for (const char* name : {"xSlider", "ySlider"}) {
      auto* slider = w.findChild<QSlider*>(name);
      QVERIFY2(slider && slider->isVisible(), name);
    }
    auto* z = w.findChild<QSlider*>("zSlider");
    QVERIFY(z && !z->isVisible());
    MechanismWindow spatial(load_preset("delta"));  // a spatial device keeps its z
    spatial.show();
    QVERIFY(QTest::qWaitForWindowExposed(&spatial));
    auto* delta_z = spatial.findChild<QSlider*>("zSlider");
    QVERIFY(delta_z && delta_z->isVisible());
  }

  // The handle on the driven point moves in a plane facing the camera; on a
  // planar device a drag asks for the point where the line of sight through
  // the handle meets the device's plane (the five-bar had refused every
  // drag that left z = 0).
  void aPlanarDevicesHandleIsDraggedInItsPlane() {
    MechanismWindow w(load_preset("five-bar"));
    QVERIFY(show_settled(w));
    const double plane = *w.mechanism().info().plane_z;
    vtkCamera* camera = w.view()->renderWindow()->GetRenderers()->GetFirstRenderer()->GetActiveCamera();
    Eigen::Vector3d eye;
    camera->GetPosition(eye.data());
    const Eigen::Vector3d x = w.endpoint();
    const Eigen::Vector3d handle = x + Eigen::Vector3d(0.5, -0.4, 0.3);  // off the plane, as a drag puts it
    const std::optional<Eigen::Vector3d> target = w.handles().inPlane(handle);
    QVERIFY(target);
    QCOMPARE(target->z(), plane);
    QVERIFY((target->head<3>() - eye).normalized().cross((handle - eye).normalized()).norm() < 1e-9);
    QVERIFY2(w.moveEndpointTo(*target), qPrintable(w.refusal()));
    QVERIFY((w.endpoint() - *target).norm() < 1e-9 * w.mechanism().size());
    // Seen along the plane (the front view, the eye in the plane), no line
    // of sight crosses it: the handle's point is dropped onto the plane, in
    // perspective and in parallel projection.
    QAction* front = action(w, "&Front view");
    QVERIFY(front);
    front->trigger();
    for (const bool parallel : {false, true}) {
      camera->SetParallelProjection(parallel);
      const Eigen::Vector3d above = w.endpoint() + Eigen::Vector3d(0.4, 0, 0.5);
      const std::optional<Eigen::Vector3d> dropped = w.handles().inPlane(above);
      QVERIFY(dropped);
      QCOMPARE(dropped->z(), plane);
      QVERIFY((dropped->head<2>() - above.head<2>()).norm() < 1e-12);
    }
  }

  // A planar device's field is the same at every height: its slice is taken
  // in the plane (no position to choose) and drawn below the linkage's rods,
  // not through them; a spatial device's slice lies where it was sampled.
  void aPlanarDevicesSliceLiesBelowItsLinkage() {
    MechanismWindow w(load_preset("five-bar"));
    QVERIFY(show_settled(w));
    QVERIFY(w.fieldScene().slice_visible());
    const double plane = *w.mechanism().info().plane_z;
    QCOMPARE(w.fieldSettings().position, plane);
    QVERIFY(!w.findChild<QSlider*>("positionSlider")->isEnabled());
    QVERIFY(w.findChild<QLabel*>("positionLabel")->text().contains("the plane"));
    double bounds[6];
    w.fieldScene().slice_actor()->GetBounds(bounds);
    QVERIFY2(bounds[5] < plane - 0.01 * w.mechanism().size(), qPrintable(QString::number(bounds[5])));
    // The normal x gives a slice the position slider moves again.
    w.findChild<QComboBox*>("normalBox")->setCurrentText("x");
    QVERIFY(QTest::qWaitFor([&] { return w.fieldsSettled(); }, 30000));
    QVERIFY(w.findChild<QSlider*>("positionSlider")->isEnabled());
    QVERIFY(w.findChild<QLabel*>("positionLabel")->text().contains("%"));

    MechanismWindow spatial(load_preset("delta"));
    QVERIFY(show_settled(spatial));
    spatial.fieldScene().slice_actor()->GetBounds(bounds);
    // A drag of the handle asks a spatial device's point to go where the handle is.
    const Eigen::Vector3d off(1, 2, 3);
    QCOMPARE(*spatial.handles().inPlane(off), off);
    const gui::FieldSettings f = spatial.fieldSettings();
    const int n = int(parse_axis(f.normal));
    QVERIFY2(std::abs(0.5 * (bounds[2 * n] + bounds[2 * n + 1]) - f.position) < 1e-6 * spatial.mechanism().size(),
             qPrintable(QString::number(bounds[2 * n])));
  }

  // The status bar is the user's: compute and frame times only from View > Show timings.
  void timingsShowOnlyWhenAsked() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    auto* compute = w.findChild<QLabel*>("computeLabel");
    auto* frame = w.findChild<QLabel*>("frameLabel");
    QVERIFY(compute && frame);
    QVERIFY(!compute->isVisible() && !frame->isVisible());
    // The isosurfaces' time is there too, not in the status bar's message.
    QVERIFY2(compute->text().contains("isosurfaces (full)"), qPrintable(compute->text()));
    QVERIFY2(!w.statusBar()->currentMessage().contains("ms"), qPrintable(w.statusBar()->currentMessage()));
    auto* timings = w.findChild<QAction*>("showTimingsAction");
    QVERIFY(timings);
    timings->trigger();
    QVERIFY(compute->isVisible() && frame->isVisible());
    QVERIFY(frame->text().contains("ms"));
    timings->trigger();
    QVERIFY(!compute->isVisible() && !frame->isVisible());
  }

  // --latency times the surfaces with and without smoothing in one run
  // (alternating), and leaves the View toggle as the user had it.
  void latencyProbeTimesTheSurfacesSmoothedAndNot() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    auto* smooth = w.findChild<QAction*>("smoothSurfacesAction");
    QVERIFY(smooth && smooth->isChecked());
    for (const bool before : {true, false}) {
      smooth->setChecked(before);
      std::ostringstream out;
      QCOMPARE(gui::run_latency_probe(w, out), 0);
      const QString table = QString::fromStdString(out.str());
      for (const char* row : {"full isosurfaces on screen, smoothed ", "full isosurfaces on screen, unsmoothed "}) {
        const auto m = QRegularExpression(QString(row) + "\\s+([0-9.]+)\\s+[0-9.]+\\s+[0-9.]+\\s+(\\d+)").match(table);
        QVERIFY2(m.hasMatch(), qPrintable(table));
        QVERIFY(m.captured(1).toDouble() > 0);
        QCOMPARE(m.captured(2).toInt(), 6);
      }
      QCOMPARE(smooth->isChecked(), before);
    }
  }
};

QTEST_MAIN(WindowDocumentTest)
#include "test_window_document.moc"
