// The window, driven as a user drives it: sliders, link lengths, endpoint
// drags, sessions and animation; checks both the model and the picture.
#include <QCheckBox>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QPushButton>
#include <QSet>
#include <QSignalSpy>
#include <QSlider>
#include <QTemporaryDir>
#include <QtTest>
#include <vtkCoordinate.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkImageData.h>
#include <vtkImageDifference.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkUnsignedCharArray.h>

#include <numbers>

#include "core/preset.h"
#include "gui/main_window.h"
#include "gui/methods_panel.h"
#include "gui/pathos2_window.h"
#include "gui/session.h"
#include "gui/vtk_widget.h"
#include "window_checks.h"
#include "render/field_scene.h"

using namespace linkscape;
using linkscape::gui::MainWindow;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

void show_fields(MainWindow& w, bool slice, bool surfaces) {
  w.findChild<QCheckBox*>("showReachBox")->setChecked(surfaces);
  w.findChild<QCheckBox*>("showWellBox")->setChecked(surfaces);
  for (QCheckBox* c : w.findChildren<QCheckBox*>())
    if (c->text() == "Slice") c->setChecked(slice);
}

}  // namespace

class MainWindowTest : public QObject {
  Q_OBJECT

 private slots:
  void init() { QSettings().clear(); }

  void slidersMoveTheModelAndThePicture() {
    MainWindow w(load_preset("parallel-12r"));
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    show_fields(w, false, false);
    wait_settled(w);
    const QImage before = frame(w);

    auto* beta = w.findChild<QSlider*>("betaSlider");
    auto* endpoint = w.findChild<QLabel*>("endpointLabel");
    QVERIFY(beta && endpoint);
    const QString endpoint_before = endpoint->text();
    beta->setValue(beta->value() - 400);  // 40 degrees
    QCOMPARE(w.pose().y(), (beta->value() / 10.0) * kDeg);
    QVERIFY(endpoint->text() != endpoint_before);
    const Eigen::Vector3d expected = parallel12r::forward(w.model(), w.pose());
    QVERIFY(endpoint->text().startsWith(QString("(%1,").arg(expected.x(), 0, 'g', 4)));
    QVERIFY2(changed_fraction(before, frame(w)) > 0.002, "moving beta did not change the picture");

    auto* alpha_box = w.findChild<QDoubleSpinBox*>("alphaBox");
    auto* alpha_slider = w.findChild<QSlider*>("alphaSlider");
    alpha_box->setValue(-30.0);
    QCOMPARE(alpha_slider->value(), -300);
    QVERIFY(std::abs(w.pose().x() + 30.0 * kDeg) < 1e-12);
  }

  void linkLengthRecomputesFieldsCoarseThenFine() {
    MainWindow w(load_preset("parallel-12r"));
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    wait_settled(w);
    const std::size_t faces_before = w.fieldScene().surface_faces(render::Surface::Reach);
    QVERIFY(faces_before > 0);
    QSignalSpy updates(&w, &MainWindow::fieldsUpdated);
    w.findChild<QDoubleSpinBox*>("L1Box")->setValue(8.0);
    QCOMPARE(w.model().L1, 8.0);
    QCOMPARE(w.model().L2, 15.0);
    wait_settled(w);
    // The first answer is the coarse one, and a fine one follows.
    QVERIFY(updates.size() >= 2);
    QCOMPARE(updates.first().at(0).toBool(), false);
    QCOMPARE(updates.last().at(0).toBool(), true);
    // L1 != L2 makes the reachable set a shell: the inner sphere appears.
    QVERIFY(w.fieldScene().surface_faces(render::Surface::Reach) > faces_before);
  }

  void endpointDragNeverChangesBranch() {
    MainWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    for (int start_branch : {0, 1}) {
      QVERIFY(w.moveEndpointTo({-12, 16, -8}, start_branch));
      QCOMPARE(w.branch(), start_branch);
      // A drag across the workspace, through the region where both branches
      // come close to each other (near the z axis and the outer sphere).
      for (int i = 0; i <= 200; ++i) {
        const double t = i / 200.0;
        const Eigen::Vector3d target = Eigen::Vector3d(-12, 16, -8) * (1 - t) + Eigen::Vector3d(14, 4, 22) * t;
        QVERIFY2(w.moveEndpointTo(target), qPrintable(w.endpointMessage()));
        QCOMPARE(w.branch(), start_branch);
        QVERIFY((parallel12r::forward(w.model(), w.pose()) - target).norm() < 1e-9);
      }
    }
    // Unreachable: the pose stays, the panel says why.
    const Eigen::Vector3d kept = w.pose();
    QVERIFY(!w.moveEndpointTo({0, 40, 0}));
    QCOMPARE(w.pose(), kept);
    QVERIFY(w.endpointMessage().startsWith("Unreachable"));
    QVERIFY(w.findChild<QLabel*>("endpointStatus")->text().startsWith("Unreachable"));
    // Singular: on the actuator plane.
    QVERIFY(!w.moveEndpointTo({5, 0, 5}));
    QCOMPARE(w.pose(), kept);
    QVERIFY(w.endpointMessage().startsWith("Singular"));
    // A jump across the actuator plane is refused rather than taken.
    QVERIFY(!w.moveEndpointTo({10, -15, 10}));
    QCOMPARE(w.pose(), kept);
  }

  void mouseDragOfTheHandleMovesTheEndpoint() {
    MainWindow w(load_preset("parallel-12r"));
    w.resize(1200, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    show_fields(w, false, false);
    wait_settled(w);
    frame(w);
    vtkRenderer* renderer = w.view()->renderWindow()->GetRenderers()->GetFirstRenderer();
    const Eigen::Vector3d d = parallel12r::forward(w.model(), w.pose());
    vtkNew<vtkCoordinate> c;
    c->SetCoordinateSystemToWorld();
    c->SetValue(d.x(), d.y(), d.z());
    const int* px = c->GetComputedDisplayValue(renderer);  // origin bottom left, device pixels
    const double dpr = w.view()->devicePixelRatioF();
    const QPoint start(int(px[0] / dpr), int(w.view()->height() - px[1] / dpr));
    const int branch = w.branch();
    const Eigen::Vector3d q0 = w.pose();
    QTest::mousePress(w.view(), Qt::LeftButton, Qt::NoModifier, start);
    for (int i = 1; i <= 10; ++i) {
      QMouseEvent move(QEvent::MouseMove, QPointF(start + QPoint(0, -4 * i)), w.view()->mapToGlobal(QPointF(start + QPoint(0, -4 * i))),
                       Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
      QApplication::sendEvent(w.view(), &move);
      QTest::qWait(10);
    }
    QTest::mouseRelease(w.view(), Qt::LeftButton, Qt::NoModifier, start + QPoint(0, -40));
    QVERIFY2((w.pose() - q0).norm() > 1e-3, "dragging the handle did not move the linkage");
    QCOMPARE(w.branch(), branch);
    // Moving up on screen raises the endpoint.
    QVERIFY(parallel12r::forward(w.model(), w.pose()).z() > d.z());
  }

  void sessionRoundTrip() {
    QTemporaryDir dir;
    const QString path = dir.filePath("s.json");
    MainWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    w.findChild<QDoubleSpinBox*>("L2Box")->setValue(12.5);
    w.setPose({0.1, 0.9, -0.2});
    w.findChild<QComboBox*>("normalBox")->setCurrentText("z");
    w.findChild<QDoubleSpinBox*>("thresholdBox")->setValue(4.0);
    QVERIFY(w.saveSession(path));

    MainWindow other(load_preset("parallel-12r"));
    other.show();
    QVERIFY(QTest::qWaitForWindowExposed(&other));
    QVERIFY(other.openSession(path));
    QCOMPARE(other.model().L2, 12.5);
    QVERIFY((other.pose() - Eigen::Vector3d(0.1, 0.9, -0.2)).norm() < 1e-12);
    QCOMPARE(other.findChild<QComboBox*>("normalBox")->currentText(), QString("z"));
    QCOMPARE(other.findChild<QDoubleSpinBox*>("thresholdBox")->value(), 4.0);
    QCOMPARE(other.session().camera->position, w.session().camera->position);
    // Recent files remember it.
    QVERIFY(QSettings().value("recentSessions").toStringList().contains(QFileInfo(path).absoluteFilePath()));
    // The shipped preset is recorded by name, so the file opens elsewhere.
    QCOMPARE(gui::load_session(path.toStdString()).mechanism, std::string("parallel-12r"));
    // A length the window's box cannot show is refused before anything changes.
    gui::Session far = other.session();
    far.parameters["L1"] = 100.0;  // the box spans 1.5 .. 45 cm for this preset
    far.pose = {0.3, 0.3, 0.3};
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, other.applySession(far));
    QCOMPARE(other.model().L1, 15.0);
    QVERIFY((other.pose() - Eigen::Vector3d(0.1, 0.9, -0.2)).norm() < 1e-12);
  }

  void animationFollowsACircleInOneBranch() {
    MainWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    show_fields(w, false, false);
    const int branch = w.branch();
    const Eigen::Vector3d d0 = parallel12r::forward(w.model(), w.pose());
    auto* play = w.findChild<QPushButton*>("playButton");
    play->setChecked(true);
    QTest::qWait(600);
    play->setChecked(false);
    const Eigen::Vector3d d1 = parallel12r::forward(w.model(), w.pose());
    QVERIFY((d1 - d0).norm() > 0.5);
    QCOMPARE(w.branch(), branch);
    // The circle lies in the slice plane (normal x): x does not change.
    QVERIFY(std::abs(d1.x() - d0.x()) < 1e-9);
  }

  void presetChooserOpensTheMechanismsWindow() {
    MainWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    auto* chooser = w.findChild<QComboBox*>("presetBox");
    QVERIFY(chooser);
    const int index = chooser->findText("pathos2");
    QVERIFY(index >= 0);
    chooser->setCurrentIndex(index);
    emit chooser->activated(index);
    QTRY_VERIFY(!w.isVisible());  // replaced, not stacked
    gui::Pathos2Window* opened = nullptr;
    for (QWidget* top : QApplication::topLevelWidgets())
      if (auto* p = qobject_cast<gui::Pathos2Window*>(top); p && p->isVisible()) opened = p;
    QVERIFY2(opened, "choosing pathos2 did not open the PATHOS-II window");
    opened->close();  // deletes itself
  }

  void methodsDockMeasuresTheCurrentLinkLengths() {
    MainWindow w(load_preset("parallel-12r"));
    w.resize(1400, 860);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    w.setLinkLengths(12.0, 18.0);
    auto* panel = w.findChild<gui::MethodsPanel*>();
    QVERIFY(panel);
    w.findChild<QDockWidget*>("methodsDock")->raise();
    panel->setHarnessSize(200, 1);
    QSignalSpy finished(panel, &gui::MethodsPanel::runFinished);
    panel->run();
    QTRY_VERIFY_WITH_TIMEOUT(finished.count() == 1, 60000);
    QVERIFY(finished.front().front().toBool());
    QVERIFY(!panel->rows().empty());
    // The run measured the window's lengths, not the preset's.
    QCOMPARE(panel->mechanism().parameters.at("L1"), 12.0);
    QCOMPARE(panel->mechanism().parameters.at("L2"), 18.0);
    QCOMPARE(w.findChild<QDoubleSpinBox*>("L1Box")->value(), 12.0);  // the panel shows them too
    // Enlarge opens the chart in a window of its own, drawn (not blank).
    panel->findChild<QPushButton*>("enlarge")->click();
    QWidget* big = nullptr;
    for (QWidget* top : QApplication::topLevelWidgets())
      if (top->isVisible() && top->windowTitle().contains("speed against accuracy")) big = top;
    QVERIFY(big);
    QVERIFY(QTest::qWaitForWindowExposed(big));
    const QImage chart = big->grab().toImage();
    QVERIFY(chart.width() >= 1000);
    chart.save("methods_chart_window.png");  // for a look by hand; not compared
    big->close();
  }

  void actuatorRangesBoundTheSlidersAndThePose() {
    MainWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    w.setPose({20 * kDeg, 65 * kDeg, 5 * kDeg});
    w.setActuatorRanges({{{-10, 10}, {-180, 180}, {-180, 180}}});
    QCOMPARE(w.findChild<QSlider*>("alphaSlider")->maximum(), 100);  // tenths of a degree
    QCOMPARE(w.findChild<QDoubleSpinBox*>("alphaMaxBox")->value(), 10.0);
    QVERIFY(std::abs(w.pose().x() - 10 * kDeg) < 1e-12);  // the pose is clamped into the range
    QCOMPARE(w.model().alpha_limits.hi, 10 * kDeg);
    // An inverted range is refused; the ranges in force stay, and the boxes show them.
    w.setActuatorRanges({{{5, -5}, {-180, 180}, {-180, 180}}});
    QCOMPARE(w.model().alpha_limits.hi, 10 * kDeg);
    QCOMPARE(w.findChild<QDoubleSpinBox*>("alphaMinBox")->value(), -10.0);
    // Sessions keep them.
    MainWindow other(load_preset("parallel-12r"));
    other.applySession(w.session());
    QCOMPARE(other.findChild<QSlider*>("alphaSlider")->maximum(), 100);
    QCOMPARE(other.model().alpha_limits.lo, -10 * kDeg);
  }

  void pictureMatchesBaselines() {
    MainWindow w(load_preset("parallel-12r"));
    w.resize(1100, 760);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    show_fields(w, false, false);
    wait_settled(w);
    compare_with_baseline(frame(w), "linkage", 10.0);
    show_fields(w, true, true);
    wait_settled(w);
    compare_with_baseline(frame(w), "linkage_and_fields", 10.0);
    // Near a singular pose: alpha close to 90 degrees.
    show_fields(w, false, false);
    w.setPose({85 * kDeg, 40 * kDeg, -30 * kDeg});
    compare_with_baseline(frame(w), "near_singular", 10.0);
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(gui::VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("LinkscapeTests");
  QApplication::setApplicationName("gui_tests");
  MainWindowTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "test_main_window.moc"
