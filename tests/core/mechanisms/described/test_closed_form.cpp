// The closed-form legs against the numerical solver (the reference) on every
// shipped description: the pattern each leg is recognised as, identical
// statuses away from the reach boundary, actuators, Jacobians and condition
// numbers within 1e-9 relative; and every closed-form answer checked on its
// own (its legs close, its branch signs hold), so that where the two differ
// the closed form is shown right.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mechanisms/described/kinematics.h"
#include "core/preset.h"
#include "tests/core/mechanisms/described/designs.h"
#include "tests/core/mechanisms/described/without_stops.h"

namespace linkscape::described {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using testing_support::random_designs;

Kinematics load(const std::string& name) {
  const Preset p = load_preset(name);
  return Kinematics(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
}

std::vector<std::string> patterns(const Kinematics& k) {
  std::vector<std::string> out;
  for (std::size_t l = 0; l < k.model().legs.size(); ++l)
    out.push_back(pattern_name(k.closed_form(int(l)) ? k.closed_form(int(l))->pattern : LegPattern::Numeric));
  return out;
}

TEST(DescribedClosedForm, RecognisesTheShippedLegs) {
  EXPECT_EQ(patterns(load("delta-described")), std::vector<std::string>(3, "crank-rod"));
  EXPECT_EQ(patterns(load("pathos2-described")), std::vector<std::string>(6, "three-revolute"));
  EXPECT_EQ(patterns(load("five-bar")), std::vector<std::string>(2, "planar-dyad"));
  EXPECT_EQ(patterns(load("haply-2diy")), std::vector<std::string>(2, "planar-dyad"));
  EXPECT_EQ(patterns(load("stewart")), std::vector<std::string>(6, "extensible"));
  EXPECT_EQ(patterns(load("three-rrr")), std::vector<std::string>(3, "planar-dyad"));
  EXPECT_EQ(patterns(load("three-rpr")), std::vector<std::string>(3, "extensible"));
  EXPECT_EQ(patterns(load("linear-delta")), std::vector<std::string>(3, "slide-rod"));
  EXPECT_EQ(patterns(load("omnid-delta")), std::vector<std::string>(3, "crank-rod"));
  EXPECT_EQ(patterns(load("hexapod-rus")), std::vector<std::string>(6, "crank-rod"));
  EXPECT_EQ(patterns(load("falcon")), std::vector<std::string>(3, "crank-parallelogram"));
}

double cond(const MatrixXd& M) {
  Eigen::JacobiSVD<MatrixXd> svd(M);
  const auto& s = svd.singularValues();
  return s(0) / s(s.size() - 1);
}

// A random pose: the position in home +- spread * size (planar: in the
// plane), each rotation within 0.4 spread rad of home, each extra within its range.
VectorXd random_pose(const Model& m, double spread, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1, 1);
  VectorXd x = m.home;
  for (std::size_t i = 0; i < m.task.size(); ++i) {
    const TaskCoordinate& t = m.task[i];
    if (t.extra >= 0) {
      const Range r = m.extras[std::size_t(t.extra)].range;
      x(Eigen::Index(i)) = r.lo + (r.hi - r.lo) * 0.5 * (unit(rng) + 1);
    } else {
      x(Eigen::Index(i)) += spread * (t.platform_coordinate < 3 ? m.size : 0.4) * unit(rng);
    }
  }
  return x;
}

// The closed form's answer, checked without the numerical solver: every
// leg's chain closes on its anchor.
double closure_miss(const Kinematics& k, const VectorXd& x, const PoseSolution& s) {
  const PlatformPose p = k.pose(x);
  double worst = 0;
  for (std::size_t l = 0; l < s.legs.size(); ++l) {
    const Kinematics::LegDrawing d = k.draw_leg(int(l), s.legs[l].state);
    worst = std::max(worst, (d.frames.back().translation() - k.anchor(int(l), p).translation()).norm());
  }
  return worst;
}

// Every leg the closed form calls unreachable with no miss (0: it closes
// only on another branch) does close its anchor: its chain ends there.
bool closes_off_branch(const Kinematics& k, const VectorXd& x, const PoseSolution& s) {
  const PlatformPose p = k.pose(x);
  bool any = false;
  for (std::size_t l = 0; l < s.legs.size(); ++l) {
    if (s.legs[l].status != Status::Unreachable) continue;
    if (s.legs[l].residual != 0) return false;
    const Eigen::Isometry3d end = k.draw_leg(int(l), s.legs[l].state).frames.back(), anchor = k.anchor(int(l), p);
    if ((end.translation() - anchor.translation()).norm() > 1e-12 * k.model().size) return false;
    any = true;
  }
  return any;
}

struct Tally {
  int poses = 0, ok = 0, mismatches = 0, off_branch = 0;
  double q = 0, J = 0, cond = 0;
};
Tally compare(const Kinematics& k, const std::string& name, int poses);

// How far a status is from ok: ok, out of limits, not converged (another
// branch only), unreachable.
int rank(Status s) {
  return s == Status::Ok ? 0 : s == Status::OutOfLimits ? 1 : s == Status::NotConverged ? 2 : 3;
}

Tally compare(const std::string& name, int poses) {
  const Tally t = compare(load(name), name, poses);
  EXPECT_GE(t.ok, poses / 20) << name;
  return t;
}

Tally compare(const Kinematics& k, const std::string& name, int poses) {
  const Model& m = k.model();
  std::mt19937_64 rng(20261127);
  Tally t;
  for (int i = 0; i < poses; ++i) {
    // Half near home (mostly reachable), half across the box (mostly not).
    const VectorXd x = random_pose(m, i % 2 ? 1.0 : 0.15, rng);
    const int branch = int(rng() % std::uint64_t(k.branches()));
    const PoseSolution fast = k.inverse(x, branch, 1e-10, LegSolver::Fastest);
    const PoseSolution slow = k.inverse(x, branch, 1e-10, LegSolver::Numeric);
    ++t.poses;
    EXPECT_EQ(fast.iterations, 0) << name << ": every leg in closed form";
    // The closed form's assemblies checked on their own: every leg closes.
    if (assembled(fast)) {
      EXPECT_LE(closure_miss(k, x, fast), 1e-12 * m.size) << name << " pose " << i;
    }
    if (fast.status == Status::Unreachable && slow.status == Status::NotConverged && closes_off_branch(k, x, fast)) {
      ++t.off_branch;  // decided by the closed form, left open by the reference
      continue;
    }
    if (fast.status != slow.status) {
      // Only where the reference's seeds stall: the closed form has found
      // (and the line above verified) more than the reference, never less.
      ++t.mismatches;
      EXPECT_LT(rank(fast.status), rank(slow.status)) << name << " pose " << i;
      continue;
    }
    if (fast.status != Status::Ok) continue;
    ++t.ok;
    for (Eigen::Index a = 0; a < fast.q.size(); ++a) {
      const bool prismatic = m.actuators[std::size_t(a)].prismatic;
      const double d = prismatic ? std::abs(fast.q(a) - slow.q(a)) / std::max(1.0, std::abs(slow.q(a)))
                                 : std::abs(std::remainder(fast.q(a) - slow.q(a), 2 * M_PI));
      t.q = std::max(t.q, d);
    }
    const JacobianParts jf = k.jacobian(x, fast), js = k.jacobian(x, slow, LegSolver::Numeric);
    EXPECT_EQ(jf.status, js.status) << name << " pose " << i;
    if (jf.status != Status::Ok || js.status != Status::Ok) continue;
    t.J = std::max(t.J, (jf.J - js.J).norm() / js.J.norm());
    t.cond = std::max(t.cond, std::abs(cond(jf.J) - cond(js.J)) / cond(js.J));
  }
  std::printf("%s: %d poses, %d ok on both; worst q %.2e, J %.2e, cond %.2e (relative); %d where the reference stalled, "
              "%d reached only off the branch\n",
              name.c_str(), t.poses, t.ok, t.q, t.J, t.cond, t.mismatches, t.off_branch);
  EXPECT_LE(t.q, 1e-9) << name;
  EXPECT_LE(t.J, 1e-9) << name;
  EXPECT_LE(t.cond, 1e-9) << name;
  return t;
}

TEST(DescribedClosedForm, DeltaAgreesWithTheNumericalSolver) { compare("delta-described", 20000); }
TEST(DescribedClosedForm, PathosAgreesWithTheNumericalSolver) { compare("pathos2-described", 4000); }
TEST(DescribedClosedForm, FiveBarAgreesWithTheNumericalSolver) { compare("five-bar", 20000); }
TEST(DescribedClosedForm, Haply2diyAgreesWithTheNumericalSolver) { compare("haply-2diy", 20000); }
TEST(DescribedClosedForm, StewartAgreesWithTheNumericalSolver) { compare("stewart", 6000); }
TEST(DescribedClosedForm, ThreeRrrAgreesWithTheNumericalSolver) { compare("three-rrr", 10000); }
TEST(DescribedClosedForm, ThreeRprAgreesWithTheNumericalSolver) { compare("three-rpr", 10000); }
TEST(DescribedClosedForm, LinearDeltaAgreesWithTheNumericalSolver) { compare("linear-delta", 10000); }
TEST(DescribedClosedForm, HexapodRusAgreesWithTheNumericalSolver) { compare("hexapod-rus", 4000); }
TEST(DescribedClosedForm, FalconAgreesWithTheNumericalSolver) { compare("falcon", 6000); }
TEST(DescribedClosedForm, OmnidDeltaAgreesWithTheNumericalSolver) { compare("omnid-delta", 10000); }

// Rods that end in a universal joint, as they start in one (RUU, PUU, UPU):
// the leg holds the platform's orientation too. Tsai's translational
// arrangements, the end's axes the start's in reverse order: the Omnid's arm
// with universal knees and platform joints, the linear Delta with universal
// elbows and wrists, and a 3-UPU.
Kinematics with_universal_ends(const std::string& name) {
  if (name == "puu") {  // the linear Delta's carriages with universal elbows and wrists
    Preset p = load_preset("linear-delta");
    nlohmann::json d = nlohmann::json::parse(p.description);
    nlohmann::json& chain = d["legs"][0]["chain"];
    chain[1] = {{"joint", "universal"}, {"name", "elbow#"}, {"axes", {{0, 1, 0}, {1, 0, 0}}}};
    chain[3] = {{"joint", "universal"}, {"name", "wrist#"}, {"axes", {{1, 0, 0}, {0, 1, 0}}}};
    return Kinematics(build_model(d.dump(), p.parameters, p.limits_deg, p.length_unit));
  }
  Preset p = name == "ruu" ? testing_support::omnid_with_universal_joints() : load_preset("omnid-delta");
  nlohmann::json d = nlohmann::json::parse(p.description);
  nlohmann::json& chain = d["legs"][0]["chain"];
  if (name == "upu") {  // a slide of 150 to 450 mm between two universals
    chain = nlohmann::json::array(
        {{{"joint", "universal"}, {"name", "base#"}, {"axes", {{0, 1, 0}, {1, 0, 0}}}},
         {{"joint", "prismatic"}, {"name", "q#"}, {"axis", {0, 0, 1}}, {"actuated", true}, {"range", {150, 450}}},
         {{"translate", {0, 0, 20}}},
         {{"joint", "universal"}, {"name", "top#"}, {"axes", {{1, 0, 0}, {0, 1, 0}}}}});
    d["legs"][0].erase("branch");
    d["home"]["z"] = 250;
    p.limits_deg.clear();
  }
  return Kinematics(build_model(d.dump(), p.parameters, p.limits_deg, p.length_unit));
}

TEST(DescribedClosedForm, RodsEndingInAUniversalJointAgreeWithTheNumericalSolver) {
  const std::map<std::string, std::string> pattern = {{"ruu", "crank-rod"}, {"puu", "slide-rod"}, {"upu", "extensible"}};
  for (const auto& [name, expected] : pattern) {
    const Kinematics k = with_universal_ends(name);
    const Model& m = k.model();
    EXPECT_EQ(patterns(k), std::vector<std::string>(3, expected)) << name;
    for (std::size_t l = 0; l < m.legs.size(); ++l) {
      ASSERT_TRUE(k.closed_form(int(l))) << name;
      EXPECT_EQ(k.closed_form(int(l))->end_joints, 2) << name;
    }
    EXPECT_GT(compare(k, name, 4000).ok, 800) << name;
    // The closed form's assemblies take the platform's orientation too.
    std::mt19937_64 rng(7);
    int assemblies = 0;
    for (int i = 0; i < 2000; ++i) {
      const VectorXd x = random_pose(m, 0.5, rng);
      const PoseSolution s = k.inverse(x, 0, 1e-10, LegSolver::Fastest);
      if (!assembled(s)) continue;
      ++assemblies;
      const PlatformPose pose = k.pose(x);
      for (std::size_t l = 0; l < m.legs.size(); ++l) {
        const Eigen::Isometry3d end = k.draw_leg(int(l), s.legs[l].state).frames.back();
        EXPECT_LE((end.linear() - k.anchor(int(l), pose).linear()).norm(), 1e-12) << name << " pose " << i;
      }
    }
    EXPECT_GT(assemblies, 200) << name;
  }
}

// Each actuator value of a rod ending in a universal joint closes twice, the
// rod half a turn about itself (the knee's second angle s or 180 deg - s):
// with the knees' second angle limited to 120..240 deg only the second
// assembly is within its limits, and the closed form keeps it (ok, not
// out-of-limits) as the numerical solver's answer does.
TEST(DescribedClosedForm, ARodEndingInAUniversalJointTakesTheAssemblyItsLimitsAllow) {
  const Preset p = testing_support::omnid_with_universal_joints({nullptr, {120, 240}});
  const Kinematics k(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
  const Kinematics balls = load("omnid-delta");  // the same arm with ball joints: its statuses
  ASSERT_TRUE(k.has_joint_limits());
  std::mt19937_64 rng(3);
  int ok = 0;
  for (int i = 0; i < 400; ++i) {
    const VectorXd x = random_pose(k.model(), 0.15, rng);
    const PoseSolution fast = k.inverse(x, 0, 1e-10, LegSolver::Fastest);
    EXPECT_EQ(fast.status, balls.inverse(x, 0, 1e-10, LegSolver::Fastest).status) << "pose " << i;
    if (fast.status != Status::Ok) continue;
    EXPECT_GE(k.stops(k.pose(x), fast).joint_margin_deg, 0) << "pose " << i;
    ++ok;
  }
  EXPECT_GT(ok, 100);
}

// A universal end takes only the orientations its leg lets it: at the
// anchor of home turned by 10 deg about x (no orientation a translational
// leg reaches) no candidate closes, and the closed form leaves the leg to the
// numerical solver rather than answer; level, it answers.
TEST(DescribedClosedForm, AUniversalEndThatCannotTakeTheOrientationIsLeftToTheSolver) {
  const Kinematics k = with_universal_ends("ruu");
  const Model& m = k.model();
  const Leg& leg = m.legs.front();
  const ClosedFormLeg& form = *k.closed_form(0);
  const Eigen::Isometry3d level = k.anchor(0, k.pose(m.home));
  LegCandidates out;
  solve_closed(form, m, leg, level, out, false, 0);
  EXPECT_FALSE(out.undecided);
  EXPECT_GE(out.count, 1);
  Eigen::Isometry3d tilted = level;
  tilted.linear() = level.linear() * Eigen::AngleAxisd(10 * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  solve_closed(form, m, leg, tilted, out, false, 0);
  EXPECT_TRUE(out.undecided);
  EXPECT_EQ(out.count, 0);
  EXPECT_EQ(out.miss, 0);
}

// The pattern is the leg's joints', not the device's: the Falcon's leg with
// its knee, lower joint and grip turning the other way and links with parts
// along the motor axis (passive stops removed: they are written for the
// joints as shipped).
TEST(DescribedClosedForm, AMirroredCrankParallelogramAgreesWithTheNumericalSolver) {
  Preset p = testing_support::without_stops(load_preset("falcon"));
  nlohmann::json d = nlohmann::json::parse(p.description);
  nlohmann::json& chain = d["legs"][0]["chain"];
  chain[1]["translate"] = {"a", 7, 0};
  chain[2]["axis"] = {0, 1, 0};
  chain[3]["translate"] = {"e", -4, 0};
  chain[6]["axis"] = {0, 0, -1};
  chain[8]["axis"] = {0, -1, 0};
  const Kinematics k(build_model(d.dump(), p.parameters, p.limits_deg, p.length_unit));
  EXPECT_EQ(patterns(k), std::vector<std::string>(3, "crank-parallelogram"));
  EXPECT_GT(compare(k, "mirrored falcon", 4000).ok, 400);
}

// In the plane a revolute stands for the ball: a slide between two
// revolutes (3-RPR) is an extensible leg, an actuated slide carrying a rod
// (3-PRR) a slide-rod; each against the numerical solver on three designs.
TEST(DescribedClosedForm, PlanarSlideLegsAgreeWithTheNumericalSolver) {
  for (const bool carried : {false, true})
    for (const auto& [rb, rp, L] : {std::tuple{10.0, 3.0, 8.0}, {12.0, 5.0, 9.5}, {8.0, 2.0, 6.5}}) {
      const Preset p = testing_support::planar_slide_legs(carried, rb, rp, L);
      const Kinematics k(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
      const std::string name = carried ? "3-PRR" : "3-RPR";
      EXPECT_EQ(patterns(k), std::vector<std::string>(3, carried ? "slide-rod" : "extensible")) << name;
      EXPECT_GT(compare(k, name, 4000).ok, 400) << name << " rb " << rb;
    }
}

// A cylinder as a designer writes it: a body of fixed length after the
// universal joint, the stroke, then the rod's end. Still extensible, and
// the Gough-Stewart platform's own answers with the stroke shifted.
TEST(DescribedClosedForm, ACylindersBodyBeforeItsSlideIsStillExtensible) {
  const Preset p = testing_support::stewart_with_cylinder_bodies();
  const Kinematics k(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
  const Kinematics plain = load("stewart");
  EXPECT_EQ(patterns(k), std::vector<std::string>(6, "extensible"));
  EXPECT_GT(compare(k, "stewart with cylinder bodies", 3000).ok, 300);
  std::mt19937_64 rng(5);
  int ok = 0;
  for (int i = 0; i < 2000; ++i) {
    const VectorXd x = random_pose(k.model(), 0.3, rng);
    const PoseSolution s = k.inverse(x, 0, 1e-10, LegSolver::Fastest), t = plain.inverse(x, 0, 1e-10, LegSolver::Fastest);
    ASSERT_EQ(s.status, t.status) << "pose " << i;
    if (s.status != Status::Ok) continue;
    ++ok;
    EXPECT_LE((s.q.array() + 6 - t.q.array()).abs().maxCoeff(), 1e-12 * k.model().size) << "pose " << i;
  }
  EXPECT_GT(ok, 200);
}

TEST(DescribedClosedForm, RandomDesignsAgreeWithTheNumericalSolver) {
  std::mt19937_64 rng(11);
  int ok = 0, mismatches = 0;
  for (const char* name : {"delta-described", "pathos2-described", "five-bar", "stewart", "three-rrr", "linear-delta",
                           "hexapod-rus", "haply-2diy", "falcon", "omnid-delta", "three-rpr"})
    for (const Kinematics& k : random_designs(name, 6, rng)) {
      const Tally t = compare(k, name, 400);
      ok += t.ok;
      mismatches += t.mismatches;
    }
  std::printf("random designs: %d poses ok on both, %d where the reference's seeds stalled\n", ok, mismatches);
  EXPECT_GT(ok, 3000);
}

// The reach bounds (distance from a leg's base to its anchor) are sound: an
// anchor outside them has no closure, as the closed form (exact) says, on
// every shipped description and random designs.
TEST(DescribedClosedForm, ReachBoundsNeverRefuseAReachableAnchor) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> unit(-1, 1);
  int refused = 0, checked = 0;
  for (const char* name : {"delta-described", "pathos2-described", "five-bar", "stewart", "three-rrr", "linear-delta",
                           "hexapod-rus", "haply-2diy", "falcon", "omnid-delta", "three-rpr"}) {
    std::vector<Kinematics> designs = random_designs(name, 4, rng);
    designs.push_back(load(name));
    for (const Kinematics& k : designs) {
      const Model& m = k.model();
      for (std::size_t leg = 0; leg < m.legs.size(); ++leg) {
        const Leg& l = m.legs[leg];
        const Range& reach = k.reach(int(leg));
        for (int i = 0; i < 2000; ++i) {
          Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();
          Eigen::Vector3d offset(unit(rng), unit(rng), m.planar ? 0.0 : unit(rng));
          anchor.translation() = l.base.translation() + 1.5 * m.size * offset;
          // The platform unturned (a level grip), or turned in the plane.
          anchor.linear() = m.planar ? Eigen::AngleAxisd(3 * unit(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix()
                                     : l.anchor.linear();
          const double distance = (anchor.translation() - l.base.translation()).norm();
          if (reach.contains(distance)) continue;
          ++refused;
          LegCandidates c;
          solve_closed(*k.closed_form(int(leg)), m, l, anchor, c);
          EXPECT_EQ(c.count, 0) << name << " leg " << l.name << " at distance " << distance;
          // (Both lengths rounded: to 1e-12 of the size.)
          EXPECT_GE(c.miss, std::max(distance - reach.hi, reach.lo - distance) - 1e-12 * m.size) << name;
          ++checked;
        }
      }
    }
  }
  std::printf("reach bounds: %d anchors refused by the bounds, each confirmed out of reach\n", refused);
  EXPECT_GT(checked, 10000);
}

}  // namespace
}  // namespace linkscape::described
