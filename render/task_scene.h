// A task volume (core/task.h) in the 3-D view: its surface as a translucent
// mesh, each vertex coloured by whether the task's criteria hold there or
// not in a pair told apart with any colour vision (Okabe-Ito blue and
// vermilion), the failing vertices again as dots drawn over the whole scene
// while they are few (at most kFewFailing of them: a speck on the far side
// is seen from any side, through the device and the surfaces), and the
// largest inscribed shape as a wireframe.
// Props are created once; new data swaps the meshes.
#pragma once

#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/task.h"

class vtkActor;
class vtkActor2D;
class vtkPolyData;
class vtkRenderer;

namespace linkscape::render {

// The surface of `task` at `centre` as triangles: a UV sphere of
// `resolution` latitude bands (2 x resolution longitudes), or a box whose
// faces are `resolution` x `resolution` grids. Throws std::invalid_argument
// for a resolution below 4.
vtkSmartPointer<vtkPolyData> task_surface(const task::TaskVolume& task, const Eigen::Vector3d& centre, int resolution);

// Okabe-Ito blue and vermilion.
inline constexpr unsigned char kMeetsColour[3] = {0, 114, 178};
inline constexpr unsigned char kFailsColour[3] = {213, 94, 0};
// The share of failing vertices up to which they are also drawn over the scene.
inline constexpr double kFewFailing = 0.1;

class TaskScene {
 public:
  TaskScene();
  ~TaskScene();
  TaskScene(const TaskScene&) = delete;
  TaskScene& operator=(const TaskScene&) = delete;

  // Adds the props to `renderer` once. Throws std::invalid_argument for null.
  void add_to(vtkRenderer* renderer);
  // Shows `surface` (from task_surface) with per-vertex colours: meets[i]
  // for point i (kMeetsColour where 1, kFailsColour where 0). Throws std::invalid_argument
  // when the sizes differ.
  void set_task(vtkPolyData* surface, const std::vector<std::uint8_t>& meets);
  // The largest inscribed shape as a wireframe (nullptr clears it).
  void set_inscribed(vtkPolyData* surface);
  void set_visible(bool visible);
  bool visible() const;
  // The task surface's actor (picking, tests).
  vtkActor* task_actor() const { return task_actor_; }
  // The failing vertices' dots, drawn over the scene (tests).
  vtkActor2D* failing_actor() const { return failing_actor_; }
  // Points of the shown task surface coloured as failing (tests).
  std::size_t failing_points() const { return failing_; }

 private:
  vtkNew<vtkActor> task_actor_, inscribed_actor_;
  vtkNew<vtkActor2D> failing_actor_;
  bool visible_ = false, has_task_ = false, has_inscribed_ = false;
  std::size_t failing_ = 0, points_ = 0;
  void update_visibility();
};

}  // namespace linkscape::render
