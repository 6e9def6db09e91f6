// The MJCF export (core/mechanisms/described/mjcf.h) in MuJoCo: every shipped
// described device loads; Linkscape's inverse kinematics, set as MuJoCo's
// joint values, closes every loop MuJoCo's equality constraints describe and
// puts the platform where Linkscape says; and with the actuators held at an
// IK solution, MuJoCo's own constraint solver brings a disturbed mechanism
// back to that pose.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "core/haptics.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/mjcf.h"
#include "core/preset.h"

namespace linkscape::described {
namespace {

struct LoadedModel {
  Preset preset;
  std::unique_ptr<Kinematics> kin;
  mjModel* m = nullptr;
  mjData* d = nullptr;
  double metres = 0.01;
  LoadedModel() = default;
  LoadedModel(const LoadedModel&) = delete;
  ~LoadedModel() {
    if (d) mj_deleteData(d);
    if (m) mj_deleteModel(m);
  }
};

std::unique_ptr<LoadedModel> load(const std::string& name) {
  auto l = std::make_unique<LoadedModel>();
  l->preset = load_preset(name);
  l->kin = std::make_unique<Kinematics>(
      build_model(l->preset.description, l->preset.parameters, l->preset.limits_deg, l->preset.length_unit));
  l->metres = haptics::metres_per(l->preset.length_unit);
  const auto path = std::filesystem::temp_directory_path() / ("linkscape_mjcf_" + name + ".xml");
  std::ofstream(path) << mjcf_model(l->preset);
  char error[1000] = "";
  l->m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  std::filesystem::remove(path);
  EXPECT_NE(l->m, nullptr) << name << ": " << error;
  if (l->m) l->d = mj_makeData(l->m);
  return l;
}

int joint(const mjModel* m, const std::string& name) {
  const int id = mj_name2id(m, mjOBJ_JOINT, name.c_str());
  EXPECT_GE(id, 0) << "no joint " << name;
  return id;
}

// Linkscape's pose (task x) and its IK solution as MuJoCo joint values: a
// hinge's the turn of Linkscape's angle nearest its home value (MuJoCo's
// angles run on from each hinge's ref, and its ranges are literal).
void set_pose(LoadedModel& l, const Eigen::VectorXd& x, const PoseSolution& s, const PoseSolution& home) {
  const Model& model = l.kin->model();
  static const char* names[6] = {"x", "y", "z", "rx", "ry", "rz"};
  for (std::size_t k = 0; k < model.task.size(); ++k) {
    const int c = model.task[k].platform_coordinate;
    if (c < 0) continue;
    const int j = joint(l.m, mjcf_platform_joint(names[c]));
    l.d->qpos[l.m->jnt_qposadr[j]] = x[Eigen::Index(k)] * (c < 3 ? l.metres : 1.0);
  }
  for (std::size_t leg = 0; leg < model.legs.size(); ++leg) {
    int sphere = 0;
    for (const Step& step : model.legs[leg].steps) {
      if (step.kind == Step::Kind::Fixed) continue;
      const int adr = l.m->jnt_qposadr[joint(l.m, step.name)];
      const LegState& state = s.legs[leg].state;
      if (step.kind == Step::Kind::Spherical) {
        // The ball turns from the home assembly's rotation.
        const Eigen::Quaterniond q(home.legs[leg].state.spheres[std::size_t(sphere)].transpose() *
                                   state.spheres[std::size_t(sphere)]);
        ++sphere;
        const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
        for (int i = 0; i < 4; ++i) l.d->qpos[adr + i] = wxyz[i];
      } else {
        double v = state.values[step.variable];
        if (step.kind == Step::Kind::Revolute) {
          const double h = home.legs[leg].state.values[step.variable];
          v = h + std::remainder(v - h, 2 * M_PI);
        }
        l.d->qpos[adr] = step.kind == Step::Kind::Prismatic ? v * l.metres : v;
      }
    }
  }
}

// The largest violation of MuJoCo's equality constraints (m or rad).
double loop_residual(const LoadedModel& l) {
  double worst = 0;
  for (int i = 0; i < l.d->nefc; ++i)
    if (l.d->efc_type[i] == mjCNSTR_EQUALITY) worst = std::max(worst, std::abs(l.d->efc_pos[i]));
  return worst;
}

Eigen::Vector3d platform_position(const LoadedModel& l) {
  const int body = mj_name2id(l.m, mjOBJ_BODY, "platform_rx");
  return Eigen::Vector3d(l.d->xpos[3 * body], l.d->xpos[3 * body + 1], l.d->xpos[3 * body + 2]);
}

// Poses around home along every task coordinate, reachable on branch 0.
std::vector<Eigen::VectorXd> poses(const Kinematics& kin) {
  const Model& model = kin.model();
  std::vector<Eigen::VectorXd> out{model.home};
  for (std::size_t k = 0; k < model.task.size(); ++k) {
    if (model.task[k].platform_coordinate < 0) continue;
    const double step = model.task[k].platform_coordinate < 3 ? 0.1 * model.size : 0.15;
    for (const double sign : {-1.0, 1.0}) {
      Eigen::VectorXd x = model.home;
      x[Eigen::Index(k)] += sign * step;
      out.push_back(x);
    }
  }
  return out;
}

class EveryDescribedPreset : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryDescribedPreset, LoadsInMuJoCoWithAJointPerDescribedJoint) {
  const auto l = load(GetParam());
  ASSERT_NE(l->m, nullptr);
  const Model& model = l->kin->model();
  int joints = 0;
  for (const Leg& leg : model.legs)
    for (const Step& step : leg.steps) joints += step.kind != Step::Kind::Fixed;
  joints += int(model.task.size() - model.extras.size());
  EXPECT_EQ(l->m->njnt, joints);
  EXPECT_EQ(l->m->nu, int(model.actuators.size()));
  EXPECT_EQ(l->m->neq, int(model.legs.size()));
}

TEST_P(EveryDescribedPreset, LinkscapesInverseKinematicsClosesMuJoCosLoops) {
  const auto l = load(GetParam());
  ASSERT_NE(l->m, nullptr);
  const Kinematics& kin = *l->kin;
  const PoseSolution home = kin.inverse(kin.model().home, 0, 1e-12);
  ASSERT_TRUE(assembled(home));
  int checked = 0;
  for (const Eigen::VectorXd& x : poses(kin)) {
    const PoseSolution s = kin.inverse(x, 0, 1e-12);
    if (s.status != Status::Ok) continue;
    set_pose(*l, x, s, home);
    mj_forward(l->m, l->d);
    EXPECT_LT(loop_residual(*l), 1e-9) << GetParam() << " at " << x.transpose();
    const PlatformPose pose = kin.pose(x);
    EXPECT_LT((platform_position(*l) - pose.p * l->metres).norm(), 1e-12) << GetParam();
    ++checked;
  }
  EXPECT_GE(checked, 3) << GetParam() << ": too few poses around home are reachable";
}

// MuJoCo's own dynamics closing the loops, every shipped device (the
// actuated joints carry their motors' rotor inertia: without it the 6-RUS
// hexapod's loops do not close, docs/model-export.md).
class SettlingPreset : public EveryDescribedPreset {};

TEST_P(SettlingPreset, MuJoCoClosesADisturbedMechanismAtLinkscapesPose) {
  const auto l = load(GetParam());
  ASSERT_NE(l->m, nullptr);
  const Kinematics& kin = *l->kin;
  const Model& model = kin.model();
  const PoseSolution home = kin.inverse(model.home, 0, 1e-12);
  Eigen::VectorXd x = model.home;
  x[0] += 0.05 * model.size;  // off home, so the answer is not the model's reference
  const PoseSolution s = kin.inverse(x, 0, 1e-12);
  ASSERT_EQ(s.status, Status::Ok);
  set_pose(*l, x, s, home);

  // Disturb every passive joint and the platform; hold the actuators at the IK solution.
  std::vector<int> held;
  for (const Actuator& a : model.actuators) held.push_back(l->m->jnt_qposadr[joint(l->m, a.name)]);
  for (int j = 0; j < l->m->njnt; ++j) {
    const int adr = l->m->jnt_qposadr[j];
    if (std::find(held.begin(), held.end(), adr) != held.end() || l->m->jnt_type[j] == mjJNT_BALL) continue;
    l->d->qpos[adr] += (l->m->jnt_type[j] == mjJNT_SLIDE ? 1e-3 : 2e-3) * ((j % 3) - 1.0);
  }
  std::vector<double> q_held;
  for (const int adr : held) q_held.push_back(l->d->qpos[adr]);
  l->m->opt.gravity[2] = 0;
  mj_forward(l->m, l->d);
  const double disturbed = loop_residual(*l);
  for (int step = 0; step < 4000; ++step) {
    mj_step(l->m, l->d);
    for (std::size_t a = 0; a < held.size(); ++a) {
      l->d->qpos[held[a]] = q_held[a];
      l->d->qvel[l->m->jnt_dofadr[joint(l->m, model.actuators[a].name)]] = 0;
    }
  }
  mj_forward(l->m, l->d);
  EXPECT_GT(disturbed, 1e-5) << "the disturbance did not open the loops";
  // MuJoCo's constraints are soft, but settle: to 2e-10 m for PATHOS-II, 1e-14 for the others.
  EXPECT_LT(loop_residual(*l), 1e-8) << GetParam();
  EXPECT_LT((platform_position(*l) - kin.pose(x).p * l->metres).norm(), 1e-8) << GetParam();
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name)
    if (c == '-') c = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Shipped, EveryDescribedPreset,
                         ::testing::Values("delta-described", "pathos2-described", "five-bar", "stewart", "falcon",
                                           "haply-2diy", "three-rrr", "linear-delta", "hexapod-rus", "omnid-delta",
                                           "three-rpr"),
                         test_name);
INSTANTIATE_TEST_SUITE_P(Shipped, SettlingPreset,
                         ::testing::Values("delta-described", "pathos2-described", "five-bar", "stewart", "falcon",
                                           "haply-2diy", "three-rrr", "linear-delta", "hexapod-rus", "omnid-delta",
                                           "three-rpr"),
                         test_name);

// The Falcon's passive-joint limits become its hinges' ranges (the turn
// holding the joint's home value), and its links capsules of their radii:
// every chain link's geom in the body of the joint before it, as long as the
// link, and at home every stated hinge within its range.
TEST(ModelExport, PassiveLimitsAndLinkRadiiReachMuJoCo) {
  const auto l = load("falcon");
  ASSERT_NE(l->m, nullptr);
  const Model& model = l->kin->model();
  const PoseSolution home = l->kin->inverse(model.home, 0, 1e-12);
  int ranges = 0, links = 0;
  for (std::size_t leg = 0; leg < model.legs.size(); ++leg) {
    const Leg& lg = model.legs[leg];
    for (const JointLimit& lim : lg.limits) {
      const int j = joint(l->m, lg.steps[std::size_t(lim.step)].name);
      ASSERT_TRUE(l->m->jnt_limited[j]) << lg.steps[std::size_t(lim.step)].name;
      const double lo = l->m->jnt_range[2 * j], hi = l->m->jnt_range[2 * j + 1];
      EXPECT_NEAR(hi - lo, lim.range.hi - lim.range.lo, 1e-12);
      EXPECT_NEAR(std::remainder(lo - lim.range.lo, 2 * M_PI), 0, 1e-12);
      const double v = home.legs[leg].state.values[lg.steps[std::size_t(lim.step)].variable];
      EXPECT_TRUE(lo <= v && v <= hi) << lg.steps[std::size_t(lim.step)].name << " at " << v;
      ++ranges;
    }
    // Chain links: the geom in the joint's body with the description's radius and length.
    for (const LinkCapsule& c : lg.capsules) {
      if (c.on != LinkCapsule::On::Chain) continue;
      const int body = mj_name2id(l->m, mjOBJ_BODY, lg.steps[std::size_t(c.frame)].name.c_str());
      bool found = false;
      for (int g = 0; g < l->m->ngeom; ++g)
        if (l->m->geom_bodyid[g] == body && l->m->geom_type[g] == mjGEOM_CAPSULE &&
            std::abs(l->m->geom_size[3 * g] - c.radius * l->metres) < 1e-12 &&
            std::abs(2 * l->m->geom_size[3 * g + 1] - (c.b - c.a).norm() * l->metres) < 1e-12)
          found = true;
      EXPECT_TRUE(found) << lg.label() << " " << c.name;
      links += found;
    }
  }
  EXPECT_EQ(ranges, 9);
  EXPECT_EQ(links, 12);
}

// The motors' ranges are the peak torque at the joint as the haptic
// measures take it: ratings given as parameters and the gear ratio count;
// a preset that rates no motor gets no range (the default rating is no
// device's).
TEST(ModelExport, MotorRangesAreThePeakTorqueAtTheJoint) {
  const auto ctrl_limits = [](const Preset& p) {
    const auto path = std::filesystem::temp_directory_path() / "linkscape_mjcf_ctrl.xml";
    std::ofstream(path) << mjcf_model(p);
    char error[1000] = "";
    mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    std::filesystem::remove(path);
    EXPECT_NE(m, nullptr) << error;
    std::vector<double> out;
    for (int a = 0; m && a < m->nu; ++a) out.push_back(m->actuator_ctrllimited[a] ? m->actuator_ctrlrange[2 * a + 1] : -1);
    if (m) mj_deleteModel(m);
    return out;
  };
  Preset rated = load_preset("delta-described");
  EXPECT_EQ(ctrl_limits(rated), std::vector<double>(3, -1.0));  // no actuator_data: no range
  apply_overrides(rated, {"peak_torque_Nm=0.5", "gear_ratio=2"});
  EXPECT_EQ(ctrl_limits(rated), std::vector<double>(3, 1.0));  // 0.5 N m through 2:1
}

TEST(ModelExport, ACompiledDeviceIsRefusedWithAReason) {
  try {
    mjcf_model(load_preset("parallel-12r"));
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("described"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace linkscape::described
