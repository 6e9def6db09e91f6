#include "render/capsule_scene.h"

#include <vtkActor.h>
#include <vtkCapsuleSource.h>
#include <vtkCommand.h>
#include <vtkCoordinate.h>
#include <vtkLineSource.h>
#include <vtkMatrix4x4.h>
#include <vtkActor2D.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty2D.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "render/world_label.h"

namespace linkscape::render {

namespace {

using Colour = std::array<double, 3>;
// Okabe & Ito's palette, told apart with every common colour-vision deficiency.
constexpr Colour kLinkColour{0.34, 0.71, 0.91};   // sky blue
constexpr Colour kPairColour{0.90, 0.62, 0.00};   // orange
constexpr Colour kCloseColour{0.84, 0.37, 0.00};  // vermillion
constexpr Colour kGapColour{0.10, 0.10, 0.15};
// Translucent enough to show the linkage inside, the pair clearly stronger.
constexpr double kLinkOpacity = 0.15, kPairOpacity = 0.45, kCloseOpacity = 0.85;

void style(vtkActor* actor, const Colour& c, double opacity) {
  actor->GetProperty()->SetColor(c[0], c[1], c[2]);
  actor->GetProperty()->SetOpacity(opacity);
}

// The capsule source's axis (y) along a -> b, centred between them.
void place(vtkActor* actor, const interference::Capsule& c) {
  const Eigen::Vector3d along = c.b - c.a;
  const double length = along.norm();
  const Eigen::Vector3d y = length > 0 ? Eigen::Vector3d(along / length) : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = y.unitOrthogonal(), z = x.cross(y);
  const Eigen::Vector3d centre = 0.5 * (c.a + c.b);
  vtkMatrix4x4* m = actor->GetUserMatrix();
  if (!m) {
    vtkNew<vtkMatrix4x4> fresh;
    actor->SetUserMatrix(fresh);
    m = fresh;
  }
  for (int r = 0; r < 3; ++r) {
    m->SetElement(r, 0, x(r));
    m->SetElement(r, 1, y(r));
    m->SetElement(r, 2, z(r));
    m->SetElement(r, 3, centre(r));
  }
  actor->Modified();
}

std::string gap_text(const interference::LinkCapsules& c, CapsuleScene::Gap gap, const std::string& unit) {
  char number[64];
  std::snprintf(number, sizeof number, "%.3g %s", std::abs(c.clearance), unit.c_str());
  const std::string what = gap == CapsuleScene::Gap::Overlap ? "overlap " : gap == CapsuleScene::Gap::Close
                                                                               ? "close: clearance "
                                                                               : "clearance ";
  return what + number + "\n" + c.links[std::size_t(c.closest[0])].name + " to " +
         c.links[std::size_t(c.closest[1])].name;
}

}  // namespace

CapsuleScene::CapsuleScene() {
  // Drawn over the scene: the gap often lies inside the translucent capsules.
  vtkNew<vtkCoordinate> world;
  world->SetCoordinateSystemToWorld();
  vtkNew<vtkPolyDataMapper2D> line_mapper;
  line_mapper->SetInputConnection(line_->GetOutputPort());
  line_mapper->SetTransformCoordinate(world);
  line_actor_->SetMapper(line_mapper);
  line_actor_->GetProperty()->SetColor(kGapColour[0], kGapColour[1], kGapColour[2]);
  line_actor_->GetProperty()->SetLineWidth(3);
  for (int k = 0; k < 2; ++k) {
    end_sources_[k]->SetThetaResolution(12);
    end_sources_[k]->SetPhiResolution(8);
    ends_[k]->SetMapper(vtkNew<vtkPolyDataMapper>());
    ends_[k]->GetMapper()->SetInputConnection(end_sources_[k]->GetOutputPort());
    style(ends_[k], kGapColour, 1.0);
  }
  style_world_label(label_);
  label_anchor_->SetCoordinateSystemToWorld();
  label_->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
  label_->GetPositionCoordinate()->SetReferenceCoordinate(label_anchor_);
  for (vtkProp* p : gap_props()) p->PickableOff();
  apply_visibility();
}

CapsuleScene::~CapsuleScene() {
  for (std::size_t i = 0; i < renderers_.size(); ++i)
    if (renderers_[i]) renderers_[i]->RemoveObserver(frame_observers_[i]);
}

void CapsuleScene::add_to(vtkRenderer* renderer) {
  if (!renderer) throw std::invalid_argument("capsule scene: expected a renderer, got null");
  if (std::find(renderers_.begin(), renderers_.end(), renderer) != renderers_.end()) return;
  renderers_.push_back(renderer);
  // The side the label stands on follows the camera: placed before each frame.
  frame_observers_.push_back(renderer->AddObserver(vtkCommand::StartEvent, this, &CapsuleScene::place_label));
  for (const LinkProps& l : links_) renderer->AddViewProp(l.actor);
  // The gap's marks after the capsules, so they are not blended under them.
  for (vtkProp* p : gap_props()) renderer->AddViewProp(p);
}

void CapsuleScene::set_links(const interference::LinkCapsules& c, const std::string& length_unit) {
  for (const interference::Link& l : c.links)
    if (!l.capsule.a.allFinite() || !l.capsule.b.allFinite() || !(l.capsule.radius >= 0))
      throw std::invalid_argument("capsule scene: link '" + l.name + "' needs finite ends and a radius >= 0");
  while (links_.size() < c.links.size()) {
    LinkProps l{vtkSmartPointer<vtkCapsuleSource>::New(), vtkSmartPointer<vtkActor>::New()};
    l.source->SetThetaResolution(20);
    l.source->SetPhiResolution(12);
    l.source->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);  // links far from the origin stay round
    l.actor->SetMapper(vtkNew<vtkPolyDataMapper>());
    l.actor->GetMapper()->SetInputConnection(l.source->GetOutputPort());
    l.actor->GetProperty()->SetSpecular(0.2);
    l.actor->PickableOff();  // picks land on the linkage inside
    for (vtkRenderer* r : renderers_)
      if (r) r->AddViewProp(l.actor);
    links_.push_back(l);
  }
  shown_ = int(c.links.size());
  for (std::size_t i = 0; i < c.links.size(); ++i) {
    const interference::Capsule& capsule = c.links[i].capsule;
    links_[i].source->SetRadius(capsule.radius);  // VTK re-executes only where a value changed
    links_[i].source->SetCylinderLength((capsule.b - capsule.a).norm());
    place(links_[i].actor, capsule);
    style(links_[i].actor, kLinkColour, kLinkOpacity);
  }
  gap_ = Gap::None;
  if (c.has_pair()) {
    const double thinner = std::min(c.links[std::size_t(c.closest[0])].capsule.radius,
                                    c.links[std::size_t(c.closest[1])].capsule.radius);
    gap_ = c.clearance < 0 ? Gap::Overlap : c.clearance < thinner ? Gap::Close : Gap::Apart;
    const bool close = gap_ != Gap::Apart;
    for (int k : c.closest) style(links_[std::size_t(k)].actor, close ? kCloseColour : kPairColour, close ? kCloseOpacity : kPairOpacity);
    const auto ends = c.gap();
    line_->SetPoint1(ends[0].data());
    line_->SetPoint2(ends[1].data());
    for (int k = 0; k < 2; ++k) {
      end_sources_[k]->SetCenter(ends[std::size_t(k)].data());
      end_sources_[k]->SetRadius(0.25 * std::max(thinner, 1e-9));
    }
    const Eigen::Vector3d middle = 0.5 * (ends[0] + ends[1]);
    label_anchor_->SetValue(middle.data());
    links_centre_ = Eigen::Vector3d::Zero();
    for (const interference::Link& l : c.links) links_centre_ += 0.5 * (l.capsule.a + l.capsule.b) / double(c.links.size());
    place_label();
    label_->SetInput(gap_text(c, gap_, length_unit).c_str());
    const Colour& frame = close ? kCloseColour : kPairColour;
    label_->GetTextProperty()->SetFrameColor(frame[0], frame[1], frame[2]);
  }
  apply_visibility();
}

// The label stands a little off the gap on the screen, on the side away
// from the links' centre (down and to the left before the view has a size),
// its text growing away from the gap.
void CapsuleScene::place_label() {
  const Eigen::Vector3d gap = Eigen::Map<const Eigen::Vector3d>(label_anchor_->GetValue());  // the gap's middle
  const Eigen::Vector3d& centre = links_centre_;
  Eigen::Vector2d away(-1, -1);
  for (vtkRenderer* r : renderers_) {
    if (!r || !r->GetRenderWindow() || r->GetSize()[0] <= 0) continue;
    vtkNew<vtkCoordinate> at;
    at->SetCoordinateSystemToWorld();
    auto display = [&](const Eigen::Vector3d& p) {
      at->SetValue(p.x(), p.y(), p.z());
      const double* d = at->GetComputedDoubleDisplayValue(r);
      return Eigen::Vector2d(d[0], d[1]);
    };
    const Eigen::Vector2d d = display(gap) - display(centre);
    if (d.norm() > 1) away = d;  // pixels
    break;
  }
  away.normalize();
  constexpr double kStandOff = 24;  // pixels
  label_->GetPositionCoordinate()->SetValue(kStandOff * away.x(), kStandOff * away.y());
  vtkTextProperty* t = label_->GetTextProperty();
  if (away.x() < 0) t->SetJustificationToRight();
  else t->SetJustificationToLeft();
  if (away.y() < 0) t->SetVerticalJustificationToTop();
  else t->SetVerticalJustificationToBottom();
}

void CapsuleScene::set_visible(bool on) {
  visible_ = on;
  apply_visibility();
}

void CapsuleScene::apply_visibility() {
  for (std::size_t i = 0; i < links_.size(); ++i) links_[i].actor->SetVisibility(visible_ && int(i) < shown_);
  const bool pair = visible_ && gap_ != Gap::None;
  for (vtkProp* p : gap_props()) p->SetVisibility(pair);
}

vtkActor* CapsuleScene::link_actor(int link) const {
  if (link < 0 || link >= shown_) throw std::out_of_range("capsule scene: no link " + std::to_string(link));
  return links_[std::size_t(link)].actor;
}

std::array<vtkProp*, 4> CapsuleScene::gap_props() const { return {line_actor_, ends_[0], ends_[1], label_}; }

vtkActor2D* CapsuleScene::gap_line() const { return line_actor_; }

std::string CapsuleScene::label_text() const { return label_->GetInput() ? label_->GetInput() : ""; }

}  // namespace linkscape::render
