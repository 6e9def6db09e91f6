#include "render/mark_scene.h"

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCoordinate.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkTextActor.h>
#include <vtkLineSource.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRenderer.h>
#include <vtkSphereSource.h>
#include <vtkTextProperty.h>

#include <stdexcept>

namespace linkscape::render {

namespace {

void style_marker(vtkActor* actor, vtkSphereSource* source, const double rgb[3]) {
  source->SetThetaResolution(16);
  source->SetPhiResolution(12);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(source->GetOutputPort());
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  actor->GetProperty()->SetAmbient(0.4);
  actor->PickableOff();  // a pick lands on the scene, never on its own marks
  actor->VisibilityOff();
}

void style_segment(SegmentMark& m, const double rgb[3]) {
  vtkNew<vtkCoordinate> world;
  world->SetCoordinateSystemToWorld();
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputConnection(m.line->GetOutputPort());
  mapper->SetTransformCoordinate(world);
  m.line_actor->SetMapper(mapper);
  m.line_actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  m.line_actor->GetProperty()->SetLineWidth(3);
  m.line_actor->PickableOff();
  m.line_actor->VisibilityOff();
  for (int k = 0; k < 2; ++k) style_marker(m.ends[k], m.end_sources[k], rgb);
  // Text on an opaque plate, so it reads over the slice and the surfaces.
  vtkTextProperty* t = m.label->GetTextProperty();
  t->SetFontSize(16);
  t->BoldOn();
  t->SetColor(0.1, 0.1, 0.15);
  t->SetBackgroundColor(1, 1, 1);
  t->SetBackgroundOpacity(0.85);
  t->SetFrame(true);
  t->SetFrameColor(rgb[0], rgb[1], rgb[2]);
  t->SetJustificationToCentered();
  t->SetVerticalJustificationToBottom();
  m.label->GetPositionCoordinate()->SetCoordinateSystemToWorld();
  m.label->PickableOff();
  m.label->VisibilityOff();
}

}  // namespace

MarkScene::MarkScene() {
  const double pick_colour[3] = {0.95, 0.45, 0.0};   // orange
  const double ruler_colour[3] = {0.85, 0.1, 0.55};  // magenta
  const double probe_colour[3] = {0.1, 0.35, 0.85};  // blue
  style_marker(pick_actor_, pick_source_, pick_colour);
  style_segment(ruler_, ruler_colour);
  style_segment(probe_, probe_colour);
  // Below its line, the ruler's above its own: two segments across the same
  // place keep their lengths apart.
  probe_.label->GetTextProperty()->SetVerticalJustificationToTop();
  set_marker_size(radius_);
}

MarkScene::~MarkScene() = default;

void MarkScene::add_to(vtkRenderer* renderer) {
  if (!renderer) throw std::invalid_argument("mark scene: expected a renderer, got null");
  renderer->AddViewProp(pick_actor_);
  for (SegmentMark* m : {&ruler_, &probe_}) {
    renderer->AddViewProp(m->line_actor);
    for (auto& end : m->ends) renderer->AddViewProp(end);
    renderer->AddViewProp(m->label);
  }
}

void MarkScene::set_marker_size(double radius) {
  if (!(radius > 0)) throw std::invalid_argument("mark scene: expected a marker radius > 0, got " + std::to_string(radius));
  radius_ = radius;
  pick_source_->SetRadius(radius);
  for (SegmentMark* m : {&ruler_, &probe_})
    for (auto& s : m->end_sources) s->SetRadius(0.8 * radius);
}

void MarkScene::set_pick(const std::optional<Eigen::Vector3d>& point) {
  pick_actor_->SetVisibility(point.has_value());
  if (point) pick_source_->SetCenter(point->data());
}

void MarkScene::set_segment(SegmentMark& m, const std::optional<Eigen::Vector3d>& a,
                            const std::optional<Eigen::Vector3d>& b, const std::string& text) {
  const std::optional<Eigen::Vector3d> ends[2] = {a, b};
  for (int k = 0; k < 2; ++k) {
    m.ends[k]->SetVisibility(ends[k].has_value());
    if (ends[k]) m.end_sources[k]->SetCenter(ends[k]->data());
  }
  const bool both = a && b;
  m.line_actor->SetVisibility(both);
  m.label->SetVisibility(both && !text.empty());
  if (!both) return;
  m.line->SetPoint1(a->data());
  m.line->SetPoint2(b->data());
  Eigen::Vector3d middle = 0.5 * (*a + *b);
  m.label->GetPositionCoordinate()->SetValue(middle.data());
  m.label->SetInput(text.c_str());
}

void MarkScene::set_ruler(const std::optional<Eigen::Vector3d>& a, const std::optional<Eigen::Vector3d>& b,
                          const std::string& text) {
  set_segment(ruler_, a, b, text);
}

void MarkScene::set_probe(const std::optional<Eigen::Vector3d>& a, const std::optional<Eigen::Vector3d>& b,
                          const std::string& text) {
  set_segment(probe_, a, b, text);
}

bool MarkScene::pick_visible() const { return pick_actor_->GetVisibility(); }
bool MarkScene::ruler_visible() const { return ruler_.line_actor->GetVisibility(); }
std::string MarkScene::ruler_text() const { return ruler_.label->GetInput() ? ruler_.label->GetInput() : ""; }
vtkActor2D* MarkScene::ruler_line() const { return ruler_.line_actor; }

}  // namespace linkscape::render
