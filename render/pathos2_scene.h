// PATHOS-II as VTK props: two translucent base plates, six legs (links as
// cylinders R1 -> R2 -> R3 -> globular centre, revolute joints as short
// cylinders along their axes, globular joints as spheres), the two top plates
// (triangles at +-h0 through the globular centres), the platform frame E,
// the world axes and the leg numbers 1-6. A failing leg can be highlighted.
//
// Every link and revolute joint draws the same shared cylinder source and
// every globular joint the same sphere source; a pose change only updates
// actor matrices. Geometry is rebuilt only when the model changes (plate
// outlines). Units: cm.
#pragma once

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <array>

#include "core/pathos2.h"

class vtkActor;
class vtkAxesActor;
class vtkBillboardTextActor3D;
class vtkCylinderSource;
class vtkPolyData;
class vtkRenderer;
class vtkSphereSource;

namespace linkscape::render {

class Pathos2Scene {
 public:
  Pathos2Scene();
  ~Pathos2Scene();
  Pathos2Scene(const Pathos2Scene&) = delete;
  Pathos2Scene& operator=(const Pathos2Scene&) = delete;

  // Adds every prop to `renderer` (once). Throws std::invalid_argument for null.
  void add_to(vtkRenderer* renderer);

  // New design: rebuilds the plates and labels and moves to `pose`. Throws
  // std::invalid_argument (scene unchanged) for an invalid model or a pose
  // the new model cannot reach (the caller decides which pose to show).
  void set_model(const pathos2::Model& model, const pathos2::Pose& pose);
  // Moves the device: transforms only. Throws std::invalid_argument (scene
  // unchanged) if the pose IK is not Ok or OutOfLimits.
  void set_pose(const pathos2::Pose& pose);
  // Draws leg `leg` (0-based) in the highlight colour; -1 clears it.
  // Throws std::invalid_argument outside -1..5.
  void set_highlighted_leg(int leg);

  const pathos2::Model& model() const { return geometry_.model; }
  const pathos2::Pose& pose() const { return pose_; }
  const pathos2::Skeleton& skeleton() const { return skeleton_; }
  int highlighted_leg() const { return highlighted_; }
  // Camera from the front-left, slightly above, framing both base plates.
  void reset_camera(vtkRenderer* renderer) const;

 private:
  void apply_pose(const pathos2::Pose& pose, const pathos2::PoseIkResult& ik);
  void apply_colours();

  pathos2::Geometry geometry_;
  pathos2::Pose pose_;
  pathos2::Skeleton skeleton_;
  int highlighted_ = -1;

  vtkNew<vtkCylinderSource> cylinder_;  // unit height along y, radius 0.5
  vtkNew<vtkSphereSource> sphere_;      // radius 0.5
  vtkNew<vtkCylinderSource> disc_;      // base plates: finer cylinder, same convention
  static constexpr int kLinksPerLeg = 3, kRevolutePerLeg = 3;
  std::array<std::array<vtkSmartPointer<vtkActor>, kLinksPerLeg>, pathos2::kLegCount> links_;
  std::array<std::array<vtkSmartPointer<vtkActor>, kRevolutePerLeg>, pathos2::kLegCount> revolutes_;
  std::array<vtkSmartPointer<vtkActor>, pathos2::kLegCount> globulars_;
  std::array<vtkSmartPointer<vtkActor>, 2> base_plates_;
  std::array<vtkSmartPointer<vtkPolyData>, 2> top_plate_shapes_;  // triangles in the plate frame
  std::array<vtkSmartPointer<vtkActor>, 2> top_plates_;
  std::array<vtkSmartPointer<vtkBillboardTextActor3D>, pathos2::kLegCount> labels_;
  vtkNew<vtkAxesActor> world_axes_;
  vtkNew<vtkAxesActor> platform_axes_;
};

}  // namespace linkscape::render
