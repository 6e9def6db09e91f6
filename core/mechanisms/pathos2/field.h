// PATHOS-II fields: the platform-centre position sampled on a grid at a fixed
// orientation and grip, with cond(Jp), cond(Jo), a signed reach margin and
// the IK status at every sample (paper Figs. 7-8; the reachable workspace at
// fixed orientation). Units: cm, rad.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "core/field.h"
#include "core/mechanisms/pathos2/pathos2.h"

namespace linkscape::pathos2 {

struct FieldRequest {
  Grid grid;                                        // positions of E in the world frame, cm
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();    // orientation (rx, ry, rz), R = Rz Ry Rx, rad
  double h0 = 7.0;                                  // grip, cm
  std::size_t memory_limit_bytes = kFieldMemoryLimitBytes;
  int threads = 0;                                  // 0 = all cores
  // Unset: the environment (field_kernel_from_environment). Scalar: every
  // sample through sample_position, the reference. The others: the pose's
  // rotation built once and the IK without the angles a sample does not use
  // (IkDetail::Field), bit for bit the same.
  std::optional<FieldKernel> kernel;
};

// Signed distance-like margin of a pose to the edge of the workspace, cm:
// > 0 inside, 0 on the boundary, < 0 outside, continuous across it. Per leg
// the smaller of the distances of its globular centre to the shell
// |a - l1 z| in [|l2 - l3|, l2 + l3] and to the cylinder where Eq. 14's c1x
// root vanishes, and of each finite joint limit's angle margin times its
// lever arm; the pose's margin is the smallest over the legs.
double reach_margin(const Geometry& geometry, const PoseIkResult& ik);

// The samples of compute_field below, for one position.
FieldSample sample_position(const Geometry& geometry, const Eigen::Vector3d& p_world_E, const FieldRequest& request);

// Field with cond = cond(Jp), cond_orientation = cond(Jo), reach_margin as
// above, residual = the largest leg-closure error of the solved angles (cm),
// status = the pose IK's status, or Singular where the pose is solved but the
// Jacobian is singular (pathos2::kMaxJacobianCondition), reachable = status Ok. Metadata: mechanism
// "pathos2", the model's parameters plus rx, ry, rz (deg), with h0 the grip sampled.
// Throws std::invalid_argument for a bad model, grid or pose, or a request
// over the memory limit; returns nullopt when cancelled.
std::optional<Field> compute_field(const Model& model, const FieldRequest& request,
                                   const FieldProgress& progress = {});

}  // namespace linkscape::pathos2
