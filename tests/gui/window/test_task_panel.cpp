// The window's Task tab for every registered device: the task drawn in the
// scene and coloured where it fails, read-outs that are core's evaluation of
// the same task and follow the design and the task's centre, the largest
// sphere placed on request.
#include <QDoubleSpinBox>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QtTest>

#include "core/preset.h"
#include "core/task.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/task_panel.h"
#include "gui/window/vtk_widget.h"
#include "render/task_scene.h"
#include "render/verify_regions.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

// Core's evaluation of the task the panel shows (its centre as the panel's
// boxes hold it), on the window's design and pose.
task::TaskReport core_report(const MechanismWindow& w, task::TaskVolume t, const std::vector<std::string>& criteria) {
  t.centre = Eigen::Vector3d(w.findChild<QDoubleSpinBox*>("taskCentreX")->value(),
                             w.findChild<QDoubleSpinBox*>("taskCentreY")->value(),
                             w.findChild<QDoubleSpinBox*>("taskCentreZ")->value());
  task::Device d;
  d.mechanism = make_mechanism(w.preset());
  d.fixed_task = w.task();
  std::vector<task::Criterion> c = {task::parse_criterion("reach")};
  for (const std::string& text : criteria) c.push_back(task::parse_criterion(text));
  return task::evaluate(d, task::resolve(d, c), t, *t.centre, task::kTaskResolution);  // fit's evaluation
}

std::string sphere_at(double diameter, const Eigen::Vector3d& c) {
  return "sphere:diameter=" + std::to_string(diameter) + ",centre=" + std::to_string(c.x()) + "," +
         std::to_string(c.y()) + "," + std::to_string(c.z());
}

}  // namespace

class TaskPanelTest : public QObject {
  Q_OBJECT

 private slots:
  void everyDeviceShowsItsTaskAndFollowsTheDesign() {
    for (const std::string& name : registered_mechanisms()) {
      MechanismWindow w(load_preset(name));
      w.resize(1000, 700);
      w.show();
      QVERIFY(QTest::qWaitForWindowExposed(&w));
      gui::TaskPanel* panel = w.taskPanel();
      const Eigen::Vector3d home = w.mechanism().home_task().head<3>();
      const double size = w.mechanism().size();
      // A small sphere at home: reachable and conditioned well enough there.
      task::TaskVolume t = task::parse_task(sphere_at(0.05 * size, home));
      panel->setTask(t.text, {"cond<20"});
      QVERIFY2(panel->report() && panel->report()->meets(), name.c_str());
      QVERIFY(w.taskScene().visible());
      QCOMPARE(w.taskScene().failing_points(), std::size_t(0));
      task::TaskReport expected = core_report(w, t, {"cond<20"});
      // fit's words for fit's evaluation.
      QVERIFY(w.findChild<QLabel*>("taskReadout")->text().contains(
          QString::fromStdString("Meets every criterion at all " + std::to_string(expected.samples) + " samples")));
      QCOMPARE(panel->report()->samples, expected.samples);
      QCOMPARE(panel->report()->fraction, expected.fraction);
      QCOMPARE(panel->report()->criteria[1].worst, expected.criteria[1].worst);

      // Moved out of reach along x: the read-outs and the colours follow.
      auto* cx = w.findChild<QDoubleSpinBox*>("taskCentreX");
      cx->setValue(home.x() + 2 * size);
      QTRY_VERIFY2(panel->report() && !panel->report()->meets(), name.c_str());
      QVERIFY(w.taskScene().failing_points() > 0);
      QVERIFY(w.findChild<QLabel*>("taskReadout")->text().contains("Fails: "));
      QVERIFY(!w.findChild<QLabel*>("taskReadout")->text().contains("(100 %) meet every criterion"));
      // Where it fails, to the device's resolution: no sampling noise (1e-17 for 0).
      const QString around = w.findChild<QLabel*>("taskReadout")->text().section("around (", 1).section(")", 0, 0);
      QVERIFY2(!around.isEmpty() && !around.contains("e-"), qPrintable(around));
      cx->setValue(home.x());
      QTRY_VERIFY(panel->report() && panel->report()->meets());

      // A new design: the read-outs are the new design's.
      const Quantity& first = w.mechanism().info().parameters.front();
      QVERIFY(w.setParameters({{first.name, 0.9 * first.value}}));
      panel->evaluateNow();
      expected = core_report(w, t, {"cond<20"});
      QCOMPARE(panel->report()->fraction, expected.fraction);
      QCOMPARE(panel->report()->criteria[1].worst, expected.criteria[1].worst);
    }
  }

  // A planar device's task is its section by the plane, as fit takes it: a
  // sphere whose centre the placement left off the plane (z = 4) is
  // evaluated on it, drawn flattened onto it, and read out in fit's words
  // (it had shown the solver's "x has z = 4 cm, but five-bar is planar").
  void aPlanarDevicesTaskIsItsSectionByThePlane() {
    for (const char* name : {"five-bar", "haply-2diy", "three-rrr"}) {
      MechanismWindow w(load_preset(name));
      w.resize(1000, 700);
      w.show();
      QVERIFY(QTest::qWaitForWindowExposed(&w));
      const Eigen::Vector3d home = w.mechanism().home_task().head<3>();
      const double size = w.mechanism().size();
      const task::TaskVolume t = task::parse_task(sphere_at(0.05 * size, home + Eigen::Vector3d(0, 0, 0.2 * size)));
      w.taskPanel()->setTask(t.text, {"cond<20"});
      QVERIFY2(w.taskPanel()->report() && w.taskPanel()->report()->meets(), name);
      QVERIFY2(w.findChild<QLabel*>("taskReadout")->text().contains("Meets every criterion"), name);
      QCOMPARE(w.taskScene().failing_points(), std::size_t(0));
    }
  }

  // Without a centre the task goes to the largest sphere of the good region:
  // the 12R's c(J) < 3 holds about 1.22 x 15 cm; a 5 cm task there meets it.
  // Verify in the Task tab: seed 001's 15 cm sphere, where fit places it at
  // L1 = L2 = 12.4 cm, proved; at 11.5 cm disproved with its point; a change
  // after a verdict marks it stale; a device without enclosures says so.
  void verifyProvesAndDisprovesInWords() {
    const std::string task = "sphere:diameter=15,centre=0.7092,-12.96,-8.385";
    for (const auto& [length, words] : {std::pair{12.4, "proved: every point"}, {11.5, "disproved"}}) {
      Preset preset = load_preset("parallel-12r");
      apply_overrides(preset, {"L1=" + std::to_string(length), "L2=" + std::to_string(length)});
      MechanismWindow w(preset);
      w.show();
      QVERIFY(QTest::qWaitForWindowExposed(&w));
      w.taskPanel()->setTask(task, {"cond<3"});
      auto* verdict = w.findChild<QLabel*>("taskVerdict");
      QTest::mouseClick(w.findChild<QPushButton*>("taskVerifyButton"), Qt::LeftButton);
      QTRY_VERIFY_WITH_TIMEOUT(verdict->text().contains(words), 60000);
      if (length < 12) QVERIFY(verdict->text().contains("c(J)"));
      // In the view: the boxes proved, or the counterexample.
      const render::VerifyRegions& regions = w.taskPanel()->verifyRegions();
      QCOMPARE(regions.counterexample(), length < 12);
      if (length > 12) QVERIFY(regions.proved() > 0);
      w.findChild<QDoubleSpinBox*>("taskCentreX")->setValue(0.5);
      QTRY_VERIFY(verdict->text().contains("changed since the last Verify"));
      QVERIFY(!regions.counterexample() && regions.proved() == 0);
    }
    MechanismWindow pathos(load_preset("pathos2"));
    pathos.show();
    QVERIFY(QTest::qWaitForWindowExposed(&pathos));
    QTest::mouseClick(pathos.findChild<QPushButton*>("taskVerifyButton"), Qt::LeftButton);
    QTRY_VERIFY_WITH_TIMEOUT(pathos.findChild<QLabel*>("taskVerdict")->text().contains("cannot be certified"), 30000);
  }

  // Criteria separated by commas, semicolons or spaces, as the command line
  // takes them; the box shows the syntax as a hint; a bare name says to quote.
  void criteriaTakeTheCommandLinesSyntax() {
    MechanismWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    auto* edit = w.findChild<QLineEdit*>("taskCriteriaEdit");
    QVERIFY(edit->placeholderText().contains("commas, semicolons or spaces"));
    w.taskPanel()->setTask("sphere:diameter=5,centre=0,15,15", {"cond<3; force_iso>0.1", "force_max>0.1"});
    QCOMPARE(edit->text(), QString("cond<3, force_iso>0.1, force_max>0.1"));
    for (const char* text : {"cond<3, force_iso>0.1;force_max>0.1", "cond<3 force_iso>0.1 force_max>0.1;"}) {
      edit->setText(text);
      const auto criteria = w.taskPanel()->criteria();
      QCOMPARE(criteria.size(), std::size_t(4));
      QCOMPARE(criteria[3].text, std::string("force_max>0.1"));
      QCOMPARE(w.taskPanel()->setting().criteria, (std::vector<std::string>{"cond<3", "force_iso>0.1", "force_max>0.1"}));
    }
    edit->setText("cond");
    try {
      w.taskPanel()->criteria();
      QFAIL("a bare name is refused");
    } catch (const std::invalid_argument& e) {
      QVERIFY2(QString(e.what()).contains("quote the criterion: 'cond<3'"), e.what());
    }
  }

  void aTaskWithoutCentreIsPlacedInTheLargestSphere() {
    MechanismWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    w.taskPanel()->setTask("sphere:diameter=5", {"cond<3"});
    QVERIFY(w.taskPanel()->largest() && w.taskPanel()->largest()->found);
    QVERIFY(std::abs(w.taskPanel()->largest()->size - 1.224 * 15) < 0.02 * 18.4);
    QVERIFY(w.taskPanel()->report()->meets());
    QVERIFY(w.findChild<QLabel*>("taskReadout")->text().contains("largest sphere"));
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, w.taskPanel()->setTask("sphere:diameter=5", {"stiffness<3"}));
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(gui::VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  TaskPanelTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "test_task_panel.moc"
