// The window's device state without a window: the branch kept along a
// drag, refusals that leave the pose, and the pose a new design keeps.
// Every taken pose is checked against the device's own forward kinematics.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "core/mechanism.h"
#include "core/preset.h"
#include "gui/window/device_state.h"

namespace linkscape::gui {
namespace {

// Residual of a pose against the device's forward kinematics (same seed as the state).
double fk_error(const DeviceState& s) {
  FkOptions o;
  o.seed = s.task();
  const FkResult r = s.mechanism().forward(s.actuators(), o);
  EXPECT_EQ(r.status, Status::Ok);
  return (r.x - s.task()).norm();
}

// A straight drag from a to b in `steps` steps; every step must be taken
// in the starting branch.
void drag(DeviceState& s, const Eigen::Vector3d& a, const Eigen::Vector3d& b, int steps) {
  const int branch = s.branch();
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector3d target = a + (b - a) * (double(i) / steps);
    ASSERT_TRUE(s.move_endpoint_to(target)) << s.refusal() << " at step " << i;
    ASSERT_EQ(s.branch(), branch);
    ASSERT_LT((s.endpoint() - target).norm(), 1e-12);
    ASSERT_LT(fk_error(s), 1e-9) << "step " << i;
  }
}

TEST(DeviceState, StartsAtHomeInItsBranch) {
  for (const char* name : {"parallel-12r", "delta", "pathos2", "delta-described"}) {
    const DeviceState s(load_preset(name));
    EXPECT_EQ(s.actuators(), s.mechanism().home_actuators()) << name;
    EXPECT_EQ(s.task(), s.mechanism().home_task()) << name;
    EXPECT_TRUE(s.refusal().empty()) << name;
    EXPECT_LT(fk_error(s), 1e-9) << name;
  }
}

TEST(DeviceState, TwelveRKeepsItsBranchAlongADrag) {
  DeviceState s(load_preset("parallel-12r"));
  ASSERT_EQ(s.mechanism().info().branches.size(), 2u);
  for (int branch : {0, 1}) {
    ASSERT_TRUE(s.move_endpoint_to({-12, 16, -8}, branch)) << s.refusal();
    ASSERT_EQ(s.branch(), branch);
    // Through the region where both branches come close to each other.
    drag(s, {-12, 16, -8}, {14, 4, 22}, 200);
  }
}

TEST(DeviceState, TwelveRRefusesWithThePoseUnchanged) {
  DeviceState s(load_preset("parallel-12r"));
  ASSERT_TRUE(s.move_endpoint_to({14, 4, 22}, 1)) << s.refusal();
  const Eigen::VectorXd q = s.actuators(), x = s.task();
  const int branch = s.branch();
  const auto unchanged = [&] {
    EXPECT_EQ(s.actuators(), q);
    EXPECT_EQ(s.task(), x);
    EXPECT_EQ(s.branch(), branch);
  };
  EXPECT_FALSE(s.move_endpoint_to({0, 40, 0}));  // beyond L1 + L2
  EXPECT_EQ(s.refusal().rfind("unreachable", 0), 0u) << s.refusal();
  EXPECT_NE(s.refusal().find("in branch 1"), std::string::npos) << s.refusal();
  unchanged();
  EXPECT_FALSE(s.move_endpoint_to({5, 0, 5}));  // on the actuator plane
  EXPECT_EQ(s.refusal().rfind("singular", 0), 0u) << s.refusal();
  unchanged();
  // Reachable in the branch, but across the actuator plane: a jump.
  EXPECT_FALSE(s.move_endpoint_to({10, -15, 10}));
  EXPECT_EQ(s.refusal().rfind("jump", 0), 0u) << s.refusal();
  unchanged();
  // The same target without tracking (the task sliders) is taken: the
  // refusal was the jump, not the point.
  Eigen::VectorXd across = x;
  across.head<3>() = Eigen::Vector3d(10, -15, 10);
  EXPECT_TRUE(s.set_task(across)) << s.refusal();
  EXPECT_TRUE(s.refusal().empty());
  EXPECT_GT(angle_distance(s.actuators(), q), kMaxTrackingStep);
}

TEST(DeviceState, AnExplicitBranchThatFailsKeepsTheBranch) {
  DeviceState s(load_preset("parallel-12r"));
  const int branch = s.branch();
  const Eigen::VectorXd q = s.actuators();
  EXPECT_FALSE(s.move_endpoint_to({0, 40, 0}, 1 - branch));
  EXPECT_EQ(s.branch(), branch);
  EXPECT_EQ(s.actuators(), q);
  EXPECT_FALSE(s.move_endpoint_to(s.endpoint(), 7));
  EXPECT_EQ(s.refusal(), "There is no branch 7.");
  // The other branch at the same point: the same task, other actuators.
  const Eigen::Vector3d p = s.endpoint();
  ASSERT_TRUE(s.move_endpoint_to(p, 1 - branch)) << s.refusal();
  EXPECT_EQ(s.branch(), 1 - branch);
  EXPECT_LT((s.endpoint() - p).norm(), 1e-12);
  EXPECT_GT(angle_distance(s.actuators(), q), 1e-3);
}

TEST(DeviceState, DeltaKeepsItsBranchAndRefusesTheUnreachable) {
  DeviceState s(load_preset("delta"));
  const Eigen::Vector3d home = s.endpoint();
  drag(s, home, home + Eigen::Vector3d(4, -3, 3), 60);
  drag(s, s.endpoint(), home + Eigen::Vector3d(-5, 2, -2), 60);
  const Eigen::VectorXd q = s.actuators();
  EXPECT_FALSE(s.move_endpoint_to({0, 0, -60}));  // below the longest reach
  EXPECT_EQ(s.actuators(), q);
  EXPECT_FALSE(s.refusal().empty());
  EXPECT_NE(s.refusal().find("the device stays at the last valid pose"), std::string::npos) << s.refusal();
  // Bad input is refused, not solved.
  EXPECT_FALSE(s.set_task(Eigen::VectorXd::Constant(2, 0.0)));
  EXPECT_EQ(s.refusal(), "The target is not 3 finite task coordinates.");
  Eigen::VectorXd nan = s.task();
  nan(1) = NAN;
  EXPECT_FALSE(s.set_task(nan));
  EXPECT_EQ(s.actuators(), q);
}

TEST(DeviceState, ForwardKinematicsRoundTripsInverse) {
  for (const char* name : {"parallel-12r", "delta", "delta-described"}) {
    DeviceState s(load_preset(name));
    Eigen::VectorXd x = s.task();
    x(0) += 1.0;
    x(2) += 0.5;
    ASSERT_TRUE(s.set_task(x)) << name << ": " << s.refusal();
    const Eigen::VectorXd q = s.actuators();
    const int branch = s.branch();
    DeviceState t(load_preset(name));
    ASSERT_TRUE(t.set_actuators(q)) << name << ": " << t.refusal();
    EXPECT_LT((t.task() - x).norm(), 1e-8) << name;
    EXPECT_EQ(t.branch(), branch) << name;
    EXPECT_FALSE(t.set_actuators(Eigen::VectorXd::Zero(q.size() + 1))) << name;
    EXPECT_LT((t.task() - x).norm(), 1e-8) << name;
  }
}

// Actuator sliders on another branch than the design's (travel widened, the
// ball joints' cones off): forward kinematics keeps the branch the arms
// are on, on the compiled and the described Delta alike.
TEST(DeviceState, ActuatorsOnAnotherBranchKeepIt) {
  for (const char* name : {"delta", "delta-described"}) {
    Preset p = load_preset(name);
    for (const char* q : {"q1", "q2", "q3"}) p.limits_deg[q] = Range{-180.0, 180.0};
    p.checks.joint_limits = false;
    DeviceState s(p);
    const Eigen::Vector3d target = s.endpoint() + Eigen::Vector3d(1.0, -0.5, 0.5);
    for (int branch = 1; branch < 8; ++branch) {
      ASSERT_TRUE(s.move_endpoint_to(target, branch)) << name << " branch " << branch << ": " << s.refusal();
      ASSERT_EQ(s.branch(), branch) << name;
      Eigen::VectorXd q = s.actuators();
      q(0) += 0.01;
      ASSERT_TRUE(s.set_actuators(q)) << name << ": " << s.refusal();
      EXPECT_EQ(s.branch(), branch) << name;
      EXPECT_LT(fk_error(s), 1e-9) << name;
    }
  }
}

TEST(DeviceState, PathosNamesTheFailingLeg) {
  DeviceState s(load_preset("pathos2"));
  const Eigen::VectorXd x = s.task();
  Eigen::VectorXd far = x;
  far(2) = 42.0;  // next to the upper base plate
  const IkResult ik = s.mechanism().inverse(far);
  ASSERT_NE(ik.status, Status::Ok);
  ASSERT_FALSE(ik.failing_part.empty());
  EXPECT_FALSE(s.set_task(far));
  EXPECT_EQ(s.task(), x);
  EXPECT_EQ(s.refusal().rfind("leg " + ik.failing_part + ": ", 0), 0u) << s.refusal();
  EXPECT_EQ(s.failing_part(), ik.failing_part);
  ASSERT_NE(s.failed(), nullptr);
  EXPECT_EQ(s.failed()->failing_part, ik.failing_part);
  Eigen::VectorXd near = x;
  near(2) += 1.0;
  EXPECT_TRUE(s.set_task(near)) << s.refusal();
  EXPECT_TRUE(s.refusal().empty());
  EXPECT_TRUE(s.failing_part().empty());
  EXPECT_EQ(s.failed(), nullptr);
}

// A small change of design keeps the task coordinates; a large one that
// puts them out of reach keeps the actuators; an invalid one is refused.
// `invalid` is refused, the refusal containing `why`.
void design_change_keeps_the_pose(const char* name, const std::string& length, double invalid, const std::string& why) {
  SCOPED_TRACE(name);
  DeviceState s(load_preset(name));
  Eigen::VectorXd x = s.task();
  x(0) += 1.0;
  ASSERT_TRUE(s.set_task(x)) << s.refusal();
  const double value = s.mechanism().parameters().at(length);

  DesignPlan grown = s.with_parameters({{length, value * 1.02}});
  ASSERT_TRUE(grown.ok()) << grown.refusal;
  EXPECT_EQ(grown.kept, DesignPlan::Kept::Task);
  EXPECT_EQ(grown.x, x);
  EXPECT_EQ(grown.branch, s.branch());
  EXPECT_EQ(s.mechanism().parameters().at(length), value);  // a plan changes nothing
  s.adopt(grown);
  EXPECT_DOUBLE_EQ(s.mechanism().parameters().at(length), value * 1.02);
  EXPECT_DOUBLE_EQ(s.preset().parameters.at(length), value * 1.02);
  EXPECT_LT(fk_error(s), 1e-8);

  const DesignPlan bad = s.with_parameters({{length, invalid}});
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(bad.refusal.find(why), std::string::npos) << bad.refusal;
  EXPECT_THROW(s.adopt(bad), std::invalid_argument);
  EXPECT_DOUBLE_EQ(s.mechanism().parameters().at(length), value * 1.02);
}

TEST(DeviceState, TwelveRDesignChangeKeepsThePose) { design_change_keeps_the_pose("parallel-12r", "L2", -1.0, "L2"); }
TEST(DeviceState, DeltaDesignChangeKeepsThePose) { design_change_keeps_the_pose("delta", "Lb", -1.0, "Lb"); }
// The described device makes a model of a negative forearm; it reaches nothing.
TEST(DeviceState, DescribedDeltaDesignChangeKeepsThePose) {
  design_change_keeps_the_pose("delta-described", "Lb", -1.0, "cannot reach its home pose; design unchanged");
}

// Out of reach of the new design: the actuators stay and the task is where
// they put the driven point (or home, said as such).
TEST(DeviceState, ADesignThatLosesTheTaskKeepsTheActuatorsOrSaysHome) {
  for (const char* name : {"delta", "delta-described"}) {
    SCOPED_TRACE(name);
    DeviceState s(load_preset(name));
    Eigen::VectorXd low = s.task();
    low(2) -= 3.0;  // lower, so a shorter forearm cannot reach it
    ASSERT_TRUE(s.set_task(low)) << s.refusal();
    const Eigen::VectorXd q = s.actuators();
    const DesignPlan plan = s.with_parameters({{"Lb", 12.0}});
    ASSERT_TRUE(plan.ok()) << plan.refusal;
    ASSERT_NE(plan.kept, DesignPlan::Kept::Task);
    EXPECT_GT((plan.x - low).norm(), 1e-3);
    if (plan.kept == DesignPlan::Kept::Actuators) {
      EXPECT_EQ(plan.q, q);
      FkOptions o;
      o.seed = low;
      EXPECT_LT((plan.mechanism->forward(q, o).x - plan.x).norm(), 1e-9);
    } else {
      EXPECT_EQ(plan.q, plan.mechanism->home_actuators());
    }
  }
}

TEST(DeviceState, ASavedPoseIsTakenOrRefusedBeforeAnythingChanges) {
  DeviceState s(load_preset("parallel-12r"));
  ASSERT_TRUE(s.move_endpoint_to({-12, 16, -8}, 1)) << s.refusal();
  const Eigen::VectorXd q = s.actuators(), x = s.task();
  DeviceState t(load_preset("parallel-12r"));
  // The saved actuators pick the branch; they are taken as saved.
  DesignPlan plan = t.with_saved_pose(t.preset(), q, x);
  EXPECT_EQ(plan.kept, DesignPlan::Kept::Task);
  EXPECT_EQ(plan.q, q);
  EXPECT_EQ(plan.branch, 1);
  t.adopt(plan);
  EXPECT_EQ(t.branch(), 1);
  // Actuators alone: FK.
  plan = t.with_saved_pose(t.preset(), q, Eigen::VectorXd());
  EXPECT_EQ(plan.kept, DesignPlan::Kept::Actuators);
  EXPECT_LT((plan.x - x).norm(), 1e-8);
  // Out of reach: home, said as such.
  Eigen::VectorXd far = x;
  far.head<3>() = Eigen::Vector3d(0, 40, 0);
  plan = t.with_saved_pose(t.preset(), Eigen::VectorXd(), far);
  EXPECT_EQ(plan.kept, DesignPlan::Kept::Home);
  EXPECT_EQ(plan.x, t.mechanism().home_task());
  // Wrong sizes and invalid designs throw; nothing changes.
  EXPECT_THROW(t.with_saved_pose(t.preset(), Eigen::VectorXd::Zero(2), x), std::invalid_argument);
  EXPECT_THROW(t.with_saved_pose(t.preset(), q, Eigen::VectorXd::Zero(5)), std::invalid_argument);
  Preset invalid = t.preset();
  invalid.parameters["L1"] = -3.0;
  EXPECT_THROW(t.with_saved_pose(invalid, q, x), std::invalid_argument);
  EXPECT_EQ(t.actuators(), q);
}

TEST(DeviceState, ActuatorLimitsClampThePoseOrAreRefused) {
  DeviceState s(load_preset("delta"));
  ASSERT_TRUE(s.takes_limits());
  const Eigen::VectorXd q = s.actuators();
  // Travel that ends just below the first actuator's angle: it is clamped there.
  const double q1_deg = q(0) * 180.0 / M_PI;
  std::string why;
  ASSERT_TRUE(s.set_actuator_limits({{"q1", {-45.0, q1_deg - 5.0}}}, why)) << why;
  EXPECT_NEAR(s.actuators()(0), (q1_deg - 5.0) * M_PI / 180.0, 1e-12);
  EXPECT_EQ(s.actuators()(1), q(1));
  EXPECT_LT(fk_error(s), 1e-9);
  EXPECT_DOUBLE_EQ(s.preset().limits_deg.at("q1").hi, q1_deg - 5.0);
  // An empty travel is refused, the limits and pose in force stay.
  const Eigen::VectorXd kept = s.actuators();
  EXPECT_FALSE(s.set_actuator_limits({{"q1", {30.0, 10.0}}}, why));
  EXPECT_FALSE(why.empty());
  EXPECT_EQ(s.actuators(), kept);
  EXPECT_DOUBLE_EQ(s.preset().limits_deg.at("q1").hi, q1_deg - 5.0);
}

}  // namespace
}  // namespace linkscape::gui
