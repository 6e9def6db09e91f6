// Any device as VTK props, drawn from its SkeletonModel (core/mechanism.h):
// per body one tube actor (its polylines) and one translucent plate actor (its
// faces), per joint one knuckle (revolute and prismatic joints as short
// cylinders along their axis, spherical and universal joints as spheres,
// actuated joints darker and larger), joint labels as billboard text, the
// endpoint marker and the base axes.
//
// Geometry is built once per model, in each body's own frame; set_pose only
// sets actor matrices (body frames), colours (a failing body turns red) and
// label positions. Every knuckle draws one shared cylinder or sphere source.
// Sizes scale with SkeletonModel::scale.
#pragma once

#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkWeakPointer.h>

#include <Eigen/Geometry>
#include <vector>

#include "core/mechanism.h"

class vtkActor;
class vtkAxesActor;
class vtkBillboardTextActor3D;
class vtkCylinderSource;
class vtkPolyData;
class vtkProp;
class vtkPolyDataMapper;
class vtkRenderer;
class vtkSphereSource;
class vtkTextActor;

namespace linkscape::render {

class SkeletonScene {
 public:
  SkeletonScene();
  ~SkeletonScene();
  SkeletonScene(const SkeletonScene&) = delete;
  SkeletonScene& operator=(const SkeletonScene&) = delete;

  // Adds every prop to `renderer`; a later set_model keeps that renderer's
  // props current. Adding the same renderer again does nothing. Throws
  // std::invalid_argument for null.
  void add_to(vtkRenderer* renderer);

  // Rebuilds every body's geometry and the joint knuckles. Keeps the current
  // pose where it fits the new model's body count, else puts every body at the
  // base frame. Throws std::invalid_argument (scene unchanged) for a joint on
  // a body that does not exist, a zero joint axis, a polyline of fewer than 2
  // or a face of fewer than 3 points, a non-finite value or a scale <= 0.
  void set_model(const SkeletonModel& model);
  // Moves the device: actor matrices, colours and label positions only.
  // Throws std::invalid_argument (scene unchanged) where the pose has not one
  // frame and one state per body, or a non-finite value.
  void set_pose(const SkeletonPose& pose);

  const SkeletonModel& model() const { return model_; }
  const SkeletonPose& pose() const { return pose_; }

  // Camera from the front-left, above (higher for a flat workspace, a planar
  // device's), framing `workspace_box` (base frame) with the device's base.
  void reset_camera(vtkRenderer* renderer, const Eigen::AlignedBox3d& workspace_box) const;
  // The camera looking along -`back` (focal point -> camera is `back`) with
  // `up` up, framing `box` with the device's base. Throws
  // std::invalid_argument for a null renderer, an empty or non-finite box, or
  // `up` parallel to `back`.
  void frame(vtkRenderer* renderer, const Eigen::AlignedBox3d& box, const Eigen::Vector3d& back,
             const Eigen::Vector3d& up) const;
  // The device's own extent in its current pose: every body's polylines and
  // faces (empty for a model without geometry).
  Eigen::AlignedBox3d device_box() const;
  // The same at `pose` (e.g. the device at home).
  Eigen::AlignedBox3d device_box(const SkeletonPose& pose) const;
  // Joint labels drawn over the scene (on a light plate) instead of in it,
  // so a slice, a surface or the base in front never hides them. Default off.
  void set_labels_in_front(bool on);
  bool labels_in_front() const { return labels_in_front_; }
  // A joint's label drawn over the scene (null where the label is empty).
  vtkTextActor* joint_front_label(int joint) const;
  // The actors a pick can land on, each with what it shows: tubes and
  // plates ("link NAME"), knuckles ("joint NAME"), the endpoint.
  struct Part {
    vtkActor* actor;
    std::string what;
  };
  std::vector<Part> pickable_parts() const;

  // The props, for tests and picking: per body its tube and plate actors
  // (null where the body has no polylines or no faces), per joint its knuckle
  // and label (null where the label is empty).
  // Throw std::out_of_range for an index outside the model.
  vtkActor* body_tube_actor(int body) const;
  vtkActor* body_face_actor(int body) const;
  vtkActor* joint_actor(int joint) const;
  vtkBillboardTextActor3D* joint_label(int joint) const;
  vtkActor* endpoint_actor() const;

 private:
  struct BodyProps {
    vtkSmartPointer<vtkPolyData> lines;  // polylines, body frame
    vtkSmartPointer<vtkPolyData> faces;  // polygons, body frame
    vtkSmartPointer<vtkActor> tube;
    vtkSmartPointer<vtkActor> plate;
  };
  struct JointProps {
    Eigen::Matrix4d knuckle_in_body;  // scaled unit source -> body frame
    vtkSmartPointer<vtkActor> knuckle;
    vtkSmartPointer<vtkBillboardTextActor3D> label;
    vtkSmartPointer<vtkTextActor> front_label;  // the same, drawn over the scene
  };

  std::vector<vtkProp*> props() const;
  void apply_pose();

  SkeletonModel model_;
  SkeletonPose pose_;
  std::vector<BodyProps> bodies_;
  std::vector<JointProps> joints_;
  std::vector<vtkWeakPointer<vtkRenderer>> renderers_;
  bool labels_in_front_ = false;

  vtkNew<vtkCylinderSource> cylinder_;  // unit height along y, radius 0.5
  vtkNew<vtkSphereSource> sphere_;      // radius 0.5
  vtkNew<vtkPolyDataMapper> cylinder_mapper_;
  vtkNew<vtkPolyDataMapper> sphere_mapper_;
  vtkNew<vtkSphereSource> endpoint_source_;
  vtkNew<vtkActor> endpoint_actor_;
  vtkNew<vtkAxesActor> axes_;
};

// How far a skeleton of `scale` reaches from a joint along the joint's
// axis: half its largest knuckle (an actuated revolute's). A planar
// device's slice lies this far (and a little more) below its plane.
double knuckle_reach(double scale);

}  // namespace linkscape::render
