// The window's layout at the sizes users run it at (1024x700 to 1600x1000):
// the colour bar beside the scene, never over it; the state read-outs in
// view; one scroll area per panel, never one inside another; the panels
// reachable from the View menu. LINKSCAPE_SCREENSHOTS=<folder> also saves
// each size with the Drive and the Field tab in front, to look at.
#include <QDir>
#include <QDockWidget>
#include <QGroupBox>
#include <QLabel>
#include <QScrollArea>
#include <QtTest>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>

#include "core/preset.h"
#include "gui/mechanism_window.h"
#include "gui/vtk_widget.h"
#include "render/field_scene.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {


void save(QWidget& w, const QString& name) {
  const QByteArray folder = qgetenv("LINKSCAPE_SCREENSHOTS");
  if (!folder.isEmpty()) w.grab().save(QDir(QString::fromLocal8Bit(folder)).filePath(name));
}

}  // namespace

class WindowLayoutTest : public QObject {
  Q_OBJECT

 private slots:
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
    QCOMPARE(renderers->GetNumberOfItems(), 2);
    vtkRenderer* scene = renderers->GetFirstRenderer();
    auto* legend = vtkRenderer::SafeDownCast(renderers->GetItemAsObject(1));
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

QTEST_MAIN(WindowLayoutTest)
#include "test_window_layout.moc"
