#include "render/world_label.h"

#include <vtkCoordinate.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

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

}  // namespace linkscape::render
