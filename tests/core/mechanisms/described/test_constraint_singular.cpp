// A constraint singularity: the legs' constraint wrenches lose rank and the
// platform gains a freedom that they held, while the actuation Jacobian
// stays well conditioned. Tsai's 3-UPU, each leg's universal joints' axes
// parallel in pairs: its couple is square to both axes of a pair, and the
// three couples lie in one plane on the surface found here from the
// geometry alone (their determinant), not from the program's wrenches.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "core/mechanism.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/preset.h"
#include "tests/core/mechanisms/described/designs.h"

namespace linkscape::described {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

constexpr double kBase = 12, kPlatform = 5;  // radii of the universal joints' centres (cm)

Preset three_upu_preset() { return testing_support::tsai_three_upu(kBase, kPlatform); }

Kinematics three_upu() {
  const Preset p = three_upu_preset();
  return Kinematics(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
}

// The legs' couples from the geometry: leg i's first base axis is the
// tangent t of its circle, its second square to t and to the leg d; the
// couple is square to both.
double couples_determinant(const Vector3d& p) {
  Matrix3d n;
  for (int i = 0; i < 3; ++i) {
    const double a = i * 2 * M_PI / 3;
    const Vector3d radial(std::cos(a), std::sin(a), 0), t(-std::sin(a), std::cos(a), 0);
    const Vector3d d = (p + kPlatform * radial - kBase * radial).normalized();
    n.col(i) = t.cross(t.cross(d).normalized());
  }
  return n.determinant();
}

TEST(DescribedConstraintSingular, ThreeUpuIsSingularWhereItsLegsCouplesLieInOnePlane) {
  const Kinematics k = three_upu();
  for (const double z : {10.0, 16.0, 20.0}) {
    // The couples' determinant changes sign along x at y = 0: bisected to its root.
    double lo = 10, hi = 16;
    ASSERT_LT(couples_determinant({lo, 0, z}) * couples_determinant({hi, 0, z}), 0) << z;
    for (int i = 0; i < 80; ++i) {
      const double mid = 0.5 * (lo + hi);
      (couples_determinant({lo, 0, z}) * couples_determinant({mid, 0, z}) <= 0 ? hi : lo) = mid;
    }
    const Vector3d at(0.5 * (lo + hi), 0, z);
    const PoseSolution s = k.inverse(at, 0, 1e-10);
    ASSERT_EQ(s.status, Status::Ok) << "every leg closes at x = " << at.x();
    const JacobianParts parts = k.jacobian(at, s);
    EXPECT_EQ(parts.status, Status::Singular) << "x = " << at.x() << ", z = " << z;
    EXPECT_TRUE(parts.constraint_singular);
    EXPECT_EQ(parts.constraint_rank, 2);
    EXPECT_LT(parts.jx_condition, 100) << "the actuators alone hold the translations there";
    // The device's own read-outs: IK and FK singular there, with no finite c(J).
    const std::shared_ptr<const Mechanism> device = described::make_mechanism(three_upu_preset());
    const IkResult ik = device->inverse(at);
    EXPECT_EQ(ik.status, Status::Singular);
    EXPECT_FALSE(std::isfinite(device->measures(ik.solutions.front().q, at).values.front()));
    // A tenth of a millimetre either side it holds again.
    for (const double dx : {-0.01, 0.01}) {
      const Vector3d near = at + Vector3d(dx, 0, 0);
      const JacobianParts p = k.jacobian(near, k.inverse(near, 0, 1e-10));
      EXPECT_EQ(p.status, Status::Ok) << "x = " << near.x();
      EXPECT_EQ(p.constraint_rank, 3);
    }
  }
}

// A device whose legs transmit only their actuation wrench (the described
// Delta's balls: the description holds the orientation) has no constraint
// wrenches to lose.
TEST(DescribedConstraintSingular, LegsWithoutConstraintWrenchesHaveNone) {
  const Kinematics upu = three_upu();
  const PoseSolution s = upu.inverse(Vector3d(0, 0, 16), 0, 1e-10);
  EXPECT_EQ(upu.jacobian(Vector3d(0, 0, 16), s).constraint_rank, 3);
  const Preset p = load_preset("delta-described");
  const Kinematics delta(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
  const PoseSolution home = delta.inverse(delta.model().home, 0, 1e-10);
  const JacobianParts parts = delta.jacobian(delta.model().home, home);
  EXPECT_EQ(parts.constraint_rank, 0);
  EXPECT_FALSE(parts.constraint_singular);
}

// An extensible leg's slide always pushes along its rod: no serial set, so
// the window's "nearest singular" never names one (it had said "leg 1
// (type I), 17 cm" on the 3-UPU, and likewise on the Stewart platform).
TEST(DescribedConstraintSingular, ExtensibleLegsHaveNoSerialSet) {
  for (const Preset& p : {three_upu_preset(), load_preset("stewart")}) {
    const std::shared_ptr<const Mechanism> device = described::make_mechanism(p);
    const VectorXd x = device->home_task();
    const SingularityReport r = device->nearest_singularity(device->home_actuators(), x);
    const std::size_t legs = r.distances.size() - 1;
    for (std::size_t l = 0; l < legs; ++l) EXPECT_TRUE(std::isinf(r.distances[l])) << p.title << " leg " << l;
    EXPECT_EQ(device->info().singular_sets[std::size_t(r.nearest)].name, "parallel") << p.title;
    EXPECT_TRUE(std::isfinite(r.distance)) << p.title;
  }
}

}  // namespace
}  // namespace linkscape::described
