#include "render/linkage_scene.h"

#include <vtkActor.h>
#include <vtkAxesActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCamera.h>
#include <vtkCaptionActor2D.h>
#include <vtkCellArray.h>
#include <vtkCylinderSource.h>
#include <vtkMatrix4x4.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTransform.h>
#include <vtkTubeFilter.h>

#include <Eigen/Geometry>

namespace linkscape::render {
namespace {

using parallel12r::kJointCount;
using parallel12r::kLinkCount;

void set_matrix(vtkActor* actor, const Eigen::Matrix4d& m) {
  vtkNew<vtkMatrix4x4> vm;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) vm->SetElement(r, c, m(r, c));
  actor->SetUserMatrix(vm);
}

// Colours by role: ground grey; each actuator's shaft and its spherical loop
// share a hue (A red, B blue, C green); the planar parallelogram is gold.
std::array<double, 3> link_colour(int link) {
  switch (link) {
    case 1: return {0.35, 0.35, 0.38};
    case 5: return {0.80, 0.25, 0.15};
    case 2: return {0.10, 0.40, 0.75};
    case 3: case 4: return {0.40, 0.62, 0.90};
    case 8: return {0.25, 0.60, 0.20};
    case 6: case 7: return {0.55, 0.80, 0.40};
    default: return {0.90, 0.68, 0.15};  // 9, 10
  }
}

vtkSmartPointer<vtkPolyData> polylines_to_vtk(const parallel12r::LinkShape& shape) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  for (const auto& line : shape.polylines) {
    lines->InsertNextCell(static_cast<vtkIdType>(line.size()));
    for (const Eigen::Vector3d& p : line) lines->InsertCellPoint(points->InsertNextPoint(p.data()));
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  return poly;
}

}  // namespace

LinkageScene::LinkageScene() {
  joint_source_->SetResolution(20);
  joint_source_->SetRadius(0.5);
  joint_source_->SetHeight(1.0);
  vtkNew<vtkPolyDataMapper> joint_mapper;
  joint_mapper->SetInputConnection(joint_source_->GetOutputPort());
  for (auto& actor : joint_actors_) {
    actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(joint_mapper);
    actor->GetProperty()->SetColor(0.82, 0.82, 0.85);
    actor->GetProperty()->SetSpecular(0.4);
  }
  for (int k = 0; k < kLinkCount; ++k) {
    link_lines_[k] = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkTubeFilter> tube;
    tube->SetInputData(link_lines_[k]);
    tube->SetNumberOfSides(12);
    tube->CappingOn();
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(tube->GetOutputPort());
    link_actors_[k] = vtkSmartPointer<vtkActor>::New();
    link_actors_[k]->SetMapper(mapper);
    const auto c = link_colour(k + 1);
    link_actors_[k]->GetProperty()->SetColor(c[0], c[1], c[2]);
    link_actors_[k]->GetProperty()->SetSpecular(0.3);
  }
  endpoint_source_->SetThetaResolution(24);
  endpoint_source_->SetPhiResolution(16);
  vtkNew<vtkPolyDataMapper> endpoint_mapper;
  endpoint_mapper->SetInputConnection(endpoint_source_->GetOutputPort());
  endpoint_actor_->SetMapper(endpoint_mapper);
  endpoint_actor_->GetProperty()->SetColor(0.95, 0.10, 0.10);
  endpoint_actor_->GetProperty()->SetSpecular(0.6);

  reach_source_->SetThetaResolution(24);
  reach_source_->SetPhiResolution(12);
  vtkNew<vtkPolyDataMapper> reach_mapper;
  reach_mapper->SetInputConnection(reach_source_->GetOutputPort());
  reach_actor_->SetMapper(reach_mapper);
  reach_actor_->GetProperty()->SetRepresentationToWireframe();
  reach_actor_->GetProperty()->SetColor(0.55, 0.60, 0.70);
  reach_actor_->GetProperty()->SetOpacity(0.10);
  reach_actor_->GetProperty()->LightingOff();
  reach_actor_->PickableOff();

  const char* names[] = {"A", "B", "C", "D"};
  for (int i = 0; i < 4; ++i) {
    labels_[i] = vtkSmartPointer<vtkBillboardTextActor3D>::New();
    labels_[i]->SetInput(names[i]);
    labels_[i]->GetTextProperty()->SetFontSize(20);
    labels_[i]->GetTextProperty()->BoldOn();
    labels_[i]->GetTextProperty()->SetColor(i == 3 ? 0.95 : 0.15, i == 3 ? 0.1 : 0.15, i == 3 ? 0.1 : 0.2);
  }
  // Axis captions at a fixed small font size rather than scaled to their box.
  for (auto* caption : {axes_->GetXAxisCaptionActor2D(), axes_->GetYAxisCaptionActor2D(),
                        axes_->GetZAxisCaptionActor2D()}) {
    caption->GetTextActor()->SetTextScaleModeToNone();
    caption->GetCaptionTextProperty()->SetFontSize(16);
    caption->GetCaptionTextProperty()->SetColor(0.2, 0.2, 0.25);
    caption->GetCaptionTextProperty()->ShadowOff();
    caption->GetCaptionTextProperty()->ItalicOff();
    caption->GetCaptionTextProperty()->BoldOff();
  }
  axes_->SetShaftTypeToCylinder();
  axes_->PickableOff();
  set_model(model_);
}

LinkageScene::~LinkageScene() = default;

void LinkageScene::add_to(vtkRenderer* renderer) {
  for (auto& a : link_actors_) renderer->AddActor(a);
  for (auto& a : joint_actors_) renderer->AddActor(a);
  for (auto& l : labels_) renderer->AddActor(l);
  renderer->AddActor(endpoint_actor_);
  renderer->AddActor(reach_actor_);
  renderer->AddActor(axes_);
}

void LinkageScene::set_model(const parallel12r::Model& model) {
  model.validate();
  model_ = model;
  rebuild_geometry();
  set_pose(q_);
}

void LinkageScene::rebuild_geometry() {
  const double scale = std::min(model_.L1, model_.L2);
  const auto shapes = parallel12r::link_shapes(model_);
  for (int k = 0; k < kLinkCount; ++k) {
    link_lines_[k]->ShallowCopy(polylines_to_vtk(shapes[k]));
    link_lines_[k]->Modified();
    auto* tube = vtkTubeFilter::SafeDownCast(link_actors_[k]->GetMapper()->GetInputAlgorithm());
    // Ground and shafts slightly thicker than the moving links.
    tube->SetRadius((k == 0 ? 0.024 : 0.018) * scale);
  }
  endpoint_source_->SetRadius(0.05 * scale);
  reach_source_->SetRadius(model_.reach());
  axes_->SetTotalLength(0.45 * model_.reach(), 0.45 * model_.reach(), 0.45 * model_.reach());
  axes_->SetCylinderRadius(0.01);
  axes_->SetConeRadius(0.3);
}

void LinkageScene::set_pose(const Eigen::Vector3d& q) {
  const parallel12r::Skeleton sk = parallel12r::skeleton(model_, q);
  q_ = q;
  for (int k = 0; k < kLinkCount; ++k) set_matrix(link_actors_[k], sk.link_frames[k].matrix());
  const double scale = std::min(model_.L1, model_.L2);
  for (int j = 0; j < kJointCount; ++j) {
    // Cylinder source: unit height along y, radius 0.5.
    const bool actuator = j < 3;
    const double length = (actuator ? 0.16 : 0.09) * scale, diameter = (actuator ? 0.10 : 0.065) * scale;
    Eigen::Affine3d T = Eigen::Affine3d::Identity();
    T.translate(sk.joint_positions[j]);
    T.rotate(Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), sk.joint_axes[j]));
    T.scale(Eigen::Vector3d(diameter, length, diameter));
    set_matrix(joint_actors_[j], T.matrix());
    if (actuator) joint_actors_[j]->GetProperty()->SetColor(0.25, 0.25, 0.28);
  }
  const Eigen::Vector3d& d = sk.endpoint;
  endpoint_actor_->SetPosition(d.x(), d.y(), d.z());
  const double lift = 0.09 * scale;
  // Actuator labels sit outside the motor ends on their shafts.
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d p = sk.joint_positions[i].normalized() * (sk.joint_positions[i].norm() + 0.3 * scale);
    labels_[i]->SetPosition(p.x(), p.y(), p.z());
  }
  labels_[3]->SetPosition(d.x(), d.y(), d.z() + lift);
}

void LinkageScene::reset_camera(vtkRenderer* renderer) const {
  const double r = model_.reach();
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(0.0, 0.15 * r, 0.05 * r);
  // From the -x side, so the default x-slice (at +x) lies behind the linkage.
  camera->SetPosition(-3.2 * r, 2.2 * r, 1.6 * r);
  camera->SetViewUp(0.0, 0.0, 1.0);
  renderer->ResetCameraClippingRange();
}

}  // namespace linkscape::render
