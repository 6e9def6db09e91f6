// What the mouse does in the view besides turning the camera: a handle on
// the driven point that the user drags (solved by IK as it moves; on a
// planar device, where the mouse's ray meets its plane), and the
// start and end of camera drags (the picture moves every frame meanwhile).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <vtkSmartPointer.h>

class vtkCallbackCommand;
class vtkHandleWidget;
class vtkPointHandleRepresentation3D;
class vtkRenderWindowInteractor;
class vtkRenderer;

namespace linkscape::gui {

class ViewHandles {
 public:
  struct Hooks {
    std::function<void(const Eigen::Vector3d&)> dragged_to;  // the handle moved there
    std::function<void()> released;                          // the drag ended (after its last move)
    std::function<void(bool)> handle_held;                   // a drag of the handle starts or ends
    std::function<void(bool)> camera_held;                   // a drag of the camera starts or ends
    std::function<std::optional<double>()> plane_z;          // a planar device's plane: drags stay in it
  };
  // The handle is drawn by `renderer` (the view's layer over the scene).
  ViewHandles(vtkRenderWindowInteractor* interactor, vtkRenderer* renderer, Hooks hooks);
  ~ViewHandles();
  ViewHandles(const ViewHandles&) = delete;
  ViewHandles& operator=(const ViewHandles&) = delete;

  // The handle at the driven point.
  void place(const Eigen::Vector3d& p);
  // Where a drag to p asks the driven point to go.
  std::optional<Eigen::Vector3d> inPlane(const Eigen::Vector3d& p) const;

 private:
  Hooks hooks_;
  vtkRenderWindowInteractor* interactor_;
  vtkSmartPointer<vtkHandleWidget> handle_;
  vtkSmartPointer<vtkPointHandleRepresentation3D> rep_;
  vtkSmartPointer<vtkCallbackCommand> handle_callback_, camera_callback_;
};

}  // namespace linkscape::gui
