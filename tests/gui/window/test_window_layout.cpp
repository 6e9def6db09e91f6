// The window's layout at the sizes users run it at (1024x700 to 1600x1000):
// the colour bar beside the scene, never over it; the state read-outs in
// view; one scroll area per panel, never one inside another; and a tooltip
// on every control of every panel, for every device. LINKSCAPE_SCREENSHOTS=<folder> also saves
// each size with the Drive and the Field tab in front, to look at.
#include <QAbstractButton>
#include <QAbstractSlider>
#include <QAbstractSpinBox>
#include <QApplication>
#include <QComboBox>
#include <QDir>
#include <QDockWidget>
#include <QGroupBox>
#include <QLabel>
#include <QMainWindow>
#include <QProgressBar>
#include <QScrollArea>
#include <QtTest>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>

#include "core/preset.h"
#include "gui/window/field_job.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/docks.h"
#include "gui/window/vtk_widget.h"
#include "render/field_scene.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {


void save(QWidget& w, const QString& name) {
  const QByteArray folder = qgetenv("LINKSCAPE_SCREENSHOTS");
  if (!folder.isEmpty()) gui::VtkWidget::grabWindow(&w).save(QDir(QString::fromLocal8Bit(folder)).filePath(name));
}

}  // namespace

class WindowLayoutTest : public QObject {
  Q_OBJECT

 private slots:
  // The status bar's progress bar shows only work that lasts and moves at
  // most every 100 ms (each step repaints at once); a pause in the reports
  // (a superseded job never reports its end) starts the clock again.
  void progressBarShowsOnlyLastingWork() {
    QMainWindow window;
    auto* view = new gui::VtkWidget(&window);
    window.setCentralWidget(view);
    gui::FieldJobRunner runner;
    const gui::FieldStatus status = gui::add_field_status(&window, view, {&runner}, [] {});
    QProgressBar* bar = status.progress;
    const auto report = [&](double f) { emit runner.progress(f); };
    report(0.1);
    QVERIFY(!bar->isVisibleTo(&window));  // a short job never shows it
    for (double f : {0.2, 0.3}) {  // reports 100 ms apart (a pause would start the clock again)
      QTest::qWait(100);
      report(f);
    }
    QVERIFY(!bar->isVisibleTo(&window));
    QTest::qWait(150);
    report(0.4);
    QVERIFY(bar->isVisibleTo(&window));
    QCOMPARE(bar->value(), 40);
    report(0.45);
    QCOMPARE(bar->value(), 40);  // within 100 ms of the last step
    QTest::qWait(120);
    report(0.6);
    QCOMPARE(bar->value(), 60);
    report(1.0);
    QVERIFY(!bar->isVisibleTo(&window));
    // A job superseded before its end, then a pause: the next one starts from zero.
    report(0.2);
    QTest::qWait(200);
    report(0.3);
    QTest::qWait(400);
    report(0.5);
    QTest::qWait(100);
    report(0.6);
    QVERIFY(!bar->isVisibleTo(&window));
  }

  void layoutHoldsFromSmallToLarge_data() {
    QTest::addColumn<QString>("device");
    QTest::addColumn<QSize>("size");
    for (const char* device : {"parallel-12r", "pathos2"})
      for (const QSize size : {QSize(1024, 700), QSize(1280, 800), QSize(1600, 1000)})
        QTest::newRow(qPrintable(QString("%1 %2x%3").arg(device).arg(size.width()).arg(size.height())))
            << QString(device) << size;
  }

  void layoutHoldsFromSmallToLarge() {
    QFETCH(QString, device);
    QFETCH(QSize, size);
    MechanismWindow w(load_preset(device.toStdString()));
    w.resize(size);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    QVERIFY(QTest::qWaitFor([&] { return w.fieldsSettled(); }, 30000));
    QTest::qWait(100);

    // The colour bar has a strip of its own: the scene's viewport ends where it begins.
    vtkRendererCollection* renderers = w.view()->renderWindow()->GetRenderers();
    QCOMPARE(renderers->GetNumberOfItems(), 3);
    vtkRenderer* scene = renderers->GetFirstRenderer();
    auto* legend = vtkRenderer::SafeDownCast(renderers->GetItemAsObject(1));
    // The handles' layer lies over the scene, through its camera and viewport.
    auto* handles = vtkRenderer::SafeDownCast(renderers->GetItemAsObject(2));
    QCOMPARE(handles->GetLayer(), 1);
    QCOMPARE(handles->GetActiveCamera(), scene->GetActiveCamera());
    for (int k = 0; k < 4; ++k) QCOMPARE(handles->GetViewport()[k], scene->GetViewport()[k]);
    QVERIFY(w.fieldScene().colour_bar_visible());
    QVERIFY(legend->GetDraw());
    QVERIFY(scene->GetViewport()[2] <= legend->GetViewport()[0] + 1e-12);
    const double strip_px = (legend->GetViewport()[2] - legend->GetViewport()[0]) * w.view()->width();
    QVERIFY2(strip_px >= 100, qPrintable(QString("colour bar strip %1 px").arg(strip_px)));
    QVERIFY(scene->GetViewport()[2] >= 0.7);  // the scene keeps most of the view

    // The state read-outs are in view with the Drive tab in front.
    w.findChild<QDockWidget*>("driveDock")->raise();
    QTest::qWait(50);
    auto* status = w.findChild<QLabel*>("statusLabel");
    QVERIFY(status->isVisible());
    QVERIFY(!status->visibleRegion().isEmpty());
    save(w, QString("layout-%1-%2x%3-drive.png").arg(device).arg(size.width()).arg(size.height()));

    // Every panel scrolls in one scroll area (its dock's), never in one inside
    // another (tables and charts scroll their own content, as they should).
    for (QDockWidget* dock : w.findChildren<QDockWidget*>())
      QVERIFY2(dock->findChildren<QScrollArea*>().size() == 1, qPrintable(dock->objectName()));
    w.findChild<QDockWidget*>("fieldDock")->raise();
    QTest::qWait(50);
    save(w, QString("layout-%1-%2x%3-field.png").arg(device).arg(size.width()).arg(size.height()));
  }
};

// Lists every control in the window's panels without a tooltip: each slider,
// spin box, combo box, check box and button says what it does.
class WindowTooltipTest : public QObject {
  Q_OBJECT
 private slots:
  void everyControlExplainsItself() {
    for (const char* device : {"parallel-12r", "pathos2", "delta"}) {
      MechanismWindow w(load_preset(device));
      w.resize(1280, 800);
      w.show();
      QVERIFY(QTest::qWaitForWindowExposed(&w));
      QStringList missing;
      // The docks, and the error panel above the view (hidden until a preset fails to load).
      QList<QWidget*> panels;
      for (QDockWidget* dock : w.findChildren<QDockWidget*>()) panels << dock;
      panels << w.findChild<QWidget*>("errorPanel");
      QVERIFY(panels.back());
      for (QWidget* dock : panels)
        for (QWidget* c : dock->findChildren<QWidget*>()) {
          const bool control = qobject_cast<QAbstractSlider*>(c) && !c->inherits("QScrollBar");
          const bool input = control || qobject_cast<QAbstractSpinBox*>(c) || qobject_cast<QComboBox*>(c) ||
                             qobject_cast<QAbstractButton*>(c);
          if (!input || c->toolTip().isEmpty() == false) continue;
          if (c->parentWidget() && c->parentWidget()->inherits("QAbstractSpinBox")) continue;  // its arrows
          if (c->inherits("QDockWidgetTitleButton") || c->inherits("QTableCornerButton") ||
              c->objectName().startsWith("qt_"))
            continue;  // Qt's own
          missing << dock->objectName() + ": " + c->metaObject()->className() + " '" + c->objectName() + "' " +
                         (qobject_cast<QAbstractButton*>(c) ? qobject_cast<QAbstractButton*>(c)->text() : QString());
        }
      for (const QString& m : missing) qWarning("%s: no tooltip: %s", device, qPrintable(m));
      QVERIFY2(missing.isEmpty(), qPrintable(QString("%1 controls of %2 have no tooltip").arg(missing.size()).arg(device)));
    }
  }
};

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  WindowLayoutTest layout;
  WindowTooltipTest tooltips;
  return QTest::qExec(&layout, argc, argv) | QTest::qExec(&tooltips, argc, argv);
}
#include "test_window_layout.moc"
