#include "gui/window/view_handles.h"

#include <vtkCallbackCommand.h>
#include <vtkCamera.h>
#include <vtkCommand.h>
#include <vtkHandleWidget.h>
#include <vtkInteractorObserver.h>
#include <vtkPointHandleRepresentation3D.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include <cmath>

namespace linkscape::gui {

ViewHandles::ViewHandles(vtkRenderWindowInteractor* interactor, vtkRenderer* renderer, Hooks hooks)
    : hooks_(std::move(hooks)), interactor_(interactor) {
  rep_ = vtkSmartPointer<vtkPointHandleRepresentation3D>::New();
  rep_->SetHandleSize(24);
  rep_->AllOff();  // a cross of three lines, no box or shadows
  rep_->GetProperty()->SetColor(0.95, 0.1, 0.1);
  rep_->GetProperty()->SetLineWidth(2);
  rep_->GetSelectedProperty()->SetLineWidth(2);
  rep_->GetSelectedProperty()->SetColor(1.0, 0.6, 0.0);
  handle_ = vtkSmartPointer<vtkHandleWidget>::New();
  handle_->SetInteractor(interactor);
  handle_->SetDefaultRenderer(renderer);
  handle_->SetRepresentation(rep_);
  handle_callback_ = vtkSmartPointer<vtkCallbackCommand>::New();
  handle_callback_->SetClientData(this);
  handle_callback_->SetCallback([](vtkObject*, unsigned long event, void* client, void*) {
    auto* self = static_cast<ViewHandles*>(client);
    if (event == vtkCommand::StartInteractionEvent || event == vtkCommand::EndInteractionEvent)
      self->hooks_.handle_held(event == vtkCommand::StartInteractionEvent);
    if (event == vtkCommand::StartInteractionEvent) return;
    double p[3];
    self->rep_->GetWorldPosition(p);
    if (const std::optional<Eigen::Vector3d> at = self->inPlane(Eigen::Vector3d(p[0], p[1], p[2])))
      self->hooks_.dragged_to(*at);
    if (event == vtkCommand::EndInteractionEvent) self->hooks_.released();
  });
  handle_->AddObserver(vtkCommand::StartInteractionEvent, handle_callback_);
  handle_->AddObserver(vtkCommand::InteractionEvent, handle_callback_);
  handle_->AddObserver(vtkCommand::EndInteractionEvent, handle_callback_);
  // Turning or zooming the camera with the mouse moves the picture too.
  camera_callback_ = vtkSmartPointer<vtkCallbackCommand>::New();
  camera_callback_->SetClientData(this);
  camera_callback_->SetCallback([](vtkObject*, unsigned long event, void* client, void*) {
    static_cast<ViewHandles*>(client)->hooks_.camera_held(event == vtkCommand::StartInteractionEvent);
  });
  if (vtkInteractorObserver* style = interactor->GetInteractorStyle()) {
    style->AddObserver(vtkCommand::StartInteractionEvent, camera_callback_);
    style->AddObserver(vtkCommand::EndInteractionEvent, camera_callback_);
  }
  handle_->EnabledOn();
}

ViewHandles::~ViewHandles() {
  handle_->EnabledOff();
  if (vtkInteractorObserver* style = interactor_->GetInteractorStyle()) style->RemoveObserver(camera_callback_);
}

// The handle moves in a plane facing the camera; a planar device's point is
// where the line of sight through it meets the device's plane.
std::optional<Eigen::Vector3d> ViewHandles::inPlane(const Eigen::Vector3d& p) const {
  const std::optional<double> plane = hooks_.plane_z ? hooks_.plane_z() : std::nullopt;
  vtkRenderer* renderer = rep_->GetRenderer();
  if (!plane || !renderer) return p;
  vtkCamera* camera = renderer->GetActiveCamera();
  Eigen::Vector3d eye, focus;
  camera->GetPosition(eye.data());
  camera->GetFocalPoint(focus.data());
  // A view along the plane (the front and side views) has no line of sight
  // across it: the handle's point dropped straight onto the plane.
  const Eigen::Vector3d view = focus - eye;
  if (std::abs(view.z()) < 0.1 * view.norm()) return Eigen::Vector3d(p.x(), p.y(), *plane);
  // Along the projection's direction under parallel projection, else from the eye.
  const Eigen::Vector3d along = camera->GetParallelProjection() ? view : Eigen::Vector3d(p - eye);
  if (std::abs(along.z()) < 1e-9 * along.norm()) return std::nullopt;
  return Eigen::Vector3d(p + (*plane - p.z()) / along.z() * along);
}

void ViewHandles::place(const Eigen::Vector3d& p) {
  Eigen::Vector3d copy = p;
  rep_->SetWorldPosition(copy.data());
}

}  // namespace linkscape::gui
