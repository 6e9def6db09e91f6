// PATHOS-II's stops (core/mechanisms/pathos2/stops.h): the globular cone and
// the link capsules the preset assumes, in IK, FK, fields, the switches and
// the preset reader.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <string>

#include "core/field_sampling.h"
#include "core/mechanism.h"
#include "core/mechanisms/pathos2/design.h"
#include "core/mechanisms/pathos2/field.h"
#include "core/mechanisms/pathos2/mechanism.h"
#include "core/mechanisms/pathos2/stops.h"
#include "core/preset.h"

namespace linkscape::pathos2 {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;
constexpr double kDeg = std::numbers::pi / 180.0;

Preset preset_with(bool joint_limits, bool interference) {
  Preset p = load_preset("pathos2");
  p.checks = {joint_limits, interference};
  return p;
}

VectorXd task(double x, double y, double z, double rx, double ry, double rz, double h0) {
  VectorXd t(7);
  t << x, y, z, rx, ry, rz, h0;
  return t;
}

// The angle between link 3 and its plate's normal, from the joint positions
// (independent of the IK's cosines).
double link3_angle_deg(const Geometry& g, const Pose& pose, int leg) {
  const Skeleton s = skeleton(g, pose, inverse(g, pose));
  const Vector3d link = (s.legs[leg].globular - s.legs[leg].r3).normalized();
  const Vector3d normal = pose.R_world_E * g.R_E_A[leg].col(2);
  return std::acos(std::clamp(link.dot(normal), -1.0, 1.0)) / kDeg;
}

// rx, ry of the poses below (rad): tilted this far, the preset's cones bind
// inside the linkage's reach.
constexpr double kTilt = -0.6, kTiltY = -0.4;

// The lowest pose at x = -1 and the tilt that takes a globular joint beyond
// the preset's cone while the linkage itself still closes.
VectorXd pose_beyond_the_cone() {
  const auto on = linkscape::make_mechanism(preset_with(true, true));
  const auto off = linkscape::make_mechanism(preset_with(false, false));
  for (double z = 12; z < 33; z += 0.5) {
    const VectorXd x = task(-1, 0, z, kTilt, kTiltY, 30 * kDeg, 7);
    if (on->inverse(x, {}).status == Status::OutOfLimits && off->inverse(x, {}).status == Status::Ok) return x;
  }
  return {};
}

TEST(Pathos2Stops, PoseBeyondTheConeIsOutOfLimitsNamingTheJoint) {
  const auto on = linkscape::make_mechanism(preset_with(true, true));
  const auto off = linkscape::make_mechanism(preset_with(false, true));
  const VectorXd x = pose_beyond_the_cone();
  ASSERT_EQ(x.size(), 7);
  const linkscape::IkResult r = on->inverse(x, {});
  ASSERT_EQ(r.status, Status::OutOfLimits);
  // The leg with the largest excess, measured from the skeleton.
  const Model m = make_pathos2(preset_with(true, true));
  const Geometry g = make_geometry(m);
  const Pose pose = Pose::from_xyz_rpy(x(0), x(1), x(2), x(3), x(4), x(5), x(6));
  int worst = 0;
  for (int leg = 1; leg < kLegCount; ++leg)
    if (link3_angle_deg(g, pose, leg) > link3_angle_deg(g, pose, worst)) worst = leg;
  EXPECT_EQ(r.failing_part, std::to_string(worst + 1));
  EXPECT_GT(link3_angle_deg(g, pose, worst), m.cone_limit / kDeg);
  char expected[96];
  std::snprintf(expected, sizeof expected, "out-of-limits: leg %d globular joint at %.1f deg beyond its %.1f deg cone",
                worst + 1, link3_angle_deg(g, pose, worst), m.cone_limit / kDeg);
  EXPECT_EQ(r.status_text, expected);
  EXPECT_TRUE(r.solutions.empty());
  // Without the joint limits the same pose solves.
  EXPECT_EQ(off->inverse(x, {}).status, Status::Ok);
}

// A pose that a leg cannot close is unreachable, naming that leg, though
// an earlier leg's globular joint lies beyond its cone: the most severe leg
// decides, in IK and in the field (SIMD kernel) alike.
TEST(Pathos2Stops, ALegThatCannotCloseOutranksAConeAnotherLegExceeds) {
  const auto on = linkscape::make_mechanism(preset_with(true, true));
  const auto off = linkscape::make_mechanism(preset_with(false, false));
  const VectorXd x = task(2.8014905594027457, -2.775921310550774, 17.630142137623885, -0.22690461925011063,
                          -0.030311746045453558, 0.5650717203516837, 6.530792824547183);
  const linkscape::IkResult without = off->inverse(x, {});
  ASSERT_EQ(without.status, Status::Unreachable);
  ASSERT_EQ(without.failing_part, "6");
  // Leg by leg: leg 1 beyond its cone, leg 6 not closing.
  const Model m = make_pathos2(preset_with(true, true));
  const PoseIkResult legs = inverse(make_geometry(m), Pose::from_xyz_rpy(x(0), x(1), x(2), x(3), x(4), x(5), x(6)));
  ASSERT_EQ(legs.legs[0].status, Status::OutOfLimits);
  ASSERT_EQ(legs.legs[5].status, Status::Unreachable);
  const linkscape::IkResult r = on->inverse(x, {});
  EXPECT_EQ(r.status, Status::Unreachable);
  EXPECT_EQ(r.failing_part, "6");
  const Vector3d p = x.head<3>(), h(1e-3, 1e-3, 1e-3);
  const auto field = on->compute_field(Grid::box(p - h, p + h, {1, 1, 1}), x, {}, 0, {});
  ASSERT_TRUE(field);
  EXPECT_EQ(int(field->status.at(0)), int(Status::Unreachable));
}

// The smallest distance between two segments by sampling both, refined
// around the best pair: independent of the closed form.
double brute_distance(const interference::Capsule& p, const interference::Capsule& q) {
  const int n = 200;
  double best = INFINITY, bs = 0, bt = 0;
  auto at = [](const interference::Capsule& c, double s) { return Vector3d(c.a + s * (c.b - c.a)); };
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double d = (at(p, double(i) / n) - at(q, double(j) / n)).norm();
      if (d < best) best = d, bs = double(i) / n, bt = double(j) / n;
    }
  for (double h = 1.0 / n; h > 1e-9; h /= 4) {
    const double s0 = bs, t0 = bt;
    for (int i = -8; i <= 8; ++i)
      for (int j = -8; j <= 8; ++j) {
        const double s = std::clamp(s0 + i * h / 4, 0.0, 1.0), t = std::clamp(t0 + j * h / 4, 0.0, 1.0);
        const double d = (at(p, s) - at(q, t)).norm();
        if (d < best) best = d, bs = s, bt = t;
      }
  }
  return best - p.radius - q.radius;
}

TEST(Pathos2Stops, ClearanceAgreesWithBruteForceSampling) {
  Model m = make_pathos2(preset_with(false, true));
  const Geometry g = make_geometry(m);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-3.0, 3.0), a(-0.25, 0.25);
  int checked = 0;
  for (int n = 0; n < 40 && checked < 3; ++n) {
    const Pose pose = Pose::from_xyz_rpy(d(rng), d(rng), 22.5 + d(rng), a(rng), a(rng), 30 * kDeg + a(rng), 7);
    const PoseIkResult ik = inverse(g, pose);
    if (ik.status != Status::Ok) continue;
    ++checked;
    const std::vector<interference::Capsule> caps = capsules(g, pose, ik);
    ASSERT_EQ(caps.size(), std::size_t(kGripCapsule + 1));
    // Every pair stops() documents, by brute force.
    double best = INFINITY;
    std::array<int, 2> pair{-1, -1};
    for (int p = 0; p <= kGripCapsule; ++p)
      for (int q = p + 1; q <= kGripCapsule; ++q) {
        const bool same_leg = q < kGripCapsule && p / 3 == q / 3;
        const bool both_r1 = q < kGripCapsule && p % 3 == 0 && q % 3 == 0;
        const bool link3_grip = q == kGripCapsule && p % 3 == 2;
        if (same_leg || both_r1 || link3_grip) continue;
        const double gap = brute_distance(caps[std::size_t(p)], caps[std::size_t(q)]);
        EXPECT_NEAR(interference::clearance(caps[std::size_t(p)], caps[std::size_t(q)]), gap, 1e-9) << p << " " << q;
        if (gap < best) best = gap, pair = {p, q};
      }
    const Stops st = stops(g, pose, ik);
    EXPECT_NEAR(st.clearance, best, 1e-9);
    EXPECT_EQ(st.pair, pair);
  }
  EXPECT_EQ(checked, 3);
}

// A pose the legs reach where two links overlap, found by a search with
// thick links (no joint limits).
TEST(Pathos2Stops, OverlappingLinksAreOutOfLimitsNamingThePair) {
  Preset preset = preset_with(false, true);
  preset.stops = R"({"link_radius": 1.5, "grip_radius": 3.0})";
  const auto mech = linkscape::make_mechanism(preset);
  const Geometry g = make_geometry(make_pathos2(preset));
  const auto plain = linkscape::make_mechanism(preset_with(false, false));
  int found = 0;
  for (double x = -6; x <= 6 && found < 3; x += 1.0)
    for (double z = 16; z <= 29 && found < 3; z += 1.0) {
      const VectorXd t = task(x, -2, z, kTilt, 0, 30 * kDeg, 7);
      if (plain->inverse(t, {}).status != Status::Ok) continue;
      const Pose pose = Pose::from_xyz_rpy(x, -2, z, kTilt, 0, 30 * kDeg, 7);
      const Stops st = stops(g, pose, inverse(g, pose));
      const linkscape::IkResult r = mech->inverse(t, {});
      if (st.clearance >= 0) {
        EXPECT_EQ(r.status, Status::Ok);
        continue;
      }
      ++found;
      EXPECT_EQ(r.status, Status::OutOfLimits);
      EXPECT_EQ(r.status_text, "out-of-limits: " + capsule_name(st.pair[0]) + " hits " + capsule_name(st.pair[1]) +
                                   " (overlap " + [&] {
                                     char v[32];
                                     std::snprintf(v, sizeof v, "%.3g", -st.clearance);
                                     return std::string(v);
                                   }() + " cm)");
      EXPECT_EQ(r.failing_part, std::to_string(st.leg_at_fault() + 1));
      EXPECT_LT(mech->reach_margin(t, 0), 0.0);
      // The design study's test of a pose agrees.
      EXPECT_FALSE(pose_inside(g, pose));
    }
  EXPECT_GT(found, 0);
}

TEST(Pathos2Stops, ForwardKinematicsReportsAPoseBeyondAStop) {
  const auto on = linkscape::make_mechanism(preset_with(true, true));
  const auto off = linkscape::make_mechanism(preset_with(false, false));
  const VectorXd beyond = pose_beyond_the_cone();
  ASSERT_EQ(beyond.size(), 7);
  const linkscape::IkResult ik = off->inverse(beyond, {});
  ASSERT_EQ(ik.status, Status::Ok);
  linkscape::FkOptions o;
  o.seed = beyond + task(0.2, -0.2, 0.3, 0.02, 0.02, 0, 0);
  const linkscape::FkResult plain = off->forward(ik.solutions[0].q, o), stopped = on->forward(ik.solutions[0].q, o);
  ASSERT_EQ(plain.status, Status::Ok);
  EXPECT_EQ(stopped.status, Status::OutOfLimits);
  EXPECT_LT((stopped.x - beyond).norm(), 1e-8);  // the pose is still found
  // Inside the cone FK stays ok.
  const linkscape::IkResult home = on->inverse(on->home_task(), {});
  ASSERT_EQ(home.status, Status::Ok);
  EXPECT_EQ(on->forward(home.solutions[0].q, {}).status, Status::Ok);
}

// A field over the home slice: each sample's joint_margin and clearance are
// the pose's own stops, its status the mechanism's IK status.
void expect_field_matches_poses(const Preset& preset, FieldKernel kernel, double rx, double ry) {
  const Model m = make_pathos2(preset);
  const Geometry g = make_geometry(m);
  FieldRequest req;
  req.grid.dims = {15, 15, 5};
  req.grid.origin = Vector3d(-7, -7, 15);
  req.grid.spacing = Vector3d(1, 1, 3);
  req.rpy = Vector3d(rx, ry, 30 * kDeg);
  req.threads = 1;
  req.kernel = kernel;
  const auto f = compute_field(m, req);
  ASSERT_TRUE(f);
  const Field::NamedArray* margin = f->extra("joint_margin");
  const Field::NamedArray* clearance = f->extra("clearance");
  ASSERT_EQ(margin != nullptr, has_joint_limits(m));
  ASSERT_TRUE(clearance);
  const auto mech = linkscape::make_mechanism(preset);
  int ok = 0, cone = 0, hit = 0;
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 15; ++j)
      for (int i = 0; i < 15; ++i) {
        const std::size_t n = f->grid.index(i, j, k);
        const Vector3d p = f->grid.point(i, j, k);
        const Pose pose = Pose::from_xyz_rpy(p.x(), p.y(), p.z(), rx, ry, 30 * kDeg, 7);
        const PoseIkResult ik = inverse(g, pose);
        const bool closes = std::none_of(ik.legs.begin(), ik.legs.end(),
                                         [](const LegSolution& l) { return l.status == Status::Unreachable; });
        if (!closes) {
          EXPECT_TRUE(std::isnan(clearance->values[n])) << n;
          if (margin) EXPECT_TRUE(std::isnan(margin->values[n])) << n;
          continue;
        }
        const Stops st = stops(g, pose, ik);
        if (margin) EXPECT_NEAR(margin->values[n], st.joint_margin_deg, 1e-9 * 180 + 1e-5 * std::abs(st.joint_margin_deg)) << n;
        EXPECT_NEAR(clearance->values[n], st.clearance, 1e-5 * std::max(1.0, std::abs(st.clearance))) << n;
        const linkscape::IkResult r = mech->inverse(task(p.x(), p.y(), p.z(), rx, ry, 30 * kDeg, 7), {});
        if (r.status == Status::OutOfLimits) {
          EXPECT_EQ(f->status[n], std::uint8_t(Status::OutOfLimits)) << n;
          EXPECT_FALSE(f->reachable[n]);
          EXPECT_LT(f->reach_margin[n], 0.0f) << n;
          (st.joint_margin_deg < 0 ? cone : hit) += 1;
        } else if (f->status[n] == std::uint8_t(Status::Ok)) {
          EXPECT_EQ(r.status, Status::Ok);
          EXPECT_GE(f->reach_margin[n], 0.0f);
          ++ok;
        }
      }
  EXPECT_GT(ok, 10);
  EXPECT_GT(has_joint_limits(m) ? cone : hit, 2);
}

TEST(Pathos2Stops, FieldArraysAreEachPosesStops) {
  for (FieldKernel kernel : {FieldKernel::Scalar, FieldKernel::Vector}) {
    SCOPED_TRACE(kernel == FieldKernel::Scalar ? "scalar" : "vector");
    expect_field_matches_poses(preset_with(true, true), kernel, kTilt, kTiltY);
    // Thick links and no cone: out-of-limits by interference alone.
    Preset thick = preset_with(false, true);
    thick.stops = R"({"link_radius": 1.5, "grip_radius": 3.0})";
    expect_field_matches_poses(thick, kernel, kTilt, 0.0);
  }
}

TEST(Pathos2Stops, SwitchesRestoreTheFieldWithoutStops) {
  const Preset off = preset_with(false, false);
  // The same model as the paper's, without a stop.
  const Model m = make_pathos2(off);
  EXPECT_FALSE(has_joint_limits(m));
  EXPECT_FALSE(has_capsules(m));
  const auto mech = linkscape::make_mechanism(off);
  EXPECT_TRUE(mech->info().extra_fields.empty());
  EXPECT_FALSE(mech->link_capsules(mech->home_actuators(), mech->home_task()));
  Grid grid;
  grid.dims = {12, 12, 12};
  grid.origin = Vector3d(-7, -7, 15.5);
  grid.spacing = Vector3d::Constant(1.25);
  const auto plain = pathos2::make_mechanism(Model::from_parameters(off.parameters))->compute_field(grid, mech->home_task(), {}, 1, {});
  const auto switched = mech->compute_field(grid, mech->home_task(), {}, 1, {});
  ASSERT_TRUE(plain && switched);
  EXPECT_TRUE(switched->extras.empty());
  const auto same = [](const auto& a, const auto& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0;
  };
  EXPECT_TRUE(same(plain->status, switched->status));
  EXPECT_TRUE(same(plain->cond, switched->cond));
  EXPECT_TRUE(same(plain->cond_orientation, switched->cond_orientation));
  EXPECT_TRUE(same(plain->reach_margin, switched->reach_margin));
  EXPECT_TRUE(same(plain->residual, switched->residual));
  // With the stops on, fewer samples are ok, and the device states both kinds.
  const auto on = linkscape::make_mechanism(preset_with(true, true))->compute_field(grid, mech->home_task(), {}, 1, {});
  ASSERT_TRUE(on);
  EXPECT_EQ(on->extras.size(), 2u);
  std::size_t ok_on = 0, ok_off = 0;
  for (std::size_t n = 0; n < grid.size(); ++n) ok_on += on->reachable[n], ok_off += switched->reachable[n];
  EXPECT_LT(ok_on, ok_off);
  EXPECT_EQ(stated_stops(off), (StopChecks{true, true}));
  // Each switch alone.
  EXPECT_EQ(linkscape::make_mechanism(preset_with(true, false))->info().extra_fields.size(), 1u);
  EXPECT_EQ(linkscape::make_mechanism(preset_with(false, true))->info().extra_fields.size(), 1u);
}

TEST(Pathos2Stops, LinkCapsulesNameTheClosestPair) {
  const auto mech = linkscape::make_mechanism(preset_with(true, true));
  const auto caps = mech->link_capsules(mech->home_actuators(), mech->home_task());
  ASSERT_TRUE(caps);
  ASSERT_EQ(caps->links.size(), std::size_t(kGripCapsule + 1));
  EXPECT_EQ(caps->links[5].name, "leg 2 link 3");
  EXPECT_EQ(caps->links[kGripCapsule].name, "grip");
  ASSERT_TRUE(caps->has_pair());
  const Model m = make_pathos2(preset_with(true, true));
  const Geometry g = make_geometry(m);
  const Pose home = home_pose(m);
  const Stops st = stops(g, home, inverse(g, home));
  EXPECT_EQ(caps->closest, st.pair);
  EXPECT_DOUBLE_EQ(caps->clearance, st.clearance);
  EXPECT_THROW(mech->link_capsules(mech->home_actuators(), task(0, 0, 80, 0, 0, 0, 7)), std::invalid_argument);
}

// The Table 2 study under the stops: a movable range ends where a stop is
// hit, and a design whose Table 1 pose overlaps is not evaluated.
TEST(Pathos2Stops, DesignRangesEndAtTheStops) {
  // A long-legged design, a 105 deg cone, 1 cm links.
  Model m = make_pathos2(preset_with(true, true));
  m.l0 = table1_model().l0;
  m.l2 = 20, m.l3 = 12, m.lp = 2;
  m.cone_limit = 105 * kDeg;
  m.link_radius = 1.0;
  const Geometry g = make_geometry(m);
  Model plain_model = m;
  plain_model.cone_limit = std::numbers::pi;
  plain_model.link_radius = plain_model.grip_radius = 0;
  const Geometry plain = make_geometry(plain_model);
  const Pose start = table1_pose(m, 30 * kDeg);
  RangeOptions o;
  const MovableRanges stopped = movable_ranges(g, start, o, true), free = movable_ranges(plain, start, o, true);
  ASSERT_EQ(stopped.start_status, Status::Ok);
  int shorter = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      const double reach = sign < 0 ? stopped.minus[axis] : stopped.plus[axis];
      const double linkage = sign < 0 ? free.minus[axis] : free.plus[axis];
      EXPECT_LE(reach, linkage + o.tolerance_cm);
      if (reach >= linkage - o.tolerance_cm) continue;
      ++shorter;
      // Just beyond the end the linkage closes, and a stop does not hold.
      Pose beyond = start;
      beyond.p_world_E[axis] += sign * (reach + 2 * o.tolerance_cm);
      EXPECT_TRUE(pose_inside(plain, beyond));
      const Stops st = stops(g, beyond, inverse(g, beyond));
      EXPECT_FALSE(st.hold()) << axis;
    }
  EXPECT_GT(shorter, 0);
  // lp = 0: the link-3 ends of a plate meet, so the Table 1 pose overlaps.
  DesignGrid grid{{14, 14, 1}, {6, 6, 1}, {0, 2, 2}, {30, 30, 15}};  // l2, l3 as the paper's; lp 0 and 2
  const DesignSearchResult r = design_search(m, grid);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[0].outcome, DesignOutcome::StartInfeasible);
  EXPECT_EQ(r.rows[1].outcome, DesignOutcome::Evaluated);
}

TEST(Pathos2Stops, PresetStopsBlockIsChecked) {
  Preset p = load_preset("pathos2");
  const auto refused = [&](const std::string& stops, const std::string& words) {
    const std::string text = R"({"mechanism": "pathos2", "length_unit": "cm",
        "parameters": {"l0": 45, "lb": 10, "l1": 7, "l2": 14, "l3": 6, "lp": 2, "h0": 7, "theta_t": 30},
        "stops": )" + stops + "}";
    try {
      parse_preset(text, "test");
      ADD_FAILURE() << stops;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  refused(R"({"cone": 60})", "unknown key 'stops.cone'");
  refused(R"({"globular_cone_deg": 200})", "stops.globular_cone_deg must be in (0, 180) deg, got 200");
  refused(R"({"link_radius": -1})", "stops.link_radius must be a positive length");
  refused(R"({"link_radius": "thick"})", "stops.link_radius");
  refused(R"({"grip_radius": 2})", "stops.grip_radius needs stops.link_radius");
  refused("[1]", "stops must be an object");
  EXPECT_THROW(parse_preset(R"({"mechanism": "parallel-12r", "parameters": {}, "stops": {}})", "t"), std::invalid_argument);
  // A cone_limit parameter replaces the stated cone.
  apply_overrides(p, {"cone_limit=120"});
  EXPECT_NEAR(make_pathos2(p).cone_limit, 120 * kDeg, 1e-15);
}

}  // namespace
}  // namespace linkscape::pathos2
