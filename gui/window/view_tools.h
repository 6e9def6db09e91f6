// The view as an instrument: picking (the Probe panel's read-out, ruler and
// line probe, drawn by a MarkScene), the standard views, parallel
// projection and what the camera frames. The window hands it its scene and
// adds its panel and menu entries.
#pragma once

#include <QObject>
#include <QString>
#include <array>
#include <functional>
#include <memory>
#include <optional>

#include <Eigen/Geometry>

#include "render/standard_views.h"

class QDockWidget;
class QMainWindow;
class QAction;
class QMenu;
class vtkRenderer;

namespace linkscape::render {
class FieldScene;
class MarkScene;
class SkeletonScene;
class TaskScene;
}  // namespace linkscape::render

namespace linkscape::gui {

class DeviceState;
class FieldDisplay;
class PickTool;
class ProbePanel;
class ViewOverlays;
class VtkWidget;

class ViewTools : public QObject {
  Q_OBJECT

 public:
  struct Scene {
    const DeviceState* state;
    VtkWidget* view;
    vtkRenderer* renderer;
    render::SkeletonScene* skeleton;
    render::FieldScene* fields;
    render::TaskScene* task;
    FieldDisplay* display;
  };
  ViewTools(const Scene& scene, QObject* parent = nullptr);
  ~ViewTools() override;

  ProbePanel* panel() const { return panel_; }
  // The Probe dock of `window`, tabbed with `tab_with`: hidden until the
  // first click in the view picks something (or View > Probe shows it).
  QDockWidget* addDock(QMainWindow* window, QDockWidget* tab_with);
  PickTool* picker() const { return picker_.get(); }
  const render::MarkScene& marks() const { return *marks_; }
  // The link capsules and the force ellipsoid (view_overlays.h).
  ViewOverlays* overlays() const { return overlays_; }

  // The camera along `view` (none: the default view from the front-left,
  // above) framing the device's workspace box or, while frameDevice(), the
  // device itself in its pose. Keeps the projection.
  void frame(const Eigen::AlignedBox3d& workspace, std::optional<render::StandardView> view);
  // Frames as the last frame() did, from the direction last chosen.
  void reframe(const Eigen::AlignedBox3d& workspace) { frame(workspace, view_); }
  bool frameDevice() const { return frame_device_; }
  void setFrameDevice(bool on) { frame_device_ = on; }
  void setParallel(bool on);
  bool parallel() const;

  // View menu entries: the standard views (Ctrl+1..4), parallel projection
  // (Ctrl+5), the framing toggle and the overlays' toggles. `workspace` gives the box to frame;
  // `framed` runs after the camera moved (the window notes its fitted camera).
  void addViewActions(QMenu* menu, std::function<Eigen::AlignedBox3d()> workspace, std::function<void()> framed);
  // The same entries, not connected (the shortcut table's menus).
  struct ViewActions {
    std::array<QAction*, 4> views{};  // front, top, side, iso
    QAction *parallel = nullptr, *labels = nullptr, *smooth = nullptr, *device = nullptr;
    QAction *capsules = nullptr, *ellipsoid = nullptr;  // ViewOverlays
  };
  static ViewActions addViewMenu(QMenu* menu);

 private:
  Scene scene_;
  std::unique_ptr<render::MarkScene> marks_;
  std::unique_ptr<PickTool> picker_;
  ProbePanel* panel_ = nullptr;
  ViewOverlays* overlays_ = nullptr;
  bool frame_device_ = false;
  std::optional<render::StandardView> view_;  // the direction last framed from
};

}  // namespace linkscape::gui
