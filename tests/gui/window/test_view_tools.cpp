// The view as an instrument: a click on the slice reads the field there, two
// Shift+clicks measure a distance, two clicks in Line probe mode plot a
// field and export it as CSV, the standard views look along their axes, a
// refused target puts the sliders back on the pose the device holds, and
// the handle on the driven point is seen over everything and dragged.
// LINKSCAPE_SCREENSHOTS=<folder> saves the window after the picks, to look at.
#include <QAction>
#include <QApplication>
#include <QCheckBox>
#include <QDir>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QScrollArea>
#include <QSlider>
#include <QStatusBar>
#include <QTabBar>
#include <QTemporaryDir>
#include <QtTest>
#include <cstdio>
#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkMapper.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRendererCollection.h>
#include <vtkCommand.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include <fstream>

#include "core/csv.h"
#include "core/preset.h"
#include "gui/window/device_state.h"
#include "gui/window/field_display.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/pick_tool.h"
#include "gui/window/probe_panel.h"
#include "gui/window/profile_chart.h"
#include "gui/window/view_tools.h"
#include "gui/window/vtk_widget.h"
#include "render/field_scene.h"
#include "render/mark_scene.h"
#include "render/skeleton_scene.h"
#include "window_checks.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

namespace {

// Display pixel (VTK's, origin bottom left) of a world point.
std::array<int, 2> to_display(vtkRenderer* r, const Eigen::Vector3d& p) {
  r->SetWorldPoint(p.x(), p.y(), p.z(), 1.0);
  r->WorldToDisplay();
  const double* d = r->GetDisplayPoint();
  return {int(std::lround(d[0])), int(std::lround(d[1]))};
}

// A click as the view hands it to VTK: press and release at one pixel.
void click(vtkRenderWindowInteractor* i, std::array<int, 2> at, bool shift = false) {
  i->SetEventInformation(at[0], at[1], 0, shift ? 1 : 0);
  i->InvokeEvent(vtkCommand::LeftButtonPressEvent);
  i->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
}

vtkRenderer* scene_renderer(MechanismWindow& w) { return w.view()->renderWindow()->GetRenderers()->GetFirstRenderer(); }

// Reachable sample centres of the slice that a click lands on (the linkage
// may stand in front of some), with the pixel to click.
struct Target {
  std::size_t sample;
  Eigen::Vector3d point;
  std::array<int, 2> pixel;
};
std::vector<Target> slice_targets(MechanismWindow& w, const Field& slice) {
  std::vector<Target> out;
  vtkRenderer* r = scene_renderer(w);
  const Grid& g = slice.grid;
  // Every third sample along the slice's axes, away from its edges.
  auto from = [&](int a) { return g.dims[a] == 1 ? 0 : 1; };
  auto below = [&](int a) { return g.dims[a] == 1 ? 1 : g.dims[a] - 1; };
  for (int k = from(2); k < below(2); k += 3)
    for (int j = from(1); j < below(1); j += 3)
      for (int i = from(0); i < below(0); i += 3) {
        const std::size_t s = g.index(i, j, k);
        if (!slice.reachable[s]) continue;
        const Eigen::Vector3d p = g.point(i, j, k);
        const auto px = to_display(r, p);
        const auto hit = w.viewTools()->picker()->pickAt(px[0], px[1]);
        if (hit && hit->what == "slice") out.push_back({s, p, px});
      }
  return out;
}

// At 1280x800, on screen.
void show_on_screen(MechanismWindow& w) {
  w.resize(1280, 800);
  w.show();
  QVERIFY(QTest::qWaitForWindowExposed(&w));
}

}  // namespace

class ViewToolsTest : public QObject {
  Q_OBJECT

 private slots:
  void clickOnTheSliceReadsTheFieldThere() {
    MechanismWindow w(load_preset("delta"));
    show_on_screen(w);
    window_checks::wait_settled(w);
    window_checks::frame(w);
    gui::ProbePanel* panel = w.viewTools()->panel();
    const std::vector<Target> targets = slice_targets(w, *fieldOf(w));
    QVERIFY2(targets.size() >= 3, "the slice is in view");
    const Field& field = *fieldOf(w);
    const Target& t = targets[targets.size() / 2];
    click(w.view()->interactor(), t.pixel);
    QVERIFY(panel->sample());
    // No tab's label is cut.
    QApplication::processEvents();
    for (const QTabBar* bar : w.findChildren<QTabBar*>())
      if (bar->isVisible())
        for (int i = 0; i < bar->count(); ++i)
          QVERIFY2(std::max(bar->tabRect(i).width(), bar->tabRect(i).height()) >  // along the text, turned or not
                       bar->fontMetrics().horizontalAdvance(bar->tabText(i)),
                   qPrintable(bar->tabText(i)));
    // No panel is cut off under the tabs: each fits its dock's width (the
    // Field panel's colour controls had run under them at every size).
    for (QDockWidget* dock : w.findChildren<QDockWidget*>()) {
      dock->raise();
      QApplication::processEvents();
      const auto* scroll = qobject_cast<QScrollArea*>(dock->widget());
      if (!scroll || !dock->isVisible()) continue;
      QVERIFY2(scroll->widget()->width() <= scroll->viewport()->width(),
               qPrintable(QString("%1: %2 > %3").arg(dock->windowTitle()).arg(scroll->widget()->width())
                              .arg(scroll->viewport()->width())));
      QVERIFY2(dock->geometry().right() < w.width() - 8, qPrintable(dock->windowTitle()));  // left of the tabs
    }
    const render::ProbeSample& s = *panel->sample();
    // The point hit lies on the slice within a pixel of the aimed sample,
    // whose value the read-out gives there.
    QCOMPARE(field.grid.index(s.nearest[0], s.nearest[1], s.nearest[2]), t.sample);
    const double pixel = (s.point - t.point).norm();
    QVERIFY2(pixel < 0.5 * field.grid.spacing.maxCoeff(), qPrintable(QString::number(pixel)));
    const render::ProbeValue* cond = s.find("cond");
    QVERIFY(cond);
    const double expected = field.cond[t.sample];
    QVERIFY2(std::abs(cond->value - expected) <= 0.05 * expected,
             qPrintable(QString("cond %1 at the pick, %2 at the sample").arg(cond->value).arg(expected)));
    if (qEnvironmentVariableIsSet("PICK_DEBUG")) qInfo("%s", qPrintable(panel->readout()));
    QVERIFY(panel->readout().contains(QString::fromStdString(cond->title)));
    QVERIFY(panel->readout().contains(render::to_string(cond->sampling)));
    QVERIFY(panel->readout().contains("Device pose: ok"));
    // The haptic measures, which the cond slice was not sampled with, at the point itself.
    QVERIFY2(panel->readout().contains("isotropic force") && panel->readout().contains("computed at the point"),
             qPrintable(panel->readout()));
    QVERIFY(panel->readout().contains(w.state().mechanism().info().length_unit.c_str()));
    QVERIFY(w.viewTools()->marks().pick_visible());

    // Hover: the resting mouse reads where it rests.
    const Target& rest = targets.front();
    panel->findChild<QCheckBox*>("probeHoverBox")->setChecked(true);
    w.view()->interactor()->SetEventInformation(rest.pixel[0], rest.pixel[1], 0, 0);
    w.view()->interactor()->InvokeEvent(vtkCommand::MouseMoveEvent);
    QTRY_VERIFY(panel->sample() && field.grid.index(panel->sample()->nearest[0], panel->sample()->nearest[1],
                                                    panel->sample()->nearest[2]) == rest.sample);
    panel->findChild<QCheckBox*>("probeHoverBox")->setChecked(false);

    // The linkage: its driven point.
    const auto tip = to_display(scene_renderer(w), w.endpoint());
    const auto on_device = w.viewTools()->picker()->pickAt(tip[0], tip[1]);
    QVERIFY(on_device);
    // The part is named: the driven point, or a link or joint beside it.
    QVERIFY2(on_device->what == "driven point" || on_device->what.startsWith("link ") ||
                 on_device->what.startsWith("joint "),
             qPrintable(on_device->what));
    QVERIFY((on_device->point - w.endpoint()).norm() < 0.05 * w.mechanism().size());

    // Ruler: two Shift+clicks.
    const Target& a = targets.front();
    const Target& b = targets.back();
    click(w.view()->interactor(), a.pixel, true);
    click(w.view()->interactor(), b.pixel, true);
    QVERIFY(panel->rulerLength());
    const double tolerance = field.grid.spacing.maxCoeff();  // a pixel is far smaller than a sample
    QVERIFY2(std::abs(*panel->rulerLength() - (b.point - a.point).norm()) < tolerance,
             qPrintable(QString("%1 vs %2").arg(*panel->rulerLength()).arg((b.point - a.point).norm())));
    QVERIFY(w.viewTools()->marks().ruler_visible());
    QVERIFY(QString::fromStdString(w.viewTools()->marks().ruler_text()).endsWith(" cm"));

    // Line probe: two clicks, a plot, a CSV that reads back.
    panel->setMode(gui::ProbePanel::Mode::Line);
    click(w.view()->interactor(), a.pixel);
    click(w.view()->interactor(), b.pixel);
    QVERIFY(panel->profile());
    QVERIFY(panel->chart()->pointCount() > 10);
    QTemporaryDir dir;
    const QString path = dir.filePath("probe.csv");
    QVERIFY(panel->exportProfile(path));
    std::ifstream in(path.toStdString());
    const Table table = read_csv(in, path.toStdString());
    QCOMPARE(table.rows.size(), panel->profile()->values.size());
    const std::size_t value = table.column("cond");
    const std::size_t distance = table.column("distance (cm)");
    for (std::size_t k = 0; k < table.rows.size(); ++k) {
      QCOMPARE(table.rows[k][distance], panel->profile()->distance[k]);
      QCOMPARE(table.rows[k][value], panel->profile()->values[k]);
    }
    if (auto* dock = w.findChild<QDockWidget*>("probeDock")) dock->raise();
    window_checks::frame(w);
    window_checks::save_screenshot(w, "view-tools-probe.png");
  }

  // A camera nobody moved frames the device in the view's new shape; one
  // the user turned stays as it is.
  void anUntouchedCameraFollowsTheViewsShape() {
    MechanismWindow w(load_preset("delta"));
    show_on_screen(w);
    window_checks::wait_settled(w);
    vtkCamera* camera = scene_renderer(w)->GetActiveCamera();
    const auto position = [&] {
      double p[3];
      camera->GetPosition(p);
      return Eigen::Vector3d(p[0], p[1], p[2]);
    };
    const Eigen::Vector3d narrow = position();
    w.resize(1920, 800);  // a wider view: the same framing needs less distance
    QTRY_VERIFY((position() - narrow).norm() > 1e-3 * w.mechanism().size());
    w.resize(1280, 800);
    QTRY_VERIFY((position() - narrow).norm() < 1e-9 * w.mechanism().size());
    camera->Azimuth(20);  // as a drag turns it
    const Eigen::Vector3d turned = position();
    w.resize(1920, 800);
    QTest::qWait(200);
    QVERIFY((position() - turned).norm() < 1e-12 * w.mechanism().size());
  }

  // A view image larger than the view is the same picture, sharper: text
  // and the colour bar's strip grow with it (at screen size they would
  // shrink to a corner of a 4K picture), and the view is as before after.
  void aLargeViewImageIsTheViewsPictureSharper() {
    MechanismWindow w(load_preset("delta"));
    show_on_screen(w);
    window_checks::wait_settled(w);
    window_checks::frame(w);
    const int width = w.view()->width(), height = w.view()->height();
    const QImage screen = w.viewImage(width, height);
    const QImage large = w.viewImage(3 * width, 3 * height);
    QCOMPARE(large.size(), QSize(3 * width, 3 * height));
    const QImage shrunk = large.scaled(width, height, Qt::IgnoreAspectRatio, Qt::SmoothTransformation);
    const double changed = window_checks::changed_fraction(screen.convertToFormat(QImage::Format_RGB32),
                                                           shrunk.convertToFormat(QImage::Format_RGB32));
    std::printf("view image at 3x, shrunk: %.4f of its pixels differ from the view's\n", changed);
    QVERIFY2(changed < 0.02, qPrintable(QString::number(changed)));
    const QImage after = w.viewImage(width, height);
    QVERIFY2(window_checks::changed_fraction(screen.convertToFormat(QImage::Format_RGB32),
                                             after.convertToFormat(QImage::Format_RGB32)) < 0.001,
             "the view is as before");
  }

  void clickOnASurfaceReadsTheSampledVolume() {
    MechanismWindow w(load_preset("delta"));
    show_on_screen(w);
    gui::FieldSettings f = w.fieldSettings();
    f.show_slice = false;
    w.applyFieldSettings(f);
    window_checks::wait_settled(w);
    window_checks::frame(w);
    // Points of the reach surface's mesh where a ray from the camera meets that surface first.
    vtkPolyData* mesh = vtkPolyData::SafeDownCast(w.fieldScene().surface_actor(render::Surface::Reach)->GetMapper()->GetInput());
    QVERIFY(mesh && mesh->GetNumberOfPoints() > 100);
    int hits = 0;
    for (vtkIdType i = 0; i < mesh->GetNumberOfPoints() && hits < 3; i += mesh->GetNumberOfPoints() / 97) {
      double p[3];
      mesh->GetPoint(i, p);
      const auto px = to_display(scene_renderer(w), Eigen::Vector3d(p[0], p[1], p[2]));
      const auto hit = w.viewTools()->picker()->pickAt(px[0], px[1]);
      if (!hit || hit->what != "reach surface") continue;
      ++hits;
      click(w.view()->interactor(), px);
      gui::ProbePanel* panel = w.viewTools()->panel();
      QVERIFY(panel->readout().contains("on the reach surface"));
      QVERIFY2(panel->readout().contains("sampled volume"), qPrintable(panel->readout()));
      // On the reach surface the reach margin is about 0: within a sample spacing.
      const Field* volume = w.fieldDisplay()->surfaces().volume.get();
      QVERIFY(volume && panel->sample());
      QVERIFY(std::abs(panel->sample()->find("reach")->value) < volume->grid.spacing.maxCoeff());
    }
    QVERIFY2(hits > 0, "some of the reach surface is in view");
  }

  void standardViewsLookAlongTheirAxes() {
    MechanismWindow w(load_preset("delta"));
    w.resize(1024, 700);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    const std::pair<QString, Eigen::Vector3d> views[] = {{"&Front view", Eigen::Vector3d::UnitY()},
                                                         {"&Top view", -Eigen::Vector3d::UnitZ()},
                                                         {"&Side view", -Eigen::Vector3d::UnitX()},
                                                         {"&Isometric view", Eigen::Vector3d(1, 1, -1).normalized()}};
    for (const auto& [text, direction] : views) {
      QAction* action = nullptr;
      for (QAction* a : w.findChildren<QAction*>())
        if (a->text() == text) action = a;
      QVERIFY2(action, qPrintable(text));
      QVERIFY(!action->shortcut().isEmpty());
      action->trigger();
      double d[3];
      scene_renderer(w)->GetActiveCamera()->GetDirectionOfProjection(d);
      QVERIFY2((Eigen::Vector3d(d[0], d[1], d[2]) - direction).norm() < 1e-9, qPrintable(text));
    }
    QAction* parallel = w.findChild<QAction*>("parallelProjectionAction");
    QVERIFY(parallel);
    parallel->trigger();
    QVERIFY(scene_renderer(w)->GetActiveCamera()->GetParallelProjection());
  }

  void aRefusedTargetPutsTheSlidersBack() {
    MechanismWindow w(load_preset("delta"));
    show_on_screen(w);
    const std::string x = w.mechanism().info().task[0].name;
    auto* box = w.findChild<QDoubleSpinBox*>(QString::fromStdString(x + "Box"));
    QVERIFY(box);
    const double held = box->value();
    Eigen::VectorXd far = w.task();
    far(0) = w.mechanism().info().task[0].range.hi;  // a corner of the travel: beyond reach
    far(2) = w.mechanism().info().task[2].range.hi;
    box->setValue(far(0));  // what a user's edit leaves in the box
    QVERIFY(!w.setTask(far));
    QCOMPARE(box->value(), held);
    QVERIFY(w.statusBar()->currentMessage().contains("Refused"));
    window_checks::frame(w);
    window_checks::save_screenshot(w, "refused-target.png");
  }

  void colourBarsSayWhatTheyShow() {
    MechanismWindow w(load_preset("delta"));
    show_on_screen(w);
    window_checks::wait_settled(w);
    auto show = [&](const std::string& field, const std::string& map) {
      gui::FieldSettings f = w.fieldSettings();
      f.field = field;
      f.colour_map = map;
      f.range_min.reset();
      f.range_max.reset();
      w.applyFieldSettings(f);
      window_checks::wait_settled(w);
      window_checks::frame(w);
    };
    show("status", "viridis");
    const std::vector<std::string> names = w.fieldScene().colour_bar_labels();
    QCOMPARE(names.size(), std::size_t(5));
    QCOMPARE(names.front(), std::string("ok"));
    QCOMPARE(names.back(), std::string("out-of-limits"));
    window_checks::save_screenshot(w, "colour-status.png");
    show("iterations", "viridis");
    const std::vector<double> ticks = w.fieldScene().colour_bar_ticks();
    QVERIFY(!ticks.empty());
    for (double t : ticks) QCOMPARE(t, std::round(t));
    show("reach", "diverging");
    const auto range = w.fieldScene().colour_bar_range();
    QVERIFY(range);
    QCOMPARE((*range)[0], -(*range)[1]);
    window_checks::save_screenshot(w, "colour-reach-diverging.png");
    show("residual", "viridis");
    window_checks::save_screenshot(w, "colour-residual.png");
  }

  // A planar device's slice is drawn under its linkage: a click on it reads
  // the slice in the plane (the point had been read where the slice is
  // drawn, outside the slice's one sample of thickness).
  void clickOnAPlanarDevicesSliceReadsItInThePlane() {
    MechanismWindow w(load_preset("five-bar"));
    show_on_screen(w);
    window_checks::wait_settled(w);
    window_checks::frame(w);
    const std::vector<Target> targets = slice_targets(w, *fieldOf(w));
    QVERIFY2(targets.size() >= 3, "the slice is in view");
    click(w.view()->interactor(), targets[targets.size() / 2].pixel);
    gui::ProbePanel* panel = w.viewTools()->panel();
    QVERIFY(panel->sample());
    QCOMPARE(panel->sample()->point.z(), *w.mechanism().info().plane_z);
    QVERIFY2(panel->readout().contains("From the slice's samples"), qPrintable(panel->readout()));
    QVERIFY2(panel->readout().contains("computed at the point"), qPrintable(panel->readout()));
  }

  void framingTheDeviceFillsTheView() {
    MechanismWindow w(load_preset("parallel-12r"));
    w.resize(1920, 1080);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    window_checks::wait_settled(w);
    // How much of the view's height or width the device's box spans.
    auto fill = [&] {
      vtkRenderer* r = scene_renderer(w);
      const Eigen::AlignedBox3d box = w.scene().device_box();
      double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d c = box.corner(Eigen::AlignedBox3d::CornerType(k));
        r->SetWorldPoint(c.x(), c.y(), c.z(), 1.0);
        r->WorldToView();
        const double* v = r->GetViewPoint();  // -1..1 across the viewport
        for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
      }
      if (lo[0] < -1 || lo[1] < -1 || hi[0] > 1 || hi[1] > 1) return -1.0;  // cut off
      return std::max(hi[0] - lo[0], hi[1] - lo[1]) / 2;
    };
    const double workspace = fill();
    QAction* device = w.findChild<QAction*>("frameDeviceAction");
    QVERIFY(device);
    device->trigger();
    const double framed = fill();
    qInfo("the device spans %.2f of the view framing its workspace, %.2f framing itself", workspace, framed);
    QVERIFY(framed > 0.8);
    QVERIFY(framed > workspace + 0.1);
    window_checks::frame(w);
    window_checks::save_screenshot(w, "frame-device-12r.png");
    w.findChild<QAction*>("parallelProjectionAction")->trigger();
    for (QAction* a : w.findChildren<QAction*>())
      if (a->text() == "&Top view") a->trigger();
    window_checks::frame(w);
    window_checks::save_screenshot(w, "top-parallel-12r.png");
  }

  // The handle the user drags is drawn over the scene: PATHOS-II's driven
  // point lies inside its grip and its slice, which had hidden the handle.
  void theHandleIsSeenOverTheGripAndTheSlice() {
    MechanismWindow w(load_preset("pathos2"));
    show_on_screen(w);
    window_checks::wait_settled(w);
    const QImage image = window_checks::frame(w);
    const auto at = to_display(scene_renderer(w), w.endpoint());
    const double ratio = double(image.height()) / w.view()->height();  // device pixels
    int red = 0;
    for (int dy = -20; dy <= 20; ++dy)
      for (int dx = -20; dx <= 20; ++dx) {
        const QColor c = image.pixelColor(int(at[0] * ratio) + dx, image.height() - 1 - int(at[1] * ratio) + dy);
        red += c.red() > 180 && c.green() < 90 && c.blue() < 90;
      }
    QVERIFY2(red >= 20, qPrintable(QString("%1 red pixels about the driven point").arg(red)));
  }

  // A press on the handle, a move and a release drag the driven point; the
  // camera stays where it was.
  void theMouseDragsTheHandle() {
    MechanismWindow w(load_preset("delta"));
    show_on_screen(w);
    window_checks::wait_settled(w);
    vtkRenderWindowInteractor* i = w.view()->interactor();
    vtkCamera* camera = scene_renderer(w)->GetActiveCamera();
    Eigen::Vector3d eye_before;
    camera->GetPosition(eye_before.data());
    const Eigen::Vector3d before = w.endpoint();
    auto at = to_display(scene_renderer(w), before);
    i->SetEventInformation(at[0], at[1]);
    i->InvokeEvent(vtkCommand::MouseMoveEvent);  // the handle lights up under the pointer
    i->InvokeEvent(vtkCommand::LeftButtonPressEvent);
    for (int step = 1; step <= 5; ++step) {
      i->SetEventInformation(at[0] + 4 * step, at[1] + 2 * step);
      i->InvokeEvent(vtkCommand::MouseMoveEvent);
    }
    i->InvokeEvent(vtkCommand::LeftButtonReleaseEvent);
    Eigen::Vector3d eye_after;
    camera->GetPosition(eye_after.data());
    QVERIFY(eye_after == eye_before);
    const Eigen::Vector3d moved = w.endpoint();
    QVERIFY2((moved - before).norm() > 0.01 * w.mechanism().size(),
             qPrintable(QString("the driven point moved %1 cm").arg((moved - before).norm())));
    // The point follows the pointer to where it was released.
    const auto now = to_display(scene_renderer(w), moved);
    QVERIFY2(std::abs(now[0] - (at[0] + 20)) <= 2 && std::abs(now[1] - (at[1] + 10)) <= 2,
             qPrintable(QString("released at (%1, %2), the point drawn at (%3, %4)")
                            .arg(at[0] + 20).arg(at[1] + 10).arg(now[0]).arg(now[1])));
  }

  void theSliceCanBeSeenThrough() {
    MechanismWindow w(load_preset("delta"));
    show_on_screen(w);
    window_checks::wait_settled(w);
    auto* slider = w.findChild<QSlider*>("sliceOpacitySlider");
    QVERIFY(slider);
    QVERIFY(!slider->toolTip().isEmpty());
    QCOMPARE(w.fieldScene().slice_actor()->GetProperty()->GetOpacity(), 1.0);
    const QImage opaque = window_checks::frame(w);
    slider->setValue(35);
    QCOMPARE(w.fieldScene().slice_actor()->GetProperty()->GetOpacity(), 0.35);
    QVERIFY(window_checks::changed_fraction(opaque, window_checks::frame(w)) > 0.01);
    window_checks::save_screenshot(w, "slice-opacity-35.png");
    slider->setValue(100);
    // Labels in front and smooth surfaces are on from the start; each can be turned off.
    QAction* labels = w.findChild<QAction*>("labelsInFrontAction");
    QVERIFY(labels);
    QVERIFY(labels->isChecked());
    QVERIFY(w.scene().labels_in_front());
    window_checks::save_screenshot(w, "labels-in-front.png");
    labels->trigger();
    QVERIFY(!w.scene().labels_in_front());
    labels->trigger();
    QAction* smooth = w.findChild<QAction*>("smoothSurfacesAction");
    QVERIFY(smooth);
    QVERIFY(smooth->isChecked());
    const QImage smoothed = window_checks::frame(w);
    window_checks::save_screenshot(w, "smooth-surfaces.png");
    smooth->trigger();
    QVERIFY(window_checks::changed_fraction(smoothed, window_checks::frame(w)) > 0.001);
  }

 private:
  static const Field* fieldOf(MechanismWindow& w);
};

const Field* ViewToolsTest::fieldOf(MechanismWindow& w) { return w.fieldDisplay()->slice(); }

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  ViewToolsTest test;
  return QTest::qExec(&test, argc, argv);
}
#include "test_view_tools.moc"
