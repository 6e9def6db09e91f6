// The window's Fit tab: a small fit run off the GUI thread (Run returns at
// once) sizes the device to the Task tab's task (the answer is core's for
// the same problem), Apply sets the design's sliders to it, the largest ratio at
// a size keeps every design at that size, Cancel stops a run, and the chart
// and CSV export. With LINKSCAPE_SCREENSHOTS=<folder> it also saves a
// picture of each window with its Fit tab in front.
#include <QCheckBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QPushButton>
#include <QSignalSpy>
#include <QtTest>
#include <filesystem>
#include <fstream>

#include "core/preset.h"
#include "gui/window/fit_panel.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/task_panel.h"
#include "gui/window/vtk_widget.h"

using namespace linkscape;
using linkscape::gui::FitPanel;
using linkscape::gui::MechanismWindow;
namespace fs = std::filesystem;

namespace {

// Coarse sampling: these tests check the panel, not the search (tests/core/test_fit.cpp).
void coarse(FitPanel* panel) { panel->setSearchSettings({24, 1, 1, {}, {}}, 8, 1e-2); }

bool run_and_wait(FitPanel* panel, int timeout_ms = 120000) {
  QSignalSpy finished(panel, &FitPanel::runFinished);
  panel->findChild<QPushButton*>("fitRun")->click();
  if (!finished.wait(timeout_ms)) return false;
  return finished.front().front().toBool();
}

// A sphere `fraction` of the device's size across, at its home point.
std::string sphere_at_home(const MechanismWindow& w, double fraction) {
  const Eigen::Vector3d home = w.mechanism().home_task().head<3>();
  return "sphere:diameter=" + std::to_string(fraction * w.mechanism().size()) + ",centre=" + std::to_string(home.x()) +
         "," + std::to_string(home.y()) + "," + std::to_string(home.z());
}

// The window shown with seed 001's task (a 15 cm sphere, c(J) < 3) in its
// Task tab, links held equal: its Fit tab, or null if it was not shown.
FitPanel* seed_001(MechanismWindow& w) {
  w.resize(1280, 800);
  w.show();
  if (!QTest::qWaitForWindowExposed(&w)) return nullptr;
  w.taskPanel()->setTask("sphere:diameter=15,centre=0,15,10", {"cond<3"});
  w.fitPanel()->setEqual("L1,L2");
  return w.fitPanel();
}

void screenshot(MechanismWindow& w, const std::string& name) {
  const char* folder = std::getenv("LINKSCAPE_SCREENSHOTS");
  if (!folder) return;
  w.findChild<QDockWidget*>("fitDock")->raise();
  QTRY_VERIFY_WITH_TIMEOUT(w.fieldsSettled(), 60000);
  QTest::qWait(300);
  fs::create_directories(folder);
  QVERIFY(gui::VtkWidget::grabWindow(&w).save(QString::fromStdString((fs::path(folder) / ("window-fit-" + name + ".png")).string())));
}

}  // namespace

class FitPanelTest : public QObject {
  Q_OBJECT

 private slots:
  // 12R, L1 = L2 held equal: the smallest design meeting a 15 cm sphere of
  // c(J) < 3 is found off the GUI thread; Apply puts it on the design sliders.
  void smallestSizeThenApplySetsTheDesign() {
    MechanismWindow w(load_preset("parallel-12r"));
    FitPanel* panel = seed_001(w);
    QVERIFY(panel);
    coarse(panel);
    panel->setBounds("L1", 5, 40);
    QSignalSpy finished(panel, &FitPanel::runFinished);
    panel->run();
    QVERIFY(panel->isRunning());  // off the GUI thread: the call returned before the search ended
    QVERIFY(finished.wait(120000));
    QVERIFY(finished.front().front().toBool());
    QVERIFY(panel->result() && panel->result()->best);
    const fit::Row& best = panel->result()->rows[*panel->result()->best];
    // The Task tab's task and criteria, the tab's variables, core's answer.
    QCOMPARE(panel->problem()->task.diameter(), 15.0);
    QVERIFY(!panel->problem()->task.centre);
    QCOMPARE(panel->problem()->criteria.back().text, std::string("cond<3"));
    QCOMPARE(panel->problem()->variables.size(), std::size_t(1));
    QCOMPARE(panel->problem()->variables[0].lo, 5.0);  // the intersection of the group's rows
    QCOMPARE(panel->problem()->variables[0].hi, 40.0);
    const fit::Result direct = fit::solve(*panel->problem());
    QVERIFY(direct.best);
    QCOMPARE(direct.rows[*direct.best].size, best.size);
    QCOMPARE(best.parameters.at("L1"), best.parameters.at("L2"));
    QVERIFY(best.meets && best.ratio >= 1);
    QVERIFY(panel->reportText().contains("smallest design meeting it: L1 = "));
    QVERIFY(panel->reportText().contains("cond<3: worst "));
    QVERIFY(panel->statusText().startsWith("smallest design meeting it"));
    // Every valid design evaluated that is smaller than the answer less its
    // rounding up (to 0.1 on each link at a tolerance of 1e-2) fails the task.
    for (const fit::Row& row : panel->result()->rows)
      if (row.invalid.empty() && row.size < best.size - 0.2 - 1e-9) QVERIFY(!row.meets);

    QVERIFY(std::abs(w.preset().parameters.at("L1") - best.parameters.at("L1")) > 1e-6);  // not yet applied
    panel->findChild<QPushButton*>("fitApply")->click();
    QCOMPARE(w.mechanism().parameters().at("L1"), best.parameters.at("L1"));
    QCOMPARE(w.mechanism().parameters().at("L2"), best.parameters.at("L2"));
    // The design panel shows it, to the box's decimals.
    auto* box = w.findChild<QDoubleSpinBox*>("L1Box");
    QVERIFY(std::abs(box->value() - best.parameters.at("L1")) <= 0.5 * std::pow(10.0, -box->decimals()));
    QVERIFY(w.mechanism().size() == best.size);
    // The task moves to where the search placed it, and meets the criteria there.
    QCOMPARE(w.findChild<QDoubleSpinBox*>("taskCentreY")->value(),
             w.findChild<QDoubleSpinBox*>("taskCentreY")->valueFromText(
                 w.findChild<QDoubleSpinBox*>("taskCentreY")->textFromValue(best.centre.y())));
    w.taskPanel()->evaluateNow();
    QVERIFY(w.taskPanel()->report());
    QVERIFY2(w.taskPanel()->report()->fraction > 0.99, "the placed task is (nearly all) in the good region");
    screenshot(w, "12r");
  }

  // One verdict: at fit's evaluation (the Task tab's resolution), the Task
  // tab after Apply gives the Fit tab's verdict on the same samples, in the
  // same words; the report's words and the CSV's meets agree.
  void theTaskTabAfterApplyGivesTheFitTabsVerdict() {
    MechanismWindow w(load_preset("parallel-12r"));
    FitPanel* panel = seed_001(w);
    QVERIFY(panel);
    panel->setSearchSettings({24, 1, 1, {}, {}}, task::kTaskResolution, 1e-2);
    panel->setBounds("L1", 5, 40);
    QVERIFY(run_and_wait(panel));
    QVERIFY(panel->result()->best);
    const fit::Row& best = panel->result()->rows[*panel->result()->best];
    const QString verdict = QString::fromStdString(task::verdict_text(best.report));
    QVERIFY2(verdict.startsWith("meets every criterion at all "), qPrintable(verdict));
    QVERIFY2(panel->reportText().contains("verdict: " + verdict), qPrintable(panel->reportText()));
    QVERIFY2(panel->statusText().contains(verdict), qPrintable(panel->statusText()));
    panel->findChild<QPushButton*>("fitApply")->click();
    w.taskPanel()->evaluateNow();
    const task::TaskReport& shown = *w.taskPanel()->report();
    QCOMPARE(shown.centre, best.centre);
    QCOMPARE(shown.samples, best.report.samples);
    QCOMPARE(shown.failing, best.report.failing);
    QCOMPARE(shown.criteria[1].worst, best.report.criteria[1].worst);
    QString words = verdict;
    words[0] = words[0].toUpper();
    QVERIFY2(w.findChild<QLabel*>("taskReadout")->text().contains(words),
             qPrintable(w.findChild<QLabel*>("taskReadout")->text()));
    // The CSV's meets is the same verdict.
    const fs::path csv = fs::temp_directory_path() / "linkscape_fit_panel_verdict.csv";
    panel->exportCsv(csv);
    std::ifstream in(csv);
    std::string header, first;
    std::getline(in, header);
    std::getline(in, first);
    QVERIFY(header.find(",meets,samples,failing,") != std::string::npos);
    QVERIFY2(first.find(",1," + std::to_string(best.report.samples) + ",0,") != std::string::npos, first.c_str());
  }

  // Placement: the centre within the region the tab gives, on the far side
  // of the base from the home point; bad region text is refused.
  void theCentreStaysWithinTheRegionGiven() {
    MechanismWindow w(load_preset("parallel-12r"));
    FitPanel* panel = seed_001(w);
    QVERIFY(panel);
    coarse(panel);
    panel->setBounds("L1", 10, 20);
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, panel->setCentreRegion("box:min=0,0,0"));
    QCOMPARE(panel->centreRegion(), std::string());
    panel->setCentreRegion("box:min=-5,-30,-30,max=5,0,0");
    QVERIFY(run_and_wait(panel));
    QCOMPARE(panel->problem()->inscribed.centres->text, std::string("box:min=-5,-30,-30,max=5,0,0"));
    const auto centre = panel->chosenCentre();
    QVERIFY(centre);
    QVERIFY2(panel->problem()->inscribed.centres->contains(*centre), qPrintable(panel->reportText()));
    QVERIFY(panel->reportText().contains("centre free within box:min=-5,-30,-30,max=5,0,0"));
    QVERIFY(panel->reportText().contains("from the home point"));
  }

  void exportsAfterTheSmallestSize() {
    MechanismWindow w(load_preset("parallel-12r"));
    FitPanel* panel = seed_001(w);
    QVERIFY(panel);
    coarse(panel);
    QVERIFY(run_and_wait(panel));

    const fs::path dir = fs::temp_directory_path() / "linkscape_fit_panel";
    fs::create_directories(dir);
    for (const char* file : {"pareto.png", "pareto.svg", "pareto.pdf", "designs.csv"}) {
      fs::remove(dir / file);
      if (fs::path(file).extension() == ".csv") panel->exportCsv(dir / file);
      else panel->exportChart(dir / file);
      QVERIFY2(fs::file_size(dir / file) > 100, file);
    }
    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, panel->exportCsv(dir / "designs.txt"));
  }

  // The Delta at its own size: every design evaluated has that size, and
  // the chosen one has the largest ratio of them.
  void largestMarginAtASizeKeepsTheSize() {
    MechanismWindow w(load_preset("delta"));
    w.resize(1280, 800);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    const double size = w.mechanism().size();
    w.taskPanel()->setTask(sphere_at_home(w, 0.3), {"cond<4"});
    FitPanel* panel = w.fitPanel();
    coarse(panel);
    panel->setMode(FitPanel::Mode::LargestMarginAtSize, size);
    QVERIFY(run_and_wait(panel));
    const fit::Result& r = *panel->result();
    const auto chosen = r.best ? r.best : r.closest;
    QVERIFY(chosen);
    for (const fit::Row& row : r.rows) {
      if (!row.invalid.empty()) continue;
      QVERIFY(std::abs(row.size - size) < 1e-9 * size);
      QVERIFY(row.ratio <= r.rows[*chosen].ratio);
    }
    QVERIFY(panel->reportText().contains("held at"));
    panel->applyDesign();
    QCOMPARE(w.mechanism().parameters().at("La"), r.rows[*chosen].parameters.at("La"));
    screenshot(w, "delta");
  }

  // Every device: the tab is built from its description (a row per design
  // parameter, the size's terms ticked), and a small fit at the device's
  // own size runs through the interface.
  void everyDeviceBuildsItsTabAndRuns() {
    for (const std::string& name : registered_mechanisms()) {
      MechanismWindow w(load_preset(name));
      w.resize(1280, 800);
      w.show();
      QVERIFY(QTest::qWaitForWindowExposed(&w));
      const std::vector<std::string> sized = fit::size_terms(w.mechanism().info());
      for (const Quantity& q : w.mechanism().info().parameters) {
        auto* box = w.findChild<QCheckBox*>(QString::fromStdString("fitFree_" + q.name));
        QCOMPARE(box != nullptr, q.in_panel);
        if (box) QCOMPARE(box->isChecked(), std::find(sized.begin(), sized.end(), q.name) != sized.end());
      }
      const double size = w.mechanism().size();
      w.taskPanel()->setTask(sphere_at_home(w, 0.1), {"cond<20"});
      FitPanel* panel = w.fitPanel();
      coarse(panel);
      panel->setCentreFree(false);
      panel->setMode(FitPanel::Mode::LargestMarginAtSize, size);
      QVERIFY2(run_and_wait(panel), name.c_str());
      const fit::Result& r = *panel->result();
      QVERIFY2(r.best, qPrintable(panel->reportText()));  // the device's own design meets a small task at home
      QVERIFY(r.rows[*r.best].ratio >= 1);
      if (name == "pathos2") screenshot(w, name);
    }
  }

  // Bad input is said in the status; Cancel stops a run and keeps the GUI alive.
  void badInputAndCancel() {
    MechanismWindow w(load_preset("parallel-12r"));
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    w.taskPanel()->setTask("sphere:diameter=15,centre=0,15,10", {"cond<3"});
    FitPanel* panel = w.fitPanel();
    panel->setBounds("L1", 30, 10);
    QVERIFY(!run_and_wait(panel));
    QVERIFY2(panel->statusText().contains("lo <= hi"), qPrintable(panel->statusText()));
    panel->setBounds("L1", 1.5, 45);
    panel->setMode(FitPanel::Mode::LargestMarginAtSize, 500);
    QVERIFY(!run_and_wait(panel));
    QVERIFY2(panel->statusText().contains("no design within the bounds has size"), qPrintable(panel->statusText()));
    QVERIFY(!panel->result());

    // Links too short for the task: a result, the closest design, not an error.
    panel->setMode(FitPanel::Mode::SmallestSize);
    coarse(panel);
    panel->setEqual("L1,L2");
    panel->setBounds("L1", 2, 5);
    panel->setBounds("L2", 2, 5);
    QVERIFY(run_and_wait(panel));
    QVERIFY(panel->result() && !panel->result()->best && panel->result()->closest);
    QVERIFY2(panel->statusText().startsWith("no design in the bounds meets it; closest: L1 = 5"),
             qPrintable(panel->statusText()));
    QCOMPARE(panel->chosenDesign().at("L2"), 5.0);

    panel->setSearchSettings({96, 2, 3, {}, {}}, 24, 1e-3);  // long enough to cancel
    QSignalSpy finished(panel, &FitPanel::runFinished);
    panel->run();
    QVERIFY(panel->isRunning());
    QTest::qWait(200);
    panel->cancel();
    QVERIFY(finished.wait(60000));
    QCOMPARE(finished.front().front().toBool(), false);
    QCOMPARE(panel->statusText(), QString("Cancelled."));
    QVERIFY(!panel->isRunning());
  }
};

int main(int argc, char** argv) {
  QSurfaceFormat::setDefaultFormat(gui::VtkWidget::defaultFormat());
  QApplication app(argc, argv);
  FitPanelTest test;
  return QTest::qExec(&test, argc, argv);
}

#include "test_fit_panel.moc"
