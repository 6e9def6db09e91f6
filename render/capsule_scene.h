// A device's links as capsules (Mechanism::link_capsules) over its
// skeleton: each link a translucent capsule, the pair that sets the
// clearance highlighted in a colour-blind-safe orange (Okabe-Ito), a line
// across the gap between their surfaces and the clearance as a label beside
// its middle (on the side away from the links, so it stays off the joints'
// labels). Where the pair is closer than the thinner link's radius the pair
// turns vermillion and nearly opaque and the label says so ("close";
// "overlap" where they interfere), so a contact reads without the colour.
//
// Props are reused: a new pose sets each capsule's matrix and, where a
// link's length or radius changed, its source; actors are made only when
// the number of links grows. Lengths in the device's length unit.
#pragma once

#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkWeakPointer.h>

#include <array>
#include <string>
#include <vector>

#include "core/interference.h"

class vtkActor;
class vtkActor2D;
class vtkCapsuleSource;
class vtkCoordinate;
class vtkLineSource;
class vtkProp;
class vtkRenderer;
class vtkSphereSource;
class vtkTextActor;

namespace linkscape::render {

class CapsuleScene {
 public:
  // How the closest pair stands: apart; closer than the thinner link's radius; overlapping.
  enum class Gap { None, Apart, Close, Overlap };

  CapsuleScene();
  ~CapsuleScene();
  CapsuleScene(const CapsuleScene&) = delete;
  CapsuleScene& operator=(const CapsuleScene&) = delete;

  // Adds the props to `renderer` (links added later join it). Throws
  // std::invalid_argument for null.
  void add_to(vtkRenderer* renderer);
  // The links at a pose; the label gives the clearance in `length_unit`.
  // Throws std::invalid_argument for a non-finite point or a radius < 0.
  void set_links(const interference::LinkCapsules& links, const std::string& length_unit);
  // Shows or hides everything (a hidden scene keeps its links).
  void set_visible(bool on);
  bool visible() const { return visible_; }

  // Introspection (tests).
  int link_count() const { return shown_; }
  vtkActor* link_actor(int link) const;  // std::out_of_range outside link_count()
  vtkActor2D* gap_line() const;  // drawn over the scene
  Gap gap() const { return gap_; }
  std::string label_text() const;
  vtkTextActor* label() const { return label_; }

 private:
  struct LinkProps {
    vtkSmartPointer<vtkCapsuleSource> source;
    vtkSmartPointer<vtkActor> actor;
  };
  void apply_visibility();
  void place_label();
  std::array<vtkProp*, 4> gap_props() const;  // the gap's line, its ends and the label

  std::vector<LinkProps> links_;
  int shown_ = 0;
  bool visible_ = true;
  Gap gap_ = Gap::None;
  std::vector<vtkWeakPointer<vtkRenderer>> renderers_;
  std::vector<unsigned long> frame_observers_;  // per renderer: the label placed before each frame
  Eigen::Vector3d links_centre_ = Eigen::Vector3d::Zero();  // the label stands away from it
  vtkNew<vtkLineSource> line_;
  vtkNew<vtkActor2D> line_actor_;
  vtkNew<vtkSphereSource> end_sources_[2];
  vtkNew<vtkActor> ends_[2];
  vtkNew<vtkTextActor> label_;
  vtkNew<vtkCoordinate> label_anchor_;  // the gap's middle; the label stands off it in pixels
};

}  // namespace linkscape::render
