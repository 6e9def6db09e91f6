// The overlays' labels: text placed at a world point and drawn over the
// scene on a light framed plate, so it reads over the slice, the surfaces
// and the linkage. Not pickable.
#pragma once

class vtkTextActor;

namespace linkscape::render {

// Styles `label` so (position it with GetPositionCoordinate()->SetValue).
void style_world_label(vtkTextActor* label);

}  // namespace linkscape::render
