// What the window's read-outs say: the method field named by the device's
// IK methods (its legend and the probe), det J with the unit of J's rows
// over its columns', the Task tab's centre boxes labelled with their axis
// and unit, and the task's centre from the device's home point.
// LINKSCAPE_SCREENSHOTS=<folder> saves the window at each, to look at.
#include <QCheckBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QtTest>
#include <vtkActor.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/preset.h"
#include "gui/window/drive_panel.h"
#include "gui/window/fit_panel.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/probe_panel.h"
#include "gui/window/quantity_control.h"
#include "gui/window/task_panel.h"
#include "gui/window/view_tools.h"
#include "render/field_scene.h"
#include "window_checks.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

void show(MechanismWindow& w) {
  w.resize(1280, 800);
  w.show();
  QVERIFY(QTest::qWaitForWindowExposed(&w));
  window_checks::wait_settled(w);
}

void raise(MechanismWindow& w, const char* dock) {
  if (auto* d = w.findChild<QDockWidget*>(dock)) d->raise();
  QTest::qWait(100);
}

// The power of `unit` in a determinant_unit text ("cm³/rad³": cm -> 3).
int power_of(const QString& text, const QString& unit) {
  const QString above = text.section('/', 0, 0);
  const int at = above.indexOf(unit);
  if (at < 0) return 0;
  static const QString kDigits = QString::fromUtf8("⁰¹²³⁴⁵⁶⁷⁸⁹");
  const int digit = at + unit.size() < above.size() ? kDigits.indexOf(above[at + unit.size()]) : -1;
  return digit < 0 ? 1 : digit;
}

}  // namespace

class WindowReadoutsTest : public QObject {
  Q_OBJECT

 private slots:
  // The 12R's method field under "fallback" (which serves each sample by
  // planar or, where it misses, newton): a legend of those names, and the
  // probe at a slice sample names its method too.
  void theMethodFieldIsNamedByTheDevicesMethods() {
    MechanismWindow w(load_preset("parallel-12r"));
    show(w);
    gui::FieldSettings f = w.fieldSettings();
    f.field = "method";
    f.method = "fallback";
    w.applyFieldSettings(f);
    window_checks::wait_settled(w);
    std::set<std::string> known;
    for (const NamedItem& m : w.mechanism().info().ik_methods) known.insert(m.name);
    const std::vector<std::string> labels = w.fieldScene().colour_bar_labels();
    QVERIFY(!labels.empty());  // a discrete legend, not a continuous bar
    QVERIFY(std::count(labels.begin(), labels.end(), "planar") == 1);
    for (const std::string& l : labels) QVERIFY2(known.count(l), l.c_str());
    // The probe on the slice, at the device's home point projected onto it.
    const gui::FieldSettings shown = w.fieldSettings();
    Eigen::Vector3d p = w.mechanism().home_task().head<3>();
    p(shown.normal[0] - 'x') = shown.position;
    gui::ProbePanel* probe = w.viewTools()->panel();
    probe->pick(p, "slice", true, false);
    QVERIFY(probe->sample());
    const render::ProbeValue* method = probe->sample()->find("method");
    QVERIFY(method);
    QVERIFY2(known.count(method->label), method->label.c_str());
    QVERIFY2(!probe->readout().contains("method code"), qPrintable(probe->readout()));
    if (auto* dock = w.findChild<QDockWidget*>("probeDock")) dock->show(), dock->raise();
    window_checks::frame(w);
    window_checks::save_screenshot(w, "readouts-method-legend.png");
  }

  void theDeterminantUnitIsTheRowsOverTheColumns() {
    QCOMPARE(gui::determinant_unit({"cm", "cm", "cm"}, {"rad", "rad", "rad"}), QString::fromUtf8("cm³/rad³"));
    QCOMPARE(gui::determinant_unit({"cm", "cm", "cm", "rad", "rad", "rad"}, std::vector<std::string>(6, "rad")),
             QString::fromUtf8("cm³/rad³"));  // a six-DOF device's twist rows
    QCOMPARE(gui::determinant_unit({"cm", "cm"}, {"rad", "rad"}), QString::fromUtf8("cm²/rad²"));
    QCOMPARE(gui::determinant_unit({"mm", "mm", "mm"}, {"mm", "mm", "mm"}), QString());  // linear actuators
    QCOMPARE(gui::determinant_unit({"cm", "rad"}, {"cm", "cm"}), QString("rad/cm"));
    QCOMPARE(gui::determinant_unit({"", "cm"}, {"rad", "cm"}), QString("1/rad"));
  }

  // The read-out's unit for every device, and its length power checked
  // against the determinant itself: the 12R scaled 10 times has det J
  // 10^p times larger at the same actuator angles, p the unit's power.
  void theDriveReadoutGivesDetJWithItsUnit() {
    for (const std::string name : {"parallel-12r", "delta", "five-bar", "linear-delta"}) {
      MechanismWindow w(load_preset(name));
      show(w);
      const MechanismInfo& info = w.mechanism().info();
      auto* det = w.findChild<QLabel*>("detLabel");
      QVERIFY(det);
      const Eigen::MatrixXd J = w.mechanism().jacobian(w.state().actuators(), w.task());
      const QString unit = gui::determinant_unit(info, int(J.rows()), int(J.cols()));
      QVERIFY2(det->text().endsWith(unit), qPrintable(det->text() + " / " + unit));
      const bool angles = std::all_of(info.actuators.begin(), info.actuators.end(),
                                      [](const Quantity& q) { return q.unit == "rad"; });
      if (angles) {
        const QString length = QString::fromStdString(info.length_unit);
        QCOMPARE(power_of(unit, length), int(J.rows()));  // every row a length over an angle
        QVERIFY2(unit.endsWith("rad" + unit.section("/", 0, 0).mid(length.size())), qPrintable(unit));
      }
      if (name == "parallel-12r") {
        raise(w, "driveDock");
        window_checks::save_screenshot(w, "readouts-det-unit.png");
      }
    }
    // The power, from the numbers: det J of the 12R scaled by 10.
    Preset p = load_preset("parallel-12r");
    const auto m1 = make_mechanism(p);
    for (const char* n : {"L1", "L2"}) p.parameters[n] *= 10;
    const auto m10 = make_mechanism(p);
    const Eigen::VectorXd q = m1->home_actuators();
    const Eigen::VectorXd x1 = m1->forward(q).x, x10 = m10->forward(q).x;
    QVERIFY((x10 - 10 * x1).norm() < 1e-9 * x10.norm());
    const double ratio = m10->measures(q, x10).det / m1->measures(q, x1).det;
    const QString unit = gui::determinant_unit(m1->info(), 3, 3);
    QCOMPARE(power_of(unit, "cm"), 3);
    QVERIFY2(std::abs(ratio / std::pow(10.0, power_of(unit, "cm")) - 1) < 1e-9, qPrintable(QString::number(ratio)));
  }

  void theTaskCentreBoxesAreLabelledAndTheCentreIsGivenFromHome() {
    MechanismWindow w(load_preset("parallel-12r"));
    show(w);
    raise(w, "taskDock");
    const QString unit = QString::fromStdString(w.mechanism().info().length_unit);
    for (const char axis : {'X', 'Y', 'Z'}) {
      auto* box = w.findChild<QDoubleSpinBox*>(QString("taskCentre%1").arg(axis));
      auto* label = w.findChild<QLabel*>(QString("taskCentreLabel%1").arg(axis));
      QVERIFY(box && label);
      QCOMPARE(label->text(), QString(QChar(axis).toLower()));
      QCOMPARE(label->buddy(), static_cast<QWidget*>(box));
      QVERIFY(label->isVisible());
      QCOMPARE(box->suffix(), " " + unit);
    }
    QCOMPARE(w.findChild<QLabel*>("taskCentreRowLabel")->text(), "Centre (" + unit + ")");
    // The Fit tab's region names its unit as well.
    bool region_labelled = false;
    for (const QLabel* l : w.fitPanel()->findChildren<QLabel*>()) region_labelled |= l->text() == "Centre within (" + unit + ")";
    QVERIFY(region_labelled);
    // The centre from the home point, in the read-out.
    const Eigen::Vector3d home = w.mechanism().home_task().head<3>();
    w.findChild<QCheckBox*>("taskShowBox")->setChecked(true);  // the read-outs follow a task shown
    w.taskPanel()->setCentre(home + Eigen::Vector3d(1, -2, 0.5));
    w.taskPanel()->evaluateNow();
    const QString text = w.taskPanel()->readout();
    QVERIFY2(text.contains("centre = home + (1, -2, 0.5) " + unit), qPrintable(text));
    // Every box inside the dock at the window's width.
    QWidget* dock = w.findChild<QDockWidget*>("taskDock")->widget();
    for (const char axis : {'X', 'Y', 'Z'}) {
      const QWidget* box = w.findChild<QDoubleSpinBox*>(QString("taskCentre%1").arg(axis));
      QVERIFY(box->mapTo(dock, QPoint(box->width(), 0)).x() <= dock->width());
    }
    QTest::qWait(100);  // the read-out laid out
    window_checks::save_screenshot(w, "readouts-task-centre.png");
  }
};

QTEST_MAIN(WindowReadoutsTest)
#include "test_window_readouts.moc"
