// Marks the window draws over its scene for measuring: the picked point, the
// ruler (two points, the segment between them, its length as a label) and
// the line probe's segment. Props are created once; new points only move them.
// Coordinates are in the device's length unit.
#pragma once

#include <vtkNew.h>

#include <Eigen/Core>
#include <optional>
#include <string>

class vtkActor;
class vtkActor2D;
class vtkTextActor;
class vtkLineSource;
class vtkRenderer;
class vtkSphereSource;

namespace linkscape::render {

// A segment between two points, marked at both ends, labelled at its middle.
// The line and the label are overlays placed at world points: drawn over
// the scene, so a slice or a surface in front never hides them.
struct SegmentMark {
  vtkNew<vtkLineSource> line;
  vtkNew<vtkActor2D> line_actor;
  vtkNew<vtkSphereSource> end_sources[2];
  vtkNew<vtkActor> ends[2];
  vtkNew<vtkTextActor> label;
};

class MarkScene {
 public:
  MarkScene();
  ~MarkScene();
  MarkScene(const MarkScene&) = delete;
  MarkScene& operator=(const MarkScene&) = delete;

  // Adds the props to `renderer` once. Throws std::invalid_argument for null.
  void add_to(vtkRenderer* renderer);
  // Marker radius in the length unit (about 1 % of the device's size).
  void set_marker_size(double radius);

  // The picked point (nothing: hidden).
  void set_pick(const std::optional<Eigen::Vector3d>& point);
  // The ruler from a to b (b absent: only a is marked), labelled `text`.
  void set_ruler(const std::optional<Eigen::Vector3d>& a, const std::optional<Eigen::Vector3d>& b,
                 const std::string& text);
  // The line probe's segment, likewise.
  void set_probe(const std::optional<Eigen::Vector3d>& a, const std::optional<Eigen::Vector3d>& b,
                 const std::string& text);

  // Introspection (tests).
  bool pick_visible() const;
  bool ruler_visible() const;  // the segment (both points) is drawn
  std::string ruler_text() const;
  vtkActor2D* ruler_line() const;

 private:
  void set_segment(SegmentMark& mark, const std::optional<Eigen::Vector3d>& a, const std::optional<Eigen::Vector3d>& b,
                   const std::string& text);
  double radius_ = 0.1;
  vtkNew<vtkSphereSource> pick_source_;
  vtkNew<vtkActor> pick_actor_;
  SegmentMark ruler_, probe_;
};

}  // namespace linkscape::render
