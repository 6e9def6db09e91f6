// The Design tab's Motors group and the Drive tab's forces: the ratings
// shown are the preset's (or a parameter's), an edit sets the rating for
// every actuator as --param does (a session saves it and reads it back),
// the Drive tab's force_iso and force_max at the pose follow it in
// proportion (forces scale with the torque) and name the torque used, and a
// rating the others contradict is refused with the old one kept.
#include <QDockWidget>
#include <QLabel>
#include <QLineEdit>
#include <QtTest>
#include <cstdlib>
#include <filesystem>

#include "core/haptics.h"
#include "core/preset.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/vtk_widget.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

// The number a read-out starts with ("1.23 N (continuous torque ...)").
double leading_number(const QString& text) { return text.section(' ', 0, 0).toDouble(); }

// Core's force_iso at the window's pose for its preset.
double core_force_iso(const MechanismWindow& w) {
  const auto m = make_mechanism(w.preset());
  const haptics::DeviceData data = haptics::device_data(w.preset(), m->info());
  return haptics::measures(m->jacobian(m->inverse(w.task(), {}).solutions.front().q, w.task()), data,
                           haptics::TorqueRating::Continuous)
      .force_iso_N;
}

// With LINKSCAPE_SCREENSHOTS=<folder>: the window with the dock `dock` in front.
void screenshot(MechanismWindow& w, const char* dock, const std::string& name) {
  const char* folder = std::getenv("LINKSCAPE_SCREENSHOTS");
  if (!folder) return;
  w.findChild<QDockWidget*>(dock)->raise();
  QTest::qWait(300);
  std::filesystem::create_directories(folder);
  gui::VtkWidget::grabWindow(&w).save(QString::fromStdString(std::string(folder) + "/" + name));
}

void edit(QLineEdit* box, const QString& text) {
  box->setText(text);
  QMetaObject::invokeMethod(box, "editingFinished");
}

}  // namespace

class DesignMotorsTest : public QObject {
  Q_OBJECT

 private slots:
  void ratingsAreInputsAndTheDriveTabShowsTheForces() {
    MechanismWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    auto* torque = w.findChild<QLineEdit*>("continuous_torque_NmEdit");
    QVERIFY(torque);
    for (const char* name : {"peak_torque_NmEdit", "gear_ratioEdit", "encoder_counts_per_revEdit", "rotor_inertia_kgm2Edit"})
      QVERIFY2(w.findChild<QLineEdit*>(name), name);
    QVERIFY(!w.findChild<QLineEdit*>("lead_m_per_revEdit"));  // revolute actuators only
    const double before = torque->text().toDouble();
    QVERIFY(before > 0);
    const double force = leading_number(w.findChild<QLabel*>("forceIsoLabel")->text());
    QVERIFY2(w.findChild<QLabel*>("forceIsoLabel")->text().contains(" N (continuous torque "),
             qPrintable(w.findChild<QLabel*>("forceIsoLabel")->text()));
    QVERIFY(w.findChild<QLabel*>("forceMaxLabel")->text().contains(" N"));
    QVERIFY(std::abs(force - core_force_iso(w)) <= 5e-4 * force);

    // Half the torque: the preset carries it as a parameter, the forces halve.
    edit(torque, QString::number(before / 2));
    QCOMPARE(w.preset().parameters.at("continuous_torque_Nm"), before / 2);
    const double halved = leading_number(w.findChild<QLabel*>("forceIsoLabel")->text());
    QVERIFY2(std::abs(halved - force / 2) <= 1e-3 * force, qPrintable(QString("%1 vs %2").arg(halved).arg(force)));
    QVERIFY(std::abs(halved - core_force_iso(w)) <= 5e-4 * halved);
    // The session keeps it and gives it back.
    const gui::Session s = w.session();
    QCOMPARE(s.parameters.at("continuous_torque_Nm"), before / 2);
    MechanismWindow again(load_preset("parallel-12r"));
    again.applySession(s);
    QCOMPARE(again.findChild<QLineEdit*>("continuous_torque_NmEdit")->text().toDouble(), before / 2);

    screenshot(w, "driveDock", "window-drive-forces.png");
    // A continuous torque above the peak is refused; the rating in force stays.
    const double peak = w.findChild<QLineEdit*>("peak_torque_NmEdit")->text().toDouble();
    edit(torque, QString::number(2 * peak));
    QCOMPARE(w.preset().parameters.at("continuous_torque_Nm"), before / 2);
    QCOMPARE(torque->text().toDouble(), before / 2);
    QVERIFY(w.findChild<QLabel*>("motorsNote")->text().contains("exceeds its peak_torque_Nm"));
    screenshot(w, "designDock", "window-design-motors.png");
    edit(torque, "abc");
    QCOMPARE(w.preset().parameters.at("continuous_torque_Nm"), before / 2);
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(gui::VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  DesignMotorsTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "test_design_motors.moc"
