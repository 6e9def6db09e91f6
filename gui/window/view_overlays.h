// What the view draws over the device at its pose, each a View toggle
// (sessions keep them by their object names): the links as capsules with
// the pair that sets the clearance ("showLinkCapsules", on where the device
// states link radii; render/capsule_scene.h) and the force ellipsoid at the
// driven point ("showForceEllipsoid", off; render/force_ellipsoid_scene.h).
#pragma once

#include <QObject>
#include <memory>
#include <utility>

class QAction;
class QMenu;
class vtkRenderer;

namespace linkscape {
class Mechanism;
namespace render {
class CapsuleScene;
class ForceEllipsoidScene;
}  // namespace render
}  // namespace linkscape

namespace linkscape::gui {

class DeviceState;
class VtkWidget;

class ViewOverlays : public QObject {
  Q_OBJECT

 public:
  ViewOverlays(const DeviceState& state, vtkRenderer* renderer, VtkWidget* view, QObject* parent = nullptr);
  ~ViewOverlays() override;

  // The two toggles added to `menu`, unconnected and unchecked.
  static std::pair<QAction*, QAction*> addActions(QMenu* menu);
  // Connects the toggles and sets them for this device: the capsules on
  // (disabled, drawing nothing, where it states no link radii), the ellipsoid off.
  void connectActions(QAction* capsules, QAction* ellipsoid);

  const render::CapsuleScene& capsules() const { return *capsules_; }
  const render::ForceEllipsoidScene& ellipsoid() const { return *ellipsoid_; }
  // The force scale in use (length unit per N; 0 before the ellipsoid is first drawn).
  double lengthPerNewton() const { return length_per_N_; }

 public slots:
  // Draws the overlays shown at the state's pose (after every change of pose or design).
  void update();

 private:
  void followDevice();
  void drawCapsules();
  void drawEllipsoid();

  const DeviceState& state_;
  VtkWidget* view_;
  std::unique_ptr<render::CapsuleScene> capsules_;
  std::unique_ptr<render::ForceEllipsoidScene> ellipsoid_;
  bool show_capsules_ = false, show_ellipsoid_ = false;
  QAction* capsules_action_ = nullptr;  // enabled while the device states link radii
  // The force scale holds for a design, so the ellipsoid's size reads across poses.
  std::weak_ptr<const Mechanism> scaled_for_;
  double length_per_N_ = 0;
};

}  // namespace linkscape::gui
