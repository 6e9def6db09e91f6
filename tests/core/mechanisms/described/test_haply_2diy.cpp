// The Haply 2DIY of assets/mechanisms/haply-2diy.json, solved by the generic
// solver for described devices, against the five-bar written here from the
// published geometry alone (Haply's hAPI, hardware version 3: arms l, distal
// links L, motor shafts d apart; docs/mechanisms/haply-2diy.md), in long double:
//
//   motor 1 at A = (0, 0), motor 2 at B = (d, 0); for the handle p and a
//   motor at M, rho = |p - M|, cos(alpha) = (l^2 + rho^2 - L^2) / (2 l rho);
//   q1 = atan2(p - A) + alpha, q2 = atan2(p - B) - alpha (both elbows out).
//   Forward: the elbows E_i = M_i + l (cos q_i, sin q_i); p is the apex, on
//   the left of E1 -> E2, of the isosceles triangle with sides L over E1 E2.
//
// The stops are the file's (assumed): travel 12..168 deg, the elbows 10 deg
// from straight and from folded, the arms capsules of radius 6 mm.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "core/field.h"
#include "core/mechanisms/described/mechanism.h"
#include "tests/core/described/described_devices_support.h"

namespace linkscape {
namespace {

using described_test::angle_difference;
using described_test::read_asset;
using described_test::svd_condition;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using nlohmann::json;
using Real = long double;
constexpr Real kPi = std::numbers::pi_v<Real>;
constexpr Real kTravel[2] = {12, 168}, kArmRadius = 6;

struct Geometry {
  Real l, L, d;
};

// The file's design values (read by a JSON reader of its own), which the
// first test holds to the published ones.
Geometry read_geometry() {
  const json p = read_asset("haply-2diy.json")["parameters"];
  return {p["l"], p["L"], p["d"]};
}

struct Leg {
  Real q;          // motor angle from +x, rad
  Real elbow_deg;  // the distal link's turn from the arm, (-180, 180]
  Vector2d motor, elbow;
};

// Both legs for the handle at (x, y), or nothing where one cannot reach.
std::optional<std::array<Leg, 2>> by_hand(const Geometry& g, Real x, Real y) {
  std::array<Leg, 2> legs;
  for (int i = 0; i < 2; ++i) {
    const Real mx = i == 0 ? 0 : g.d, side = i == 0 ? 1 : -1;
    const Real rho = std::hypot(x - mx, y);
    const Real c = (g.l * g.l + rho * rho - g.L * g.L) / (2 * g.l * rho);
    if (!(std::abs(c) <= 1)) return std::nullopt;
    Leg& leg = legs[std::size_t(i)];
    leg.q = std::atan2(y, x - mx) + side * std::acos(c);
    const Real ex = mx + g.l * std::cos(leg.q), ey = g.l * std::sin(leg.q);
    leg.elbow_deg = std::remainder(std::atan2(y - ey, x - ex) - leg.q, 2 * kPi) * 180 / kPi;
    leg.motor = Vector2d(double(mx), 0);
    leg.elbow = Vector2d(double(ex), double(ey));
  }
  return legs;
}

// The handle for motor angles q (the assembly the file's home is on).
Vector2d forward_by_hand(const Geometry& g, Real q1, Real q2) {
  const Real e1x = g.l * std::cos(q1), e1y = g.l * std::sin(q1);
  const Real e2x = g.d + g.l * std::cos(q2), e2y = g.l * std::sin(q2);
  const Real hx = e2x - e1x, hy = e2y - e1y, m = std::hypot(hx, hy);
  const Real up = std::sqrt(g.L * g.L - m * m / 4) / m;
  return Vector2d(double((e1x + e2x) / 2 - up * hy), double((e1y + e2y) / 2 + up * hx));
}

bool within_travel(const std::array<Leg, 2>& legs) {
  for (const Leg& leg : legs)
    if (const Real deg = std::remainder(leg.q, 2 * kPi) * 180 / kPi; deg < kTravel[0] || deg > kTravel[1]) return false;
  return true;
}

// The nearest elbow's distance to its stop (deg): left -170..-10, right 10..170.
Real elbow_margin(const std::array<Leg, 2>& legs) {
  const Real e1 = legs[0].elbow_deg, e2 = legs[1].elbow_deg;
  return std::min({e1 + 170, -10 - e1, e2 - 10, 170 - e2});
}

// The gap between the two arms' capsules, by the plane's segment distance.
double arms_clearance(const std::array<Leg, 2>& legs) {
  const auto point_to_segment = [](const Vector2d& p, const Vector2d& a, const Vector2d& b) {
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return (p - a - t * (b - a)).norm();
  };
  const auto turn = [](const Vector2d& a, const Vector2d& b, const Vector2d& c) {
    return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  };
  const Vector2d &a = legs[0].motor, &b = legs[0].elbow, &c = legs[1].motor, &e = legs[1].elbow;
  const bool cross = turn(a, b, c) * turn(a, b, e) < 0 && turn(c, e, a) * turn(c, e, b) < 0;
  const double gap = cross ? 0
                           : std::min({point_to_segment(a, c, e), point_to_segment(b, c, e),
                                       point_to_segment(c, a, b), point_to_segment(e, a, b)});
  return gap - 2 * double(kArmRadius);
}

// Which of the file's bounds a variant keeps.
struct Bounds {
  bool travel, elbows, arms;
};

// The shipped file with only `keep` of its bounds.
Preset variant(Bounds keep) {
  Preset p = load_preset("haply-2diy");
  if (!keep.travel) p.limits_deg.clear();
  json d = json::parse(p.description);
  for (json& leg : d["legs"])
    for (json& step : leg["chain"]) {
      if (!keep.elbows && !step.value("actuated", false)) step.erase("range_deg");
      if (!keep.arms) step.erase("radius"), step.erase("link");
    }
  p.description = d.dump();
  return p;
}

bool ok_by_hand(const std::optional<std::array<Leg, 2>>& legs, Bounds b) {
  return legs && (!b.travel || within_travel(*legs)) && (!b.elbows || elbow_margin(*legs) >= 0) &&
         (!b.arms || arms_clearance(*legs) >= 0);
}

class Haply2diy : public ::testing::Test {
 protected:
  Geometry g = read_geometry();
  std::shared_ptr<const Mechanism> m = make_mechanism(load_preset("haply-2diy"));
};

// hAPI's Pantograph, hardware version 3: l = 0.07 m, L = 0.09 m, d = 0.038 m.
TEST_F(Haply2diy, TheFileStatesThePublishedGeometry) {
  EXPECT_EQ(g.l, 70);
  EXPECT_EQ(g.L, 90);
  EXPECT_EQ(g.d, 38);
  EXPECT_EQ(load_preset("haply-2diy").length_unit, "mm");
}

// What `linkscape describe -m haply-2diy` prints of the legs and their bounds.
TEST_F(Haply2diy, DescribeListsTheLegsTravelStopsAndArms) {
  const std::string text = described::describe(load_preset("haply-2diy"));
  for (const char* line : {"space: planar, size 179 mm (d/2 + l + L)\n", "branches: 1\n", "  leg left: planar-dyad\n",
                           "    actuator q2 (revolute), travel 12 .. 168 deg\n",
                           "    reach: 20 .. 160 mm from its base to its anchor\n",
                           "    limit: joint elbow1: -170 .. -10 deg\n",
                           "    link: arm2, radius 6 mm, length 70 mm\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line << " in\n" << text;
}

TEST_F(Haply2diy, InverseKinematicsMatchesTheClosedFormAndItsStops) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(-80, 120), y(-30, 170);
  int ok = 0, beyond = 0, unreachable = 0;
  double worst = 0;
  for (int k = 0; k < 600; ++k) {
    const Vector3d p(x(rng), y(rng), 0);
    const auto legs = by_hand(g, p.x(), p.y());
    const IkResult r = m->inverse(p);
    if (!legs) {
      EXPECT_EQ(r.status, Status::Unreachable) << p.transpose();
      ++unreachable;
      continue;
    }
    const bool ok_here = ok_by_hand(legs, {true, true, true});
    EXPECT_EQ(r.status, ok_here ? Status::Ok : Status::OutOfLimits) << p.transpose();
    ok += ok_here;
    beyond += !ok_here;
    ASSERT_EQ(r.solutions.size(), 1u) << p.transpose();
    for (int i = 0; i < 2; ++i)
      worst = std::max(worst, std::abs(angle_difference(r.solutions[0].q[i], double((*legs)[std::size_t(i)].q))));
  }
  std::printf("Haply 2DIY IK: %d ok, %d beyond a stop, %d unreachable; worst difference %.1e rad\n", ok, beyond,
              unreachable, worst);
  EXPECT_GT(ok, 100);
  EXPECT_GT(beyond, 100);
  EXPECT_LT(worst, 1e-12);
}

// Motor angles of random handle positions within every stop, by hand.
std::vector<std::array<Leg, 2>> poses_within_stops(const Geometry& g, int tries) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> x(-60, 100), y(40, 150);
  std::vector<std::array<Leg, 2>> out;
  for (int k = 0; k < tries; ++k)
    if (const auto legs = by_hand(g, x(rng), y(rng)); ok_by_hand(legs, {true, true, true})) out.push_back(*legs);
  return out;
}

TEST_F(Haply2diy, ForwardKinematicsFromHomeReturnsTheHandle) {
  const auto poses = poses_within_stops(g, 200);
  ASSERT_GT(poses.size(), 60u);
  double worst = 0;
  for (const auto& [left, right] : poses) {
    const FkResult f = m->forward(VectorXd(Eigen::Vector2d(double(left.q), double(right.q))));
    ASSERT_EQ(f.status, Status::Ok);
    worst = std::max(worst, (f.x.head<2>() - forward_by_hand(g, left.q, right.q)).norm());
  }
  std::printf("Haply 2DIY FK from home: %zu poses, worst distance %.1e mm\n", poses.size(), worst);
  EXPECT_LT(worst, 1e-9);
}

TEST_F(Haply2diy, JacobianIsTheInverseOfTheClosedFormsDerivative) {
  const Vector3d p(-10.0, 110.0, 0);
  const IkResult r = m->inverse(p);
  ASSERT_EQ(r.status, Status::Ok);
  const VectorXd q = r.solutions.front().q;
  Eigen::Matrix2d dq_dx;
  const Real h = 1e-5L;
  for (int j = 0; j < 2; ++j) {
    const Real dx = j == 0 ? h : 0, dy = j == 1 ? h : 0;
    const auto plus = by_hand(g, p.x() + dx, p.y() + dy), minus = by_hand(g, p.x() - dx, p.y() - dy);
    for (int i = 0; i < 2; ++i)
      dq_dx(i, j) = double(((*plus)[std::size_t(i)].q - (*minus)[std::size_t(i)].q) / (2 * h));
  }
  const Eigen::MatrixXd J = m->jacobian(q, p);
  ASSERT_EQ(J.rows(), 2);
  EXPECT_LT((J * dq_dx - Eigen::Matrix2d::Identity()).norm(), 1e-8);
  const Measures measures = m->measures(q, p);
  EXPECT_EQ(measures.status, Status::Ok);
  EXPECT_NEAR(measures.values[0], svd_condition(J), 1e-9 * svd_condition(J));
}

// IK names the elbow beyond its stop and the arms that meet.
TEST_F(Haply2diy, IkNamesTheElbowAndTheArmsThatStopIt) {
  const auto stretched = by_hand(g, -63.5, 123.5);  // the right leg all but straight
  ASSERT_TRUE(stretched && within_travel(*stretched));
  ASSERT_LT(elbow_margin(*stretched), 0);
  const IkResult elbow = m->inverse(Vector3d(-63.5, 123.5, 0));
  EXPECT_EQ(elbow.status, Status::OutOfLimits);
  EXPECT_EQ(elbow.status_text,
            "out-of-limits: leg right joint elbow2 at 4.9 deg beyond its range 10.0 deg to 170.0 deg");

  const auto crossed = by_hand(g, -12.5, -23.5);  // below the motors, the arms across each other
  ASSERT_TRUE(crossed && within_travel(*crossed) && elbow_margin(*crossed) > 0);
  ASSERT_LT(arms_clearance(*crossed), 0);
  const IkResult arms = m->inverse(Vector3d(-12.5, -23.5, 0));
  EXPECT_EQ(arms.status, Status::OutOfLimits);
  EXPECT_NE(arms.status_text.find("out-of-limits: leg left arm1 hits leg right arm2"), std::string::npos)
      << arms.status_text;
}

// The reachable area (1 mm samples over the file's box, in the plane) as the
// bounds are added, sample by sample against the closed form, and the field's
// joint margin and clearance against it (docs/mechanisms/haply-2diy.md).
TEST_F(Haply2diy, WorkspaceWithAndWithoutItsStopsMatchesTheClosedForm) {
  const Grid grid = Grid::box({-160, -60, -1}, {200, 180, 1}, {360, 240, 1});
  const std::array<std::pair<Bounds, int>, 5> variants{{{{false, false, false}, 48108},
                                                        {{true, false, false}, 12200},
                                                        {{true, true, false}, 11694},
                                                        {{true, false, true}, 10496},
                                                        {{true, true, true}, 10214}}};
  for (const auto& [bounds, documented] : variants) {
    const auto device = make_mechanism(variant(bounds));
    const Field field = *device->compute_field(grid, device->home_task(), IkOptions{}, 2, {});
    int ok = 0, by_hand_ok = 0, mismatches = 0;
    double worst_margin = 0, worst_gap = 0;
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i) {
        const std::size_t at = grid.index(i, j, 0);
        const Vector3d p = grid.point(i, j, 0);
        const auto legs = by_hand(g, p.x(), p.y());
        const bool expected = ok_by_hand(legs, bounds), got = Status(field.status[at]) == Status::Ok;
        ok += got;
        by_hand_ok += expected;
        mismatches += expected != got;
        if (!bounds.elbows || !bounds.arms || !legs) continue;
        worst_margin = std::max(worst_margin, std::abs(field.extra("joint_margin")->values[at] -
                                                       double(elbow_margin(*legs))));
        worst_gap = std::max(worst_gap, std::abs(field.extra("clearance")->values[at] - arms_clearance(*legs)));
      }
    std::printf("bounds travel %d elbows %d arms %d: %d mm^2 ok, worst joint margin %.1e deg, clearance %.1e mm\n",
                bounds.travel, bounds.elbows, bounds.arms, ok, worst_margin, worst_gap);
    EXPECT_EQ(mismatches, 0);
    EXPECT_EQ(by_hand_ok, documented);
    EXPECT_EQ(ok, documented);
    if (bounds.elbows && bounds.arms) {
      EXPECT_LT(worst_margin, 1e-4);  // float storage of values up to 180 deg
      EXPECT_LT(worst_gap, 1e-4);
    }
  }
}

}  // namespace
}  // namespace linkscape
