#include "render/force_ellipsoid_scene.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkCoordinate.h>
#include <vtkMatrix4x4.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRegularPolygonSource.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "render/world_label.h"

namespace linkscape::render {

namespace {

// Okabe & Ito's blue: apart from the skeleton's hues and the links' orange.
constexpr double kShapeColour[3] = {0.0, 0.45, 0.70};
constexpr double kAxesColour[3] = {0.0, 0.25, 0.45};
constexpr double kShapeOpacity = 0.25;

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

}  // namespace

double length_per_newton(double largest_N, double target_length) {
  if (!(largest_N > 0) || !(target_length > 0) || !std::isfinite(largest_N) || !std::isfinite(target_length))
    throw std::invalid_argument("force scale: expected a force and a length, both finite and > 0, got " +
                                number(largest_N) + " N and " + number(target_length));
  const double raw = target_length / largest_N;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double best = decade;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (std::abs(std::log(m * decade / raw)) < std::abs(std::log(best / raw))) best = m * decade;
  return best;
}

ForceEllipsoidScene::ForceEllipsoidScene() {
  sphere_->SetRadius(1);
  sphere_->SetThetaResolution(40);
  sphere_->SetPhiResolution(24);
  disk_->SetRadius(1);
  disk_->SetNumberOfSides(72);
  disk_->SetNormal(0, 0, 1);
  // Double points: the drawn surface is the ellipsoid's to rounding (tests hold it to 1e-9).
  sphere_->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  disk_->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);
  shape_actor_->SetMapper(vtkNew<vtkPolyDataMapper>());
  shape_actor_->GetProperty()->SetColor(kShapeColour[0], kShapeColour[1], kShapeColour[2]);
  shape_actor_->GetProperty()->SetOpacity(kShapeOpacity);
  shape_actor_->GetProperty()->SetSpecular(0.3);
  shape_actor_->SetUserMatrix(vtkNew<vtkMatrix4x4>());
  vtkNew<vtkPoints> tips;
  tips->SetDataTypeToDouble();
  axes_->SetPoints(tips);
  axes_->SetLines(vtkNew<vtkCellArray>());
  axes_actor_->SetMapper(vtkNew<vtkPolyDataMapper>());
  static_cast<vtkPolyDataMapper*>(axes_actor_->GetMapper())->SetInputData(axes_);
  axes_actor_->GetProperty()->SetColor(kAxesColour[0], kAxesColour[1], kAxesColour[2]);
  axes_actor_->GetProperty()->SetLineWidth(3);
  style_world_label(label_);
  label_->GetTextProperty()->SetFrameColor(kShapeColour[0], kShapeColour[1], kShapeColour[2]);
  label_->GetTextProperty()->SetVerticalJustificationToTop();
  shape_actor_->PickableOff();
  axes_actor_->PickableOff();
  apply_visibility();
}

ForceEllipsoidScene::~ForceEllipsoidScene() = default;

void ForceEllipsoidScene::add_to(vtkRenderer* renderer) {
  if (!renderer) throw std::invalid_argument("force ellipsoid scene: expected a renderer, got null");
  for (vtkProp* p : std::initializer_list<vtkProp*>{axes_actor_, shape_actor_, label_}) renderer->AddViewProp(p);
  keep_in_view(label_, renderer);  // a device at the view's right edge had its caption cut off
}

void ForceEllipsoidScene::set_ellipsoid(const Shown& s) {
  const haptics::ForceEllipsoid& e = s.ellipsoid;
  const Eigen::Index d = e.semi_axes_N.size();
  if (e.status != Status::Ok || (d != 2 && d != 3) || e.axes.rows() != d || e.axes.cols() != d ||
      !e.semi_axes_N.allFinite() || !(e.semi_axes_N.minCoeff() > 0) || !s.centre.allFinite() ||
      !(s.length_per_N > 0) || !std::isfinite(s.length_per_N))
    throw std::invalid_argument("force ellipsoid scene: expected a bounded ellipsoid of 2 or 3 axes at a finite "
                                "point and a length per newton > 0");
  // Columns: each semi-axis in the base frame, drawn length (a planar device's in its xy plane).
  Eigen::Matrix3d axes = Eigen::Matrix3d::Zero();
  axes.topLeftCorner(d, d) = e.axes * (s.length_per_N * e.semi_axes_N).asDiagonal();
  if (d == 2) axes(2, 2) = 1;  // the disk has no thickness to scale
  vtkMatrix4x4* m = shape_actor_->GetUserMatrix();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m->SetElement(r, c, axes(r, c));
    m->SetElement(r, 3, s.centre(r));
  }
  shape_actor_->Modified();
  auto* mapper = static_cast<vtkPolyDataMapper*>(shape_actor_->GetMapper());
  if (d == 3) mapper->SetInputConnection(sphere_->GetOutputPort());
  else mapper->SetInputConnection(disk_->GetOutputPort());
  vtkPoints* points = axes_->GetPoints();
  points->SetNumberOfPoints(2 * d);
  vtkNew<vtkCellArray> lines;
  for (int k = 0; k < d; ++k) {
    const Eigen::Vector3d tip = s.centre + axes.col(k), tail = s.centre - axes.col(k);
    points->SetPoint(2 * k, tip.data());
    points->SetPoint(2 * k + 1, tail.data());
    const vtkIdType ends[2] = {2 * k, 2 * k + 1};
    lines->InsertNextCell(2, ends);
  }
  axes_->SetLines(lines);
  points->Modified();
  axes_count_ = int(d);
  std::string semi;
  for (int k = 0; k < d; ++k) semi += (k ? ", " : "") + number(e.semi_axes_N(k));
  const std::string label = "force ellipsoid (" + s.torque + " torque)\nsemi-axes " + semi + " N\nforce_iso " +
                            number(s.force_iso_N) + " N, force_max " + number(s.force_max_N) + " N\ndrawn at " +
                            number(s.length_per_N) + " " + s.length_unit + " per N";
  label_->SetInput(label.c_str());
  // Beside the ellipsoid, past its widest reach along x.
  const Eigen::Vector3d corner = s.centre + Eigen::Vector3d(axes.row(0).cwiseAbs().sum(), 0, 0);
  label_->GetPositionCoordinate()->SetValue(corner.data());
  shape_ = true;
  apply_visibility();
}

void ForceEllipsoidScene::set_hidden(const Eigen::Vector3d& centre, const std::string& why) {
  shape_ = false;
  axes_count_ = 0;
  label_->SetInput(("force ellipsoid hidden: " + why).c_str());
  if (centre.allFinite()) label_->GetPositionCoordinate()->SetValue(centre.data());
  apply_visibility();
}

void ForceEllipsoidScene::set_visible(bool on) {
  visible_ = on;
  apply_visibility();
}

void ForceEllipsoidScene::apply_visibility() {
  shape_actor_->SetVisibility(visible_ && shape_);
  axes_actor_->SetVisibility(visible_ && shape_);
  label_->SetVisibility(visible_ && label_->GetInput() && *label_->GetInput());
}

Eigen::Vector3d ForceEllipsoidScene::axis_tip(int k) const {
  if (k < 0 || k >= axes_count_) throw std::out_of_range("force ellipsoid scene: no axis " + std::to_string(k));
  Eigen::Vector3d p;
  axes_->GetPoints()->GetPoint(2 * k, p.data());
  return p;
}

vtkActor* ForceEllipsoidScene::shape_actor() const { return shape_actor_; }

std::string ForceEllipsoidScene::label_text() const { return label_->GetInput() ? label_->GetInput() : ""; }

}  // namespace linkscape::render
