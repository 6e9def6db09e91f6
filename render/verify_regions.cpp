#include "render/verify_regions.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>

#include <stdexcept>

namespace linkscape::render {

vtkSmartPointer<vtkPolyData> boxes_mesh(const std::vector<verify::Box>& boxes) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> faces;
  // Each face: the axis it is normal to, its side, and its corners in order
  // around it (as bits of the two other axes).
  for (const verify::Box& b : boxes)
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side) {
        const int a = (axis + 1) % 3, c = (axis + 2) % 3;
        vtkIdType ids[4];
        for (int k = 0; k < 4; ++k) {
          // Counter-clockwise seen from outside: e_a x e_c is +axis, so the
          // low side runs the other way round.
          const int j = side ? k : 3 - k;
          const int ua = (j == 1 || j == 2) ? 1 : 0, uc = j >= 2 ? 1 : 0;
          Eigen::Vector3d p;
          p(axis) = side ? b.hi(axis) : b.lo(axis);
          p(a) = ua ? b.hi(a) : b.lo(a);
          p(c) = uc ? b.hi(c) : b.lo(c);
          ids[k] = points->InsertNextPoint(p.data());
        }
        faces->InsertNextCell(4, ids);
      }
  vtkSmartPointer<vtkPolyData> out = vtkSmartPointer<vtkPolyData>::New();
  out->SetPoints(points);
  out->SetPolys(faces);
  return out;
}

VerifyRegions::VerifyRegions() {
  for (vtkActor* actor : {proved_actor_.Get(), undecided_actor_.Get(), counterexample_actor_.Get()}) {
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->ScalarVisibilityOff();
    actor->SetMapper(mapper);
    actor->PickableOff();
    actor->VisibilityOff();
  }
  proved_actor_->GetProperty()->SetRepresentationToWireframe();
  proved_actor_->GetProperty()->SetColor(0.0, 0.62, 0.45);  // bluish green
  proved_actor_->GetProperty()->SetOpacity(0.25);
  undecided_actor_->GetProperty()->SetColor(0.9, 0.62, 0.0);  // orange
  undecided_actor_->GetProperty()->SetOpacity(0.6);
  counterexample_actor_->GetProperty()->SetColor(0.84, 0.37, 0.0);  // vermillion
  counterexample_actor_->GetProperty()->SetAmbient(0.6);
}

VerifyRegions::~VerifyRegions() = default;

void VerifyRegions::add_to(vtkRenderer* renderer) {
  if (!renderer) throw std::invalid_argument("verify regions: null renderer");
  for (vtkActor* actor : {proved_actor_.Get(), undecided_actor_.Get(), counterexample_actor_.Get()})
    if (!renderer->HasViewProp(actor)) renderer->AddActor(actor);
}

void VerifyRegions::show(const verify::Result& r, double marker_radius) {
  if (!(marker_radius > 0)) throw std::invalid_argument("verify regions: the marker's radius must be positive");
  const auto set = [](vtkActor* actor, vtkPolyData* mesh, bool visible) {
    static_cast<vtkPolyDataMapper*>(actor->GetMapper())->SetInputData(mesh);
    actor->SetVisibility(visible);
  };
  set(proved_actor_, boxes_mesh(r.proved_boxes), !r.proved_boxes.empty());
  set(undecided_actor_, boxes_mesh(r.undecided_boxes), !r.undecided_boxes.empty());
  proved_ = r.proved_boxes.size();
  undecided_ = r.undecided_boxes.size();
  counterexample_ = r.counterexample.has_value();
  vtkNew<vtkSphereSource> ball;
  if (r.counterexample) ball->SetCenter(r.counterexample->point.data());
  ball->SetRadius(marker_radius);
  ball->SetThetaResolution(16);
  ball->SetPhiResolution(12);
  ball->Update();
  set(counterexample_actor_, ball->GetOutput(), counterexample_);
}

void VerifyRegions::clear() {
  for (vtkActor* actor : {proved_actor_.Get(), undecided_actor_.Get(), counterexample_actor_.Get()})
    actor->VisibilityOff();
  proved_ = undecided_ = 0;
  counterexample_ = false;
}

}  // namespace linkscape::render
