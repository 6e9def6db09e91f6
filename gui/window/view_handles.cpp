#include "gui/window/view_handles.h"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkHandleWidget.h>
#include <vtkInteractorObserver.h>
#include <vtkPointHandleRepresentation3D.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>

namespace linkscape::gui {

ViewHandles::ViewHandles(vtkRenderWindowInteractor* interactor, Hooks hooks)
    : hooks_(std::move(hooks)), interactor_(interactor) {
  rep_ = vtkSmartPointer<vtkPointHandleRepresentation3D>::New();
  rep_->SetHandleSize(18);
  rep_->AllOff();
  rep_->GetProperty()->SetColor(0.95, 0.1, 0.1);
  rep_->GetSelectedProperty()->SetColor(1.0, 0.6, 0.0);
  handle_ = vtkSmartPointer<vtkHandleWidget>::New();
  handle_->SetInteractor(interactor);
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
    self->hooks_.dragged_to(Eigen::Vector3d(p[0], p[1], p[2]));
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

void ViewHandles::place(const Eigen::Vector3d& p) {
  Eigen::Vector3d copy = p;
  rep_->SetWorldPosition(copy.data());
}

}  // namespace linkscape::gui
