// The methods panel: Run measures off the GUI thread, fills the table and
// paints the chart; Cancel stops a run; PATHOS-II parameters are accepted.
#include <QLabel>
#include <QPushButton>
#include <QTableWidget>
#include <QtTest>

#include "core/preset.h"
#include "gui/methods_panel.h"

using linkscape::gui::MethodsPanel;

namespace {

// Fraction of pixels of the widget's rendering that are not near-white.
double inked_fraction(QWidget& w) {
  const QImage image = w.grab().toImage().convertToFormat(QImage::Format_RGB32);
  std::size_t inked = 0;
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const QRgb c = image.pixel(x, y);
      if (qRed(c) < 200 || qGreen(c) < 200 || qBlue(c) < 200) ++inked;
    }
  return double(inked) / double(image.width() * image.height());
}

}  // namespace

class TestMethodsPanel : public QObject {
  Q_OBJECT

 private slots:
  void runFillsTheTableAndPaintsTheChart() {
    MethodsPanel panel;
    panel.resize(1000, 800);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    linkscape::Preset preset = linkscape::load_preset("parallel-12r");
    linkscape::apply_overrides(preset, {"L1=1", "L2=0.7"});
    panel.setMechanism(preset);
    panel.setHarnessSize(200, 1);
    auto* chart = panel.findChild<QWidget*>("chart");
    QVERIFY(chart);
    const double blank = inked_fraction(*chart);
    QSignalSpy finished(&panel, &MethodsPanel::runFinished);
    panel.findChild<QPushButton*>("run")->click();
    QVERIFY(panel.isRunning());
    QVERIFY(!panel.findChild<QPushButton*>("run")->isEnabled());
    // The GUI thread keeps processing events while the worker measures.
    QTRY_VERIFY_WITH_TIMEOUT(finished.count() == 1, 60000);
    QCOMPARE(finished.front().front().toBool(), true);
    QVERIFY(!panel.isRunning());
    QCOMPARE(panel.rows().size(), std::size_t(13));  // 5 IK, 4 Jacobian, 4 conditioning (no fields)
    auto* table = panel.findChild<QTableWidget*>("table");
    QVERIFY(table);
    QCOMPARE(table->rowCount(), 13);
    QCOMPARE(table->item(0, 0)->text(), QString("ik"));
    QVERIFY(!table->item(0, 4)->text().isEmpty());
    QVERIFY(panel.statusText().startsWith("Measured"));
    const double drawn = inked_fraction(*chart);
    QVERIFY2(drawn > 0.02 && drawn > 3 * blank,
             qPrintable(QString("inked fraction %1 (before the run %2)").arg(drawn).arg(blank)));
  }

  void pathos2ParametersAndCancel() {
    MethodsPanel panel;
    panel.resize(900, 700);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    panel.setMechanism(linkscape::load_preset("pathos2"));
    panel.setHarnessSize(100, 1);
    QSignalSpy finished(&panel, &MethodsPanel::runFinished);
    panel.run();
    QTRY_VERIFY_WITH_TIMEOUT(finished.count() == 1, 60000);
    QCOMPARE(finished.front().front().toBool(), true);
    for (const auto& r : panel.rows()) QCOMPARE(r.mechanism, std::string("pathos2"));
    QCOMPARE(panel.findChild<QTableWidget*>("table")->rowCount(), int(panel.rows().size()));
    QVERIFY(panel.rows().size() >= 10);

    // A large run cancelled at once keeps the previous rows and says so.
    const auto before = panel.rows().size();
    panel.setHarnessSize(200000, 5);
    panel.run();
    QVERIFY(panel.isRunning());
    panel.findChild<QPushButton*>("cancel")->click();
    QTRY_VERIFY_WITH_TIMEOUT(finished.count() == 2, 60000);
    QCOMPARE(finished.back().front().toBool(), false);
    QCOMPARE(panel.rows().size(), before);
    QCOMPARE(panel.statusText(), QString("Cancelled."));
  }

  void destroyingARunningPanelStopsItsWorker() {
    auto* panel = new MethodsPanel;
    panel->setHarnessSize(200000, 5);
    panel->run();
    delete panel;  // cancels and joins; no queued call reaches a dead object
    QTest::qWait(50);
  }
};

QTEST_MAIN(TestMethodsPanel)
#include "test_methods_panel.moc"
