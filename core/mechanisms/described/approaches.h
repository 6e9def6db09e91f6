// Where a described device's stability sweeps approach its singular sets
// (Mechanism::singular_approaches): points on each set, found along rays
// from home, in the model's task coordinates. A sweep's target at eps is
// home + (1 - eps) (end - home).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/mechanisms/described/kinematics.h"

namespace linkscape::described {

struct ApproachEnds {
  int set = 0;  // index into the device's singular sets: the legs' serial sets, then the parallel set
  std::vector<Eigen::VectorXd> ends;
};

// Each leg's serial set: rays along the base axes to the last pose that
// assembles (bisected), each end given to the leg with the smallest serial
// margin there. The parallel (type II) set: rays along each platform
// coordinate of the task (a length, or an angle up to a half turn) to the
// first sign change of det Jx on branch 0 with every leg closed (bisected).
// Sets no ray reaches are left out.
std::vector<ApproachEnds> singular_approach_ends(const Kinematics& kin);

}  // namespace linkscape::described
