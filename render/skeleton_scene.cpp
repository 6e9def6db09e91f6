#include "render/skeleton_scene.h"

#include <vtkActor.h>
#include <vtkAxesActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCamera.h>
#include <vtkCaptionActor2D.h>
#include <vtkCellArray.h>
#include <vtkCoordinate.h>
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
#include <vtkTubeFilter.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace linkscape::render {
namespace {

using Colour = std::array<double, 3>;

// Sizes as fractions of SkeletonModel::scale: links read as rods, joints as
// knuckles a little thicker than the rods, motors larger still.
constexpr double kTubeRadius = 0.018, kGroundTubeRadius = 0.024;
constexpr double kRevoluteLength = 0.09, kRevoluteDiameter = 0.065;
constexpr double kPrismaticLength = 0.22, kPrismaticDiameter = 0.05;
constexpr double kBallDiameter = 0.075;
constexpr double kActuatedGrowth = 1.5;  // actuated knuckles are this much larger
constexpr double kEndpointRadius = 0.05;
constexpr double kLabelOffset = 0.22;  // from the joint, away from the base z axis
constexpr double kAxesLength = 0.8;

constexpr Colour kGroundColour{0.35, 0.35, 0.38};
constexpr Colour kGroundPlateColour{0.62, 0.67, 0.76};
// Moving bodies cycle through these hues (no red: red marks a failing body).
constexpr std::array<Colour, 7> kBodyColours{{
    {0.12, 0.42, 0.75},  // blue
    {0.18, 0.60, 0.22},  // green
    {0.90, 0.68, 0.15},  // gold
    {0.55, 0.36, 0.74},  // purple
    {0.95, 0.55, 0.10},  // orange
    {0.05, 0.65, 0.72},  // teal
    {0.55, 0.36, 0.24},  // brown
}};
constexpr Colour kFailingColour{0.92, 0.06, 0.06};
constexpr Colour kJointColour{0.80, 0.80, 0.83};
constexpr Colour kActuatedColour{0.22, 0.22, 0.25};
constexpr Colour kEndpointColour{0.85, 0.15, 0.70};  // magenta, apart from the failing red
constexpr double kPlateOpacity = 0.35;

void set_colour(vtkActor* actor, const Colour& c) { actor->GetProperty()->SetColor(c[0], c[1], c[2]); }

// Reuses the prop's matrix: a pose change allocates nothing.
void set_matrix(vtkProp3D* prop, const Eigen::Matrix4d& m) {
  vtkMatrix4x4* vm = prop->GetUserMatrix();
  if (!vm) {
    vtkNew<vtkMatrix4x4> fresh;
    prop->SetUserMatrix(fresh);
    vm = fresh;
  }
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) vm->SetElement(r, c, m(r, c));
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

void validate(const SkeletonModel& model) {
  if (!(model.scale > 0) || !std::isfinite(model.scale))
    throw std::invalid_argument("skeleton: scale must be finite and > 0, got " + std::to_string(model.scale));
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = model.bodies[b];
    const std::string where = "skeleton body " + std::to_string(b) + " '" + body.name + "': ";
    for (const auto& line : body.polylines) {
      if (line.size() < 2) throw std::invalid_argument(where + "a polyline needs at least 2 points");
      if (!std::all_of(line.begin(), line.end(), finite))
        throw std::invalid_argument(where + "non-finite polyline point");
    }
    for (const auto& face : body.faces) {
      if (face.size() < 3) throw std::invalid_argument(where + "a face needs at least 3 points");
      if (!std::all_of(face.begin(), face.end(), finite)) throw std::invalid_argument(where + "non-finite face point");
    }
  }
  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& joint = model.joints[j];
    const std::string where = "skeleton joint " + std::to_string(j) + " '" + joint.name + "': ";
    if (joint.body < 0 || joint.body >= int(model.bodies.size()))
      throw std::invalid_argument(where + "body " + std::to_string(joint.body) + " does not exist (" +
                                  std::to_string(model.bodies.size()) + " bodies)");
    if (!finite(joint.p_body_joint) || !finite(joint.axis_body_joint))
      throw std::invalid_argument(where + "non-finite point or axis");
    const bool has_axis = joint.type == JointType::Revolute || joint.type == JointType::Prismatic;
    if (has_axis && joint.axis_body_joint.norm() == 0.0) throw std::invalid_argument(where + "zero axis");
  }
}

// Polylines as VTK lines; consecutive repeated points are dropped (the tube
// filter cannot orient a zero-length segment).
vtkSmartPointer<vtkPolyData> lines_of(const Body& body) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> lines;
  for (const auto& line : body.polylines) {
    std::vector<vtkIdType> ids;
    for (std::size_t k = 0; k < line.size(); ++k)
      if (k == 0 || line[k] != line[k - 1]) ids.push_back(points->InsertNextPoint(line[k].data()));
    if (ids.size() >= 2) lines->InsertNextCell(vtkIdType(ids.size()), ids.data());
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetLines(lines);
  return poly;
}

vtkSmartPointer<vtkPolyData> faces_of(const Body& body) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> polys;
  for (const auto& face : body.faces) {
    polys->InsertNextCell(vtkIdType(face.size()));
    for (const Eigen::Vector3d& p : face) polys->InsertCellPoint(points->InsertNextPoint(p.data()));
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  return poly;
}

// The shared unit source (cylinder: height 1 along y, radius 0.5; sphere:
// radius 0.5) placed at the joint in its body's frame.
Eigen::Matrix4d knuckle_matrix(const Joint& joint, double scale) {
  const double grow = joint.actuated ? kActuatedGrowth : 1.0;
  Eigen::Affine3d T = Eigen::Affine3d::Identity();
  T.translate(joint.p_body_joint);
  switch (joint.type) {
    case JointType::Revolute:
    case JointType::Prismatic: {
      const bool revolute = joint.type == JointType::Revolute;
      const double length = grow * scale * (revolute ? kRevoluteLength : kPrismaticLength);
      const double diameter = grow * scale * (revolute ? kRevoluteDiameter : kPrismaticDiameter);
      T.rotate(Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), joint.axis_body_joint.normalized()));
      T.scale(Eigen::Vector3d(diameter, length, diameter));
      break;
    }
    case JointType::Spherical:
    case JointType::Universal:
      T.scale(grow * scale * kBallDiameter);
      break;
  }
  return T.matrix();
}

Colour body_colour(const SkeletonModel& model, int body) {
  if (model.bodies[body].ground) return kGroundColour;
  int moving_index = 0;  // colours follow the moving bodies only
  for (int b = 0; b < body; ++b) moving_index += model.bodies[b].ground ? 0 : 1;
  return kBodyColours[moving_index % kBodyColours.size()];
}

void style_axes(vtkAxesActor* axes) {
  for (auto* caption : {axes->GetXAxisCaptionActor2D(), axes->GetYAxisCaptionActor2D(),
                        axes->GetZAxisCaptionActor2D()}) {
    caption->GetTextActor()->SetTextScaleModeToNone();
    caption->GetCaptionTextProperty()->SetFontSize(16);
    caption->GetCaptionTextProperty()->SetColor(0.2, 0.2, 0.25);
    caption->GetCaptionTextProperty()->ShadowOff();
    caption->GetCaptionTextProperty()->ItalicOff();
    caption->GetCaptionTextProperty()->BoldOff();
  }
  axes->SetShaftTypeToCylinder();
  axes->SetCylinderRadius(0.01);
  axes->SetConeRadius(0.3);
  axes->PickableOff();
}

}  // namespace

SkeletonScene::SkeletonScene() {
  cylinder_->SetResolution(20);
  cylinder_->SetRadius(0.5);
  cylinder_->SetHeight(1.0);
  sphere_->SetRadius(0.5);
  sphere_->SetThetaResolution(20);
  sphere_->SetPhiResolution(14);
  cylinder_mapper_->SetInputConnection(cylinder_->GetOutputPort());
  sphere_mapper_->SetInputConnection(sphere_->GetOutputPort());

  endpoint_source_->SetThetaResolution(24);
  endpoint_source_->SetPhiResolution(16);
  vtkNew<vtkPolyDataMapper> endpoint_mapper;
  endpoint_mapper->SetInputConnection(endpoint_source_->GetOutputPort());
  endpoint_actor_->SetMapper(endpoint_mapper);
  set_colour(endpoint_actor_, kEndpointColour);
  endpoint_actor_->GetProperty()->SetSpecular(0.6);
  style_axes(axes_);
  set_model(SkeletonModel{});
}

SkeletonScene::~SkeletonScene() {
  // Leave nothing behind in renderers that outlive the scene.
  for (vtkRenderer* r : renderers_)
    if (r)
      for (vtkProp* p : props()) r->RemoveViewProp(p);
}

vtkActor* SkeletonScene::body_tube_actor(int body) const { return bodies_.at(body).tube; }
vtkActor* SkeletonScene::body_face_actor(int body) const { return bodies_.at(body).plate; }
vtkActor* SkeletonScene::joint_actor(int joint) const { return joints_.at(joint).knuckle; }
vtkBillboardTextActor3D* SkeletonScene::joint_label(int joint) const { return joints_.at(joint).label; }
vtkActor* SkeletonScene::endpoint_actor() const { return endpoint_actor_; }

std::vector<vtkProp*> SkeletonScene::props() const {
  std::vector<vtkProp*> out;
  for (const BodyProps& b : bodies_)
    if (b.tube) out.push_back(b.tube);
  for (const JointProps& j : joints_) out.push_back(j.knuckle);
  out.push_back(endpoint_actor_);
  out.push_back(axes_);
  // Translucent, blended in this order after the opaque props: the plates,
  // then the labels over them.
  for (const BodyProps& b : bodies_)
    if (b.plate) out.push_back(b.plate);
  for (const JointProps& j : joints_)
    if (j.label) out.push_back(j.label);
  for (const JointProps& j : joints_)  // overlays: drawn after the scene's props
    if (j.front_label) out.push_back(j.front_label);
  return out;
}

void SkeletonScene::add_to(vtkRenderer* renderer) {
  if (!renderer) throw std::invalid_argument("SkeletonScene::add_to: renderer is null");
  // Forget renderers that have been destroyed.
  std::erase_if(renderers_, [](const vtkWeakPointer<vtkRenderer>& r) { return r == nullptr; });
  if (std::find(renderers_.begin(), renderers_.end(), renderer) != renderers_.end()) return;
  renderers_.emplace_back(renderer);
  for (vtkProp* p : props()) renderer->AddViewProp(p);
}

void SkeletonScene::set_model(const SkeletonModel& model) {
  validate(model);
  const double s = model.scale;

  std::vector<BodyProps> bodies(model.bodies.size());
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = model.bodies[b];
    BodyProps& parts = bodies[b];
    if (!body.polylines.empty()) {
      parts.lines = lines_of(body);
      vtkNew<vtkTubeFilter> tube;
      tube->SetInputData(parts.lines);
      tube->SetRadius((body.ground ? kGroundTubeRadius : kTubeRadius) * s);
      tube->SetNumberOfSides(12);
      tube->CappingOn();
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputConnection(tube->GetOutputPort());
      parts.tube = vtkSmartPointer<vtkActor>::New();
      parts.tube->SetMapper(mapper);
      parts.tube->GetProperty()->SetSpecular(0.3);
      parts.tube->GetProperty()->SetSpecularPower(20);
    }
    if (!body.faces.empty()) {
      parts.faces = faces_of(body);
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputData(parts.faces);
      parts.plate = vtkSmartPointer<vtkActor>::New();
      parts.plate->SetMapper(mapper);
      parts.plate->GetProperty()->SetOpacity(kPlateOpacity);
      parts.plate->GetProperty()->EdgeVisibilityOn();
      parts.plate->GetProperty()->SetLineWidth(1.5);
      parts.plate->PickableOff();
    }
  }

  std::vector<JointProps> joints(model.joints.size());
  for (std::size_t j = 0; j < model.joints.size(); ++j) {
    const Joint& joint = model.joints[j];
    JointProps& parts = joints[j];
    parts.knuckle_in_body = knuckle_matrix(joint, s);
    const bool ball = joint.type == JointType::Spherical || joint.type == JointType::Universal;
    parts.knuckle = vtkSmartPointer<vtkActor>::New();
    parts.knuckle->SetMapper(ball ? sphere_mapper_.Get() : cylinder_mapper_.Get());
    parts.knuckle->GetProperty()->SetSpecular(0.4);
    parts.knuckle->GetProperty()->SetSpecularPower(20);
    if (!joint.label.empty()) {
      parts.label = vtkSmartPointer<vtkBillboardTextActor3D>::New();
      parts.label->SetInput(joint.label.c_str());
      vtkTextProperty* text = parts.label->GetTextProperty();
      text->SetFontSize(20);
      text->BoldOn();
      text->SetJustificationToCentered();
      text->SetVerticalJustificationToCentered();
      parts.label->PickableOff();
      parts.front_label = vtkSmartPointer<vtkTextActor>::New();
      parts.front_label->SetInput(joint.label.c_str());
      vtkTextProperty* front = parts.front_label->GetTextProperty();
      front->ShallowCopy(text);
      front->SetBackgroundColor(1, 1, 1);
      front->SetBackgroundOpacity(0.7);
      parts.front_label->GetPositionCoordinate()->SetCoordinateSystemToWorld();
      parts.front_label->PickableOff();
    }
  }

  // Nothing can fail from here on: swap the props in every renderer.
  std::erase_if(renderers_, [](const vtkWeakPointer<vtkRenderer>& r) { return r == nullptr; });
  for (vtkRenderer* r : renderers_)
    for (vtkProp* p : props()) r->RemoveViewProp(p);
  model_ = model;
  bodies_ = std::move(bodies);
  joints_ = std::move(joints);
  for (vtkRenderer* r : renderers_)
    for (vtkProp* p : props()) r->AddViewProp(p);

  endpoint_source_->SetRadius(kEndpointRadius * s);
  axes_->SetTotalLength(kAxesLength * s, kAxesLength * s, kAxesLength * s);

  if (pose_.X_world_body.size() != model_.bodies.size()) {
    pose_.X_world_body.assign(model_.bodies.size(), Eigen::Isometry3d::Identity());
    pose_.states.assign(model_.bodies.size(), BodyState::Normal);
    pose_.p_world_endpoint.setZero();
  }
  apply_pose();
}

void SkeletonScene::set_pose(const SkeletonPose& pose) {
  const std::size_t n = model_.bodies.size();
  if (pose.X_world_body.size() != n || pose.states.size() != n)
    throw std::invalid_argument("skeleton pose: " + std::to_string(pose.X_world_body.size()) + " frames and " +
                                std::to_string(pose.states.size()) + " states for " + std::to_string(n) +
                                " bodies");
  for (const Eigen::Isometry3d& frame : pose.X_world_body)
    if (!frame.matrix().allFinite()) throw std::invalid_argument("skeleton pose: non-finite body frame");
  if (!pose.p_world_endpoint.allFinite()) throw std::invalid_argument("skeleton pose: non-finite endpoint");
  pose_ = pose;
  apply_pose();
}

void SkeletonScene::apply_pose() {
  const double s = model_.scale;
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const Eigen::Matrix4d frame = pose_.X_world_body[b].matrix();
    const bool failing = pose_.states[b] == BodyState::Failing;
    const Colour colour = failing ? kFailingColour : body_colour(model_, int(b));
    if (vtkActor* tube = bodies_[b].tube) {
      set_matrix(tube, frame);
      set_colour(tube, colour);
    }
    if (vtkActor* plate = bodies_[b].plate) {
      set_matrix(plate, frame);
      const Colour fill = failing || !model_.bodies[b].ground ? colour : kGroundPlateColour;
      set_colour(plate, fill);
      plate->GetProperty()->SetEdgeColor(0.6 * fill[0], 0.6 * fill[1], 0.6 * fill[2]);
    }
  }
  for (std::size_t j = 0; j < joints_.size(); ++j) {
    const Joint& joint = model_.joints[j];
    const Eigen::Isometry3d& frame = pose_.X_world_body[joint.body];
    const bool failing = pose_.states[joint.body] == BodyState::Failing;
    set_matrix(joints_[j].knuckle, frame.matrix() * joints_[j].knuckle_in_body);
    // Motors stay dark so they can be found; passive joints share their body's failure.
    set_colour(joints_[j].knuckle, joint.actuated ? kActuatedColour : failing ? kFailingColour : kJointColour);
    if (vtkBillboardTextActor3D* label = joints_[j].label) {
      const Eigen::Vector3d at = frame * joint.p_body_joint;
      // Beside the joint, away from the base z axis (straight up on the axis).
      Eigen::Vector3d away(at.x(), at.y(), 0.0);
      away = away.norm() > 1e-9 * s ? away.normalized() : Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d p = at + kLabelOffset * s * away;
      label->SetPosition(p.x(), p.y(), p.z());
      const Colour c = failing ? kFailingColour : body_colour(model_, joint.body);
      label->GetTextProperty()->SetColor(0.75 * c[0], 0.75 * c[1], 0.75 * c[2]);
      vtkTextActor* front = joints_[j].front_label;
      front->GetPositionCoordinate()->SetValue(p.x(), p.y(), p.z());
      front->GetTextProperty()->SetColor(0.75 * c[0], 0.75 * c[1], 0.75 * c[2]);
      label->SetVisibility(!labels_in_front_);
      front->SetVisibility(labels_in_front_);
    }
  }
  endpoint_actor_->SetPosition(pose_.p_world_endpoint.x(), pose_.p_world_endpoint.y(), pose_.p_world_endpoint.z());
}

void SkeletonScene::set_labels_in_front(bool on) {
  labels_in_front_ = on;
  apply_pose();
}

vtkTextActor* SkeletonScene::joint_front_label(int joint) const { return joints_.at(joint).front_label; }

void SkeletonScene::reset_camera(vtkRenderer* renderer, const Eigen::AlignedBox3d& workspace_box) const {
  // From the front-left, above; a flat workspace (a planar device's) from
  // higher up, so that its plane is not seen nearly edge-on.
  const Eigen::Vector3d sizes = workspace_box.sizes();
  const bool flat = sizes.z() < 0.1 * std::max(sizes.x(), sizes.y());
  frame(renderer, workspace_box, Eigen::Vector3d(-0.95, -1.45, flat ? 2.6 : 0.85), Eigen::Vector3d::UnitZ());
}

Eigen::AlignedBox3d SkeletonScene::device_box() const { return device_box(pose_); }

Eigen::AlignedBox3d SkeletonScene::device_box(const SkeletonPose& pose) const {
  Eigen::AlignedBox3d box;
  for (std::size_t b = 0; b < model_.bodies.size() && b < pose.X_world_body.size(); ++b) {
    const Eigen::Isometry3d& T = pose.X_world_body[b];
    for (const auto& line : model_.bodies[b].polylines)
      for (const Eigen::Vector3d& p : line) box.extend(T * p);
    for (const auto& face : model_.bodies[b].faces)
      for (const Eigen::Vector3d& p : face) box.extend(T * p);
  }
  return box;
}

std::vector<SkeletonScene::Part> SkeletonScene::pickable_parts() const {
  std::vector<Part> out;
  for (std::size_t b = 0; b < bodies_.size(); ++b)
    for (vtkActor* a : {bodies_[b].tube.Get(), bodies_[b].plate.Get()})
      if (a) out.push_back({a, "link " + model_.bodies[b].name});
  for (std::size_t j = 0; j < joints_.size(); ++j) out.push_back({joints_[j].knuckle, "joint " + model_.joints[j].name});
  out.push_back({endpoint_actor_, "driven point"});
  return out;
}

void SkeletonScene::frame(vtkRenderer* renderer, const Eigen::AlignedBox3d& box, const Eigen::Vector3d& back_in,
                          const Eigen::Vector3d& up_in) const {
  if (!renderer) throw std::invalid_argument("SkeletonScene::frame: renderer is null");
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite())
    throw std::invalid_argument("SkeletonScene::frame: the box is empty or not finite");
  const Eigen::Vector3d back = back_in.normalized();
  if (!back.allFinite() || (up_in - up_in.dot(back) * back).norm() < 1e-9 * up_in.norm())
    throw std::invalid_argument("SkeletonScene::frame: expected a view direction and an up vector not parallel to it");
  // The base does not move: framing it with the box keeps the view steady
  // while the device moves.
  Eigen::AlignedBox3d frame_box = box;
  for (std::size_t b = 0; b < model_.bodies.size(); ++b) {
    if (!model_.bodies[b].ground) continue;
    const Eigen::Isometry3d& T = pose_.X_world_body[b];
    for (const auto& line : model_.bodies[b].polylines)
      for (const Eigen::Vector3d& p : line) frame_box.extend(T * p);
    for (const auto& face : model_.bodies[b].faces)
      for (const Eigen::Vector3d& p : face) frame_box.extend(T * p);
  }
  const Eigen::Vector3d focal = frame_box.center();
  // A box smaller than the device (or a single point) would leave no distance to view from.
  const Eigen::Vector3d half_scale = Eigen::Vector3d::Constant(0.5 * model_.scale);
  frame_box.extend(focal - half_scale);
  frame_box.extend(focal + half_scale);
  // The distance (or parallel scale) fits every corner of the box into the
  // view with a small margin.
  const Eigen::Vector3d up = (up_in - up_in.dot(back) * back).normalized();
  const Eigen::Vector3d right = up.cross(back);
  double aspect = 1.0;  // width / height of the viewport, where it has a window
  if (renderer->GetRenderWindow()) {
    const int* size = renderer->GetSize();
    if (size[0] > 0 && size[1] > 0) aspect = double(size[0]) / size[1];
  }
  constexpr double kFill = 0.9;  // of the half-height and half-width
  vtkCamera* camera = renderer->GetActiveCamera();
  const double tan_half = std::tan(0.5 * camera->GetViewAngle() * std::numbers::pi / 180.0);
  double distance = 0.0, half_height = 0.0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d c = frame_box.corner(Eigen::AlignedBox3d::CornerType(k)) - focal;
    const double needed = std::max(std::abs(c.dot(up)), std::abs(c.dot(right)) / aspect) / kFill;
    half_height = std::max(half_height, needed);
    distance = std::max(distance, c.dot(back) + needed / tan_half);
  }
  const Eigen::Vector3d position = focal + distance * back;
  camera->SetFocalPoint(focal.data());
  camera->SetPosition(position.data());
  camera->SetViewUp(up.data());
  camera->SetParallelScale(half_height);
  renderer->ResetCameraClippingRange();
}

double knuckle_reach(double scale) {
  return 0.5 * std::max({kRevoluteLength, kPrismaticDiameter, kBallDiameter}) * kActuatedGrowth * scale;
}

}  // namespace linkscape::render
