// Stability sweeps of PATHOS-II (core/stability.h): each leg towards its
// stretched, folded and elbow sets, and poses towards the reach boundary and
// the actuated singular set, with long-double references
// (core/mechanisms/pathos2/methods.h). Units: cm, rad.
#pragma once

#include <vector>

#include "core/mechanisms/pathos2/pathos2.h"
#include "core/stability.h"

namespace linkscape::stability {

inline constexpr SweepPath kPathos2Paths[] = {SweepPath::LegStretched, SweepPath::LegFolded, SweepPath::LegElbow,
                                              SweepPath::Reach, SweepPath::ActuatedSingular};

// PATHOS-II paths (kPathos2Paths). Leg paths: family "ik", methods
// closed-form (pathos2::leg_inverse), newton (home-pose seed), newton-near
// (seeded 1e-3 rad from the reference); cond and sigma_min of the 3x3 leg
// Jacobian; predicted u (l1 + l2 + l3 + pi |J|_F) / sigma_min. Pose paths:
// family "fk" nine-sensor, numeric (home seed), numeric-near (seed 1e-3 cm,
// rad off), error the pose error of pathos2_methods::pose_error against the
// nearest exact solution; cond = cond(J_twist_from_qdot), sigma_min =
// 1 / |S J|_2 with S = diag(1 / (l2 + l3) I, I), predicted
// u sqrt(6) (pi + (l0 + l2 + l3) |M|_F) |S J|_2 (the rounding of the six
// angles and of their evaluation mapped through J); jacobian analytic,
// central-difference, forward-difference (predicted u cond(J)); conditioning
// closed-form, svd (predicted u max(cond Jp, cond Jo)). Throws
// std::invalid_argument for bad options.
std::vector<SweepRow> run_pathos2_sweeps(const pathos2::Model& model, const SweepOptions& options = {});

}  // namespace linkscape::stability
