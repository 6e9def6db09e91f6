#include "gui/window/view_tools.h"

#include <QAction>
#include <QDockWidget>
#include <QMainWindow>
#include <QKeySequence>
#include <QMenu>
#include <tuple>
#include <vtkCamera.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>

#include "core/haptics.h"
#include "gui/window/device_state.h"
#include "gui/window/docks.h"
#include "gui/window/field_display.h"
#include "gui/window/pick_tool.h"
#include "gui/window/probe_panel.h"
#include "gui/window/view_overlays.h"
#include "gui/window/vtk_widget.h"
#include "render/field_probe.h"
#include "render/field_scene.h"
#include "render/mark_scene.h"
#include "render/skeleton_scene.h"
#include "render/task_scene.h"

namespace linkscape::gui {

namespace {
constexpr int kSmoothingIterations = 20;  // windowed-sinc passes: the grid's ripples gone, the shape kept
}  // namespace

ViewTools::ViewTools(const Scene& scene, QObject* parent)
    : QObject(parent),
      scene_(scene),
      marks_(std::make_unique<render::MarkScene>()),
      picker_(std::make_unique<PickTool>(scene.view->interactor(), scene.renderer)) {
  marks_->add_to(scene.renderer);
  overlays_ = new ViewOverlays(*scene.state, scene.renderer, scene.view, this);
  ProbePanel::Hooks hooks;
  hooks.field_at = [this](const Eigen::Vector3d& p, QString* source) -> const Field* {
    const Field* slice = scene_.display->slice();
    if (slice && render::inside_cells(slice->grid, p)) {
      *source = tr("slice");
      return slice;
    }
    const Field* volume = scene_.display->surfaces().volume.get();
    if (volume && render::inside_cells(volume->grid, p)) {
      *source = tr("sampled volume");
      return volume;
    }
    return nullptr;
  };
  hooks.pose_status = [this] {
    const std::string& why = scene_.state->refusal();
    return why.empty() ? tr("ok") : tr("the last target was refused: %1").arg(QString::fromStdString(why));
  };
  hooks.marks_changed = [this] { scene_.view->requestRender(); };
  hooks.haptics_at = [this](const Eigen::Vector3d& p, const Field& near) -> std::optional<Field> {
    const DeviceState& state = *scene_.state;
    try {
      const haptics::DeviceData data = haptics::device_data(state.preset(), state.mechanism().info());
      IkOptions options;
      options.method = scene_.display->settings().method;
      options.branch = near.branch;
      // One sample centred on p: the measures there, not between samples.
      const Eigen::Vector3d half = Eigen::Vector3d::Constant(1e-6 * state.mechanism().size());
      return haptics::sample_field(state.mechanism(), Grid::box(p - half, p + half, {1, 1, 1}), state.task(), options,
                                   1, {}, &data);
    } catch (const std::invalid_argument&) {
      return std::nullopt;  // no actuator data, or a point the device cannot take
    }
  };
  panel_ = new ProbePanel(marks_.get(), hooks, QString::fromStdString(scene.state->mechanism().info().length_unit));
  picker_->setTargets([this] {
    PickTool::Targets t;
    t.opaque.push_back({scene_.fields->slice_actor(), tr("slice")});
    for (const render::SkeletonScene::Part& part : scene_.skeleton->pickable_parts())
      t.opaque.push_back({part.actor, QString::fromStdString(part.what)});
    t.translucent = {{scene_.fields->surface_actor(render::Surface::WellConditioned), tr("well-conditioned surface")},
                     {scene_.fields->surface_actor(render::Surface::Reach), tr("reach surface")},
                     {scene_.task->task_actor(), tr("task volume")}};
    marks_->set_marker_size(0.012 * scene_.skeleton->model().scale);
    return t;
  });
  auto pick = [this](const PickTool::Hit& hit, bool click, bool shift) {
    // A planar device's fields and measures are its plane's: a point picked
    // on its slice (drawn under the linkage) or a surface is read there.
    Eigen::Vector3d p = hit.point;
    if (const std::optional<double> plane = scene_.state->mechanism().info().plane_z) p.z() = *plane;
    panel_->pick(p, hit.what, click, shift);
  };
  connect(picker_.get(), &PickTool::clicked, this, [pick](const PickTool::Hit& h, bool shift) { pick(h, true, shift); });
  connect(picker_.get(), &PickTool::hovered, this, [pick](const PickTool::Hit& h) { pick(h, false, false); });
  connect(panel_, &ProbePanel::hoverToggled, picker_.get(), &PickTool::setHover);
  // New samples: the read-out and the profile show them.
  connect(scene.display, &FieldDisplay::fieldsUpdated, panel_, [this](bool fine) {
    if (fine) panel_->refresh();
  });
}

ViewTools::~ViewTools() = default;

QDockWidget* ViewTools::addDock(QMainWindow* window, QDockWidget* tab_with) {
  QDockWidget* dock = add_dock(window, tr("Probe"), "probeDock", panel_);
  window->tabifyDockWidget(tab_with, dock);
  // Shown from the start, so that its tab says the view can be probed.
  connect(picker_.get(), &PickTool::clicked, dock, [dock] {
    dock->show();  // closed since
    dock->raise();
  });
  return dock;
}

void ViewTools::frame(const Eigen::AlignedBox3d& workspace, std::optional<render::StandardView> view) {
  view_ = view;
  const Eigen::AlignedBox3d device = scene_.skeleton->device_box();
  const Eigen::AlignedBox3d& box = frame_device_ && !device.isEmpty() ? device : workspace;
  if (!view) {
    scene_.skeleton->reset_camera(scene_.renderer, box);
    return;
  }
  const render::ViewDirection d = render::view_direction(*view);
  scene_.skeleton->frame(scene_.renderer, box, d.back, d.up);
}

void ViewTools::setParallel(bool on) {
  scene_.renderer->GetActiveCamera()->SetParallelProjection(on);
  scene_.view->requestRender();
}

bool ViewTools::parallel() const { return scene_.renderer->GetActiveCamera()->GetParallelProjection() != 0; }

ViewTools::ViewActions ViewTools::addViewMenu(QMenu* menu) {
  ViewActions a;
  const QString views[] = {tr("&Front view"), tr("&Top view"), tr("&Side view"), tr("&Isometric view")};
  int key = Qt::Key_1;
  for (int i = 0; i < 4; ++i) {
    a.views[std::size_t(i)] = menu->addAction(views[i]);
    a.views[std::size_t(i)]->setShortcut(QKeySequence(Qt::CTRL | Qt::Key(key++)));
  }
  a.parallel = menu->addAction(tr("&Parallel projection"));
  a.parallel->setObjectName("parallelProjectionAction");
  a.parallel->setCheckable(true);
  a.parallel->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_5));
  a.labels = menu->addAction(tr("Joint &labels in front"));
  a.labels->setObjectName("labelsInFrontAction");
  a.labels->setCheckable(true);
  a.labels->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_6));
  a.labels->setStatusTip(tr("Draw the joint labels over the slice, the surfaces and the base, on a light plate"));
  a.smooth = menu->addAction(tr("S&mooth workspace surfaces"));
  a.smooth->setObjectName("smoothSurfacesAction");
  a.smooth->setCheckable(true);
  a.smooth->setStatusTip(tr("Smooth the grid's facets and ripples off the drawn surfaces (exports keep the extracted mesh)"));
  a.device = menu->addAction(tr("Frame the &device, not its workspace"));
  a.device->setObjectName("frameDeviceAction");
  a.device->setCheckable(true);
  a.device->setStatusTip(tr("Reset camera and the standard views frame the device in its pose instead of the middle "
                            "of its sampling box"));
  std::tie(a.capsules, a.ellipsoid) = ViewOverlays::addActions(menu);
  return a;
}

void ViewTools::addViewActions(QMenu* menu, std::function<Eigen::AlignedBox3d()> workspace,
                               std::function<void()> framed) {
  const ViewActions a = addViewMenu(menu);
  const render::StandardView views[] = {render::StandardView::Front, render::StandardView::Top,
                                        render::StandardView::Side, render::StandardView::Iso};
  for (int i = 0; i < 4; ++i)
    connect(a.views[std::size_t(i)], &QAction::triggered, this, [this, view = views[i], workspace, framed] {
      frame(workspace(), view);
      framed();
      scene_.view->requestRender();
    });
  connect(a.parallel, &QAction::toggled, this, &ViewTools::setParallel);
  connect(a.labels, &QAction::toggled, this, [this](bool on) {
    scene_.skeleton->set_labels_in_front(on);
    scene_.view->requestRender();
  });
  connect(a.smooth, &QAction::toggled, this, [this](bool on) {
    scene_.fields->set_surface_smoothing(on ? kSmoothingIterations : 0);
    const SurfaceResult& shown = scene_.display->surfaces();
    scene_.fields->set_surface(render::Surface::Reach, shown.reach);
    scene_.fields->set_surface(render::Surface::WellConditioned, shown.well_conditioned);
    scene_.view->requestRender();
  });
  overlays_->connectActions(a.capsules, a.ellipsoid);
  // On from the start: labels hidden behind the slice and staircased surfaces
  // are what a new user would otherwise see first.
  a.labels->setChecked(true);
  a.smooth->setChecked(true);
  connect(a.device, &QAction::toggled, this, [this, workspace, framed](bool on) {
    setFrameDevice(on);
    reframe(workspace());
    framed();
    scene_.view->requestRender();
  });
}

}  // namespace linkscape::gui
