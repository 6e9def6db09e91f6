#include "gui/window/pick_tool.h"

#include <vtkActor.h>
#include <vtkCellPicker.h>
#include <vtkCommand.h>
#include <vtkInteractorObserver.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>

#include <cstdlib>

namespace linkscape::gui {

namespace {
constexpr int kClickSlop = 4;        // pixels a click may move and still be a click
constexpr int kHoverRestMs = 120;    // the mouse at rest this long is read on hover
}  // namespace

PickTool::PickTool(vtkRenderWindowInteractor* interactor, vtkRenderer* renderer, QObject* parent)
    : QObject(parent), interactor_(interactor), renderer_(renderer) {
  picker_->PickFromListOn();
  picker_->SetTolerance(0.002);  // lines (none are targets) and cell edges
  // Observed ahead of the interactor style, never aborting: the camera
  // still gets every event. While a button is down the style holds the
  // interactor's focus and alone sees its events, so the release is read
  // from the style's end of interaction.
  for (unsigned long e : {vtkCommand::LeftButtonPressEvent, vtkCommand::MouseMoveEvent, vtkCommand::LeaveEvent})
    tags_.push_back(interactor_->AddObserver(e, this, &PickTool::onEvent, 1.0f));
  if (vtkInteractorObserver* style = interactor_->GetInteractorStyle())
    style_tag_ = style->AddObserver(vtkCommand::EndInteractionEvent, this, &PickTool::onEvent);
  hover_timer_.setSingleShot(true);
  hover_timer_.setInterval(kHoverRestMs);
  connect(&hover_timer_, &QTimer::timeout, this, [this] {
    const int* p = interactor_->GetEventPosition();
    if (const auto hit = pickAt(p[0], p[1])) emit hovered(*hit);
  });
}

PickTool::~PickTool() {
  for (unsigned long tag : tags_) interactor_->RemoveObserver(tag);
  if (vtkInteractorObserver* style = interactor_->GetInteractorStyle()) style->RemoveObserver(style_tag_);
}

void PickTool::setHover(bool on) {
  hover_ = on;
  if (!on) hover_timer_.stop();
}

std::optional<PickTool::Hit> PickTool::pickFrom(const std::vector<Target>& targets, int x, int y) {
  picker_->InitializePickList();
  for (const Target& t : targets)
    if (t.actor) picker_->AddPickList(t.actor);
  if (!picker_->Pick(x, y, 0, renderer_)) return std::nullopt;
  vtkActor* actor = picker_->GetActor();
  for (const Target& t : targets)
    if (t.actor == actor) {
      const double* p = picker_->GetPickPosition();
      return Hit{Eigen::Vector3d(p[0], p[1], p[2]), t.what};
    }
  return std::nullopt;
}

std::optional<PickTool::Hit> PickTool::pickAt(int x, int y) {
  if (!targets_) return std::nullopt;
  const Targets t = targets_();
  if (auto hit = pickFrom(t.opaque, x, y)) return hit;
  return pickFrom(t.translucent, x, y);
}

void PickTool::onEvent(vtkObject*, unsigned long event, void*) {
  const int* p = interactor_->GetEventPosition();
  switch (event) {
    case vtkCommand::LeftButtonPressEvent:
      pressed_ = button_down_ = true;
      press_x_ = p[0];
      press_y_ = p[1];
      hover_timer_.stop();
      break;
    case vtkCommand::MouseMoveEvent:
      if (hover_ && !button_down_) hover_timer_.start();
      break;
    case vtkCommand::EndInteractionEvent: {
      button_down_ = false;
      const bool click = pressed_ && std::abs(p[0] - press_x_) <= kClickSlop && std::abs(p[1] - press_y_) <= kClickSlop;
      pressed_ = false;  // else a drag: the camera's
      if (click)
        if (const auto hit = pickAt(p[0], p[1])) emit clicked(*hit, interactor_->GetShiftKey() != 0);
      break;
    }
    case vtkCommand::LeaveEvent:
      hover_timer_.stop();
      break;
    default:
      break;
  }
}

}  // namespace linkscape::gui
