// A certified verdict (core/verify) in the 3-D view: the boxes proved to
// meet every criterion as a faint green wireframe, the boxes left undecided
// as translucent amber blocks, and the counterexample that disproves the
// task as a red ball. Colours: the Okabe-Ito palette's bluish green,
// orange and vermillion, told apart without red-green vision.
#pragma once

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <cstddef>
#include <vector>

#include "core/verify/verify.h"

class vtkActor;
class vtkPolyData;
class vtkRenderer;

namespace linkscape::render {

// The boxes as one mesh: six quadrilateral faces each, wound outwards (24
// points, so that faces keep flat normals).
vtkSmartPointer<vtkPolyData> boxes_mesh(const std::vector<verify::Box>& boxes);

class VerifyRegions {
 public:
  VerifyRegions();
  ~VerifyRegions();
  VerifyRegions(const VerifyRegions&) = delete;
  VerifyRegions& operator=(const VerifyRegions&) = delete;

  // Adds the props to `renderer` once. Throws std::invalid_argument for null.
  void add_to(vtkRenderer* renderer);
  // Shows the result's kept boxes (verify::Options::keep_boxes) and its
  // counterexample, a ball of `marker_radius` (length unit). Throws
  // std::invalid_argument for a radius that is not positive.
  void show(const verify::Result& result, double marker_radius);
  void clear();
  // What is shown (tests): boxes proved and undecided, and whether a counterexample is.
  std::size_t proved() const { return proved_; }
  std::size_t undecided() const { return undecided_; }
  bool counterexample() const { return counterexample_; }

 private:
  vtkNew<vtkActor> proved_actor_, undecided_actor_, counterexample_actor_;
  std::size_t proved_ = 0, undecided_ = 0;
  bool counterexample_ = false;
};

}  // namespace linkscape::render
