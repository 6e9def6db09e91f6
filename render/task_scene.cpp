#include "render/task_scene.h"

#include <vtkActor.h>
#include <vtkAppendPolyData.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkTriangleFilter.h>
#include <vtkUnsignedCharArray.h>

#include <stdexcept>

namespace linkscape::render {

vtkSmartPointer<vtkPolyData> task_surface(const task::TaskVolume& task, const Eigen::Vector3d& centre, int resolution) {
  if (resolution < 4) throw std::invalid_argument("task surface: resolution must be at least 4");
  vtkNew<vtkTriangleFilter> triangles;
  if (task.shape == task::Shape::Sphere) {
    vtkNew<vtkSphereSource> sphere;
    sphere->SetCenter(centre.data());
    sphere->SetRadius(task.diameter() / 2);
    sphere->SetThetaResolution(2 * resolution);
    sphere->SetPhiResolution(resolution);
    triangles->SetInputConnection(sphere->GetOutputPort());
  } else {
    vtkNew<vtkAppendPolyData> faces;
    const Eigen::Vector3d half = task.size / 2;
    for (int axis = 0; axis < 3; ++axis)
      for (double side : {-1.0, 1.0}) {
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        Eigen::Vector3d origin = centre - half, p1 = origin, p2 = origin;
        origin(axis) = p1(axis) = p2(axis) = centre(axis) + side * half(axis);
        p1(a) += task.size(a);
        p2(b) += task.size(b);
        vtkNew<vtkPlaneSource> face;
        face->SetOrigin(origin.data());
        face->SetPoint1(side > 0 ? p1.data() : p2.data());  // outward normals
        face->SetPoint2(side > 0 ? p2.data() : p1.data());
        face->SetResolution(resolution, resolution);
        face->Update();
        faces->AddInputData(face->GetOutput());
      }
    triangles->SetInputConnection(faces->GetOutputPort());
  }
  triangles->Update();
  vtkSmartPointer<vtkPolyData> out = triangles->GetOutput();
  return out;
}

TaskScene::TaskScene() {
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetScalarModeToUsePointData();
  mapper->SetColorModeToDirectScalars();
  task_actor_->SetMapper(mapper);
  // Nearly opaque and lit mostly by ambient light, so that its colours read
  // true through the translucent workspace surfaces around it.
  task_actor_->GetProperty()->SetOpacity(0.8);
  task_actor_->GetProperty()->SetAmbient(0.5);
  task_actor_->GetProperty()->SetDiffuse(0.5);
  vtkNew<vtkPolyDataMapper> inscribed_mapper;
  inscribed_mapper->ScalarVisibilityOff();
  inscribed_actor_->SetMapper(inscribed_mapper);
  inscribed_actor_->GetProperty()->SetRepresentationToWireframe();
  inscribed_actor_->GetProperty()->SetColor(0.15, 0.35, 0.75);
  inscribed_actor_->GetProperty()->SetOpacity(0.35);
  inscribed_actor_->PickableOff();
  update_visibility();
}

TaskScene::~TaskScene() = default;

void TaskScene::add_to(vtkRenderer* renderer) {
  if (!renderer) throw std::invalid_argument("task scene: null renderer");
  if (!renderer->HasViewProp(task_actor_)) renderer->AddActor(task_actor_);
  if (!renderer->HasViewProp(inscribed_actor_)) renderer->AddActor(inscribed_actor_);
}

void TaskScene::set_task(vtkPolyData* surface, const std::vector<std::uint8_t>& meets) {
  if (!surface || surface->GetNumberOfPoints() != vtkIdType(meets.size()))
    throw std::invalid_argument("task scene: one flag per surface point expected");
  vtkNew<vtkPolyData> copy;
  copy->ShallowCopy(surface);
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetName("meets");
  colours->SetNumberOfComponents(3);
  colours->SetNumberOfTuples(vtkIdType(meets.size()));
  failing_ = 0;
  for (std::size_t i = 0; i < meets.size(); ++i) {
    const unsigned char good[3] = {60, 170, 90}, bad[3] = {220, 50, 40};
    colours->SetTypedTuple(vtkIdType(i), meets[i] ? good : bad);
    failing_ += !meets[i];
  }
  copy->GetPointData()->SetScalars(colours);
  vtkPolyDataMapper::SafeDownCast(task_actor_->GetMapper())->SetInputData(copy);
  has_task_ = true;
  update_visibility();
}

void TaskScene::set_inscribed(vtkPolyData* surface) {
  has_inscribed_ = surface && surface->GetNumberOfPoints() > 0;
  if (has_inscribed_) {
    vtkNew<vtkPolyData> copy;
    copy->ShallowCopy(surface);
    vtkPolyDataMapper::SafeDownCast(inscribed_actor_->GetMapper())->SetInputData(copy);
  }
  update_visibility();
}

void TaskScene::set_visible(bool visible) {
  visible_ = visible;
  update_visibility();
}

bool TaskScene::visible() const { return visible_ && has_task_; }

void TaskScene::update_visibility() {
  task_actor_->SetVisibility(visible_ && has_task_);
  inscribed_actor_->SetVisibility(visible_ && has_inscribed_);
}

}  // namespace linkscape::render
