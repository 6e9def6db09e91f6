// The methods panel: Run measures off the GUI thread and fills the chart (one
// series per method, the rows' numbers) and the table; the table sorts
// numerically; exact and non-finite results are accounted for; hover shows a
// point's method, time and error; Enlarge opens a window that Esc and Ctrl+W
// close; Cancel stops a run; the panel stays usable in the window at
// 1280x800 and 1024x700.
#include <QChart>
#include <QChartView>
#include <QComboBox>
#include <QDockWidget>
#include <QLabel>
#include <QLineSeries>
#include <QPushButton>
#include <QScatterSeries>
#include <QSplitter>
#include <QTableWidget>
#include <QToolTip>
#include <QtTest>

#include <cmath>
#include <limits>

#include "core/preset.h"
#include "gui/window/mechanism_window.h"
#include "gui/figures/method_chart.h"
#include "gui/window/methods_panel.h"
#include "gui/window/vtk_widget.h"
#include "gui/window/methods_view.h"

using linkscape::gui::MethodsPanel;
using linkscape::gui::MethodsView;
using linkscape::methods::MethodRow;

namespace {

constexpr double kFloor = linkscape::gui::kExactErrorFloor;

std::vector<QScatterSeries*> method_series(const MethodsView& view) {
  std::vector<QScatterSeries*> out;
  for (QAbstractSeries* s : view.chart()->series())
    if (auto* scatter = qobject_cast<QScatterSeries*>(s)) out.push_back(scatter);
  return out;
}

MethodRow row(const std::string& method, double seconds, double error) {
  MethodRow r;
  r.mechanism = "parallel-12r";
  r.family = "ik";
  r.method = method;
  r.samples = 100;
  r.seconds_per_evaluation = seconds;
  r.error_median = error;
  r.error_p99 = 2 * error;
  r.error_max = 3 * error;
  r.error_unit = "rad";
  return r;
}

// Rows whose times sort differently as text ("1e-05" < "2e-06") and as numbers.
std::vector<MethodRow> crafted_rows() {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {row("planar", 2e-6, 2.5e-15), row("newton", 1e-5, 1e-12), row("closed", 3e-7, 0),
          row("paper", 9e-8, 4e-9), row("broken", 5e-7, nan)};
}

std::vector<double> column_numbers(const QTableWidget& table, int column) {
  std::vector<double> out;
  for (int i = 0; i < table.rowCount(); ++i) out.push_back(table.item(i, column)->text().toDouble());
  return out;
}

}  // namespace

class TestMethodsPanel : public QObject {
  Q_OBJECT

 private slots:
  void runChartsEveryMethodWithTheRowsNumbers() {
    MethodsPanel panel;
    panel.resize(440, 700);
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    linkscape::Preset preset = linkscape::load_preset("parallel-12r");
    linkscape::apply_overrides(preset, {"L1=1", "L2=0.7"});
    panel.setMechanism(preset);
    panel.setHarnessSize(200, 1);
    QVERIFY(method_series(*panel.view()).empty());
    QSignalSpy finished(&panel, &MethodsPanel::runFinished);
    panel.findChild<QPushButton*>("run")->click();
    QVERIFY(panel.isRunning());
    QVERIFY(!panel.findChild<QPushButton*>("run")->isEnabled());
    // The GUI thread keeps processing events while the worker measures.
    QTRY_VERIFY_WITH_TIMEOUT(finished.count() == 1, 60000);
    QCOMPARE(finished.front().front().toBool(), true);
    QVERIFY(!panel.isRunning());
    const auto& rows = panel.rows();
    QCOMPARE(rows.size(), std::size_t(13));  // 5 IK, 4 Jacobian, 4 conditioning (no fields)
    QVERIFY(panel.statusText().startsWith("Measured"));

    MethodsView& view = *panel.view();
    QCOMPARE(view.families(), QStringList({"ik", "jacobian", "conditioning"}));
    std::size_t charted = 0;
    for (const QString& family : view.families()) {
      view.setFamily(family);
      QCOMPARE(view.family(), family);
      // One series per method of the family, its points the rows' (time, error)
      // in the chart's coordinates (log10).
      std::vector<const MethodRow*> expected;
      for (const auto& r : rows)
        if (QString::fromStdString(r.family) == family) expected.push_back(&r);
      const auto series = method_series(view);
      std::size_t points = 0;
      for (QScatterSeries* s : series) {
        const QList<QPointF> p = s->points();
        std::vector<const MethodRow*> of_method;
        for (const MethodRow* r : expected)
          if (QString::fromStdString(r->method) == s->name()) of_method.push_back(r);
        QCOMPARE(qsizetype(of_method.size()), p.size());
        for (qsizetype k = 0; k < p.size(); ++k) {
          QCOMPARE(std::pow(10.0, p[k].x()), of_method[std::size_t(k)]->seconds_per_evaluation);
          QCOMPARE(std::pow(10.0, p[k].y()), std::max(of_method[std::size_t(k)]->error_median, kFloor));
        }
        points += std::size_t(p.size());
      }
      QCOMPARE(points, expected.size());  // every row of the family, once
      const QString legend = view.findChild<QLabel*>("legend")->text();
      for (QScatterSeries* s : series)
        QVERIFY2(legend.contains(QString(s->name()).replace('-', QChar(0x2011))), qPrintable(legend));
      charted += points;
      // The Pareto front is drawn.
      bool front = false;
      for (QAbstractSeries* s : view.chart()->series())
        front |= s->name() == "Pareto front" && qobject_cast<QLineSeries*>(s)->count() > 0;
      QVERIFY(front);
    }
    QCOMPARE(charted, rows.size());
    auto* table = panel.findChild<QTableWidget*>("table");
    QVERIFY(table);
    QCOMPARE(table->rowCount(), 13);
  }

  void tableSortsNumbersNumerically() {
    MethodsView view;
    view.setRows(crafted_rows());
    QTableWidget& table = *view.table();
    QVERIFY(table.isSortingEnabled());
    table.sortByColumn(3, Qt::AscendingOrder);  // what a click on "time / eval" does
    QCOMPARE(column_numbers(table, 3), std::vector<double>({9e-8, 3e-7, 5e-7, 2e-6, 1e-5}));
    table.sortByColumn(3, Qt::DescendingOrder);
    QCOMPARE(column_numbers(table, 3), std::vector<double>({1e-5, 2e-6, 5e-7, 3e-7, 9e-8}));
    // Errors: numbers in order, the non-finite one after them.
    table.sortByColumn(4, Qt::AscendingOrder);
    QStringList methods;
    for (int i = 0; i < table.rowCount(); ++i) methods << table.item(i, 1)->text();
    QCOMPARE(methods, QStringList({"closed", "planar", "newton", "paper", "broken"}));
    QCOMPARE(table.item(4, 4)->text(), QString("nan"));
    // Text columns sort as text.
    table.sortByColumn(1, Qt::AscendingOrder);
    QCOMPARE(table.item(0, 1)->text(), QString("broken"));
  }

  void exactAndNonFiniteResultsAreAccountedFor() {
    MethodsView view;
    view.setRows(crafted_rows());
    const auto series = method_series(view);
    QCOMPARE(series.size(), std::size_t(4));  // "broken" (NaN error) is only in the table
    for (QScatterSeries* s : series) {
      QVERIFY(s->name() != "broken");
      if (s->name() == "closed") QCOMPARE(s->at(0).y(), std::log10(kFloor));
    }
    QVERIFY2(view.note().contains("1 exact result (error 0) drawn at 1e-18") &&
                 view.note().contains("1 row with a non-finite value or a zero time: only in the table"),
             qPrintable(view.note()));
    QCOMPARE(view.table()->rowCount(), 5);
    QVERIFY(view.pointTip("closed", QPointF(std::log10(3e-7), std::log10(kFloor))).contains("0 (exact; drawn at 1e-18)"));
  }

  void hoverShowsMethodTimeAndError() {
    MethodsView view;
    view.resize(440, 500);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setRows(crafted_rows());
    const QString tip = view.pointTip("planar", QPointF(std::log10(2e-6), std::log10(2.5e-15)));
    QVERIFY2(tip.startsWith("planar") && tip.contains("time: 2 µs per evaluation") &&
                 tip.contains("median error: 2.5e-15 rad"),
             qPrintable(tip));
    QVERIFY(view.pointTip("no such method", QPointF(std::log10(2e-6), std::log10(2.5e-15))).isEmpty());
    // The hover signal of the series shows that text.
    for (QScatterSeries* s : method_series(view))
      if (s->name() == "planar") emit s->hovered(s->at(0), true);
    QTRY_COMPARE(QToolTip::text(), tip);
    QToolTip::hideText();
    QTRY_VERIFY(!QToolTip::isVisible());

    // The mouse over the "paper" marker shows its text.
    auto* chart_view = view.findChild<QChartView*>("chart");
    for (QScatterSeries* s : method_series(view))
      if (s->name() == "paper") {
        const QPointF in_chart = view.chart()->mapToPosition(s->at(0), s);
        const QPoint at = chart_view->mapFromScene(view.chart()->mapToScene(in_chart));
        QTest::mouseMove(chart_view->viewport(), at + QPoint(0, 8));
        QTest::mouseMove(chart_view->viewport(), at);
      }
    QTRY_VERIFY(QToolTip::isVisible());
    QVERIFY2(QToolTip::text().startsWith("paper") && QToolTip::text().contains("90 ns per evaluation"),
             qPrintable(QToolTip::text()));
  }

  void zoomAndReset() {
    MethodsView view;
    view.resize(440, 500);
    view.show();
    QVERIFY(QTest::qWaitForWindowExposed(&view));
    view.setRows(crafted_rows());
    const auto range = [&] {
      auto* axis = view.chart()->axes(Qt::Horizontal).front();
      return std::make_pair(axis->property("min").toDouble(), axis->property("max").toDouble());
    };
    const auto all = range();
    QVERIFY(all.first <= std::log10(9e-8) && all.second >= std::log10(1e-5));
    // A rubber band dragged with the mouse over the middle of the plot zooms in.
    auto* chart_view = view.findChild<QChartView*>("chart");
    const QRectF plot = view.chart()->plotArea().adjusted(60, 40, -60, -40);
    auto to_view = [&](QPointF p) { return chart_view->mapFromScene(view.chart()->mapToScene(p)); };
    QTest::mousePress(chart_view->viewport(), Qt::LeftButton, {}, to_view(plot.topLeft()));
    QTest::mouseMove(chart_view->viewport(), to_view(plot.center()));
    QTest::mouseMove(chart_view->viewport(), to_view(plot.bottomRight()));
    QTest::mouseRelease(chart_view->viewport(), Qt::LeftButton, {}, to_view(plot.bottomRight()));
    QTRY_VERIFY(range().second - range().first < all.second - all.first);
    view.findChild<QPushButton*>("resetZoom")->click();
    QCOMPARE(range(), all);
    // So does zoomIn; a double-click zooms out again.
    view.chart()->zoomIn(view.chart()->plotArea().adjusted(50, 50, -50, -50));
    QVERIFY(range().second - range().first < all.second - all.first);
    QTest::mouseDClick(chart_view->viewport(), Qt::LeftButton, {}, to_view(view.chart()->plotArea().center()));
    QCOMPARE(range(), all);
  }

  void enlargeOpensAWindowThatEscAndCtrlWClose() {
    MethodsPanel panel;
    panel.show();
    QVERIFY(QTest::qWaitForWindowExposed(&panel));
    QVERIFY(!panel.enlargedWindow());
    panel.findChild<QPushButton*>("enlarge")->click();
    QWidget* window = panel.enlargedWindow();
    QVERIFY(window);
    QVERIFY(window->isWindow());
    QVERIFY(QTest::qWaitForWindowExposed(window));
    QVERIFY(!window->windowTitle().isEmpty());
    QVERIFY(window->minimumSize() != window->maximumSize());  // resizable
    const QSize screen = window->screen()->availableGeometry().size();
    QVERIFY2(window->width() < screen.width() && window->width() >= screen.width() / 2,
             qPrintable(QString("%1 of %2").arg(window->width()).arg(screen.width())));
    QVERIFY(window->findChild<MethodsView*>());
    QTest::keyClick(window, Qt::Key_Escape);
    QTRY_VERIFY(!window->isVisible());

    panel.enlarge();
    QTRY_VERIFY(window->isVisible());
    window->activateWindow();
    QVERIFY(QTest::qWaitForWindowActive(window));
    QTest::keyClick(window, Qt::Key_W, Qt::ControlModifier);
    QTRY_VERIFY(!window->isVisible());
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

  // The window at two screen sizes with the Methods tab raised: the status
  // shown whole, the chart and at least three table rows in view. With
  // LINKSCAPE_SCREENSHOTS set to a folder, writes window-methods-WxH.png there.
  void panelIsUsableInTheWindowAtSmallScreens() {
    for (const QSize size : {QSize(1280, 800), QSize(1024, 700)}) {
      linkscape::gui::MechanismWindow w(linkscape::load_preset("parallel-12r"));
      w.resize(size);
      w.show();
      QVERIFY(QTest::qWaitForWindowExposed(&w));
      w.findChild<QDockWidget*>("methodsDock")->raise();
      auto* panel = w.findChild<MethodsPanel*>();
      panel->setHarnessSize(200, 1);
      QSignalSpy finished(panel, &MethodsPanel::runFinished);
      panel->run();
      QTRY_VERIFY_WITH_TIMEOUT(finished.count() == 1, 120000);
      QTest::qWait(200);
      auto* status = panel->findChild<QLabel*>("status");
      QVERIFY(status->isVisible());
      QVERIFY2(status->height() >= status->heightForWidth(status->width()),
               qPrintable(QString("status %1 px high, needs %2").arg(status->height()).arg(status->heightForWidth(status->width()))));
      auto* chart = panel->findChild<QWidget*>("chart");
      QVERIFY2(chart->isVisible() && chart->height() >= 200 && chart->width() >= 260,
               qPrintable(QString("chart %1x%2").arg(chart->width()).arg(chart->height())));
      auto* table = panel->findChild<QTableWidget*>("table");
      const int visible_rows = table->viewport()->height() / table->rowHeight(0);
      QVERIFY2(table->isVisible() && visible_rows >= 3, qPrintable(QString("%1 table rows in view").arg(visible_rows)));
      // Everything inside the screen: the panel ends within the window.
      const QRect in_window(panel->mapTo(&w, QPoint(0, 0)), panel->size());
      QVERIFY(w.rect().contains(in_window));
      const QString folder = qEnvironmentVariable("LINKSCAPE_SCREENSHOTS");
      if (!folder.isEmpty()) {
        const QString name = QString("%1/window-methods-%2x%3").arg(folder).arg(size.width()).arg(size.height());
        QVERIFY(linkscape::gui::VtkWidget::grabWindow(&w).save(name + ".png"));
        panel->view()->setFamily("jacobian");
        QTest::qWait(200);  // the chart lays out its new axes on the next event loop pass
        QVERIFY(panel->grab().save(name + "-jacobian.png"));
        panel->enlarge();
        QVERIFY(QTest::qWaitForWindowExposed(panel->enlargedWindow()));
        QVERIFY(panel->enlargedWindow()->grab().save(name + "-enlarged.png"));
      }
    }
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
