// The force ellipsoid (core/force_ellipsoid.h) at the driven point: a
// translucent ellipsoid (a planar device: an ellipse in its plane) drawn at
// a length per newton, its semi-axes as lines, and a label giving them, the
// device's force_iso and force_max and the scale. Where the pose has no
// bounded ellipsoid the shape is hidden and the label says why.
//
// Props are made once; a new pose sets the ellipsoid's matrix, the axes'
// points and the label. Lengths in the device's length unit.
#pragma once

#include <vtkNew.h>

#include <Eigen/Core>
#include <string>

#include "core/force_ellipsoid.h"

class vtkActor;
class vtkPolyData;
class vtkRegularPolygonSource;
class vtkRenderer;
class vtkSphereSource;
class vtkTextActor;

namespace linkscape::render {

// The scale to draw forces at: the length per newton from 1, 2, 5 x 10^k
// nearest to making `largest_N` newtons `target_length` long. Throws
// std::invalid_argument unless both are finite and > 0.
double length_per_newton(double largest_N, double target_length);

class ForceEllipsoidScene {
 public:
  ForceEllipsoidScene();
  ~ForceEllipsoidScene();
  ForceEllipsoidScene(const ForceEllipsoidScene&) = delete;
  ForceEllipsoidScene& operator=(const ForceEllipsoidScene&) = delete;

  // Adds the props to `renderer`. Throws std::invalid_argument for null.
  void add_to(vtkRenderer* renderer);

  struct Shown {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the driven point (base frame)
    haptics::ForceEllipsoid ellipsoid;                 // status Ok: every semi-axis finite
    double length_per_N = 1;                           // > 0
    double force_iso_N = 0, force_max_N = 0;           // for the label
    std::string length_unit, torque;                   // "mm"; "continuous"
  };
  // Throws std::invalid_argument (scene unchanged) for an ellipsoid that is
  // not Ok, of other than 2 or 3 axes, or a non-finite or non-positive value.
  void set_ellipsoid(const Shown& shown);
  // The shape hidden; `why` labelled at `centre`.
  void set_hidden(const Eigen::Vector3d& centre, const std::string& why);
  // Shows or hides everything.
  void set_visible(bool on);
  bool visible() const { return visible_; }

  // Introspection (tests): whether the shape is drawn, the drawn tip of
  // semi-axis k (base frame), the label.
  bool shape_shown() const { return shape_; }
  Eigen::Vector3d axis_tip(int k) const;
  vtkActor* shape_actor() const;
  std::string label_text() const;

 private:
  void apply_visibility();
  bool visible_ = true, shape_ = false;
  int axes_count_ = 0;
  vtkNew<vtkSphereSource> sphere_;           // unit sphere (spatial)
  vtkNew<vtkRegularPolygonSource> disk_;     // unit disk in z = 0 (planar)
  vtkNew<vtkActor> shape_actor_;
  vtkNew<vtkPolyData> axes_;                 // centre +- each semi-axis
  vtkNew<vtkActor> axes_actor_;
  vtkNew<vtkTextActor> label_;
};

}  // namespace linkscape::render
