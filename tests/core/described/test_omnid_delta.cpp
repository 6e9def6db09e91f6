// The Omnid's Delta arm of assets/mechanisms/omnid-delta.json against the
// closed form of its own firmware (github.com/omnid/nuhal, delta_robot.c),
// written here in long double from the published geometry alone (none of it
// calls the solver):
//
//   arm k's joint axis at B_k = R (cos 120k, sin 120k, 0), horizontal and
//   square to the radius; its knee K_k = B_k + La (cos t u_k + sin t z), u_k
//   the radial unit vector, t from the horizontal outward and up; platform
//   joint P_k = p + r u_k; the tube |P_k - K_k| = Lb.
//   IK: E cos t + F sin t + G = 0 by the tangent half-angle s = tan(t/2):
//       s = (-F +- sqrt(E^2 + F^2 - G^2)) / (G - E), with (in the arm's
//       frame: a along u_k, b along it turned 90 deg, z) E = 2 La (R - r - a),
//       F = -2 La z, G = La^2 - Lb^2 + (R - r)^2 - 2 (R - r) a + |p|^2;
//       the firmware's outward knee: the + root where
//       (r - R + a) sin t+ < z cos t+, else the - root.
//   J:  f_k = P_k - K_k; f_k . pdot = f_k . dK_k/dt tdot: Jx = [f_k^T],
//       Jq = diag(f_k . La (-sin t u_k + cos t z)), J = Jx^-1 Jq.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <optional>
#include <random>

#include "described_devices_support.h"

using namespace linkscape;
using namespace linkscape::described_test;
namespace {

using Real = long double;
using Vector3r = Eigen::Matrix<Real, 3, 1>;
using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr Real kPi = 3.141592653589793238462643383279502884L;

struct OmnidDelta {
  Real R = 0, r = 0, La = 0, Lb = 0, lo = 0, hi = 0;  // mm, rad

  static OmnidDelta from_file() {
    const auto j = read_asset("omnid-delta.json");
    const auto& p = j.at("parameters");
    const auto& travel = j.at("actuator_limits_deg").at("q1");
    return {p.at("R").get<Real>(),        p.at("r").get<Real>(),          p.at("La").get<Real>(),
            p.at("Lb").get<Real>(),       travel.at(0).get<Real>() * kPi / 180, travel.at(1).get<Real>() * kPi / 180};
  }
  static Vector3r radial(int k) {
    return {std::cos(Real(120 * k) * kPi / 180), std::sin(Real(120 * k) * kPi / 180), 0};
  }
  // The arm angles, or none where an arm cannot reach.
  std::optional<Vector3r> ik(const Vector3d& target) const {
    const Vector3r p = target.cast<Real>();
    Vector3r t;
    for (int k = 0; k < 3; ++k) {
      const Real a = p.dot(radial(k)), z = p.z();
      const Real E = 2 * La * (R - r - a), F = -2 * La * z;
      const Real G = La * La - Lb * Lb + (R - r) * (R - r) - 2 * (R - r) * a + p.squaredNorm();
      const Real disc = E * E + F * F - G * G;
      if (disc < 0) return std::nullopt;
      const Real plus = 2 * std::atan((-F + std::sqrt(disc)) / (G - E));
      const Real minus = 2 * std::atan((-F - std::sqrt(disc)) / (G - E));
      t(k) = (r - R + a) * std::sin(plus) < z * std::cos(plus) ? plus : minus;
    }
    return t;
  }
  Vector3r knee(int k, Real t) const { return R * radial(k) + La * (std::cos(t) * radial(k) + std::sin(t) * Vector3r::UnitZ()); }
  Matrix3d jacobian(const Vector3d& target, const Vector3r& t) const {
    Eigen::Matrix<Real, 3, 3> Jx, Jq = Eigen::Matrix<Real, 3, 3>::Zero();
    for (int k = 0; k < 3; ++k) {
      const Vector3r f = target.cast<Real>() + r * radial(k) - knee(k, t(k));
      Jx.row(k) = f.transpose();
      Jq(k, k) = f.dot(La * (-std::sin(t(k)) * radial(k) + std::cos(t(k)) * Vector3r::UnitZ()));
    }
    return (Jx.inverse() * Jq).cast<double>();
  }
  bool in_travel(const Vector3r& t) const { return (t.array() >= lo).all() && (t.array() <= hi).all(); }
};

TEST(OmnidDeltaDevice, TheFileStatesTheFirmwaresGeometryAndTravel) {
  const OmnidDelta g = OmnidDelta::from_file();
  // nuhal, include/common/parameters.cmake and parameters.h.in at 8c4392f (m, deg).
  EXPECT_EQ(g.R, Real(180));
  EXPECT_EQ(g.r, Real(62));
  EXPECT_EQ(g.La, Real(200));
  EXPECT_EQ(g.Lb, Real(368));
  EXPECT_EQ(g.lo, Real(0));
  EXPECT_NEAR(double(g.hi), 80 * std::numbers::pi / 180, 1e-15);
}

TEST(OmnidDeltaDevice, InverseKinematicsStatusesAndJacobianMatchTheFirmwaresClosedForm) {
  const OmnidDelta g = OmnidDelta::from_file();
  const auto m = load_device("omnid-delta.json");
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> across(-300, 300), height(0, 600);
  Verdicts v;
  Real worst_q = 0;
  double worst_j = 0;
  for (int i = 0; i < 6000; ++i) {
    const Vector3d p(across(rng), across(rng), height(rng));
    const std::optional<Vector3r> t = g.ik(p);
    const IkResult res = m->inverse(p);
    if (!v.check(res, t.has_value(), t && g.in_travel(*t), i)) continue;
    worst_q = std::max(worst_q, (res.solutions[0].q.cast<Real>() - *t).cwiseAbs().maxCoeff());
    const Matrix3d expected = g.jacobian(p, *t);
    worst_j = std::max(worst_j, (m->jacobian(res.solutions[0].q, p) - expected).norm() / expected.norm());
  }
  RecordProperty("worst_q_rad", scientific(double(worst_q)));
  RecordProperty("worst_J_relative", scientific(worst_j));
  EXPECT_GT(v.ok, 300);
  EXPECT_GT(v.out_of_limits, 1000);
  EXPECT_GT(v.unreachable, 1000);
  EXPECT_LE(worst_q, 1e-12L);
  EXPECT_LE(worst_j, 1e-9);
}

// The device with its links given the radii docs/mechanisms/omnid-delta.md
// assumes: the arms 15 mm, the tubes 10 mm.
std::shared_ptr<const Mechanism> with_link_radii() {
  Preset p = load_preset(asset_path("omnid-delta.json"));
  nlohmann::json d = nlohmann::json::parse(p.description);
  nlohmann::json& chain = d["legs"][0]["chain"];
  chain[1]["radius"] = 15;
  chain[1]["link"] = "arm#";
  chain[3]["radius"] = 10;
  chain[3]["link"] = "tube#";
  p.description = d.dump();
  return make_mechanism(p);
}

// The firmware's workspace limits (x, y within 100 mm of the base's centre,
// z from 200 to 450 mm: parameters.h.in) in cells of 5 mm, in both readings
// of its frame: the kinematics' (z = 0 at the arms' joint axes) and the base
// plate's (the axes 46.375 mm above it). Sample by sample as the closed form
// says, with the counts of docs/mechanisms/omnid-delta.md; with the links
// given radii, no cell changes.
struct BoxCounts {
  int cells = 0, reached = 0, in_travel = 0, mismatches = 0, blocked = 0;
};

BoxCounts count_box(const OmnidDelta& g, const Mechanism& m, const Mechanism& capsules, double z_floor) {
  BoxCounts n;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j)
      for (int k = 0; k < 50; ++k) {
        const Vector3d p(-97.5 + 5 * i, -97.5 + 5 * j, z_floor + 2.5 + 5 * k);
        const std::optional<Vector3r> t = g.ik(p);
        const Status expected = !t ? Status::Unreachable : g.in_travel(*t) ? Status::Ok : Status::OutOfLimits;
        const Status got = m.inverse(p).status;
        ++n.cells;
        n.reached += t.has_value();
        n.in_travel += got == Status::Ok;
        if (got != expected && ++n.mismatches <= 5) ADD_FAILURE() << "at " << p.transpose() << ": " << int(got);
        n.blocked += capsules.inverse(p).status != got;
      }
  return n;
}

TEST(OmnidDeltaDevice, TheFirmwaresWorkspaceBoxWithAndWithoutTheTravel) {
  const OmnidDelta g = OmnidDelta::from_file();
  const auto m = load_device("omnid-delta.json");
  const auto capsules = with_link_radii();
  ASSERT_FALSE(capsules->info().extra_fields.empty());  // its clearance field: the capsules are checked
  const BoxCounts axes = count_box(g, *m, *capsules, 200);
  EXPECT_EQ(axes.mismatches, 0);
  EXPECT_EQ(axes.cells, 80000);
  EXPECT_EQ(axes.reached, 80000);
  EXPECT_EQ(axes.in_travel, 60910);
  EXPECT_EQ(axes.blocked, 0);
  const BoxCounts plate = count_box(g, *m, *capsules, 200 - 46.375);
  EXPECT_EQ(plate.mismatches, 0);
  EXPECT_EQ(plate.reached, 78738);
  EXPECT_EQ(plate.in_travel, 46212);
  EXPECT_EQ(plate.blocked, 0);
}

// Far from home, forward kinematics walks the actuators there in steps; a
// step that converged slowly (the rods' idle spin) had been called
// singular and returned as the answer, a pose for other actuators. Each
// answer is the pose whose IK gives q back.
TEST(OmnidDeltaDevice, ForwardKinematicsFarFromHomeAnswersForTheActuatorsAsked) {
  const auto m = load_device("omnid-delta.json");
  std::mt19937_64 rng(7);
  std::vector<Eigen::VectorXd> targets = {(Eigen::VectorXd(3) << 0.7755431616088554, 1.0950509542314932, 0.14815669566823902).finished()};
  for (int i = 0; i < 40; ++i) {
    Eigen::VectorXd q(3);
    for (int k = 0; k < 3; ++k) {
      const Range r = m->info().actuators[std::size_t(k)].range;
      q(k) = std::uniform_real_distribution<double>(r.lo, r.hi)(rng);
    }
    targets.push_back(q);
  }
  int ok = 0;
  for (const Eigen::VectorXd& q : targets) {
    const FkResult fk = m->forward(q);
    EXPECT_NE(fk.status, Status::Singular) << q.transpose();
    if (fk.status != Status::Ok) continue;
    ++ok;
    IkOptions near;
    near.seed = q;
    double closest = INFINITY;
    for (const IkSolution& s : m->inverse(fk.x, near).solutions) closest = std::min(closest, (s.q - q).cwiseAbs().maxCoeff());
    EXPECT_LT(closest, 1e-9) << q.transpose();
  }
  EXPECT_GT(ok, 30);
}

}  // namespace
