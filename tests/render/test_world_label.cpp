// The overlays' captions: kept inside the view.
#include <gtest/gtest.h>

#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include "render/world_label.h"
#include "tests/render/offscreen_view.h"

namespace linkscape::render {
namespace {

// A caption near the view's right edge is drawn to the left of its point
// (the force ellipsoid's had run off the view), and back once there is room.
TEST(WorldLabel, ACaptionNearTheRightEdgeTurnsLeft) {
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  offscreen_view::set_up(window, renderer, {0, 0, 50}, {0, 1, 0}, 10);  // 15 px a unit: x = 12 is 380 px across
  vtkNew<vtkTextActor> label;
  style_world_label(label);
  label->SetInput("force ellipsoid (continuous torque)");
  renderer->AddViewProp(label);
  keep_in_view(label, renderer);
  label->GetPositionCoordinate()->SetValue(12, 0, 0);
  window->Render();
  EXPECT_EQ(label->GetTextProperty()->GetJustification(), VTK_TEXT_RIGHT);
  label->GetPositionCoordinate()->SetValue(-10, 0, 0);
  window->Render();
  EXPECT_EQ(label->GetTextProperty()->GetJustification(), VTK_TEXT_LEFT);
}

}  // namespace
}  // namespace linkscape::render
