// The window, driven as a user drives it: sliders and spin boxes move the
// model, and the picture changes with them.
#include <QDoubleSpinBox>
#include <QLabel>
#include <QSet>
#include <QSlider>
#include <QtTest>
#include <numbers>

#include "core/preset.h"
#include "gui/main_window.h"
#include "gui/vtk_widget.h"

using namespace linkscape;
using linkscape::gui::MainWindow;

namespace {

// Number of distinct colours: a blank or black view has a handful.
int distinct_colours(const QImage& image) {
  QSet<QRgb> colours;
  for (int y = 0; y < image.height(); y += 2)
    for (int x = 0; x < image.width(); x += 2) colours.insert(image.pixel(x, y));
  return int(colours.size());
}

// Fraction of pixels that differ by more than a small tolerance per channel.
double changed_fraction(const QImage& a, const QImage& b) {
  if (a.size() != b.size()) return 1.0;
  int changed = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const QRgb p = a.pixel(x, y), q = b.pixel(x, y);
      if (std::abs(qRed(p) - qRed(q)) + std::abs(qGreen(p) - qGreen(q)) + std::abs(qBlue(p) - qBlue(q)) > 24)
        ++changed;
    }
  return double(changed) / (a.width() * a.height());
}

QImage frame(MainWindow& w) {
  w.view()->update();
  QTest::qWait(50);
  return w.view()->grabFramebuffer();
}

}  // namespace

class MainWindowTest : public QObject {
  Q_OBJECT

 private slots:
  void slidersMoveTheModelAndThePicture() {
    MainWindow w(load_preset("parallel-12r"));
    w.resize(1000, 700);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    const QImage before = frame(w);
    QVERIFY2(distinct_colours(before) > 50, "the 3-D view looks blank");

    auto* beta = w.findChild<QSlider*>("betaSlider");
    auto* endpoint = w.findChild<QLabel*>("endpointLabel");
    QVERIFY(beta && endpoint);
    const QString endpoint_before = endpoint->text();
    beta->setValue(beta->value() - 400);  // 40 degrees
    QCOMPARE(w.pose().y(), (beta->value() / 10.0) * std::numbers::pi / 180.0);
    QVERIFY(endpoint->text() != endpoint_before);
    const Eigen::Vector3d expected = parallel12r::forward(w.model(), w.pose());
    QVERIFY(endpoint->text().startsWith(QString("(%1,").arg(expected.x(), 0, 'g', 4)));
    const QImage after = frame(w);
    QVERIFY2(changed_fraction(before, after) > 0.002, "moving beta did not change the picture");

    // The spin box and the slider stay in step.
    auto* alpha_box = w.findChild<QDoubleSpinBox*>("alphaBox");
    auto* alpha_slider = w.findChild<QSlider*>("alphaSlider");
    alpha_box->setValue(-30.0);
    QCOMPARE(alpha_slider->value(), -300);
    QVERIFY(std::abs(w.pose().x() + 30.0 * std::numbers::pi / 180.0) < 1e-12);
  }

  void linkLengthsRebuildTheLinkage() {
    MainWindow w(load_preset("parallel-12r"));
    w.resize(1000, 700);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    const QImage before = frame(w);
    auto* l1 = w.findChild<QDoubleSpinBox*>("L1Box");
    QVERIFY(l1);
    l1->setValue(8.0);
    QCOMPARE(w.model().L1, 8.0);
    QCOMPARE(w.model().L2, 15.0);
    QVERIFY(changed_fraction(before, frame(w)) > 0.002);
  }

  void conditionReadoutFollowsThePose() {
    MainWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    w.setPose(parallel12r::home_pose(0));  // c(J) = 1 for L1 = L2
    QCOMPARE(w.findChild<QLabel*>("condLabel")->text(), QString("1"));
    w.setPose(Eigen::Vector3d(0.2, 0.7, 0.7));  // stretched: singular
    QVERIFY(w.findChild<QLabel*>("condLabel")->text().contains("singular"));
    QVERIFY(w.findChild<QLabel*>("singularLabel")->text().startsWith("stretched"));
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(gui::VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  MainWindowTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "test_main_window.moc"
