// The compiled Delta's ball-joint cones (core/mechanisms/delta/stops.h): the
// same as the described Delta's, in IK, FK, fields, the switch, the preset
// reader and verify.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>

#include "core/mechanism.h"
#include "core/mechanisms/delta/delta.h"
#include "core/mechanisms/delta/field.h"
#include "core/mechanisms/delta/mechanism.h"
#include "core/mechanisms/delta/stops.h"
#include "core/preset.h"
#include "core/task.h"
#include "core/verify/verify.h"

namespace linkscape::delta {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;
constexpr double kDeg = std::numbers::pi / 180;

Preset delta_preset(bool joint_limits) {
  Preset p = load_preset("delta");
  p.checks.joint_limits = joint_limits;
  return p;
}

// The angle between two directions from the joint positions, independent of ball_angles.
double angle_deg(const Vector3d& a, const Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) / kDeg;
}

TEST(DeltaStops, ConesAgreeWithTheDescribedDelta) {
  const auto compiled = linkscape::make_mechanism(delta_preset(true));
  const auto described = linkscape::make_mechanism(load_preset("delta-described"));
  const auto plain = linkscape::make_mechanism(delta_preset(false));
  const Vector3d home = compiled->home_task();
  int ok = 0, beyond = 0;
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j)
      for (int k = -4; k <= 4; ++k) {
        const VectorXd x = home + Vector3d(i, j, k) * 1.5;
        const linkscape::IkResult c = compiled->inverse(x, {}), d = described->inverse(x, {});
        if (plain->inverse(x, {}).status != Status::Ok) continue;
        ASSERT_EQ(c.status, d.status) << x.transpose() << " " << c.status_text << " / " << d.status_text;
        if (c.status == Status::Ok) ++ok;
        if (c.status != Status::OutOfLimits) continue;
        ++beyond;
        EXPECT_EQ(c.failing_part, d.failing_part);
        EXPECT_EQ(c.status_text, d.status_text);
        EXPECT_LT(compiled->reach_margin(x, 0), 0.0);
      }
  EXPECT_GT(ok, 50);
  EXPECT_GT(beyond, 20);
}

TEST(DeltaStops, AnglesAreThoseOfTheDrawnJoints) {
  const Model m = make_delta_model(delta_preset(true));
  const Vector3d p = home_position(m) + Vector3d(2, -3, 1.5);
  const IkResult r = inverse(m, p);
  ASSERT_NE(r.status, Status::Unreachable);
  const Skeleton s = skeleton(m, r.q_actuated, p);
  for (int leg = 0; leg < kLegCount; ++leg) {
    const Vector3d arm = s.X_world_body[1 + leg].linear().col(0), arm_z = s.X_world_body[1 + leg].linear().col(2);
    const Vector3d rod = s.X_world_body[4 + leg].linear().col(0);
    const Vector3d elbow_axis = std::cos(104 * kDeg) * arm - std::sin(104 * kDeg) * arm_z;
    const Vector3d wrist_axis = -std::cos(49 * kDeg) * leg_radial(leg) - std::sin(49 * kDeg) * Vector3d::UnitZ();
    const BallAngles a = ball_angles(m, leg, r.q_actuated(leg), p);
    EXPECT_NEAR(a.elbow / kDeg, angle_deg(elbow_axis, rod), 1e-9) << leg;
    EXPECT_NEAR(a.wrist / kDeg, angle_deg(rod, wrist_axis), 1e-9) << leg;
  }
}

TEST(DeltaStops, ForwardKinematicsReportsAPoseBeyondACone) {
  const auto on = linkscape::make_mechanism(delta_preset(true));
  const auto off = linkscape::make_mechanism(delta_preset(false));
  const Vector3d home = on->home_task();
  int checked = 0;
  for (int i = -4; i <= 4 && checked < 5; ++i)
    for (int k = -4; k <= 4 && checked < 5; ++k) {
      const VectorXd x = home + Vector3d(i, 0.5, k) * 1.5;
      const linkscape::IkResult plain = off->inverse(x, {}), stopped = on->inverse(x, {});
      if (plain.status != Status::Ok || stopped.status != Status::OutOfLimits) continue;
      ++checked;
      const linkscape::FkResult fk = on->forward(plain.solutions[0].q, {});
      EXPECT_EQ(fk.status, Status::OutOfLimits) << x.transpose();
      EXPECT_LT((fk.x - x).norm(), 1e-9);
      EXPECT_EQ(off->forward(plain.solutions[0].q, {}).status, Status::Ok);
    }
  EXPECT_GT(checked, 0);
}

void expect_same(const SampleArray<float>& a, const SampleArray<float>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << what;
}

TEST(DeltaStops, FieldJointMarginIsEachPosesAndTheSwitchRestoresTheField) {
  const auto on = linkscape::make_mechanism(delta_preset(true));
  const auto off = linkscape::make_mechanism(delta_preset(false));
  const Vector3d home = on->home_task();
  const Grid grid = Grid::box(home - Vector3d(8, 8, 8), home + Vector3d(8, 8, 8), {13, 12, 11});
  for (FieldKernel kernel : {FieldKernel::Scalar, FieldKernel::Vector, FieldKernel::VectorMirrored}) {
    setenv("LINKSCAPE_FIELD_KERNEL", kernel == FieldKernel::Scalar ? "scalar" : kernel == FieldKernel::Vector ? "vector" : "vector-mirrored", 1);
    const auto f = on->compute_field(grid, home, {}, 1, {});
    const auto plain = off->compute_field(grid, home, {}, 1, {});
    ASSERT_TRUE(f && plain);
    EXPECT_TRUE(plain->extras.empty());
    const Field::NamedArray* margin = f->extra("joint_margin");
    ASSERT_TRUE(margin);
    int beyond = 0;
    for (int k = 0; k < 11; ++k)
      for (int j = 0; j < 12; ++j)
        for (int i = 0; i < 13; ++i) {
          const std::size_t n = grid.index(i, j, k);
          const Vector3d p = grid.point(i, j, k);
          const linkscape::IkResult ik = on->inverse(p, {});
          if (ik.status == Status::Unreachable) {
            EXPECT_TRUE(std::isnan(margin->values[n]));
            continue;
          }
          const JointStops st = joint_stops(make_delta_model(delta_preset(true)), ik.solutions[0].q, p);
          EXPECT_NEAR(margin->values[n], st.margin_deg, 1e-4) << n;
          if (ik.status == Status::OutOfLimits && !ik.status_text.empty()) {
            ++beyond;
            EXPECT_EQ(f->status[n], std::uint8_t(Status::OutOfLimits)) << n;
            EXPECT_LT(f->reach_margin[n], 0.0f) << n;
          }
          if (f->status[n] == std::uint8_t(Status::Ok)) EXPECT_EQ(ik.status, Status::Ok) << n;
        }
    EXPECT_GT(beyond, 20);
    // Without the cones the field is today's, bit for bit.
    const auto today = make_mechanism(Model::from_parameters(delta_preset(false).parameters, {}, "cm"))->compute_field(grid, home, {}, 1, {});
    ASSERT_TRUE(today);
    expect_same(plain->cond, today->cond, "cond");
    expect_same(plain->reach_margin, today->reach_margin, "reach_margin");
    EXPECT_EQ(plain->status, today->status);
  }
  unsetenv("LINKSCAPE_FIELD_KERNEL");
}

TEST(DeltaStops, PresetStatesTheDescribedDeltasCones) {
  EXPECT_EQ(stated_stops(load_preset("delta")), (StopChecks{true, false}));
  const Model m = make_delta_model(delta_preset(true));
  EXPECT_NEAR(m.elbow_axis, 104 * kDeg, 1e-15);
  EXPECT_NEAR(m.elbow_cone, 60 * kDeg, 1e-15);
  EXPECT_NEAR(m.wrist_axis, 49 * kDeg, 1e-15);
  EXPECT_NEAR(m.wrist_cone, 45 * kDeg, 1e-15);
  EXPECT_FALSE(make_delta_model(delta_preset(false)).has_cones());
  const auto refused = [](const std::string& stops, const std::string& words) {
    try {
      parse_preset(R"({"mechanism": "delta", "parameters": {}, "stops": )" + stops + "}", "test");
      ADD_FAILURE() << stops;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused(R"({"link_radius": 1})", "unknown key 'stops.link_radius'");
  refused(R"({"elbow_cone_deg": 0})", "stops.elbow_cone_deg must be in (0, 180) deg, got 0");
  refused(R"({"wrist_axis_deg": "down"})", "stops.wrist_axis_deg");
}

TEST(DeltaStops, VerifySaysItsConesAreNotCovered) {
  const Preset on = delta_preset(true);
  task::TaskVolume task = task::parse_task("box:size=2,2,2");
  task.centre = Vector3d(linkscape::make_mechanism(on)->home_task());
  verify::Options o;
  o.time_limit_seconds = 20;
  const verify::Result r = verify::verify(on, task, {task::parse_criterion("reach")}, o);
  EXPECT_EQ(r.not_covered, "its passive-joint limits");
  std::ostringstream report;
  verify::write_report(report, r);
  EXPECT_NE(report.str().find("not covered: its passive-joint limits"), std::string::npos);
  EXPECT_TRUE(verify::verify(delta_preset(false), task, {task::parse_criterion("reach")}, o).not_covered.empty());
}

}  // namespace
}  // namespace linkscape::delta
