// The PATHOS-II window, driven as a user drives it: pose sliders (IK),
// actuator sliders (numerical FK beside the nine-sensor closed form), design
// sliders and the live fields; checks both the model and the picture.
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QSignalSpy>
#include <QSlider>
#include <QTemporaryDir>
#include <QTimer>
#include <QtTest>
#include <vtkImageData.h>
#include <vtkImageDifference.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <cstring>
#include <numbers>

#include "core/pathos2.h"
#include "core/preset.h"
#include "gui/main_window.h"
#include "gui/pathos2_window.h"
#include "gui/vtk_widget.h"
#include "window_checks.h"
#include "render/field_scene.h"
#include "render/pathos2_scene.h"

using namespace linkscape;
using linkscape::gui::Pathos2Window;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// The numerical FK converges to 1e-12 rad in the actuator angles; the
// nine-sensor closed form is exact up to rounding. Both poses must agree far
// below anything visible: 1e-6 cm.
constexpr double kFkAgreementCm = 1e-6;

// Pixels of the highlight red (the device uses no other saturated red).
int red_pixels(const QImage& image) {
  int n = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QRgb p = image.pixel(x, y);
      if (qRed(p) > 150 && qGreen(p) < 60 && qBlue(p) < 60) ++n;
    }
  return n;
}

void show_fields(Pathos2Window& w, bool slice, bool reach) {
  w.findChild<QCheckBox*>("showSliceBox")->setChecked(slice);
  w.findChild<QCheckBox*>("showReachBox")->setChecked(reach);
}

}  // namespace

class Pathos2WindowTest : public QObject {
  Q_OBJECT

 private slots:
  void init() { QSettings().clear(); }

  void poseSlidersMoveTheModelAndThePicture() {
    Pathos2Window w(load_preset("pathos2"));
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    show_fields(w, false, false);
    wait_settled(w);
    const QImage before = frame(w);
    auto* q1 = w.findChild<QLabel*>("q1Label");
    QVERIFY(q1);
    const QString q1_before = q1->text();

    w.findChild<QSlider*>("xSlider")->setValue(300);  // 3 cm
    QCOMPARE(w.pose().p_world_E.x(), 3.0);
    QCOMPARE(w.ik().status, Status::Ok);
    QVERIFY(q1->text() != q1_before);
    // The legs follow the IK of the pose shown.
    const pathos2::PoseIkResult expected = pathos2::inverse(w.model(), w.pose());
    QVERIFY((expected.q_active - w.activeAngles()).cwiseAbs().maxCoeff() < 1e-12);
    QVERIFY((w.scene().skeleton().p_world_E - w.pose().p_world_E).norm() < 1e-12);
    QVERIFY2(changed_fraction(before, frame(w)) > 0.002, "moving x did not change the picture");

    w.findChild<QDoubleSpinBox*>("rxBox")->setValue(10.0);
    QVERIFY(std::abs(w.pose().rpy().x() - 10.0 * kDeg) < 1e-12);
    QCOMPARE(w.findChild<QSlider*>("rxSlider")->value(), 1000);
  }

  void unreachablePoseKeepsTheLastValidPoseAndNamesTheLeg() {
    Pathos2Window w(load_preset("pathos2"));
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    show_fields(w, false, false);
    wait_settled(w);
    const pathos2::Pose valid = w.pose();
    const int red_before = red_pixels(frame(w));
    auto* status = w.findChild<QLabel*>("poseStatus");
    QVERIFY(status);

    w.findChild<QDoubleSpinBox*>("zBox")->setValue(42.0);  // next to the upper base plate
    const pathos2::PoseIkResult ik = pathos2::inverse(w.model(), pathos2::Pose::from_xyz_rpy(
                                                                     0, 0, 42.0, 0, 0, 30 * kDeg, valid.h0));
    QVERIFY(ik.status != Status::Ok);
    QVERIFY((w.pose().p_world_E - valid.p_world_E).norm() == 0.0);
    const QString expected = QString("leg %1: ").arg(ik.failing_leg + 1);
    QVERIFY2(w.refusal().startsWith(expected), qPrintable(w.refusal()));
    QVERIFY(w.refusal().contains("unreachable") || w.refusal().contains("singular") ||
            w.refusal().contains("out of limits"));
    QCOMPARE(status->text(), w.refusal());
    QCOMPARE(w.scene().highlighted_leg(), ik.failing_leg);
    // The failing leg is drawn in red where the user looks.
    const QImage refused = frame(w);
    refused.save(QDir::currentPath() + "/pathos2_refused.png");  // for inspection
    QVERIFY2(red_pixels(refused) > red_before + 200, "the failing leg is not highlighted in the view");

    // A reachable pose is taken again and clears the message and highlight.
    w.findChild<QDoubleSpinBox*>("zBox")->setValue(24.0);
    QCOMPARE(w.pose().p_world_E.z(), 24.0);
    QVERIFY(w.refusal().isEmpty());
    QCOMPARE(w.scene().highlighted_leg(), -1);
  }

  void actuatorSlidersMoveThePlatesByNumericalFk() {
    Pathos2Window w(load_preset("pathos2"));
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    show_fields(w, false, false);
    wait_settled(w);
    w.setDrive(Pathos2Window::Drive::Actuators);
    QVERIFY(w.findChild<QSlider*>("q1Slider")->isVisible());
    QVERIFY(!w.findChild<QSlider*>("xSlider")->isVisible());
    const QImage before = frame(w);
    const pathos2::Pose start = w.pose();
    auto* q1 = w.findChild<QDoubleSpinBox*>("q1Box");
    auto* q5 = w.findChild<QDoubleSpinBox*>("q5Box");
    QVERIFY(q1 && q5);
    const double q1_target = q1->value() + 6.0, q5_target = q5->value() - 4.0;
    q1->setValue(q1_target);
    q5->setValue(q5_target);
    QVERIFY2(w.refusal().isEmpty(), qPrintable(w.refusal()));
    QVERIFY((w.pose().p_world_E - start.p_world_E).norm() > 0.1);  // the plates moved
    QVERIFY(std::abs(std::remainder(w.activeAngles()(0) - q1_target * kDeg, 2 * std::numbers::pi)) < 1e-9);
    QVERIFY(std::abs(std::remainder(w.activeAngles()(4) - q5_target * kDeg, 2 * std::numbers::pi)) < 1e-9);
    QVERIFY(w.numericFk() && w.nineSensorFk());
    QCOMPARE(w.numericFk()->status, Status::Ok);
    QCOMPARE(w.nineSensorFk()->status, Status::Ok);
    const double dp = (w.numericFk()->pose.p_world_E - w.nineSensorFk()->pose.p_world_E).norm();
    QVERIFY2(dp < kFkAgreementCm, qPrintable(QString("numerical and nine-sensor FK differ by %1 cm").arg(dp)));
    QVERIFY((w.numericFk()->pose.R_world_E - w.nineSensorFk()->pose.R_world_E).norm() < 1e-8);
    QVERIFY(w.findChild<QLabel*>("fkDifferenceLabel")->text().contains("cm"));
    // The pose panel follows, so switching back continues from here.
    QVERIFY(std::abs(w.findChild<QDoubleSpinBox*>("xBox")->value() - w.pose().p_world_E.x()) < 0.006);
    QVERIFY2(changed_fraction(before, frame(w)) > 0.002, "moving actuators did not change the picture");
  }

  void designSliderRecomputesTheSliceCoarseThenFine() {
    Pathos2Window w(load_preset("pathos2"));
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    wait_settled(w);
    QVERIFY(w.fieldScene().slice_visible());
    QVERIFY(w.fieldScene().surface_faces(render::Surface::Reach) > 0);
    QCOMPARE(w.fieldScene().colour_bar_title().substr(0, 8), std::string("cond(Jp)"));
    QSignalSpy slices(&w, &Pathos2Window::sliceUpdated);
    w.findChild<QDoubleSpinBox*>("l2Box")->setValue(15.0);
    QCOMPARE(w.model().l2, 15.0);
    // The change returned before its fields were computed: they run off the GUI thread.
    QVERIFY(!w.fieldsSettled());
    wait_settled(w);
    QVERIFY(slices.size() >= 2);
    QCOMPARE(slices.first().at(0).toBool(), false);  // coarse first
    QCOMPARE(slices.last().at(0).toBool(), true);    // then full resolution

    // cond(Jo) on the same slice (render accepts "cond_jo" for six-DOF fields).
    w.findChild<QComboBox*>("fieldBox")->setCurrentIndex(1);
    QCOMPARE(w.fieldScene().colour_bar_title().substr(0, 8), std::string("cond(Jo)"));
  }

  void sessionRoundTrip() {
    QTemporaryDir dir;
    const QString path = dir.filePath("p2.json");
    Pathos2Window w(load_preset("pathos2"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    pathos2::Model m = w.model();
    m.l2 = 15.0;
    QVERIFY(w.setModel(m));
    const pathos2::Pose p = pathos2::Pose::from_xyz_rpy(1.0, -0.5, 23.0, 0.05, 0.0, 0.6, 6.5);
    QVERIFY(w.setPose(p));
    w.findChild<QComboBox*>("fieldBox")->setCurrentIndex(1);  // cond(Jo)
    QVERIFY(w.saveSession(path));

    Pathos2Window other(load_preset("pathos2"));
    other.show();
    QVERIFY(QTest::qWaitForWindowExposed(&other));
    QVERIFY(other.openSession(path));
    QCOMPARE(other.model().l2, 15.0);
    QCOMPARE(other.findChild<QDoubleSpinBox*>("l2Box")->value(), 15.0);  // the panel shows it
    QVERIFY((other.pose().p_world_E - p.p_world_E).norm() < 1e-12);
    QVERIFY((other.pose().R_world_E - p.R_world_E).norm() < 1e-12);
    QCOMPARE(other.pose().h0, 6.5);
    QCOMPARE(other.findChild<QDoubleSpinBox*>("xBox")->value(), 1.0);  // the pose panel shows it
    QCOMPARE(other.findChild<QComboBox*>("fieldBox")->currentIndex(), 1);
    // A parallel-12r session opens the 12R window in this one's place.
    gui::MainWindow twelve(load_preset("parallel-12r"));
    const QString other_path = dir.filePath("12r.json");
    QVERIFY(twelve.saveSession(other_path));
    QVERIFY(other.openSession(other_path));
    QTRY_VERIFY(!other.isVisible());
    gui::MainWindow* opened = nullptr;
    for (QWidget* top : QApplication::topLevelWidgets())
      if (auto* m = qobject_cast<gui::MainWindow*>(top); m && m != &twelve && m->isVisible()) opened = m;
    QVERIFY(opened);
    QVERIFY((opened->pose() - twelve.pose()).norm() < 1e-12);
    opened->close();
  }

  void homeMatchesBaseline() {
    Pathos2Window w(load_preset("pathos2"));
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    wait_settled(w);
    compare_with_baseline(frame(w), "pathos2_home", 10.0);
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(gui::VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("LinkscapeTests");
  QApplication::setApplicationName("pathos2_window_tests");
  Pathos2WindowTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "test_pathos2_window.moc"
