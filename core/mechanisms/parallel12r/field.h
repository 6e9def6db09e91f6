// The 12R hand controller's field kernel: c(J), the reach margin and the
// solver's diagnostics at every sample of a grid (core/field.h), through the
// shared parallel loop (core/field_sampling.h). The planar method runs a
// closed form without trigonometry on rows of samples in SIMD vectors
// (field_simd.cpp); the other methods call parallel12r::inverse per sample.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>

#include "core/field.h"
#include "core/mechanisms/parallel12r/parallel12r.h"

namespace linkscape {

// How the planar method's samples are computed (core/field.h): Scalar, one
// sample at a time, the reference; Vector, rows of samples in SIMD vectors;
// VectorMirrored, the same, computing half of each x row and mirroring it
// where that is exact (alpha range symmetric, grid x coordinates mirrored).
// The vectorised kernels use the best SIMD instruction set of the CPU
// (core/simd.h) and agree with the scalar reference as
// tests/core/mechanisms/parallel12r/test_field_simd.cpp states.
using PlanarKernel = FieldKernel;

struct FieldRequest {
  Grid grid;
  parallel12r::IkMethod method = parallel12r::IkMethod::Planar;
  int branch = 0;  // assembly branch whose configuration is evaluated (0 or 1)
  parallel12r::IkOptions ik;
  // Requests needing more memory than this are refused before any work.
  std::size_t memory_limit_bytes = kFieldMemoryLimitBytes;
  // Threads for the parallel loop; 0 = all cores (OpenMP default).
  int threads = 0;
  // Unset: the environment variable LINKSCAPE_FIELD_KERNEL (scalar, vector or
  // vector-mirrored), else VectorMirrored. Other methods ignore it.
  std::optional<PlanarKernel> kernel;
};

// Samples the 12R mechanism on request.grid. Throws std::invalid_argument for
// a bad request or one over the memory limit (the message gives both sizes),
// or a bad LINKSCAPE_FIELD_KERNEL or LINKSCAPE_SIMD_TARGET.
std::optional<Field> compute_field(const parallel12r::Model& model, const FieldRequest& request,
                                   const FieldProgress& progress = {});

// The same per-sample evaluation compute_field uses, for a single point.
// method_used is std::uint8_t(parallel12r::IkMethod) of the solution: the
// requested method, or under IkMethod::Fallback Planar or Newton.
FieldSample sample_point(const parallel12r::Model& model, const Eigen::Vector3d& p, const FieldRequest& request);

}  // namespace linkscape
