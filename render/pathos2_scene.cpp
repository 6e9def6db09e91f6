#include "render/pathos2_scene.h"

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

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

namespace linkscape::render {
namespace {

using pathos2::kLegCount;

// Sizes in cm, chosen for the Table 1 device (l0 = 45, l2 = 14): links read
// as rods, joints as knuckles a little thicker than the rods.
constexpr double kLinkDiameter = 0.9;
constexpr double kJointDiameter = 1.5, kJointLength = 2.0;
constexpr double kActiveDiameter = 2.2, kActiveLength = 2.8;  // R1, the motors
constexpr double kGlobularDiameter = 1.3;
// The top plates are drawn this much larger than the triangle through their
// globular centres (a plate extends beyond its joints).
constexpr double kTopPlateScale = 1.6;
constexpr double kPlateThickness = 0.6;
constexpr double kPlatformAxes = 4.0;

// One hue per leg (no red: red marks a failing leg).
constexpr std::array<std::array<double, 3>, kLegCount> kLegColours{{
    {0.12, 0.42, 0.75},  // 1 blue
    {0.18, 0.60, 0.22},  // 2 green
    {0.55, 0.36, 0.74},  // 3 purple
    {0.95, 0.55, 0.10},  // 4 orange
    {0.55, 0.36, 0.24},  // 5 brown
    {0.05, 0.65, 0.72},  // 6 teal
}};
constexpr std::array<double, 3> kHighlight{0.92, 0.06, 0.06};
constexpr std::array<double, 3> kJointColour{0.80, 0.80, 0.83};
constexpr std::array<double, 3> kActiveColour{0.22, 0.22, 0.25};
constexpr std::array<double, 3> kTopPlateColour{0.85, 0.66, 0.12};

void set_matrix(vtkProp3D* prop, const Eigen::Matrix4d& m) {
  vtkNew<vtkMatrix4x4> vm;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) vm->SetElement(r, c, m(r, c));
  prop->SetUserMatrix(vm);
}

// The shared cylinder (unit height along y, radius 0.5) centred at `centre`,
// its axis along `axis`, with the given length and diameter.
Eigen::Matrix4d cylinder_matrix(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double length,
                                double diameter) {
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  T.translate(centre);
  T.rotate(Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), axis.normalized()));
  T.scale(Eigen::Vector3d(diameter, length, diameter));
  return T.matrix();
}

void set_colour(vtkActor* actor, const std::array<double, 3>& c) { actor->GetProperty()->SetColor(c[0], c[1], c[2]); }

void style_axes(vtkAxesActor* axes, int font_size) {
  for (auto* caption : {axes->GetXAxisCaptionActor2D(), axes->GetYAxisCaptionActor2D(),
                        axes->GetZAxisCaptionActor2D()}) {
    caption->GetTextActor()->SetTextScaleModeToNone();
    caption->GetCaptionTextProperty()->SetFontSize(font_size);
    caption->GetCaptionTextProperty()->SetColor(0.2, 0.2, 0.25);
    caption->GetCaptionTextProperty()->ShadowOff();
    caption->GetCaptionTextProperty()->ItalicOff();
    caption->GetCaptionTextProperty()->BoldOff();
  }
  axes->SetShaftTypeToCylinder();
  axes->SetCylinderRadius(0.02);
  axes->SetConeRadius(0.35);
  axes->PickableOff();
}

}  // namespace

Pathos2Scene::Pathos2Scene() {
  cylinder_->SetResolution(20);
  cylinder_->SetRadius(0.5);
  cylinder_->SetHeight(1.0);
  disc_->SetResolution(72);
  disc_->SetRadius(0.5);
  disc_->SetHeight(1.0);
  sphere_->SetRadius(0.5);
  sphere_->SetThetaResolution(20);
  sphere_->SetPhiResolution(14);

  // One mapper per shared source: every actor of a kind draws the same data.
  auto shared = [](vtkAlgorithmOutput* port) {
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputConnection(port);
    return mapper;
  };
  auto cylinder_mapper = shared(cylinder_->GetOutputPort());
  auto sphere_mapper = shared(sphere_->GetOutputPort());
  auto disc_mapper = shared(disc_->GetOutputPort());
  auto actor_of = [](vtkPolyDataMapper* mapper) {
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    actor->GetProperty()->SetSpecular(0.3);
    actor->GetProperty()->SetSpecularPower(20);
    return actor;
  };
  for (int i = 0; i < kLegCount; ++i) {
    for (auto& a : links_[i]) a = actor_of(cylinder_mapper);
    for (auto& a : revolutes_[i]) a = actor_of(cylinder_mapper);
    globulars_[i] = actor_of(sphere_mapper);
    labels_[i] = vtkSmartPointer<vtkBillboardTextActor3D>::New();
    labels_[i]->SetInput(std::to_string(i + 1).c_str());
    labels_[i]->GetTextProperty()->SetFontSize(22);
    labels_[i]->GetTextProperty()->BoldOn();
    labels_[i]->PickableOff();
  }
  for (int p = 0; p < 2; ++p) {
    base_plates_[p] = actor_of(disc_mapper);
    base_plates_[p]->GetProperty()->SetColor(0.62, 0.67, 0.76);
    base_plates_[p]->GetProperty()->SetOpacity(0.35);
    base_plates_[p]->PickableOff();
    top_plate_shapes_[p] = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(top_plate_shapes_[p]);
    top_plates_[p] = vtkSmartPointer<vtkActor>::New();
    top_plates_[p]->SetMapper(mapper);
    set_colour(top_plates_[p], kTopPlateColour);
    top_plates_[p]->GetProperty()->EdgeVisibilityOn();
    top_plates_[p]->GetProperty()->SetEdgeColor(0.45, 0.32, 0.02);
    top_plates_[p]->GetProperty()->SetLineWidth(2.0);
  }
  style_axes(world_axes_, 16);
  style_axes(platform_axes_, 13);
  platform_axes_->SetTotalLength(kPlatformAxes, kPlatformAxes, kPlatformAxes);
  platform_axes_->SetXAxisLabelText("xE");
  platform_axes_->SetYAxisLabelText("yE");
  platform_axes_->SetZAxisLabelText("zE");
  apply_colours();

  const pathos2::Model model;
  set_model(model, pathos2::home_pose(model));
}

Pathos2Scene::~Pathos2Scene() = default;

void Pathos2Scene::add_to(vtkRenderer* renderer) {
  if (!renderer) throw std::invalid_argument("Pathos2Scene::add_to: renderer is null");
  for (int i = 0; i < kLegCount; ++i) {
    for (auto& a : links_[i]) renderer->AddActor(a);
    for (auto& a : revolutes_[i]) renderer->AddActor(a);
    renderer->AddActor(globulars_[i]);
    renderer->AddActor(labels_[i]);
  }
  for (int p = 0; p < 2; ++p) {
    renderer->AddActor(top_plates_[p]);
    renderer->AddActor(base_plates_[p]);  // translucent: after the opaque props
  }
  renderer->AddActor(world_axes_);
  renderer->AddActor(platform_axes_);
}

void Pathos2Scene::set_model(const pathos2::Model& model, const pathos2::Pose& pose) {
  pathos2::Geometry geometry = pathos2::make_geometry(model);  // validates
  const pathos2::PoseIkResult ik = pathos2::inverse(geometry, pose);
  if (ik.status != Status::Ok && ik.status != Status::OutOfLimits)
    throw std::invalid_argument("pathos2 scene: the pose is not reachable with this design (leg " +
                                std::to_string(ik.failing_leg + 1) + " " + std::string(to_string(ik.status)) + ")");
  geometry_ = std::move(geometry);

  // Base plates: discs just outside the R1 joints, flush with the plate plane.
  const double l0 = model.l0;
  double radius = 0;
  for (const auto& p : geometry_.p_world_B) radius = std::max(radius, std::hypot(p.x(), p.y()));
  radius += 0.5 * kActiveLength + 1.0;
  const double z_plate[] = {-0.5 * kPlateThickness, l0 + 0.5 * kPlateThickness};
  for (int p = 0; p < 2; ++p)
    set_matrix(base_plates_[p], cylinder_matrix({0, 0, z_plate[p]}, Eigen::Vector3d::UnitZ(), kPlateThickness,
                                                2 * radius));

  // Top plates: triangles through the globular centres, in the plate frame
  // (E shifted by side * h0 along z_E; the shift is part of the pose matrix).
  for (int p = 0; p < 2; ++p) {
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> cells;
    cells->InsertNextCell(3);
    const Eigen::Vector3d centre = (geometry_.p_E_attach_plate[3 * p] + geometry_.p_E_attach_plate[3 * p + 1] +
                                    geometry_.p_E_attach_plate[3 * p + 2]) / 3.0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d corner = centre + kTopPlateScale * (geometry_.p_E_attach_plate[3 * p + k] - centre);
      cells->InsertCellPoint(points->InsertNextPoint(corner.data()));
    }
    top_plate_shapes_[p]->SetPoints(points);
    top_plate_shapes_[p]->SetPolys(cells);
    top_plate_shapes_[p]->Modified();
  }

  // Leg numbers outside their R1 joints.
  for (int i = 0; i < kLegCount; ++i) {
    const Eigen::Vector3d& r1 = geometry_.p_world_B[i];
    const Eigen::Vector3d radial = Eigen::Vector3d(r1.x(), r1.y(), 0).normalized();
    const Eigen::Vector3d at = r1 + 4.5 * radial + Eigen::Vector3d(0, 0, i < 3 ? -0.5 : 3.0);
    labels_[i]->SetPosition(at.x(), at.y(), at.z());
  }
  const double axes = 0.22 * l0;
  world_axes_->SetTotalLength(axes, axes, axes);
  apply_pose(pose, ik);
}

void Pathos2Scene::set_pose(const pathos2::Pose& pose) {
  const pathos2::PoseIkResult ik = pathos2::inverse(geometry_, pose);
  if (ik.status != Status::Ok && ik.status != Status::OutOfLimits)
    throw std::invalid_argument("pathos2 scene: leg " + std::to_string(ik.failing_leg + 1) + " is " +
                                std::string(to_string(ik.status)));
  apply_pose(pose, ik);
}

void Pathos2Scene::apply_pose(const pathos2::Pose& pose, const pathos2::PoseIkResult& ik) {
  skeleton_ = pathos2::skeleton(geometry_, pose, ik);
  pose_ = pose;
  for (int i = 0; i < kLegCount; ++i) {
    const pathos2::LegSkeleton& leg = skeleton_.legs[i];
    const Eigen::Vector3d* chain[] = {&leg.r1, &leg.r2, &leg.r3, &leg.globular};
    for (int k = 0; k < kLinksPerLeg; ++k) {
      const Eigen::Vector3d d = *chain[k + 1] - *chain[k];
      set_matrix(links_[i][k], cylinder_matrix(0.5 * (*chain[k] + *chain[k + 1]), d, d.norm(), kLinkDiameter));
    }
    set_matrix(revolutes_[i][0], cylinder_matrix(leg.r1, leg.r1_axis, kActiveLength, kActiveDiameter));
    set_matrix(revolutes_[i][1], cylinder_matrix(leg.r2, leg.r2_axis, kJointLength, kJointDiameter));
    set_matrix(revolutes_[i][2], cylinder_matrix(leg.r3, leg.r3_axis, kJointLength, kJointDiameter));
    Eigen::Affine3d G = Eigen::Affine3d::Identity();
    G.translate(leg.globular);
    G.scale(kGlobularDiameter);
    set_matrix(globulars_[i], G.matrix());
  }
  Eigen::Affine3d T_world_E = Eigen::Affine3d::Identity();
  T_world_E.translate(pose.p_world_E);
  T_world_E.rotate(pose.R_world_E);
  for (int p = 0; p < 2; ++p) {
    const double side = geometry_.grip_side[3 * p];
    set_matrix(top_plates_[p], (T_world_E * Eigen::Translation3d(0, 0, side * pose.h0)).matrix());
  }
  set_matrix(platform_axes_, T_world_E.matrix());
}

void Pathos2Scene::set_highlighted_leg(int leg) {
  if (leg < -1 || leg >= kLegCount)
    throw std::invalid_argument("Pathos2Scene: leg index must be -1..5, got " + std::to_string(leg));
  highlighted_ = leg;
  apply_colours();
}

void Pathos2Scene::apply_colours() {
  for (int i = 0; i < kLegCount; ++i) {
    const auto& c = i == highlighted_ ? kHighlight : kLegColours[i];
    for (auto& a : links_[i]) set_colour(a, c);
    set_colour(revolutes_[i][0], kActiveColour);
    set_colour(revolutes_[i][1], kJointColour);
    set_colour(revolutes_[i][2], kJointColour);
    set_colour(globulars_[i], i == highlighted_ ? kHighlight : kJointColour);
    labels_[i]->GetTextProperty()->SetColor(c[0] * 0.8, c[1] * 0.8, c[2] * 0.8);
  }
}

void Pathos2Scene::reset_camera(vtkRenderer* renderer) const {
  const double l0 = geometry_.model.l0;
  double radius = 0;
  for (const auto& p : geometry_.p_world_B) radius = std::max(radius, std::hypot(p.x(), p.y()));
  radius += 2.0;
  vtkCamera* camera = renderer->GetActiveCamera();
  const Eigen::Vector3d focal(0, 0, 0.5 * l0);
  const Eigen::Vector3d direction = Eigen::Vector3d(-0.95, -1.45, 0.85).normalized();
  const Eigen::Vector3d position = focal + 3.0 * l0 * direction;
  camera->SetFocalPoint(focal.data());
  camera->SetPosition(position.data());
  camera->SetViewUp(0.0, 0.0, 1.0);
  // Frame the device's box with its leg numbers (not its bounding sphere,
  // which leaves margins).
  double bounds[6] = {-radius, radius, -radius, radius, -4.0, l0 + 4.5};
  renderer->ResetCamera(bounds);
  camera->Zoom(1.12);
  renderer->ResetCameraClippingRange();
}

}  // namespace linkscape::render
