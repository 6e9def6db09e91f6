// The 12R linkage as VTK props: one tube actor per link, one cylinder per
// joint (all sharing one source), the endpoint, base axes, actuator labels
// and a faint reach sphere.
//
// Geometry is built per link in the link's own frame and only rebuilt when
// the model changes; a pose change only updates each actor's matrix.
#pragma once

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/parallel12r.h"

class vtkActor;
class vtkAxesActor;
class vtkBillboardTextActor3D;
class vtkCylinderSource;
class vtkPolyData;
class vtkProp;
class vtkRenderer;
class vtkSphereSource;

namespace linkscape::render {

class LinkageScene {
 public:
  LinkageScene();
  ~LinkageScene();
  LinkageScene(const LinkageScene&) = delete;
  LinkageScene& operator=(const LinkageScene&) = delete;

  // Adds every prop of the scene to `renderer` (once).
  void add_to(vtkRenderer* renderer);
  // Rebuilds link geometry for new lengths; keeps the current pose.
  void set_model(const parallel12r::Model& model);
  // Moves the linkage: updates transforms only.
  void set_pose(const Eigen::Vector3d& q_actuated);

  const parallel12r::Model& model() const { return model_; }
  const Eigen::Vector3d& pose() const { return q_; }
  // Camera placement that frames the whole reach sphere obliquely.
  void reset_camera(vtkRenderer* renderer) const;

 private:
  void rebuild_geometry();

  parallel12r::Model model_;
  Eigen::Vector3d q_ = parallel12r::home_pose(0);
  std::array<vtkSmartPointer<vtkPolyData>, parallel12r::kLinkCount> link_lines_;
  std::array<vtkSmartPointer<vtkActor>, parallel12r::kLinkCount> link_actors_;
  std::array<vtkSmartPointer<vtkActor>, parallel12r::kJointCount> joint_actors_;
  std::array<vtkSmartPointer<vtkBillboardTextActor3D>, 4> labels_;  // A, B, C, D
  vtkNew<vtkCylinderSource> joint_source_;
  vtkNew<vtkSphereSource> endpoint_source_;
  vtkNew<vtkSphereSource> reach_source_;
  vtkNew<vtkActor> endpoint_actor_;
  vtkNew<vtkActor> reach_actor_;
  vtkNew<vtkAxesActor> axes_;
};

}  // namespace linkscape::render
