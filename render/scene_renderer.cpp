#include "render/scene_renderer.h"

#include <vtkObjectFactory.h>

namespace linkscape::render {

vtkStandardNewMacro(SceneRenderer);

void SceneRenderer::DeviceRenderTranslucentPolygonalGeometry(vtkFrameBufferObjectBase* fbo) {
  if (GetUseDepthPeeling()) {
    vtkOpenGLRenderer::DeviceRenderTranslucentPolygonalGeometry(fbo);
    return;
  }
  // Plain "over" blending into the current framebuffer: vtkOpenGLActor turns
  // depth writes off for translucent props, the window's blend function is
  // VTK's default (source alpha, one minus source alpha).
  LastRenderingUsedDepthPeeling = 0;
  UpdateTranslucentPolygonalGeometry();
}

}  // namespace linkscape::render
