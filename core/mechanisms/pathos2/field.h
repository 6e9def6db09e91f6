// PATHOS-II fields: the platform-centre position sampled on a grid at a fixed
// orientation and grip, with cond(Jp), cond(Jo), a signed reach margin and
// the IK status at every sample (paper Figs. 7-8; the reachable workspace at
// fixed orientation). Units: cm, rad.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "core/field.h"
#include "core/field_sampling.h"
#include "core/mechanisms/pathos2/pathos2.h"

namespace linkscape::pathos2 {

struct FieldRequest {
  Grid grid;                                        // positions of E in the world frame, cm
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();    // orientation (rx, ry, rz), R = Rz Ry Rx, rad
  double h0 = 7.0;                                  // grip, cm
  std::size_t memory_limit_bytes = kFieldMemoryLimitBytes;
  int threads = 0;                                  // 0 = all cores
  // Unset: the environment (field_kernel_from_environment). Scalar: every
  // sample through sample_position, the reference. Vector and
  // VectorMirrored (the same: the field has no exact mirror): rows of
  // samples in SIMD vectors (sample_row_vector below), the statuses exactly
  // the reference's.
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

// ---- The fast kernel ----------------------------------------------------------

// The per-point fast path: the pose's orientation and grip built once
// (`oriented`, whose globular offsets are `offsets`), the IK without the
// angles a sample does not use (IkDetail::Field). Bit for bit
// sample_position but for the reach margin and the residual (within
// rounding: sqrt for hypot, the closure from the legs' cosines).
FieldSample sample_oriented(const Geometry& geometry, const Pose& oriented, const GlobularOffsets& offsets,
                            const Eigen::Vector3d& p_world_E);

// What the vectorised kernel needs of a field, computed once with the
// reference's own expressions (so that the IK's statuses come out with its
// bits): per leg R_world_B (row by row), p_world_B, the globular offset,
// the world z axis of the attachment frame A_i (R_world_E R_E_A col 2, as
// inverse_with forms it) and the same in the leg frame, and the branch sign.
struct FieldSetup {
  struct Leg {
    std::array<double, 9> R{};  // R_world_B, R[3 r + c] = R(r, c)
    std::array<double, 3> p_B{}, offset{}, z_A{}, z_A_in_B{};
    double branch_sign = 1.0;
  };
  std::array<Leg, kLegCount> legs;
  double cos_cone = -1.0, cos_t2 = -1.0, cos_t3 = -1.0;  // std::cos of the limits
  bool check_cone = false, check_t2 = false, check_t3 = false;  // limit < pi
  double length_scale = 1.0;  // the power of two near l2 + l3 that makes M dimensionless
};
FieldSetup field_setup(const Geometry& geometry, const Pose& oriented, const GlobularOffsets& offsets);

// The samples of a grid row in SIMD vectors (field_simd.cpp) with the best
// instruction set of the CPU (core/simd.h): sample_position's statuses,
// reachable flags, methods and infinities exactly, its finite floats within
// the tolerance field_simd.cpp states. Lanes it cannot decide with
// certainty go to sample_oriented.
void sample_row_vector(const Geometry& geometry, const FieldSetup& setup, const Pose& oriented,
                       const GlobularOffsets& offsets, const Grid& grid, const detail::GridRow& row,
                       const detail::FieldRowOut& out);

}  // namespace linkscape::pathos2
