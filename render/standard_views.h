// The view directions of the window's View menu: front, top, side and an
// isometric view, in the device's base frame (z up).
#pragma once

#include <Eigen/Core>

namespace linkscape::render {

enum class StandardView { Front, Top, Side, Iso };

struct ViewDirection {
  Eigen::Vector3d back;  // focal point -> camera, unit
  Eigen::Vector3d up;    // the screen's up, unit, normal to back
};

// Front: looking along +y; top: looking down -z with +y up; side: looking
// along -x (from the right); iso: from (-1, -1, 1), front-left above.
inline ViewDirection view_direction(StandardView view) {
  switch (view) {
    case StandardView::Front: return {-Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
    case StandardView::Top: return {Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY()};
    case StandardView::Side: return {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ()};
    case StandardView::Iso: break;
  }
  const Eigen::Vector3d back = Eigen::Vector3d(-1, -1, 1).normalized();
  return {back, (Eigen::Vector3d::UnitZ() - back.z() * back).normalized()};
}

}  // namespace linkscape::render
