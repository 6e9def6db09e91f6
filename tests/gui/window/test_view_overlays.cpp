// View > Show link capsules and View > Show force ellipsoid: the toggles
// exist under their session names, default per device (capsules on where
// the device states link radii), change what the view draws, and follow
// the pose as the sliders move it. LINKSCAPE_SCREENSHOTS=<folder> saves the
// view with each overlay, to look at.
#include <QAction>
#include <QApplication>
#include <QDir>
#include <QLabel>
#include <QtTest>
#include <vtkActor.h>
#include <vtkMatrix4x4.h>

#include <cmath>
#include <cstdio>

#include "core/force_ellipsoid.h"
#include "core/preset.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/view_overlays.h"
#include "gui/window/view_tools.h"
#include "render/capsule_scene.h"
#include "render/force_ellipsoid_scene.h"
#include "window_checks.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

QAction* action(MechanismWindow& w, const char* name) {
  QAction* a = w.findChild<QAction*>(name);
  if (!a) qFatal("no action %s", name);
  return a;
}

const gui::ViewOverlays& overlays(MechanismWindow& w) { return *w.viewTools()->overlays(); }

// On screen without fields: frames then change only with the overlays.
void show_settled(MechanismWindow& w) {
  gui::FieldSettings none = w.fieldSettings();
  none.show_slice = none.show_reach = none.show_well_conditioned = false;
  w.applyFieldSettings(none);
  w.resize(1100, 800);
  w.show();
  QVERIFY(QTest::qWaitForWindowExposed(&w));
  window_checks::wait_settled(w);
}

void save_view(MechanismWindow& w, const QString& name) {
  const QByteArray folder = qgetenv("LINKSCAPE_SCREENSHOTS");
  if (!folder.isEmpty()) w.viewImage(900, 700).save(QDir(QString::fromLocal8Bit(folder)).filePath(name));
}

std::string three_digits(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

// The ellipsoid the window should draw at its pose (continuous torque).
haptics::ForceEllipsoid ellipsoid_at(MechanismWindow& w) {
  const Mechanism& m = w.mechanism();
  return haptics::force_ellipsoid(m.jacobian(w.actuators(), w.task()), haptics::device_data(w.preset(), m.info()),
                                  haptics::TorqueRating::Continuous);
}

}  // namespace

class ViewOverlaysTest : public QObject {
  Q_OBJECT

 private slots:
  void togglesDefaultPerDevice() {
    MechanismWindow falcon(load_preset("falcon"));
    QVERIFY(action(falcon, "showLinkCapsules")->isEnabled());
    QVERIFY(action(falcon, "showLinkCapsules")->isChecked());
    QVERIFY(!action(falcon, "showForceEllipsoid")->isChecked());
    QVERIFY(overlays(falcon).capsules().visible());
    QCOMPARE(overlays(falcon).capsules().link_count(), 18);
    QVERIFY(!overlays(falcon).ellipsoid().visible());
    // A device without link radii: nothing to show, the toggle disabled
    // (left checked, so a window opened from this one keeps the default).
    MechanismWindow delta(load_preset("delta"));
    QVERIFY(action(delta, "showLinkCapsules")->isChecked());
    QVERIFY(!action(delta, "showLinkCapsules")->isEnabled());
    QVERIFY(!overlays(delta).capsules().visible());
    QCOMPARE(overlays(delta).capsules().link_count(), 0);
    // A compiled device with assumed link radii (PATHOS-II's stops): its 18 links and the grip.
    MechanismWindow pathos2(load_preset("pathos2"));
    show_settled(pathos2);
    QVERIFY(action(pathos2, "showLinkCapsules")->isEnabled());
    QVERIFY(overlays(pathos2).capsules().visible());
    QCOMPARE(overlays(pathos2).capsules().link_count(), 19);
    save_view(pathos2, "pathos2-capsules.png");
  }

  void capsulesFollowThePoseAndCanBeHidden() {
    MechanismWindow w(load_preset("falcon"));
    show_settled(w);
    const render::CapsuleScene& scene = overlays(w).capsules();
    auto expected = w.mechanism().link_capsules(w.actuators(), w.task());
    QVERIFY(expected && expected->has_pair());
    QVERIFY(scene.label_text().find(three_digits(expected->clearance)) != std::string::npos);
    vtkActor* thigh = scene.link_actor(1);  // leg 1's first chain link
    const Eigen::Vector3d before(thigh->GetMatrix()->GetElement(0, 3), thigh->GetMatrix()->GetElement(1, 3),
                                 thigh->GetMatrix()->GetElement(2, 3));
    save_view(w, "falcon-capsules.png");
    // A slider's move: the same actors, moved, the label the new pose's.
    Eigen::VectorXd x = w.task();
    x(0) += 30;
    x(2) += 20;
    QVERIFY(w.setTask(x));
    QCOMPARE(scene.link_actor(1), thigh);
    const Eigen::Vector3d after(thigh->GetMatrix()->GetElement(0, 3), thigh->GetMatrix()->GetElement(1, 3),
                                thigh->GetMatrix()->GetElement(2, 3));
    QVERIFY((after - before).norm() > 1);
    expected = w.mechanism().link_capsules(w.actuators(), w.task());
    QVERIFY(scene.label_text().find(three_digits(expected->clearance)) != std::string::npos);
    save_view(w, "falcon-capsules-moved.png");
    const QImage with = window_checks::frame(w);
    action(w, "showLinkCapsules")->trigger();
    QVERIFY(!scene.visible());
    QVERIFY(!scene.link_actor(1)->GetVisibility());
    QVERIFY(window_checks::changed_fraction(with, window_checks::frame(w)) > 0.005);
  }

  void ellipsoidIsDrawnAtTheDrivenPoint() {
    MechanismWindow w(load_preset("falcon"));
    show_settled(w);
    action(w, "showLinkCapsules")->trigger();  // the ellipsoid alone
    const QImage without = window_checks::frame(w);
    action(w, "showForceEllipsoid")->trigger();
    const render::ForceEllipsoidScene& scene = overlays(w).ellipsoid();
    QVERIFY(scene.visible() && scene.shape_shown());
    QVERIFY(window_checks::changed_fraction(without, window_checks::frame(w)) > 0.005);
    const double scale = overlays(w).lengthPerNewton();
    QVERIFY(scale > 0);
    auto check_axes = [&] {
      const haptics::ForceEllipsoid e = ellipsoid_at(w);
      for (int k = 0; k < 3; ++k)
        QVERIFY((scene.axis_tip(k) - w.endpoint() - scale * e.semi_axes_N(k) * e.axes.col(k)).norm() < 1e-9);
    };
    check_axes();
    // The label gives the force_iso the Drive tab shows (to its 4 digits).
    const haptics::Measures h =
        haptics::measures(w.mechanism().jacobian(w.actuators(), w.task()),
                          haptics::device_data(w.preset(), w.mechanism().info()), haptics::TorqueRating::Continuous);
    QVERIFY(scene.label_text().find("force_iso " + three_digits(h.force_iso_N) + " N") != std::string::npos);
    const double shown = w.findChild<QLabel*>("forceIsoLabel")->text().section(' ', 0, 0).toDouble();
    QVERIFY(std::abs(shown - h.force_iso_N) < 1e-3 * h.force_iso_N);
    save_view(w, "falcon-force-ellipsoid.png");
    Eigen::VectorXd x = w.task();
    x(1) -= 25;
    QVERIFY(w.setTask(x));
    check_axes();  // moved with the pose, at the same scale
    QCOMPARE(overlays(w).lengthPerNewton(), scale);
    action(w, "showForceEllipsoid")->trigger();
    QVERIFY(!scene.shape_actor()->GetVisibility());
  }

  void aPlanarDevicesEllipseLiesInItsPlane() {
    MechanismWindow w(load_preset("five-bar"));
    show_settled(w);
    action(w, "showForceEllipsoid")->trigger();
    const render::ForceEllipsoidScene& scene = overlays(w).ellipsoid();
    QVERIFY(scene.shape_shown());
    for (int k = 0; k < 2; ++k) QCOMPARE(scene.axis_tip(k).z(), w.endpoint().z());
    save_view(w, "five-bar-force-ellipse.png");
  }

  void withoutForcesTheEllipsoidSaysWhy() {
    Preset p = load_preset("delta");
    p.length_unit = "unit";  // forces need a real length
    MechanismWindow w(p);
    action(w, "showForceEllipsoid")->trigger();
    const render::ForceEllipsoidScene& scene = overlays(w).ellipsoid();
    QVERIFY(!scene.shape_shown());
    QVERIFY(scene.label_text().find("hidden: haptic measures need") != std::string::npos);
  }
};

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  ViewOverlaysTest test;
  return QTest::qExec(&test, argc, argv);
}
#include "test_view_overlays.moc"
