// The window's document keeps only valid input and whole gestures: criteria
// the Task tab rejects and Hold equal groups the Fit tab cannot use stay in
// their boxes but are not saved; the Fit tab's settings and last result, the
// slice's opacity and the View menu's toggles travel in the session; a drag is one undo step from press to release, however slowly it
// goes; Ctrl+Shift+S is Save As on plain X11 too.
#include <QAction>
#include <QDockWidget>
#include <QFileDialog>
#include <QLineEdit>
#include <QMainWindow>
#include <QMenu>
#include <QMessageBox>
#include <QPushButton>
#include <QSlider>
#include <QTemporaryDir>
#include <QUndoStack>
#include <QtTest>
#include <vtkCamera.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>

#include <algorithm>
#include <map>

#include "core/preset.h"
#include "gui/window/fit_panel.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/session.h"
#include "gui/window/session_history.h"
#include "gui/window/task_panel.h"
#include "gui/window/vtk_widget.h"
#include "gui/window/window_document.h"
#include "gui/window/window_menus.h"
#include "settled.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

using window_tests::show_settled;

// Types `text` into the line edit named `name` and finishes the edit.
QLineEdit* type_into(MechanismWindow& w, const char* name, const QString& text) {
  auto* edit = w.findChild<QLineEdit*>(name);
  if (!edit) return nullptr;
  edit->setText(text);
  emit edit->editingFinished();
  return edit;
}

}  // namespace

class WindowSessionTest : public QObject {
  Q_OBJECT

 private slots:
  void rejectedCriteriaStayInTheBoxButTheSessionKeepsTheLastValid() {
    QTemporaryDir dir;
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    QVERIFY(type_into(w, "taskCriteriaEdit", "cond<2.5"));
    QTest::qWait(gui::SessionHistory::kSettleMs + 100);  // taken as a step
    QLineEdit* edit = type_into(w, "taskCriteriaEdit", "cond<x");  // rejected: not a criterion
    QVERIFY(edit);
    QTest::qWait(gui::SessionHistory::kSettleMs + 100);
    const QString path = dir.filePath("s.json");
    QVERIFY(w.saveSession(path));
    QCOMPARE(edit->text(), QString("cond<x"));  // the user's text stays to be fixed
    const gui::Session saved = gui::load_session(path.toStdString());  // and the file opens again
    QVERIFY(saved.task_volume);
    QCOMPARE(saved.task_volume->criteria, std::vector<std::string>{"cond<2.5"});
  }

  void fitSettingsRoundTripAndRejectedGroupsAreNotSaved() {
    QTemporaryDir dir;
    const QString path = dir.filePath("fit.json");
    gui::FitSetting chosen;
    {
      MechanismWindow w(load_preset("parallel-12r"));
      QVERIFY(show_settled(w));
      gui::FitPanel* fit = w.fitPanel();
      fit->setFree({"L1", "L2"});
      fit->setBounds("L1", 6, 24);
      fit->setBounds("L2", 7, 22);
      fit->setMode(gui::FitPanel::Mode::LargestMarginAtSize, 28);
      fit->setCentreFree(false);
      QVERIFY(type_into(w, "fitEqual", "L1,L2"));
      chosen = fit->setting();
      QLineEdit* equal = type_into(w, "fitEqual", "L1,nonsense");  // no such parameter: rejected
      QVERIFY(w.saveSession(path));
      QCOMPARE(equal->text(), QString("L1,nonsense"));
    }
    const gui::Session saved = gui::load_session(path.toStdString());
    QVERIFY(saved.fit);
    QCOMPARE(saved.fit->equal, std::string("L1,L2"));
    QVERIFY(*saved.fit == chosen);
    QCOMPARE(saved.fit->free, (std::vector<std::string>{"L1", "L2"}));
    QCOMPARE(saved.fit->bounds.at("L1")[0], 6.0);
    QVERIFY(saved.fit->largest_margin);
    QCOMPARE(saved.fit->size, 28.0);
    QVERIFY(!saved.fit->centre_free);
    // Opened again, the tab shows them.
    MechanismWindow back(load_preset("parallel-12r"));
    QVERIFY(show_settled(back));
    QVERIFY(back.fitPanel()->setting() != chosen);  // a new window starts elsewhere
    QVERIFY(back.openSession(path));
    QVERIFY(back.fitPanel()->setting() == chosen);
  }

  // The slice's opacity and every checkable View-menu toggle, found by its
  // action's object name: saved, and set again (with their effect) when the
  // session opens; a toggle added later is kept with no more code.
  void sliceOpacityAndEveryViewToggleRoundTrip() {
    QTemporaryDir dir;
    const QString path = dir.filePath("view.json");
    std::map<std::string, bool> flipped;
    auto add_later_toggle = [](MechanismWindow& w) {
      QAction* later = w.findChild<QMenu*>("viewMenu")->addAction("A toggle added later");
      later->setObjectName("laterToggleAction");
      later->setCheckable(true);
      return later;
    };
    {
      MechanismWindow w(load_preset("parallel-12r"));
      QVERIFY(show_settled(w));
      auto* menu = w.findChild<QMenu*>("viewMenu");
      QVERIFY(menu);
      // Every checkable entry but the docks' has a stable name (what sessions key it by).
      std::vector<const QAction*> docks;
      for (const QDockWidget* d : w.findChildren<QDockWidget*>()) docks.push_back(d->toggleViewAction());
      int toggles = 0;
      for (const QAction* a : menu->actions())
        if (a->isCheckable() && std::find(docks.begin(), docks.end(), a) == docks.end()) {
          QVERIFY2(!a->objectName().isEmpty(), qPrintable(a->text()));
          ++toggles;
        }
      add_later_toggle(w);
      const std::map<std::string, bool> before = gui::view_toggles(&w);
      QCOMPARE(int(before.size()), toggles + 1);
      for (const char* name : {"labelsInFrontAction", "smoothSurfacesAction", "parallelProjectionAction",
                               "showTimingsAction", "laterToggleAction"})
        QVERIFY2(before.count(name), name);
      for (const auto& [name, on] : before) flipped[name] = !on;
      QVERIFY(gui::apply_view_toggles(&w, flipped).isEmpty());
      w.findChild<QSlider*>("sliceOpacitySlider")->setValue(40);
      QCOMPARE(w.fieldSettings().slice_opacity, 0.4);
      QVERIFY(w.saveSession(path));
    }
    const gui::Session saved = gui::load_session(path.toStdString());
    QCOMPARE(saved.field.slice_opacity, 0.4);
    QVERIFY(saved.view == flipped);
    MechanismWindow back(load_preset("parallel-12r"));
    QVERIFY(show_settled(back));
    QAction* later = add_later_toggle(back);
    QVERIFY(gui::view_toggles(&back) != flipped);  // a new window starts as it starts
    QVERIFY(back.openSession(path));
    QVERIFY(gui::view_toggles(&back) == flipped);
    QCOMPARE(later->isChecked(), flipped.at("laterToggleAction"));
    QCOMPARE(back.findChild<QSlider*>("sliceOpacitySlider")->value(), 40);
    QCOMPARE(back.fieldSettings().slice_opacity, 0.4);
    // The toggles took effect: the camera's projection follows its toggle.
    vtkCamera* camera = back.view()->renderWindow()->GetRenderers()->GetFirstRenderer()->GetActiveCamera();
    QCOMPARE(bool(camera->GetParallelProjection()), flipped.at("parallelProjectionAction"));
  }

  // The Fit tab's centre region and its last result: saved, and shown again
  // when the session opens (the report, the verdict, Apply's design).
  void theFitRegionAndLastResultRoundTrip() {
    QTemporaryDir dir;
    const QString path = dir.filePath("fit-result.json");
    QString report, status;
    std::map<std::string, double> design;
    std::optional<Eigen::Vector3d> centre;
    const std::string region = "box:min=-8,0,0,max=8,30,30";
    {
      MechanismWindow w(load_preset("parallel-12r"));
      QVERIFY(show_settled(w));
      w.taskPanel()->setTask("sphere:diameter=8", {"cond<3"});
      gui::FitPanel* fit = w.fitPanel();
      fit->setSearchSettings({24, 1, 1, {}, {}}, 8, 1e-2);  // coarse: the session is tested, not the search
      fit->setEqual("L1,L2");
      fit->setCentreFree(true);
      fit->setCentreRegion(region);
      QSignalSpy finished(fit, &gui::FitPanel::runFinished);
      fit->run();
      QVERIFY(finished.wait(120000));
      QVERIFY(finished.front().front().toBool());
      report = fit->reportText();
      status = fit->statusText();
      design = fit->chosenDesign();
      centre = fit->chosenCentre();
      QVERIFY(!design.empty() && centre);
      QVERIFY2(status.contains("centre = home + ("), qPrintable(status));
      QVERIFY(w.saveSession(path));
    }
    const gui::Session saved = gui::load_session(path.toStdString());
    QVERIFY(saved.fit && saved.fit_result);
    QCOMPARE(saved.fit->centre_region, region);
    MechanismWindow back(load_preset("parallel-12r"));
    QVERIFY(show_settled(back));
    QVERIFY(back.fitPanel()->reportText().isEmpty());
    QVERIFY(back.openSession(path));
    gui::FitPanel* fit = back.fitPanel();
    QCOMPARE(fit->centreRegion(), region);
    QCOMPARE(fit->reportText(), report);
    QCOMPARE(fit->statusText(), status);
    QVERIFY(fit->showsSavedOutcome());
    QVERIFY(fit->chosenDesign() == design);
    QVERIFY(fit->chosenCentre() && (*fit->chosenCentre() - *centre).norm() == 0);
    // Apply sets the saved design and moves the task to where the search placed it.
    auto* apply = fit->findChild<QPushButton*>("fitApply");
    QVERIFY(apply->isEnabled());
    apply->click();
    for (const auto& [name, value] : design) QCOMPARE(back.mechanism().parameters().at(name), value);
    QVERIFY((*back.taskPanel()->volume().centre - *centre).norm() < 1e-9);
    // Saved again, the result is the same (not lost for want of a run).
    QVERIFY(back.saveSession(dir.filePath("again.json")));
    QVERIFY(*gui::load_session(dir.filePath("again.json").toStdString()).fit_result == *saved.fit_result);
  }

  void aDragIsOneUndoStepFromPressToRelease() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    auto* drive = w.findChild<QDockWidget*>("driveDock");
    QVERIFY(drive);
    QSlider* slider = nullptr;
    for (QSlider* s : drive->widget()->findChildren<QSlider*>())
      if (s->isEnabled() && s->maximum() > s->minimum()) {
        slider = s;
        break;
      }
    QVERIFY(slider);
    const int step = std::max(1, (slider->maximum() - slider->minimum()) / 100);
    QUndoStack* stack = w.history()->stack();
    const int before = stack->count();
    // A slow drag: pauses longer than the settling time between moves.
    QTest::mousePress(drive->widget(), Qt::LeftButton, {}, QPoint(2, 2));
    for (int k = 1; k <= 3; ++k) {
      slider->setValue(slider->value() + step);
      QTest::qWait(gui::SessionHistory::kSettleMs + 150);
    }
    QCOMPARE(stack->count(), before);  // nothing is a step while the button is held
    const Eigen::VectorXd held = w.task();
    QTest::mouseRelease(drive->widget(), Qt::LeftButton, {}, QPoint(2, 2));
    QVERIFY(QTest::qWaitFor([&] { return stack->count() == before + 1; }, 2000));
    QTest::qWait(gui::SessionHistory::kSettleMs + 150);
    QCOMPARE(stack->count(), before + 1);  // one step for the whole drag
    stack->undo();
    QVERIFY((w.task() - held).norm() > 0);  // back to before the drag
    // Without a button held, changes still settle into steps of their own.
    stack->redo();
    for (int k = 1; k <= 2; ++k) {
      slider->setValue(slider->value() - step);
      QVERIFY2(QTest::qWaitFor([&] { return stack->count() == before + 1 + k; }, 5000), qPrintable(w.refusal()));
    }
  }

  // A device made again from its reloaded file takes the history over:
  // the steps before the reload, the reload itself, and the saved mark.
  void aReloadedDeviceTakesTheUndoHistoryOver() {
    gui::Session state;  // what the window holds
    const auto capture = [&] { return state; };
    const auto restore = [&](const gui::Session& s) { state = s; };
    gui::SessionHistory before(capture, restore);
    before.reset("doc.json");
    for (double L1 : {10.0, 11.0}) {
      state.parameters["L1"] = L1;
      before.flush();
    }
    before.markSaved("doc.json");
    state.parameters["L1"] = 12.0;
    before.flush();
    state.parameters["L1"] = 11.5;  // the file's design, read again
    gui::SessionHistory after(capture, restore);
    after.reset({});
    after.adopt(before, "reload");
    QCOMPARE(after.stack()->count(), 4);
    QCOMPARE(after.stack()->undoText(), QString("reload"));
    QCOMPARE(after.path(), QString("doc.json"));
    QVERIFY(after.modified());
    for (double L1 : {12.0, 11.0}) {
      after.stack()->undo();
      QCOMPARE(state.parameters.at("L1"), L1);
    }
    QVERIFY(!after.modified());  // the state that was saved
    after.stack()->undo();
    QCOMPARE(state.parameters.at("L1"), 10.0);
  }

  // Reloading over changes the file does not have asks first.
  void reloadingOverChangesAsks() {
    QMainWindow window;
    gui::Session state;
    gui::WindowDocument document(&window, {[&] { return state; }, [&](const gui::Session& s) { state = s; },
                                           [](const gui::Session&, const Preset&, const QString&) {},
                                           [] { return QString("device"); }, [] { return QString(); }});
    QVERIFY(document.mayReload());  // nothing changed: no question
    state.parameters["L1"] = 12;
    document.history()->noteChange();
    document.setInteractive(true);
    for (const QMessageBox::StandardButton answer : {QMessageBox::Cancel, QMessageBox::Yes}) {
      int asked = 0;
      QTimer click;
      connect(&click, &QTimer::timeout, [&] {
        for (QWidget* top : QApplication::topLevelWidgets())
          if (auto* box = qobject_cast<QMessageBox*>(top); box && box->isVisible()) {
            ++asked;
            box->button(answer)->click();
          }
      });
      click.start(50);
      QCOMPARE(document.mayReload(), answer == QMessageBox::Yes);
      QCOMPARE(asked, 1);
    }
  }

  void ctrlShiftSAsksWhereToSaveAs() {
    MechanismWindow w(load_preset("parallel-12r"));
    QVERIFY(show_settled(w));
    w.activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(&w));
    QString asked;  // the title of the file dialog the key opened
    QTimer answer;
    connect(&answer, &QTimer::timeout, [&] {
      for (QWidget* top : QApplication::topLevelWidgets())
        if (auto* dialog = qobject_cast<QFileDialog*>(top); dialog && dialog->isVisible()) {
          asked = dialog->windowTitle();
          dialog->reject();
        }
    });
    answer.start(50);
    QTest::keyClick(&w, Qt::Key_S, Qt::ControlModifier | Qt::ShiftModifier);
    QVERIFY(QTest::qWaitFor([&] { return !asked.isEmpty(); }, 10000));
    QCOMPARE(asked, QString("Save session as"));
  }
};

QTEST_MAIN(WindowSessionTest)
#include "test_window_session.moc"
