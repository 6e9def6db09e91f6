// The scalar closed path's shortcuts give what the plain path gives, on every
// shipped description: a field's sample (inverse_into leaving last joints
// open where the pose does not assemble) against inverse(); candidates left
// open and closed later against candidates closed at once; a three-revolute
// leg's candidates made for a branch against all of them sifted by its angle
// rules; a chain walked part way against the whole walk; an angle rule's
// sign against the sine's; a locked universal joint singular on both
// paths to a leg's Jacobian row.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/preset.h"

namespace linkscape::described {
namespace {

using Eigen::Isometry3d;
using Eigen::VectorXd;

// Task vectors around home: positions within the device's size (the
// orientation and extras as at home, then turned a little).
std::vector<VectorXd> poses_around_home(const Model& m, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<VectorXd> out;
  for (int i = 0; i < count; ++i) {
    VectorXd x = m.home;
    for (int c = 0; c < (m.planar ? 2 : 3); ++c) x(c) += 0.8 * m.size * unit(rng);
    for (std::size_t t = 0; t < m.task.size(); ++t)
      if (m.task[t].platform_coordinate >= 3) x(Eigen::Index(t)) += 0.1 * unit(rng);
    out.push_back(x);
  }
  return out;
}

// The device as a field samples it (its stops as the preset switches them).
Kinematics load(const std::string& name) {
  const Preset p = load_preset(name);
  Model m = build_model(p.description, p.parameters, p.limits_deg, p.length_unit);
  switch_off_stops(m, p.checks);
  return Kinematics(std::move(m));
}

bool same_state(const LegState& a, const LegState& b) {
  if (a.values != b.values || a.spheres.size() != b.spheres.size()) return false;
  for (std::size_t i = 0; i < a.spheres.size(); ++i)
    if (a.spheres[i] != b.spheres[i]) return false;
  return true;
}

TEST(DescribedScalarPath, SampleGivesWhatInverseGives) {
  int open_legs = 0;
  for (const std::string& name : described_presets()) {
    SCOPED_TRACE(name);
    const Kinematics k = load(name);
    const Model& m = k.model();
    int assembled_poses = 0;
    PoseSolution lazy;  // reused, as a field's thread reuses it
    for (int branch = 0; branch < std::min(k.branches(), 4); ++branch)
      for (const VectorXd& x : poses_around_home(m, 300, 5 + unsigned(branch))) {
        const PoseSolution plain = k.inverse(x, branch, 1e-10);
        k.inverse_into(k.pose(x), branch, 1e-10, LegSolver::Fastest, lazy, false);
        ASSERT_EQ(int(lazy.status), int(plain.status));
        ASSERT_EQ(lazy.failing_leg, plain.failing_leg);
        ASSERT_EQ(lazy.q, plain.q);
        ASSERT_EQ(lazy.residual, plain.residual);
        ASSERT_EQ(lazy.stops.joint_margin_deg, plain.stops.joint_margin_deg);
        ASSERT_EQ(lazy.stops.clearance, plain.stops.clearance);
        ASSERT_EQ(lazy.legs.size(), plain.legs.size());
        const bool whole = assembled(plain);
        assembled_poses += whole;
        for (std::size_t l = 0; l < plain.legs.size(); ++l) {
          ASSERT_EQ(int(lazy.legs[l].status), int(plain.legs[l].status));
          ASSERT_EQ(lazy.legs[l].residual, plain.legs[l].residual);
          if (whole) {
            EXPECT_FALSE(lazy.legs[l].open_end) << "leg " << l;
            EXPECT_TRUE(same_state(lazy.legs[l].state, plain.legs[l].state)) << "leg " << l;
          }
          open_legs += lazy.legs[l].open_end;
        }
        if (whole) {
          const JacobianParts a = k.jacobian(x, plain);
          JacobianParts b;
          k.jacobian_into(k.pose(x), lazy, LegSolver::Fastest, b);
          ASSERT_EQ(int(a.status), int(b.status));
          EXPECT_EQ(a.J, b.J);
          EXPECT_EQ(a.jx_condition, b.jx_condition);
        }
      }
    EXPECT_GT(assembled_poses, 0);
  }
  EXPECT_GT(open_legs, 0);  // the shortcut was taken
}

// Each closed-form leg at anchors around home.
template <class Check>
void for_closed_legs(const Kinematics& k, unsigned seed, Check check) {
  const Model& m = k.model();
  for (const VectorXd& x : poses_around_home(m, 200, seed)) {
    const PlatformPose p = k.pose(x);
    for (int leg = 0; leg < int(m.legs.size()); ++leg)
      if (const ClosedFormLeg* form = k.closed_form(leg)) check(leg, *form, k.anchor(leg, p));
  }
}

TEST(DescribedScalarPath, OpenEndsCloseAsTheEagerOnes) {
  for (const std::string& name : described_presets()) {
    SCOPED_TRACE(name);
    const Kinematics k = load(name);
    int closed_later = 0;
    for_closed_legs(k, 11, [&](int leg, const ClosedFormLeg& form, const Isometry3d& anchor) {
      const Leg& l = k.model().legs[std::size_t(leg)];
      LegCandidates eager, open;
      solve_closed(form, k.model(), l, anchor, eager);
      solve_closed(form, k.model(), l, anchor, open, true);
      ASSERT_EQ(open.count, eager.count);
      ASSERT_EQ(open.undecided, eager.undecided);
      ASSERT_EQ(open.miss, eager.miss);
      for (int i = 0; i < open.count; ++i) {
        LegState s = open.states[std::size_t(i)];
        if (open.open[std::size_t(i)]) {
          close_open_end(form, k.model(), l, anchor, s, open.end_frames[std::size_t(i)]);
          ++closed_later;
        }
        EXPECT_TRUE(same_state(s, eager.states[std::size_t(i)])) << "leg " << leg << " candidate " << i;
      }
    });
    if (name == "pathos2-described" || name == "delta-described") {
      EXPECT_GT(closed_later, 0);
    }
  }
}

TEST(DescribedScalarPath, BranchCandidatesAreAllCandidatesSiftedByTheAngleRules) {
  const Kinematics k = load("pathos2-described");
  const Model& m = k.model();
  int dropped = 0, kept = 0;
  for_closed_legs(k, 23, [&](int leg, const ClosedFormLeg& form, const Isometry3d& anchor) {
    ASSERT_EQ(form.pattern, LegPattern::ThreeRevolute);
    const Leg& l = m.legs[std::size_t(leg)];
    LegCandidates all, sifted;
    solve_closed(form, m, l, anchor, all);
    solve_closed(form, m, l, anchor, sifted, false, 0);
    std::vector<const LegState*> expected;
    for (int i = 0; i < all.count; ++i) {
      bool keeps = true;
      for (const BranchRule& r : l.rules) {
        ASSERT_EQ(r.kind, BranchRule::Kind::Angle);
        const double v = std::sin(all.states[std::size_t(i)].values(l.steps[std::size_t(r.steps[0])].variable));
        keeps = keeps && (v > 0 ? 1 : v < 0 ? -1 : 0) * wanted_sign(r, 0) >= 0;
      }
      if (keeps) expected.push_back(&all.states[std::size_t(i)]);
    }
    ASSERT_EQ(sifted.count, int(expected.size()));
    if (sifted.count < all.count) {  // (it may also be set where a rejected angle had no solution)
      EXPECT_TRUE(sifted.dropped);
    }
    for (int i = 0; i < sifted.count; ++i) EXPECT_TRUE(same_state(sifted.states[std::size_t(i)], *expected[std::size_t(i)]));
    dropped += all.count - sifted.count;
    kept += sifted.count;
  });
  EXPECT_GT(dropped, 0);
  EXPECT_GT(kept, 0);
}

TEST(DescribedScalarPath, PartWalkMatchesTheWholeWalk) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> angle(-3, 3);
  for (const std::string& name : described_presets()) {
    SCOPED_TRACE(name);
    const Kinematics k = load(name);
    for (const Leg& l : k.model().legs) {
      LegState s;
      s.values = VectorXd::NullaryExpr(l.variables, [&] { return angle(rng); });
      for (int i = 0; i < l.spheres; ++i)
        s.spheres.push_back(internal::rotation_of(Eigen::Vector3d(angle(rng), angle(rng), angle(rng)) / 3));
      const internal::Chain whole = internal::walk(l, s);
      internal::Chain part;
      for (int through = 0; through < int(l.steps.size()); ++through) {
        internal::walk_into(l, s, part, through);
        ASSERT_EQ(int(part.step_centre.size()), through + 1);
        for (int i = 0; i <= through; ++i) {
          EXPECT_EQ(part.step_centre[std::size_t(i)], whole.step_centre[std::size_t(i)]);
          EXPECT_EQ(part.step_axis[std::size_t(i)], whole.step_axis[std::size_t(i)]);
        }
      }
    }
  }
}

TEST(DescribedScalarPath, SineSignIsTheSignOfTheSine) {
  const double pi = 3.141592653589793;
  std::vector<double> angles{0.0, -0.0, pi, -pi, std::nextafter(pi, 4.0), -std::nextafter(pi, 4.0), 2 * pi, -2 * pi,
                             1e-300, -1e-300, 5e-324, std::nextafter(pi, 0.0), 7.0, -7.0};
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> any(-8, 8);
  for (int i = 0; i < 100000; ++i) angles.push_back(any(rng));
  for (double t : angles) {
    const double v = std::sin(t);
    EXPECT_EQ(sine_sign(t), v > 0 ? 1 : v < 0 ? -1 : 0) << t;
  }
}


// A leg whose passive joints lose a freedom is singular whichever path gives
// its Jacobian row: the hexapod's first leg with its universal joint locked
// (the rod turned about the second axis onto the first, a quarter turn from
// square to it) in the closed
// wrench's test and in the rank of the numerical path's QR; a little off the
// lock, in neither.
TEST(DescribedScalarPath, LockedUniversalJointIsSingularOnBothPaths) {
  const Kinematics k = load("hexapod-rus");
  const Model& m = k.model();
  const PoseSolution home = k.inverse(m.home, 0, 1e-10, LegSolver::Fastest);
  ASSERT_EQ(home.status, Status::Ok);
  const Leg& leg = m.legs.front();
  int second_axis = -1;
  for (const Step& step : leg.steps)
    if (step.name == "U1.2") second_axis = step.variable;
  ASSERT_GE(second_axis, 0);
  const double quarter = 1.5707963267948966;
  for (const double off_lock : {0.0, 0.05}) {
    PoseSolution turned = home;
    turned.legs.front().state.values(second_axis) = quarter - off_lock;
    for (const LegSolver solver : {LegSolver::Fastest, LegSolver::Numeric}) {
      SCOPED_TRACE(::testing::Message() << "off the lock " << off_lock << " rad, "
                                        << (solver == LegSolver::Numeric ? "numerical" : "closed") << " row");
      const JacobianParts parts = k.jacobian(m.home, turned, solver);
      if (off_lock == 0.0) {
        EXPECT_EQ(parts.status, Status::Singular);
        EXPECT_EQ(parts.singular_leg, 0);
        EXPECT_EQ(parts.serial_margin.front(), 0.0);
      } else {
        EXPECT_GT(parts.serial_margin.front(), 1e-3 * m.size);
      }
    }
  }
}

}  // namespace
}  // namespace linkscape::described
