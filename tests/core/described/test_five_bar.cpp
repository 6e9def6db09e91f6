// The planar five-bar of assets/mechanisms/five-bar.json, solved by the
// generic solver for described devices, against the five-bar's closed forms
// written here from the geometry alone (none of it calls the solver):
//
//   base joints A1 = (-d/2, 0), A2 = (d/2, 0); elbows E_i = A_i + a (cos q_i, sin q_i);
//   the end point P at distance b from both elbows.
//   IK: per leg, P on the circle of radius b about E_i: with D = |P - A_i|,
//       phi = atan2(P - A_i), g = acos((a^2 + D^2 - b^2) / (2 a D)),
//       q_i = phi +- g (left elbow out: +, right elbow out: -).
//   FK: the two intersections of the circles of radius b about E1 and E2.
//   J:  |P - E_i|^2 = b^2 differentiated: (P - E_i).dP - (P - E_i).(dE_i/dq_i) dq_i = 0,
//       so Jx = [(P - E_1)^T; (P - E_2)^T], Jq = diag(-(P - E_i).a(-sin q_i, cos q_i)),
//       J = dP/dq = -Jx^-1 Jq.
//   Reach: leg i reaches P iff |a - b| <= |P - A_i| <= a + b.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <random>

#include "core/haptics.h"
#include "described_devices_support.h"

using namespace linkscape;
using namespace linkscape::described_test;
using Eigen::Matrix2d;
using Eigen::Vector2d;
using Eigen::VectorXd;

namespace {

// The design as the file gives it, read without the preset loader.
struct FiveBar {
  double d = 0, a = 0, b = 0;
  std::array<Range, 2> limits{};  // rad

  static FiveBar from_file() {
    const auto j = read_asset("five-bar.json");
    FiveBar f;
    f.d = j.at("parameters").at("d").get<double>();
    f.a = j.at("parameters").at("a").get<double>();
    f.b = j.at("parameters").at("b").get<double>();
    const auto& lim = j.at("actuator_limits_deg");
    for (int i = 0; i < 2; ++i) {
      const auto& r = lim.at(i == 0 ? "q1" : "q2");
      f.limits[std::size_t(i)] = {r.at(0).get<double>() * kDeg, r.at(1).get<double>() * kDeg};
    }
    return f;
  }

  Vector2d base(int i) const { return {i == 0 ? -d / 2 : d / 2, 0.0}; }
  Vector2d elbow(int i, double q) const { return base(i) + a * Vector2d(std::cos(q), std::sin(q)); }

  // Distance of P to the edge of leg i's annulus |a - b| <= |P - A_i| <= a + b:
  // > 0 inside, < 0 outside.
  double annulus_margin(int i, const Vector2d& p) const {
    const double dist = (p - base(i)).norm();
    return std::min(a + b - dist, dist - std::abs(a - b));
  }
  bool reaches(const Vector2d& p) const { return annulus_margin(0, p) > 0 && annulus_margin(1, p) > 0; }

  // Leg i's actuator angle with the elbow out (away from the other leg) or in.
  std::optional<double> leg_ik(int i, const Vector2d& p, bool elbow_out) const {
    const Vector2d v = p - base(i);
    const double dist = v.norm();
    if (annulus_margin(i, p) < 0) return std::nullopt;
    const double c = std::clamp((a * a + dist * dist - b * b) / (2 * a * dist), -1.0, 1.0);
    const double phi = std::atan2(v.y(), v.x()), g = std::acos(c);
    const bool plus = (i == 0) == elbow_out;
    return plus ? phi + g : phi - g;
  }
  // The file's branch numbering: bit 0 set = the left leg's rule negative
  // (elbow in), bit 1 = the right leg's.
  std::optional<Vector2d> ik(const Vector2d& p, int branch) const {
    const auto q1 = leg_ik(0, p, (branch & 1) == 0), q2 = leg_ik(1, p, (branch & 2) == 0);
    if (!q1 || !q2) return std::nullopt;
    return Vector2d(*q1, *q2);
  }

  // Both assemblies: first the end point to the left of E1 -> E2 (above the
  // elbows, the working mode), then the mirror below.
  std::optional<std::array<Vector2d, 2>> fk(const Vector2d& q) const {
    const Vector2d e1 = elbow(0, q(0)), e2 = elbow(1, q(1));
    const double c = (e2 - e1).norm();
    if (c >= 2 * b || c == 0) return std::nullopt;
    const Vector2d u = (e2 - e1) / c, n(-u.y(), u.x());
    const double h = std::sqrt(b * b - c * c / 4);
    const Vector2d mid = (e1 + e2) / 2;
    return std::array<Vector2d, 2>{mid + h * n, mid - h * n};
  }
  double fk_height(const Vector2d& q) const {
    const double c = (elbow(1, q(1)) - elbow(0, q(0))).norm();
    return std::sqrt(std::max(0.0, b * b - c * c / 4));
  }

  Matrix2d jacobian(const Vector2d& q, const Vector2d& p) const {
    Matrix2d jx, jq = Matrix2d::Zero();
    for (int i = 0; i < 2; ++i) {
      const Vector2d w = p - elbow(i, q(i));
      jx.row(i) = w.transpose();
      jq(i, i) = -w.dot(a * Vector2d(-std::sin(q(i)), std::cos(q(i))));
    }
    return -jx.inverse() * jq;
  }

  // The documented reach margin inside: the smallest moment arm, about a base
  // joint, of the force a distal link carries (distance of A_i to line E_i P).
  double moment_arm(int i, double q, const Vector2d& p) const {
    const Vector2d e = elbow(i, q), u = (p - e).normalized(), r = e - base(i);
    return std::abs(r.x() * u.y() - r.y() * u.x());
  }

  // Which way A_i -> E_i -> P turns (z of the cross product of the two links).
  double turn(int i, double q, const Vector2d& p) const {
    const Vector2d e = elbow(i, q), r1 = e - base(i), r2 = p - e;
    return r1.x() * r2.y() - r1.y() * r2.x();
  }

  // The representative of leg i's angle q in [lo, lo + 2 pi).
  double from_lower_limit(int i, double q) const {
    const double lo = limits[std::size_t(i)].lo, turn = 2 * std::numbers::pi;
    return lo + std::fmod(std::fmod(q - lo, turn) + turn, turn);
  }
  bool within_limits(int i, double q, double margin) const {
    const double w = from_lower_limit(i, q);
    return w >= limits[std::size_t(i)].lo + margin && w <= limits[std::size_t(i)].hi - margin;
  }
  bool outside_limits(int i, double q, double margin) const {
    const double w = from_lower_limit(i, q);
    return w > limits[std::size_t(i)].hi + margin && w < limits[std::size_t(i)].lo + 2 * std::numbers::pi - margin;
  }
};

class FiveBarDevice : public ::testing::Test {
 protected:
  void SetUp() override {
    geometry = FiveBar::from_file();
    m = load_device("five-bar.json");
    ix = index_of_name(m->info().task, "x");
    iy = index_of_name(m->info().task, "y");
    ASSERT_GE(ix, 0);
    ASSERT_GE(iy, 0);
  }
  VectorXd task(const Vector2d& p) const {
    VectorXd x = m->home_task();
    x(ix) = p.x();
    x(iy) = p.y();
    return x;
  }
  Vector2d point(const VectorXd& x) const { return {x(ix), x(iy)}; }

  FiveBar geometry;
  std::shared_ptr<const Mechanism> m;
  int ix = -1, iy = -1;
};

}  // namespace

// The description as the interface shows it: actuators q1, q2 in rad with
// the file's travel, the task x, y (and the unmodelled z), c(J), the four
// elbow branches, home where both elbows are square (0, sqrt(a^2 + b^2 -
// d^2/4)) and out.
TEST_F(FiveBarDevice, DescriptionHomeAndTravel) {
  const MechanismInfo& info = m->info();
  ASSERT_EQ(info.actuators.size(), 2u);
  EXPECT_EQ(info.actuators[0].name, "q1");
  EXPECT_EQ(info.actuators[1].name, "q2");
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(info.actuators[std::size_t(i)].unit, "rad");
    EXPECT_NEAR(info.actuators[std::size_t(i)].range.lo, geometry.limits[std::size_t(i)].lo, 1e-12);
    EXPECT_NEAR(info.actuators[std::size_t(i)].range.hi, geometry.limits[std::size_t(i)].hi, 1e-12);
  }
  EXPECT_EQ(info.branches.size(), 4u);
  ASSERT_FALSE(info.measures.empty());
  EXPECT_EQ(info.measures.front().name, "cond");
  EXPECT_EQ(info.length_unit, "cm");

  const VectorXd home = m->home_task();
  EXPECT_DOUBLE_EQ(home(ix), 0.0);
  EXPECT_DOUBLE_EQ(home(iy), std::sqrt(10.0 * 10.0 + 14.0 * 14.0 - 6.0 * 6.0 / 4));
  const Vector2d q = *geometry.ik(point(home), 0);
  const VectorXd qh = m->home_actuators();
  ASSERT_EQ(qh.size(), 2);
  EXPECT_NEAR(angle_difference(qh(0), q(0)), 0.0, 1e-9);
  EXPECT_NEAR(angle_difference(qh(1), q(1)), 0.0, 1e-9);
  // Elbows out at home: q1 = 134.42 deg, q2 = 45.58 deg (symmetric).
  EXPECT_NEAR(q(0) / kDeg, 134.42, 0.01);
  EXPECT_NEAR(q(0) + q(1), std::numbers::pi, 1e-12);
  // Nearly isotropic there: c(J) = 1.0204.
  const double c = svd_condition(geometry.jacobian(q, point(home)));
  EXPECT_NEAR(c, 1.0204, 1e-4);
  const Measures mh = m->measures(qh, home);
  ASSERT_EQ(mh.status, Status::Ok);
  EXPECT_NEAR(mh.values.at(0), c, 1e-9 * c);
}

// 1.2 x 10^4 points over the whole reach, every branch (4.8 x 10^4 solves): outside either leg's
// annulus the status is unreachable; inside, away from the annuli's edges
// (every elbow bent by more than asin 0.05) and from the travel's ends, the
// status is ok with the circle-intersection angles (1e-9 rad), or
// out-of-limits where an angle lies outside the travel.
TEST_F(FiveBarDevice, InverseMatchesCircleIntersectionOnEveryBranch) {
  std::mt19937_64 rng(15001);
  std::uniform_real_distribution<double> ux(-27, 27), uy(-8, 27);
  const double edge = 1e-6 * m->size();
  int ok = 0, unreachable = 0, out_of_limits = 0, refused_inside = 0, wrong_outside = 0;
  double worst = 0;
  std::array<int, 4> ok_per_branch{};
  for (int n = 0; n < 12000; ++n) {
    const Vector2d p(ux(rng), uy(rng));
    const VectorXd x = task(p);
    const double margin = std::min(geometry.annulus_margin(0, p), geometry.annulus_margin(1, p));
    for (int branch = 0; branch < 4; ++branch) {
      IkOptions options;
      options.branch = branch;
      const IkResult r = m->inverse(x, options);
      if (margin < -edge) {
        EXPECT_EQ(r.status, Status::Unreachable) << "branch " << branch << " at " << p.transpose();
        if (r.status == Status::Unreachable) ++unreachable;
        continue;
      }
      if (margin < edge) continue;  // on the edge: either answer
      const Vector2d q = *geometry.ik(p, branch);
      const double arm = std::min(geometry.moment_arm(0, q(0), p), geometry.moment_arm(1, q(1), p));
      if (arm < 0.05 * geometry.a) continue;  // near a serial singularity
      if (!(svd_condition(geometry.jacobian(q, p)) < 1e4)) continue;  // near a parallel one (elbows meet)
      // The branch rules as the file states them: left (tip1, elbow1, q1)
      // and right (q2, elbow2, tip2) both positive on branch 0.
      EXPECT_EQ(-geometry.turn(0, q(0), p) > 0, (branch & 1) == 0);
      EXPECT_EQ(geometry.turn(1, q(1), p) > 0, (branch & 2) == 0);
      const double lim = 1e-6;
      const bool inside = geometry.within_limits(0, q(0), lim) && geometry.within_limits(1, q(1), lim);
      const bool outside = geometry.outside_limits(0, q(0), lim) || geometry.outside_limits(1, q(1), lim);
      if (inside) {
        if (r.status != Status::Ok) {
          if (refused_inside++ < 5)
            ADD_FAILURE() << "branch " << branch << " at " << p.transpose() << " (angles " << q.transpose()
                          << " inside the travel): " << to_string(r.status) << ", failing " << r.failing_part;
          continue;
        }
        ASSERT_EQ(r.solutions.size(), 1u);
        EXPECT_EQ(r.solutions[0].branch, branch);
        const VectorXd& qs = r.solutions[0].q;
        const double e = std::max(std::abs(angle_difference(qs(0), q(0))), std::abs(angle_difference(qs(1), q(1))));
        EXPECT_LT(e, 1e-9) << "branch " << branch << " at " << p.transpose() << ": q " << qs.transpose()
                           << " against " << q.transpose();
        worst = std::max(worst, e);
        // Reported within the travel as stated (186 deg of 0..210, not -174).
        for (int i = 0; i < 2; ++i)
          EXPECT_TRUE(geometry.limits[std::size_t(i)].contains(qs(i))) << "q" << i + 1 << " = " << qs(i);
        ++ok;
        ++ok_per_branch[std::size_t(branch)];
      } else if (outside) {
        if (r.status == Status::OutOfLimits) {
          ++out_of_limits;
        } else if (wrong_outside++ < 5) {
          ADD_FAILURE() << "branch " << branch << " at " << p.transpose() << " (angles " << q.transpose()
                        << " outside the travel): " << to_string(r.status) << ", expected out-of-limits";
        }
      }
    }
  }
  RecordProperty("ok", ok);
  RecordProperty("unreachable", unreachable);
  RecordProperty("out_of_limits", out_of_limits);
  RecordProperty("worst_angle_rad", scientific(worst));
  EXPECT_EQ(refused_inside, 0) << "targets inside the reach and the travel not solved";
  EXPECT_EQ(wrong_outside, 0) << "targets outside the travel not reported out-of-limits";
  EXPECT_GT(ok, 10000);
  EXPECT_GT(unreachable, 10000);
  for (int branch = 0; branch < 4; ++branch) EXPECT_GT(ok_per_branch[std::size_t(branch)], 1000) << branch;
  std::printf("five-bar IK: %d ok (per branch %d %d %d %d), %d unreachable, %d out of limits, worst %.3g rad; "
              "%d inside not solved, %d outside the travel not out-of-limits\n",
              ok, ok_per_branch[0], ok_per_branch[1], ok_per_branch[2], ok_per_branch[3], unreachable, out_of_limits,
              worst, refused_inside, wrong_outside);
}

// A planar device says so (MechanismInfo::plane_z: the plane z = 0) and
// refuses a question off its plane in every point-wise call, naming z and
// the plane; in its plane it answers with the closed-form angles.
TEST_F(FiveBarDevice, PlanarDeviceRefusesZOffItsPlane) {
  ASSERT_TRUE(m->info().plane_z.has_value());
  EXPECT_EQ(*m->info().plane_z, 0.0);
  const int iz = index_of_name(m->info().task, "z");
  ASSERT_EQ(iz, 2);
  EXPECT_EQ(m->home_task()(iz), 0.0);
  const Vector2d p(2, 15);
  const VectorXd in_plane = task(p);
  const IkResult r = m->inverse(in_plane);
  ASSERT_EQ(r.status, Status::Ok);
  const Vector2d q = *geometry.ik(p, r.solutions[0].branch);
  EXPECT_LT(std::abs(angle_difference(r.solutions[0].q(0), q(0))), 1e-9);
  EXPECT_LT(std::abs(angle_difference(r.solutions[0].q(1), q(1))), 1e-9);
  EXPECT_EQ(m->forward(r.solutions[0].q).x(iz), 0.0);
  // J has the rows x, y: z is not driven.
  EXPECT_EQ(m->jacobian(r.solutions[0].q, in_plane).rows(), 2);
  for (const double z : {1e300, 1.0, -1e-6}) {
    VectorXd x = in_plane;
    x(iz) = z;
    const VectorXd& qs = r.solutions[0].q;
    FkOptions seeded;
    seeded.seed = x;
    const std::vector<std::pair<const char*, std::function<void()>>> calls = {
        {"inverse", [&] { m->inverse(x); }},
        {"forward seed", [&] { m->forward(qs, seeded); }},
        {"jacobian", [&] { m->jacobian(qs, x); }},
        {"measures", [&] { m->measures(qs, x); }},
        {"reach_margin", [&] { m->reach_margin(x); }},
        {"nearest_singularity", [&] { m->nearest_singularity(qs, x); }},
        {"skeleton_pose", [&] { m->skeleton_pose(qs, x); }}};
    for (const auto& [name, call] : calls) {
      try {
        call();
        ADD_FAILURE() << name << " answered at z = " << z;
      } catch (const std::invalid_argument& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("z = "), std::string::npos) << name << ": " << message;
        EXPECT_NE(message.find("plane z = 0"), std::string::npos) << name << ": " << message;
      }
    }
  }
}

// A parallel (type II) singularity: both elbows at E = (0, sqrt(a^2 - d^2/4)),
// so both distal links pull along the same line E P and Jx = [(P - E)^T;
// (P - E)^T] has rank 1, for any P on the circle of radius b about E. There
// J is reported singular (measures: singular, c(J) = inf), and so are IK
// (on the branch of those elbows) and FK of those angles.
TEST_F(FiveBarDevice, TypeIISingularPoseIsSingularInInverseAndForward) {
  const double a = geometry.a, d = geometry.d, b = geometry.b;
  const Vector2d E(0, std::sqrt(a * a - d * d / 4));
  const Vector2d q(std::atan2(E.y(), E.x() + d / 2), std::atan2(E.y(), E.x() - d / 2));
  ASSERT_TRUE(geometry.within_limits(0, q(0), 0.1) && geometry.within_limits(1, q(1), 0.1));
  int checked = 0;
  for (const double t : {0.0, 0.3, 2.6, 3.1}) {
    const Vector2d p = E + b * Vector2d(std::cos(t), std::sin(t));
    if (!(std::min(geometry.annulus_margin(0, p), geometry.annulus_margin(1, p)) > 0.5)) continue;
    int branch = -1;  // the branch whose elbows are at E
    for (int k = 0; k < 4; ++k)
      if (const auto qk = geometry.ik(p, k);
          qk && std::abs(angle_difference((*qk)(0), q(0))) < 1e-9 && std::abs(angle_difference((*qk)(1), q(1))) < 1e-9)
        branch = k;
    ASSERT_GE(branch, 0) << p.transpose();
    const VectorXd x = task(p);
    const Measures at = m->measures(q, x);
    EXPECT_EQ(at.status, Status::Singular) << p.transpose();
    EXPECT_TRUE(std::isinf(at.values.at(0)));
    IkOptions options;
    options.branch = branch;
    const IkResult ik = m->inverse(x, options);
    EXPECT_EQ(ik.status, Status::Singular) << "IK at " << p.transpose() << ", branch " << branch;
    FkOptions fo;
    fo.seed = x;
    const FkResult fk = m->forward(q, fo);
    EXPECT_EQ(fk.status, Status::Singular) << "FK of " << q.transpose() << " seeded at " << p.transpose();
    EXPECT_EQ(m->measures(q, fk.x).status, Status::Singular);
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

// The haptic measures of a planar device, forces in its plane, against the
// closed form with J_p = J (m/rad, the file's cm converted) and the preset's
// ratings (Linkscape's defaults: the file has no actuator_data):
//   force_iso = min_i tau / |J_p e_i|, force_max = max over s = +-1 of
//   tau |J_p^-T (1, s)|, resolution = max_i (2 pi / counts) |J_p e_i|,
//   inertia = 1 / lambda_min(J_p M^-1 J_p^T), M = I_rotor Id (2 x 2, by hand).
// The haptic field of a slice holds the same values.
TEST_F(FiveBarDevice, HapticMeasuresMatchTheClosedForm) {
  const Preset preset = load_preset(asset_path("five-bar.json"));
  const haptics::DeviceData data = haptics::device_data(preset, m->info());
  ASSERT_EQ(data.position_rows, 2);
  const haptics::Rating rating = haptics::default_rating();
  const double tau = rating.continuous_torque_Nm, rotor = *rating.rotor_inertia_kgm2;
  std::mt19937_64 rng(15009);
  std::uniform_real_distribution<double> ux(-6, 6), uy(12, 21);
  for (int n = 0; n < 50; ++n) {
    const Vector2d p(ux(rng), uy(rng));
    const VectorXd x = task(p);
    const IkResult r = m->inverse(x);
    ASSERT_EQ(r.status, Status::Ok) << p.transpose();
    const Vector2d q = *geometry.ik(p, r.solutions[0].branch);
    const Matrix2d Jp = geometry.jacobian(q, p) * 0.01;
    const haptics::Measures h = haptics::measures(m->jacobian(r.solutions[0].q, x), data, haptics::TorqueRating::Continuous);
    const double iso = tau / std::max(Jp.col(0).norm(), Jp.col(1).norm());
    const Matrix2d inverse_transpose = Jp.transpose().inverse();
    const double largest = tau * std::max((inverse_transpose * Vector2d(1, 1)).norm(), (inverse_transpose * Vector2d(1, -1)).norm());
    const double resolution_mm = 1e3 * 2 * std::numbers::pi / rating.encoder_counts_per_rev *
                                 std::max(Jp.col(0).norm(), Jp.col(1).norm());
    const Matrix2d S = Jp * Jp.transpose() / rotor;
    const double lambda_min = 0.5 * (S(0, 0) + S(1, 1)) - std::hypot(0.5 * (S(0, 0) - S(1, 1)), S(0, 1));
    EXPECT_NEAR(h.force_iso_N, iso, 1e-9 * iso) << p.transpose();
    EXPECT_NEAR(h.force_max_N, largest, 1e-9 * largest) << p.transpose();
    EXPECT_NEAR(h.resolution_mm, resolution_mm, 1e-9 * resolution_mm) << p.transpose();
    ASSERT_TRUE(h.inertia_kg.has_value());
    EXPECT_NEAR(*h.inertia_kg, 1 / lambda_min, 1e-8 / lambda_min) << p.transpose();
  }
  // A box of two z layers: the plane's field, extruded.
  const Grid grid = Grid::box({-6, 12, -1}, {6, 21, 1}, {6, 5, 2});
  const auto field = haptics::sample_field(*m, grid, m->home_task(), {}, 1, {}, &data);
  ASSERT_TRUE(field.has_value());
  const auto* iso = field->extra("force_iso");
  ASSERT_NE(iso, nullptr);
  int reachable = 0;
  for (std::size_t s = 0; s < grid.size(); ++s) {
    if (!field->reachable[s]) continue;
    ++reachable;
    const Eigen::Vector3d point = grid.point(int(s % 6), int((s / 6) % 5), int(s / 30));
    const VectorXd x = task({point.x(), point.y()});
    const IkResult r = m->inverse(x);
    ASSERT_EQ(r.status, Status::Ok);
    EXPECT_FLOAT_EQ(iso->values[s], float(haptics::measures(m->jacobian(r.solutions[0].q, x), data, {}).force_iso_N));
  }
  EXPECT_GT(reachable, 30);
}

// 10^4 actuator pairs over the travel: the two circle intersections are
// the two assemblies, and FK seeded near either (within 2% of the size) lands
// on it to 1e-9 of the size. (The shipped design always assembles: the
// elbows are at most d + 2a = 26 cm apart, less than 2b = 28 cm.)
TEST_F(FiveBarDevice, ForwardMatchesCircleIntersectionInBothAssemblies) {
  std::mt19937_64 rng(15003);
  std::uniform_real_distribution<double> u1(geometry.limits[0].lo, geometry.limits[0].hi),
      u2(geometry.limits[1].lo, geometry.limits[1].hi), noise(-1, 1);
  const double size = m->size();
  int solved = 0;
  double worst = 0;
  long iterations = 0;
  for (int n = 0; n < 10000; ++n) {
    const Vector2d q(u1(rng), u2(rng));
    const auto points = geometry.fk(q);
    ASSERT_TRUE(points.has_value()) << q.transpose();
    const double height = geometry.fk_height(q);
    if (height < 0.05 * geometry.b) continue;  // near the parallel singularity (P on E1 E2)
    for (int mode = 0; mode < 2; ++mode) {
      const Vector2d p = (*points)[std::size_t(mode)];
      if (!(svd_condition(geometry.jacobian(q, p)) < 1e3)) continue;  // distal links nearly aligned
      // Leave out assemblies where a leg is nearly stretched or folded: its
      // angle there is ill-defined.
      if (std::min(geometry.moment_arm(0, q(0), p), geometry.moment_arm(1, q(1), p)) < 0.05 * geometry.a) continue;
      FkOptions options;
      options.seed = task(p + 0.02 * size * Vector2d(noise(rng), noise(rng)).normalized() * std::abs(noise(rng)));
      const FkResult r = m->forward(q, options);
      ASSERT_EQ(r.status, Status::Ok) << "q " << q.transpose() << " mode " << mode;
      const double e = (point(r.x) - p).norm();
      EXPECT_LT(e, 1e-9 * size) << "q " << q.transpose() << " mode " << mode << ": " << point(r.x).transpose()
                                << " against " << p.transpose();
      worst = std::max(worst, e);
      iterations += r.iterations;
      ++solved;
    }
  }
  RecordProperty("solved", solved);
  RecordProperty("worst_over_size", scientific(worst / size));
  EXPECT_GT(solved, 10000);
  std::printf("five-bar FK: %d solved, worst %.3g of the size, mean %.2f iterations\n", solved, worst / size,
              double(iterations) / std::max(solved, 1));
}

// With shorter distal links (b = 11 cm, --param b=11) the elbows can be
// farther apart than 2b: FK of such angles is never ok; where they assemble
// FK seeded at the working assembly finds it. Angles outside the travel are
// reported out-of-limits (core/status.h; the compiled devices do so, e.g.
// DeltaForward.ReportsActuatorRanges).
TEST_F(FiveBarDevice, ForwardRefusesWhatDoesNotAssembleOrLiesOutsideTheTravel) {
  Preset preset = load_preset(asset_path("five-bar.json"));
  apply_overrides(preset, {"b=11"});
  const auto shorter = make_mechanism(preset);
  FiveBar g = geometry;
  g.b = 11;
  std::mt19937_64 rng(15007);
  std::uniform_real_distribution<double> u1(g.limits[0].lo, g.limits[0].hi), u2(g.limits[1].lo, g.limits[1].hi);
  int refused = 0, solved = 0;
  for (int n = 0; n < 10000; ++n) {
    const Vector2d q(u1(rng), u2(rng));
    const double gap = (g.elbow(1, q(1)) - g.elbow(0, q(0))).norm() - 2 * g.b;
    if (gap > 1e-3 * g.b) {
      const FkResult r = shorter->forward(q);
      EXPECT_NE(r.status, Status::Ok) << q.transpose();
      ++refused;
    } else if (gap < -1e-3 * g.b && g.fk_height(q) > 0.05 * g.b) {
      const Vector2d p = (*g.fk(q))[0];
      if (!(svd_condition(g.jacobian(q, p)) < 1e3)) continue;
      if (std::min(g.moment_arm(0, q(0), p), g.moment_arm(1, q(1), p)) < 0.05 * g.a) continue;
      FkOptions options;
      options.seed = task(p);
      const FkResult r = shorter->forward(q, options);
      ASSERT_EQ(r.status, Status::Ok) << q.transpose();
      EXPECT_LT((point(r.x) - p).norm(), 1e-9 * shorter->size());
      ++solved;
    }
  }
  EXPECT_GT(refused, 1000);
  EXPECT_GT(solved, 1000);
  std::map<std::string, int> statuses;
  for (int n = 0; n < 200; ++n) {
    Vector2d q = *geometry.ik(Vector2d(0, 17), 0);
    const int leg = n % 2;
    q(leg) = geometry.limits[std::size_t(leg)].hi + 0.05 + 0.001 * n;
    FkOptions options;
    options.seed = task((*geometry.fk(q))[0]);  // seeded at the answer
    const FkResult r = m->forward(q, options);
    if (r.status != Status::OutOfLimits && statuses[std::string(to_string(r.status))]++ < 3)
      ADD_FAILURE() << "q " << q.transpose() << " (q" << leg + 1 << " beyond its travel's end "
                    << geometry.limits[std::size_t(leg)].hi << "): FK status " << to_string(r.status)
                    << ", expected out-of-limits";
  }
  for (const auto& [status, count] : statuses) std::printf("five-bar FK outside the travel: %d %s\n", count, status.c_str());
  EXPECT_TRUE(statuses.empty());
  std::printf("five-bar FK with b = 11: %d refused, %d solved\n", refused, solved);
}

// FK from its default seed (home) finds the working assembly (end point above
// the elbows) within 5 cm of home. Farther out (x in +-8, y in 10..22, both
// legs 0.5 cm inside their reach) it may stop short
// (not-converged) but never reports ok at a wrong point.
TEST_F(FiveBarDevice, ForwardFromHomeFindsTheWorkingAssembly) {
  std::mt19937_64 rng(15004);
  std::uniform_real_distribution<double> ux(-5, 5), uy(12, 21), wx(-8, 8), wy(10, 22);
  for (int n = 0; n < 500; ++n) {
    const Vector2d p(ux(rng), uy(rng));
    const Vector2d q = *geometry.ik(p, 0);
    const FkResult r = m->forward(q);
    ASSERT_EQ(r.status, Status::Ok) << p.transpose();
    EXPECT_LT((point(r.x) - (*geometry.fk(q))[0]).norm(), 1e-9 * m->size()) << p.transpose();
  }
  int tried = 0, ok = 0;
  std::map<std::string, int> others;
  while (tried < 10000) {
    const Vector2d p(wx(rng), wy(rng));
    if (std::min(geometry.annulus_margin(0, p), geometry.annulus_margin(1, p)) < 0.5) continue;
    const Vector2d q = *geometry.ik(p, 0);
    ++tried;
    const FkResult r = m->forward(q);
    if (r.status == Status::Ok) {
      EXPECT_LT((point(r.x) - p).norm(), 1e-9 * m->size()) << p.transpose();
      ++ok;
    } else {
      ++others[std::string(to_string(r.status))];
    }
  }
  std::printf("five-bar FK from home, x in +-8, y in 10..22: %d of %d ok", ok, tried);
  for (const auto& [status, count] : others) std::printf(", %d %s", count, status.c_str());
  std::printf("\n");
  EXPECT_GT(ok, 9000);
}

// J = -Jx^-1 Jq and c(J) at 10^4 points on branch 0 (c(J) < 100), to
// 1e-9 relative; det J too.
TEST_F(FiveBarDevice, JacobianAndConditionMatchTheClosedForm) {
  std::mt19937_64 rng(15005);
  std::uniform_real_distribution<double> ux(-22, 22), uy(-2, 24);
  const int icond = measure_index(*m, "cond");
  ASSERT_GE(icond, 0);
  int compared = 0, off = 0;
  double worst_j = 0, worst_c = 0, worst_det = 0;
  while (compared < 10000) {
    const Vector2d p(ux(rng), uy(rng));
    if (std::min(geometry.annulus_margin(0, p), geometry.annulus_margin(1, p)) < 1e-3) continue;
    const Vector2d q = *geometry.ik(p, 0);
    const Matrix2d j = geometry.jacobian(q, p);
    const double c = svd_condition(j);
    if (!(c < 100)) continue;
    const VectorXd x = task(p);
    const VectorXd qv = q;
    const Eigen::MatrixXd js = m->jacobian(qv, x);
    ASSERT_EQ(js.rows(), 2);
    ASSERT_EQ(js.cols(), 2);
    const double ej = (js - j).norm() / j.norm();
    const Measures ms = m->measures(qv, x);
    ASSERT_EQ(ms.status, Status::Ok) << p.transpose();
    const double ec = std::abs(ms.values.at(std::size_t(icond)) - c) / c;
    const double edet = std::abs(ms.det - j.determinant()) / std::abs(j.determinant());
    if (!(ej < 1e-9 && ec < 1e-9 && edet < 1e-9) && off++ < 5)
      ADD_FAILURE() << "at " << p.transpose() << " (q " << q.transpose() << "): J\n"
                    << js << "\nagainst\n"
                    << j << "\nc(J) " << ms.values.at(std::size_t(icond)) << " against " << c << ", det " << ms.det
                    << " against " << j.determinant();
    worst_j = std::max(worst_j, ej);
    worst_c = std::max(worst_c, ec);
    worst_det = std::max(worst_det, edet);
    ++compared;
  }
  RecordProperty("worst_jacobian_relative", scientific(worst_j));
  RecordProperty("worst_cond_relative", scientific(worst_c));
  RecordProperty("worst_det_relative", scientific(worst_det));
  EXPECT_EQ(off, 0) << "points where J, c(J) or det J are off by more than 1e-9";
  std::printf("five-bar J: %d points, %d off, worst J %.3g, c(J) %.3g, det %.3g (relative)\n", compared, off, worst_j,
              worst_c, worst_det);
}

// The reach boundary on branch 0 (2 x 10^4 points, 1e-6 of the size off
// every edge): reach_margin > 0 exactly where both annuli
// |a - b| <= |P - A_i| <= a + b hold and both elbows-out angles lie within
// the travel; < 0 outside an annulus or the travel. Inside, where the travel
// is not the nearer edge, it equals the documented serial margin, the
// smallest moment arm of a distal link's force about its base joint; outside
// an annulus it is never above minus the distance by which the leg that
// misses most misses (a leg's residual is at least its distance to the
// point), and the documented value: an upper bound of that distance, close to it near the boundary.
TEST_F(FiveBarDevice, ReachMarginSignIsTheAnnulusAndTravelTest) {
  std::mt19937_64 rng(15006);
  std::uniform_real_distribution<double> ux(-30, 30), uy(-30, 30);
  const double size = m->size(), edge = 1e-6 * size;
  int inside = 0, outside_annulus = 0, outside_travel = 0, value_checked = 0, value_off = 0, inside_off = 0;
  double worst_inside = 0, worst_outside = 0, worst_outside_relative = 0, worst_near = 0;
  std::vector<double> outside_relative;
  for (int n = 0; n < 20000; ++n) {
    const Vector2d p(ux(rng), uy(rng));
    const double annulus = std::min(geometry.annulus_margin(0, p), geometry.annulus_margin(1, p));
    if (std::abs(annulus) < edge) continue;
    const double r = m->reach_margin(task(p), 0);
    ASSERT_TRUE(std::isfinite(r)) << p.transpose();
    if (annulus < 0) {
      ++outside_annulus;
      EXPECT_LT(r, 0.0) << p.transpose();
      const double miss = -annulus;  // the larger of the two legs' misses
      EXPECT_LE(r, -miss + 1e-9 * size) << p.transpose();
      // Documented: outside, minus an upper bound of the miss distance from a
      // Gauss-Newton closest approach stopped once it gains less than 0.1 %
      // per step (the closest approach is a singular configuration, the leg
      // stretched or folded, where Gauss-Newton converges slowly); within 25 % of it, and within 5 % of it where
      // the miss is below 1 % of the size, near the boundary the mesh follows.
      const double allowed = miss < 0.01 * size ? 0.05 * miss : 0.25 * miss;
      if (std::abs(r + miss) > allowed + 1e-9 * size && value_off++ < 3)
        ADD_FAILURE() << "at " << p.transpose() << " the leg that misses most misses by " << miss
                      << " cm; reach_margin " << r;
      if (miss < 0.01 * size) worst_near = std::max(worst_near, std::abs(r + miss) / miss);
      worst_outside = std::max(worst_outside, std::abs(r + miss));
      worst_outside_relative = std::max(worst_outside_relative, std::abs(r + miss) / miss);
      outside_relative.push_back(std::abs(r + miss) / miss);
      continue;
    }
    const Vector2d q = *geometry.ik(p, 0);
    // Distance of each angle to the nearer end of its travel (rad; < 0 outside).
    double travel = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 2; ++i) {
      const Range lim = geometry.limits[std::size_t(i)];
      const double mid = (lim.lo + lim.hi) / 2, v = mid + angle_difference(q(i), mid);
      travel = std::min(travel, std::min(v - lim.lo, lim.hi - v));
    }
    if (std::abs(travel) < 1e-6) continue;
    if (travel < 0) {
      ++outside_travel;
      EXPECT_LT(r, 0.0) << p.transpose() << ": angles " << q.transpose() << " outside the travel";
      continue;
    }
    ++inside;
    const double arm = std::min(geometry.moment_arm(0, q(0), p), geometry.moment_arm(1, q(1), p));
    const bool value = arm < travel * size;
    if ((!(r > 0) || (value && !(std::abs(r - arm) <= 1e-9 * size))) && inside_off++ < 5)
      ADD_FAILURE() << "at " << p.transpose() << " (inside, angles " << q.transpose() << "): reach_margin " << r
                    << (value ? ", the moment arm " : ", travel margin ") << (value ? arm : travel * size);
    if (value) {
      worst_inside = std::max(worst_inside, std::abs(r - arm));
      ++value_checked;
    }
  }
  RecordProperty("inside", inside);
  RecordProperty("outside_annulus", outside_annulus);
  RecordProperty("outside_travel", outside_travel);
  RecordProperty("worst_inside_value", scientific(worst_inside));
  RecordProperty("worst_outside_value", scientific(worst_outside));
  EXPECT_GT(inside, 2000);
  EXPECT_GT(outside_annulus, 5000);
  EXPECT_GT(outside_travel, 1000);
  EXPECT_EQ(value_off, 0) << "outside values off the miss distance by more than documented";
  std::printf("five-bar reach outside, within 1 %% of the size of the boundary: worst %.3g relative\n", worst_near);
  EXPECT_EQ(inside_off, 0) << "inside points with a wrong sign or value";
  std::sort(outside_relative.begin(), outside_relative.end());
  std::printf("five-bar reach: %d inside (%d values), %d outside an annulus, %d outside the travel; worst value "
              "inside %.3g cm (%d wrong); outside %d values off by more than documented, worst %.3g cm (%.3g "
              "relative), median %.3g relative\n",
              inside, value_checked, outside_annulus, outside_travel, worst_inside, inside_off, value_off, worst_outside,
              worst_outside_relative, outside_relative.empty() ? 0.0 : outside_relative[outside_relative.size() / 2]);
}

// The reference itself, without the solver: circle-intersection FK undoes
// the circle-intersection IK on every branch, and the closed-form J matches
// central differences of that FK.
TEST(FiveBarReference, ClosedFormsAreConsistent) {
  const FiveBar g = FiveBar::from_file();
  std::mt19937_64 rng(15000);
  std::uniform_real_distribution<double> ux(-20, 20), uy(-5, 22);
  int checked = 0;
  while (checked < 2000) {
    const Vector2d p(ux(rng), uy(rng));
    if (std::min(g.annulus_margin(0, p), g.annulus_margin(1, p)) < 0.5) continue;
    for (int branch = 0; branch < 4; ++branch) {
      const Vector2d q = *g.ik(p, branch);
      for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR((g.elbow(i, q(i)) - g.base(i)).norm(), g.a, 1e-12);
        EXPECT_NEAR((p - g.elbow(i, q(i))).norm(), g.b, 1e-12);
      }
      const auto points = g.fk(q);
      ASSERT_TRUE(points.has_value());
      const int mode = ((*points)[0] - p).norm() < ((*points)[1] - p).norm() ? 0 : 1;
      const Matrix2d j = g.jacobian(q, p);
      if (!(svd_condition(j) < 100)) continue;  // FK and differences lose digits near singularities
      EXPECT_LT(((*points)[std::size_t(mode)] - p).norm(), 1e-11);
      Matrix2d fd;
      const double h = 1e-6;
      for (int k = 0; k < 2; ++k) {
        Vector2d qp = q, qm = q;
        qp(k) += h;
        qm(k) -= h;
        fd.col(k) = ((*g.fk(qp))[std::size_t(mode)] - (*g.fk(qm))[std::size_t(mode)]) / (2 * h);
      }
      EXPECT_LT((fd - j).norm() / j.norm(), 1e-6) << fd << "\nagainst\n" << j;
    }
    ++checked;
  }
}
