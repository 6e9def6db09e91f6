// Reading back what a test's render window shows: the colour buffer as an
// image, and pixels of a 400 x 300 parallel view of scale 1.5 (100 pixels
// per unit, the view's centre at pixel (200, 150), y up).
#pragma once

#include <vtkCamera.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkWindowToImageFilter.h>

#include <array>
#include <cmath>

namespace offscreen_view {

using Rgb = std::array<int, 3>;

inline vtkSmartPointer<vtkImageData> grab(vtkRenderWindow* window) {
  window->Render();
  vtkNew<vtkWindowToImageFilter> filter;
  filter->SetInput(window);
  filter->ReadFrontBufferOff();
  filter->SetInputBufferTypeToRGB();
  filter->Update();
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->DeepCopy(filter->GetOutput());
  return image;
}

// A 400 x 300 offscreen window showing `renderer` in parallel projection,
// from `eye` towards the origin, `scale` units from the centre to the top.
inline void set_up(vtkRenderWindow* window, vtkRenderer* renderer, const std::array<double, 3>& eye,
                   const std::array<double, 3>& up, double scale) {
  window->SetOffScreenRendering(1);
  window->SetSize(400, 300);
  window->AddRenderer(renderer);
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(eye[0], eye[1], eye[2]);
  camera->SetViewUp(up[0], up[1], up[2]);
  camera->SetParallelScale(scale);
}

inline Rgb pixel(vtkImageData* image, int x, int y) {
  const auto* p = static_cast<const unsigned char*>(image->GetScalarPointer(x, y, 0));
  return {p[0], p[1], p[2]};
}

// The pixel showing the point (a, b) in the view's (right, up) coordinates.
inline Rgb at(vtkImageData* image, double a, double b) {
  return pixel(image, int(std::floor(200 + 100 * a)), int(std::floor(150 + 100 * b)));
}

}  // namespace offscreen_view
