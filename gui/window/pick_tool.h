// Picking in the 3-D view: a click (a press and release without a drag)
// or, while hover is on, the resting mouse, shoots a ray with a
// vtkCellPicker into the props it is given and reports the nearest point
// hit. Opaque props (the slice, the linkage) are tried first; the
// translucent ones (the workspace and task surfaces) only where the ray
// misses those, so the slice is read through the surfaces in front of it.
// It only listens: the camera still turns on a drag.
#pragma once

#include <QObject>
#include <QTimer>
#include <QString>
#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <vtkNew.h>

class vtkActor;
class vtkCellPicker;
class vtkObject;
class vtkRenderer;
class vtkRenderWindowInteractor;

namespace linkscape::gui {

class PickTool : public QObject {
  Q_OBJECT

 public:
  struct Target {
    vtkActor* actor;
    QString what;  // "slice", "reach surface", "linkage", ...
  };
  struct Hit {
    Eigen::Vector3d point;
    QString what;
  };

  PickTool(vtkRenderWindowInteractor* interactor, vtkRenderer* renderer, QObject* parent = nullptr);
  ~PickTool() override;

  struct Targets {
    std::vector<Target> opaque;       // tried first
    std::vector<Target> translucent;  // tried where the ray misses those
  };
  // Asked at every pick, so the props of a new design are found.
  void setTargets(std::function<Targets()> targets) { targets_ = std::move(targets); }
  void setHover(bool on);
  bool hover() const { return hover_; }

  // The nearest target under display pixel (x, y) (VTK's: origin at the
  // bottom left), or nothing.
  std::optional<Hit> pickAt(int x, int y);

 signals:
  // A click; `shift` while Shift was held.
  void clicked(const Hit& hit, bool shift);
  // The mouse rested over a target while hover is on.
  void hovered(const Hit& hit);

 private:
  void onEvent(vtkObject* caller, unsigned long event, void* data);
  std::optional<Hit> pickFrom(const std::vector<Target>& targets, int x, int y);

  vtkRenderWindowInteractor* interactor_;
  vtkRenderer* renderer_;
  vtkNew<vtkCellPicker> picker_;
  std::function<Targets()> targets_;
  std::vector<unsigned long> tags_;
  unsigned long style_tag_ = 0;
  int press_x_ = 0, press_y_ = 0;
  bool pressed_ = false, hover_ = false, button_down_ = false;
  QTimer hover_timer_;  // picks once the mouse rests, not on every move
};

}  // namespace linkscape::gui
