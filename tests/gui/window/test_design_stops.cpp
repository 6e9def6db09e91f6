// The Design tab's Stops group: a switch for each kind of stop the device
// states (the Falcon both, the described Delta its ball-joint cones only,
// the 12R none: no group); unticking one makes the device as
// --joint-limits off does (its field gone, so the Task tab's bound on it is
// refused), and a session keeps the switch through its file and gives it
// back to a new window.
#include <QAction>
#include <QCheckBox>
#include <QGroupBox>
#include <QLabel>
#include <QtTest>
#include <filesystem>

#include "core/preset.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/session.h"
#include "gui/window/task_panel.h"
#include "gui/window/vtk_widget.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

bool lists_field(const MechanismWindow& w, const std::string& name) {
  const auto device = make_mechanism(w.preset());  // alive while its description is read
  for (const NamedItem& f : device->info().extra_fields)
    if (f.name == name) return true;
  return false;
}

}  // namespace

class DesignStopsTest : public QObject {
  Q_OBJECT

 private slots:
  void aSwitchPerStatedStopOnlyAndNoneWithoutStops() {
    MechanismWindow twelve(load_preset("parallel-12r"));
    QVERIFY(!twelve.findChild<QGroupBox*>("stopsGroup"));
    QVERIFY(!twelve.findChild<QCheckBox*>("jointLimitsCheck"));
    QVERIFY(!twelve.findChild<QCheckBox*>("interferenceCheck"));
    MechanismWindow delta(load_preset("delta-described"));
    QVERIFY(delta.findChild<QCheckBox*>("jointLimitsCheck"));
    QVERIFY(!delta.findChild<QCheckBox*>("interferenceCheck"));  // its links have no radius
  }

  void aSwitchTurnsItsStopOffAndASessionKeepsIt() {
    MechanismWindow w(load_preset("falcon"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    auto* joints = w.findChild<QCheckBox*>("jointLimitsCheck");
    auto* links = w.findChild<QCheckBox*>("interferenceCheck");
    QVERIFY(joints && links);
    QVERIFY(joints->isChecked() && links->isChecked());
    QVERIFY(lists_field(w, "joint_margin"));

    // The Task tab bounds the joint margin as fit does.
    w.taskPanel()->setTask("sphere:diameter=10,centre=0,0,120", {"joint_margin>5"});
    w.taskPanel()->evaluateNow();
    QVERIFY(w.taskPanel()->report() && w.taskPanel()->report()->meets());
    QVERIFY2(w.taskPanel()->readout().contains("joint_margin&gt;5: worst "), qPrintable(w.taskPanel()->readout()));

    joints->click();
    QVERIFY(!w.preset().checks.joint_limits);
    QVERIFY(w.preset().checks.interference);
    // No limits, no margin to bound: the tab says so.
    w.taskPanel()->evaluateNow();
    QVERIFY(!w.taskPanel()->report());
    const QString refusal = w.findChild<QLabel*>("taskReadout")->text();
    QVERIFY2(refusal.contains("unknown measure 'joint_margin'") && refusal.contains("clearance"), qPrintable(refusal));
    QVERIFY(!lists_field(w, "joint_margin"));  // the device as --joint-limits off makes it
    QVERIFY(lists_field(w, "clearance"));
    QVERIFY(joints->isVisible());  // still offered: the preset states the limits

    // Through a file, into a new window.
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "linkscape_design_stops.json";
    QVERIFY(w.saveSession(QString::fromStdString(file.string())));
    const gui::Session read = gui::load_session(file);
    QCOMPARE(read.checks, (StopChecks{.joint_limits = false, .interference = true}));
    MechanismWindow again(load_preset("falcon"));
    again.applySession(read);
    QVERIFY(!again.preset().checks.joint_limits);
    QVERIFY(!again.findChild<QCheckBox*>("jointLimitsCheck")->isChecked());
    QVERIFY(again.findChild<QCheckBox*>("interferenceCheck")->isChecked());

    // Back on: the limits are checked again.
    joints->click();
    QVERIFY(w.preset().checks.joint_limits);
    QVERIFY(lists_field(w, "joint_margin"));

    // View > Show link capsules follows the interference switch, off and on again.
    auto* capsules = w.findChild<QAction*>("showLinkCapsules");
    QVERIFY(capsules && capsules->isEnabled());
    links->click();
    QVERIFY(!w.preset().checks.interference);
    QVERIFY(!capsules->isEnabled());
    links->click();
    QVERIFY(capsules->isEnabled());
  }

  void aSessionsStopsAreChecked() {
    const std::string head = R"({"format": "linkscape-session", "mechanism": "falcon", "task": {"x": 0, "y": 0, "z": 120}, )";
    QCOMPARE(gui::parse_session(head + R"("stops": {"interference": false}})", "s").checks,
             (StopChecks{.joint_limits = true, .interference = false}));
    for (const auto& [stops, error] : std::vector<std::pair<std::string, std::string>>{
             {R"({"joint_limits": "off"})", "stops.joint_limits must be true or false"},
             {R"({"joints": false})", "joints"}}) {
      try {
        gui::parse_session(head + R"("stops": )" + stops + "}", "s");
        QFAIL(stops.c_str());
      } catch (const std::invalid_argument& e) {
        QVERIFY2(std::string(e.what()).find(error) != std::string::npos, e.what());
      }
    }
    try {
      gui::parse_session(R"({"format": "linkscape-session", "mechanism": "delta-described", "task": {"x": 0, "y": 0,
                           "z": -15}, "stops": {"interference": false}})", "s");
      QFAIL("a switch for links the device does not give a radius");
    } catch (const std::invalid_argument& e) {
      QVERIFY2(std::string(e.what()).find("stops.interference: the device states no link radii") != std::string::npos,
               e.what());
    }
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(gui::VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  DesignStopsTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "test_design_stops.moc"
