// A leg of no known pattern closes its anchor at a few isolated assemblies;
// the numerical solver's seeds may find one outside the actuator's travel
// while another lies within it. An arm with offset elbows (revolute
// actuator, crank, two passive revolutes a short link apart, rod, ball) has
// every assembly on a line of actuator angles, found here by a scan of one
// equation in the actuator angle, independently of the solver.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>

#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/preset.h"

namespace linkscape::described {
namespace {

using Eigen::Vector3d;

constexpr double kR = 9.5, kr = 5.0, kLa = 8.0, ke = 2.0, kLb = 15.0;  // cm
constexpr double kLo = -60, kHi = 90;                                     // travel, degrees

const char* kOffsetElbowArm = R"({
  "space": "spatial", "task": ["x", "y", "z"], "home": {"x": 0, "y": 0, "z": "-0.8*Lb"}, "size": "La + e + Lb",
  "legs": [{ "name": "#", "copies": 3,
    "base": [{"rz": "k*120*deg"}, {"translate": ["R", 0, 0]}],
    "chain": [
      {"joint": "revolute", "name": "q#", "axis": [0, 1, 0], "actuated": true},
      {"translate": ["La", 0, 0]},
      {"joint": "revolute", "name": "ea#", "axis": [0, 1, 0]},
      {"translate": ["e", 0, 0]},
      {"joint": "revolute", "name": "eb#", "axis": [0, 0, 1]},
      {"translate": ["Lb", 0, 0]},
      {"joint": "spherical", "name": "w#"}],
    "anchor": [{"rz": "k*120*deg"}, {"translate": ["r", 0, 0]}],
    "branch": {"triple": ["q#", "ea#", "anchor"]}}]})";

Kinematics offset_elbow_arm() {
  Preset p;
  p.mechanism = kMechanismName;
  p.length_unit = "cm";
  p.parameters = {{"R", kR}, {"r", kr}, {"La", kLa}, {"e", ke}, {"Lb", kLb}};
  for (const char* q : {"q1", "q2", "q3"}) p.limits_deg[q] = {kLo, kHi};
  p.description = kOffsetElbowArm;
  return Kinematics(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
}

enum class Verdict { Within, None, Unclear };

// Leg k's assemblies on branch 0 within the travel, for the platform at p.
// In the leg's frame, with the elbow E = La (cos q, 0, -sin q) and d = a - E
// (a the anchor), the passive joints close when e + Lb cos(eb) = +-|d_xz| and
// Lb sin(eb) = d_y: f(q) = ((+-|d_xz| - e) / Lb)^2 + (d_y / Lb)^2 - 1 = 0.
// The branch is the sign of (E x d) . y. Unclear: a root at the travel's
// end, a tangent root or one on the branch's boundary.
Verdict leg_within_travel(int k, const Vector3d& p) {
  const double turn = k * 2 * M_PI / 3;
  const Eigen::Matrix3d to_leg = Eigen::AngleAxisd(-turn, Vector3d::UnitZ()).toRotationMatrix();
  const Vector3d a = to_leg * p + Vector3d(kr - kR, 0, 0);
  constexpr int kScan = 6000;
  bool unclear = false;
  for (const double side : {1.0, -1.0}) {
    double f0 = 0;
    for (int i = 0; i <= kScan; ++i) {
      const double q = (kLo + (kHi - kLo) * i / kScan) * M_PI / 180;
      const Vector3d d = a - kLa * Vector3d(std::cos(q), 0, -std::sin(q));
      const double f = std::pow((side * std::hypot(d.x(), d.z()) - ke) / kLb, 2) + std::pow(d.y() / kLb, 2) - 1;
      if (i > 0 && (f0 < 0) != (f < 0)) {
        const double triple = -kLa * std::sin(q) * d.x() - kLa * std::cos(q) * d.z();
        const bool clear = std::abs(f - f0) > 1e-6 && std::abs(triple) > 1e-2 * kLb * kLb && i > 20 &&
                           i < kScan - 20;
        if (clear && triple > 0) return Verdict::Within;
        unclear = unclear || !clear;
      }
      f0 = f;
    }
  }
  return unclear ? Verdict::Unclear : Verdict::None;
}

TEST(DescribedTravelSearch, AnArmWithOffsetElbowsIsOkWhereverEveryLegHasAnAssemblyWithinItsTravel) {
  const Kinematics arm = offset_elbow_arm();
  ASSERT_EQ(arm.closed_form_count(), 0) << "the arm's legs are solved numerically";
  int within = 0, decided = 0;
  constexpr int kGrid = 40;
  for (const double y : {0.0, 4.0})  // the plane of leg 1, and one off every leg's
    for (int i = 0; i < kGrid; ++i)
      for (int j = 0; j < kGrid; ++j) {
        const Vector3d p(-20 + 40.0 * (i + 0.5) / kGrid, y, -35 + 30.0 * (j + 0.5) / kGrid);
        Verdict all = Verdict::Within;
        for (int k = 0; k < 3 && all == Verdict::Within; ++k) all = leg_within_travel(k, p);
        if (all == Verdict::Unclear) continue;
        ++decided;
        const PoseSolution s = arm.inverse(p, 0, 1e-10);
        if (all == Verdict::Within) {
          ++within;
          EXPECT_EQ(s.status, Status::Ok) << "every leg has an assembly within its travel at " << p.transpose();
        } else {
          EXPECT_NE(s.status, Status::Ok) << "a leg has none within its travel at " << p.transpose();
        }
      }
  std::cout << within << " of " << decided << " decided samples within the travel\n";
  // The grid crosses the reachable region and its surroundings.
  EXPECT_GT(within, 200);
  EXPECT_GT(decided - within, 200);
}

}  // namespace
}  // namespace linkscape::described
