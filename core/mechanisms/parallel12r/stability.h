// Stability sweeps of the 12R hand controller (core/stability.h): approach
// each singular set along a path, eps = 1e-1 down to 1e-12, and record for
// every method the error against a long-double reference, the residual, the
// iterations and the status. The prediction each IK error is compared with is the first-order
// error of a backward-stable solver, u B(q) / sigma_min(J) with u = 2^-53 and
// B = methods::backward_error_scale (the rounding of target, angles and
// Eqs. 11-13 in double), about u c(J) for unit-scale lengths away from the
// actuator plane.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/mechanisms/parallel12r/parallel12r.h"
#include "core/stability.h"

namespace linkscape::stability {

inline constexpr SweepPath kParallel12rPaths[] = {SweepPath::CosAlpha, SweepPath::BetaGamma,   SweepPath::BetaGammaPi,
                                                  SweepPath::ZAxis,    SweepPath::OuterSphere, SweepPath::InnerSphere};

// Runs every path. Methods: ik paper, planar, newton, dls, fallback (default
// seeds) and newton-near (seeded 1e-3 rad from the reference: Newton's own
// accuracy, apart from its basin); jacobian analytic, central-difference,
// forward-difference, complex-step; conditioning closed-form,
// closed-form-fast, svd, normal-equations. Throws std::invalid_argument for
// bad options.
std::vector<SweepRow> run_stability_sweeps(const parallel12r::Model& model, const SweepOptions& options = {});

// The target, and the configuration on the path (joint paths) or nearest to
// it (Cartesian paths, from the planar closed form), of one sweep point.
struct SweepPoint {
  Eigen::Vector3d target;
  Eigen::Vector3d q_path;
  double distance = 0;
};
SweepPoint sweep_point(const parallel12r::Model& model, SweepPath path, double eps, int base_point, unsigned seed);

}  // namespace linkscape::stability
