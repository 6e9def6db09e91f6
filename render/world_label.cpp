#include "render/world_label.h"

#include <vtkCommand.h>
#include <vtkCoordinate.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkWeakPointer.h>

namespace linkscape::render {

void style_world_label(vtkTextActor* label) {
  vtkTextProperty* t = label->GetTextProperty();
  t->SetFontSize(14);
  t->SetColor(0.1, 0.1, 0.15);
  t->SetBackgroundColor(1, 1, 1);
  t->SetBackgroundOpacity(0.85);
  t->SetFrame(true);
  label->GetPositionCoordinate()->SetCoordinateSystemToWorld();
  label->PickableOff();
}

namespace {

// Flips the label's justification before each frame of its renderer.
class KeepInView : public vtkCommand {
 public:
  static KeepInView* New() { return new KeepInView; }
  vtkWeakPointer<vtkTextActor> label;

  void Execute(vtkObject* caller, unsigned long, void*) override {
    auto* renderer = vtkRenderer::SafeDownCast(caller);
    if (!label || !renderer || !label->GetVisibility() || !renderer->GetRenderWindow()) return;
    const int* window = renderer->GetRenderWindow()->GetSize();
    const double right = renderer->GetViewport()[2] * window[0];
    double size[2];
    label->GetSize(renderer, size);
    const double x = label->GetPositionCoordinate()->GetComputedDoubleDisplayValue(renderer)[0];
    vtkTextProperty* t = label->GetTextProperty();
    const bool past = x + size[0] > right - 4;  // pixels
    if (past && t->GetJustification() != VTK_TEXT_RIGHT) t->SetJustificationToRight();
    if (!past && t->GetJustification() == VTK_TEXT_RIGHT && x + size[0] + 4 < right - 4) t->SetJustificationToLeft();
  }
};

}  // namespace

void keep_in_view(vtkTextActor* label, vtkRenderer* renderer) {
  vtkNew<KeepInView> command;
  command->label = label;
  renderer->AddObserver(vtkCommand::StartEvent, command);
}

}  // namespace linkscape::render
