// A described device drawn as the window draws any device (core/skeleton.h):
// the base ring, each leg's links between its joints, the platform bodies;
// built once from the description, posed from a solved assembly.
#pragma once

#include <string>
#include <vector>

#include "core/mechanism.h"
#include "core/mechanisms/described/kinematics.h"

namespace linkscape::described {

struct Skeleton {
  Skeleton() = default;
  explicit Skeleton(const Kinematics& kin);

  // The pose of every body: the links from the legs' solved states, the
  // platform bodies from `platform`; a leg named `failing_leg` marked failing.
  SkeletonPose pose(const Kinematics& kin, const PoseSolution& assembly, const PlatformPose& platform,
                    const std::string& failing_leg) const;

  SkeletonModel model;

 private:
  struct LinkBody {
    int leg, step, body;  // the body after a leg's step
  };
  std::vector<LinkBody> link_bodies_;
  int platform_body_ = 0;  // the first platform body
};

}  // namespace linkscape::described
