// The overlays' labels: text placed at a world point and drawn over the
// scene on a light framed plate, so it reads over the slice, the surfaces
// and the linkage. Not pickable.
#pragma once

class vtkRenderer;
class vtkTextActor;

namespace linkscape::render {

// Styles `label` so (position it with GetPositionCoordinate()->SetValue).
void style_world_label(vtkTextActor* label);

// Keeps a left-justified world label inside `renderer`'s viewport: before
// each frame, one whose text would run past the viewport's right edge is
// drawn to the left of its point instead, and back when there is room.
void keep_in_view(vtkTextActor* label, vtkRenderer* renderer);

}  // namespace linkscape::render
