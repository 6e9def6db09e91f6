// The Delta's field kernel: c(J), the reach margin and the IK diagnostics at
// every sample of a grid (core/field.h), through the shared parallel loop
// (core/field_sampling.h).
//
// The reference sample (FieldKernel::Scalar, and the Newton IK) calls
// inverse, reach_margin and jacobian per point. The fast kernel
// (FieldKernel::Vector and VectorMirrored, the default; the closed IK only)
// takes rows of samples in SIMD vectors with run-time dispatch
// (field_simd.cpp); it agrees with the reference as
// tests/core/mechanisms/delta/test_field.cpp states.
//
// VectorMirrored also uses the Delta's mirror symmetry: reflecting y maps leg
// 0 onto itself and leg 1 onto leg 2, with the same actuator angles, so where
// legs 1 and 2 have the same range and elbow, the sample at (x, -y, z) is the
// one at (x, y, z) with two legs swapped, and c(J), the reach margin, the
// residual and the status are unchanged. In double it holds to rounding
// (cos and sin of 120 and 240 degrees are not exact mirrors), which is the
// kernel's own agreement with the reference; the samples whose status could
// hang on it are the ones the kernel hands to the reference anyway, and
// there the reference is called at each mirrored point itself. So the rows
// of the grid's upper half in y are the lower half's, computed once.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "core/field.h"
#include "core/field_sampling.h"
#include "core/mechanisms/delta/delta.h"

namespace linkscape::delta {

struct FieldRequest {
  Grid grid;
  IkMethod method = IkMethod::Closed;
  IkOptions ik;  // ik.branch: the elbow choice evaluated
  std::size_t memory_limit_bytes = kFieldMemoryLimitBytes;
  int threads = 0;  // 0 = all cores
  // Unset: the environment (field_kernel_from_environment). Scalar is the
  // reference; the Newton method always uses it.
  std::optional<FieldKernel> kernel;
};

// Field with cond = c(J) of the requested branch's configuration where its
// IK is Ok (+inf elsewhere and where J is singular), reach_margin =
// reach_margin(...).value, the IK status, residual (+inf where unreachable),
// iterations, method_used (0 closed, 1 newton). Metadata: mechanism "delta",
// the model's parameters. Throws std::invalid_argument for a bad model,
// branch, grid or LINKSCAPE_FIELD_KERNEL, or a request over the memory
// limit; returns nullopt when cancelled.
std::optional<Field> compute_field(const Model& model, const FieldRequest& request,
                                   const FieldProgress& progress = {});

// The reference: one sample through inverse, reach_margin and jacobian.
FieldSample sample_point(const Model& model, const Eigen::Vector3d& p_base_platform, const FieldRequest& request);

// The reference's cones (stops.h) on a sample of it: returns the joint margin
// in degrees where every leg closes on the request's branch (NaN elsewhere);
// an Ok sample beyond a cone becomes out-of-limits (not reachable, c(J)
// +inf), and the reach margin is at most the size times the margin in rad.
float cones_of_sample(const Model& model, const Eigen::Vector3d& p_base_platform, const FieldRequest& request,
                      FieldSample& sample);

// ---- The fast kernel ----------------------------------------------------------

// The legs' constant geometry: cos and sin of phi_i, as leg_radial computes
// them (e_i = (cos phi_i, sin phi_i, 0), A_i = R e_i), and of the centre and
// the half width of each actuator range. Validates the model.
struct FieldLegs {
  std::array<double, kLegCount> cos_phi{}, sin_phi{};
  std::array<double, kLegCount> cos_centre{}, sin_centre{}, cos_half_width{}, sin_half_width{};
};
FieldLegs field_legs(const Model& model);

// Whether the mirror in y holds for this request (see above): legs 1 and 2
// with the same range and elbow, rows along x, and grid y coordinates that
// are exact negatives of each other.
bool mirror_holds(const Model& model, const FieldRequest& request);

// The row y -> -y of a grid row: where the same samples go. The row is
// referred to, not copied: the copy, a load wider than the stores that had
// just written the row, waited for every earlier store (the last row's
// streaming stores) to drain (docs/performance.md).
struct RowMirror {
  const detail::GridRow& row;
  detail::FieldRowOut out;
};

// The closed-IK samples of a grid row in SIMD vectors (field_simd.cpp) with
// the best instruction set of the CPU (core/simd.h): sample_point's, but for
// the last bits of c(J), the reach margin and the residual; the statuses are
// its exactly. With `mirror`, also the mirror row's (mirror_holds). Where
// the model states cones, `joint_margin` (the grid's array) gets the row's
// joint margins and the samples cones_of_sample's changes.
void sample_row_vector(const Model& model, const FieldLegs& legs, const FieldRequest& request, const Grid& grid,
                       const detail::GridRow& row, const detail::FieldRowOut& out, const RowMirror* mirror = nullptr,
                       float* joint_margin = nullptr);

}  // namespace linkscape::delta
