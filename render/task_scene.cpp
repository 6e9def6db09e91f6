#include "render/task_scene.h"

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkCoordinate.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkPoints.h>
#include <vtkProperty2D.h>
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
  // Failing samples again as dots over everything, so the far side's show too.
  vtkNew<vtkCoordinate> world;
  world->SetCoordinateSystemToWorld();
  vtkNew<vtkPolyDataMapper2D> failing_mapper;
  failing_mapper->SetTransformCoordinate(world);
  failing_mapper->ScalarVisibilityOff();
  failing_actor_->SetMapper(failing_mapper);
  failing_actor_->GetProperty()->SetColor(kFailsColour[0] / 255.0, kFailsColour[1] / 255.0, kFailsColour[2] / 255.0);
  failing_actor_->GetProperty()->SetPointSize(6);
  failing_actor_->PickableOff();
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
  if (!renderer->HasViewProp(failing_actor_)) renderer->AddViewProp(failing_actor_);
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
  points_ = meets.size();
  vtkNew<vtkPoints> failing_points;
  vtkNew<vtkCellArray> failing_verts;
  for (std::size_t i = 0; i < meets.size(); ++i) {
    colours->SetTypedTuple(vtkIdType(i), meets[i] ? kMeetsColour : kFailsColour);
    if (meets[i]) continue;
    failing_verts->InsertNextCell(1);
    failing_verts->InsertCellPoint(failing_points->InsertNextPoint(surface->GetPoint(vtkIdType(i))));
    ++failing_;
  }
  copy->GetPointData()->SetScalars(colours);
  vtkNew<vtkPolyData> failing;
  failing->SetPoints(failing_points);
  failing->SetVerts(failing_verts);
  vtkPolyDataMapper2D::SafeDownCast(failing_actor_->GetMapper())->SetInputData(failing);
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
  // Few failing samples are a speck that may sit on the far side: shown
  // over everything. Many are a region the surface's own colours show.
  const bool few = failing_ > 0 && double(failing_) <= kFewFailing * double(points_);
  failing_actor_->SetVisibility(visible_ && has_task_ && few);
}

}  // namespace linkscape::render
