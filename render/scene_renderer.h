// The renderer the window draws its scene with: a vtkOpenGLRenderer whose
// translucent props (workspace surfaces, plates, joint labels) are blended
// over the opaque ones in a single pass, in prop order.
//
// VTK 9.1's renderer, with depth peeling off, always draws translucent props
// through vtkOrderIndependentTranslucentPass: two full-size floating-point
// targets cleared, drawn into and composited every frame, even for three
// small text labels. Under software OpenGL that is about a quarter of the
// linkage's frame (docs/performance.md). With depth peeling on (the window's
// "Exact transparency") this renderer peels as vtkOpenGLRenderer does.
#pragma once

#include <vtkOpenGLRenderer.h>

namespace linkscape::render {

class SceneRenderer : public vtkOpenGLRenderer {
 public:
  static SceneRenderer* New();
  vtkTypeMacro(SceneRenderer, vtkOpenGLRenderer)

  void DeviceRenderTranslucentPolygonalGeometry(vtkFrameBufferObjectBase* fbo = nullptr) override;

 protected:
  SceneRenderer() = default;
  ~SceneRenderer() override = default;

 private:
  SceneRenderer(const SceneRenderer&) = delete;
  void operator=(const SceneRenderer&) = delete;
};

}  // namespace linkscape::render
