// The described Delta and PATHOS-II (assets/mechanisms/*-described.json),
// solved by the generic numerical solver, against the compiled closed forms:
// IK, FK, the Jacobian and the condition numbers over 10^5 random poses each.
// Condition numbers are settled against a long-double SVD of the compiled J
// (the compiled Delta's closed-form c(J) loses digits where two singular
// values meet, e.g. at home).
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "core/mechanism.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/preset.h"
#include "tests/core/mechanisms/described/without_stops.h"

namespace linkscape {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using LongMatrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;

long double reference_cond(const MatrixXd& J) {
  Eigen::JacobiSVD<LongMatrix> svd(J.cast<long double>());
  const auto& s = svd.singularValues();
  return s(0) / s(s.size() - 1);
}

struct Worst {
  double q = 0, J = 0, cond = 0, compiled_cond = 0, fk = 0;
  int compared = 0, fk_compared = 0, status_mismatch = 0;
};

void print(const char* name, const Worst& w) {
  std::printf("%s: %d poses compared (%d by FK); worst |q| %.2e rad, J %.2e rel, cond %.2e rel "
              "(compiled closed form %.2e), FK %.2e of size; status mismatches %d\n",
              name, w.compared, w.fk_compared, w.q, w.J, w.cond, w.compiled_cond, w.fk, w.status_mismatch);
}

// Prints w and checks it: at least 10^5 poses, every difference within 1e-9, no status mismatch.
void expect_agreement(const char* name, const Worst& w) {
  print(name, w);
  EXPECT_GE(w.compared, 100000) << name;
  EXPECT_LE(w.q, 1e-9) << name;
  EXPECT_LE(w.J, 1e-9) << name;
  EXPECT_LE(w.cond, 1e-9) << name;
  EXPECT_LE(w.fk, 1e-9) << name;
  EXPECT_EQ(w.status_mismatch, 0) << name;
}

TEST(DescribedDelta, AgreesWithTheCompiledDeltaAt1e5Poses) {
  // Both without their ball-joint cones (DeltaStops.ConesAgreeWithTheDescribedDelta compares them with).
  Preset linkage = load_preset("delta");
  linkage.checks.joint_limits = false;
  const auto compiled = make_mechanism(linkage);
  const auto described = make_mechanism(testing_support::without_stops(load_preset("delta-described")));
  ASSERT_EQ(described->info().actuators.size(), 3u);
  const double size = compiled->size();
  EXPECT_DOUBLE_EQ(described->size(), size);
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> angle(-45.0 * M_PI / 180, 90.0 * M_PI / 180), unit(-1, 1);
  Worst w;
  IkOptions ik;
  ik.branch = 0;
  for (int attempt = 0; w.compared < 100000 && attempt < 400000; ++attempt) {
    const VectorXd q0 = VectorXd::NullaryExpr(3, [&] { return angle(rng); });
    const FkResult f = compiled->forward(q0, {});
    if (f.status != Status::Ok) continue;
    const VectorXd x = f.x;
    // Statuses may differ only within rounding of the boundary.
    if (std::abs(compiled->reach_margin(x, 0)) < 1e-6 * size) continue;
    const IkResult c = compiled->inverse(x, ik), d = described->inverse(x, ik);
    if (c.status != d.status) {
      ++w.status_mismatch;
      ADD_FAILURE() << "status at (" << x.transpose() << "): compiled " << to_string(c.status) << ", described "
                    << to_string(d.status);
      continue;
    }
    if (c.status != Status::Ok) continue;
    const VectorXd& qc = c.solutions.front().q;
    const VectorXd& qd = d.solutions.front().q;
    w.q = std::max(w.q, (qc - qd).cwiseAbs().maxCoeff());
    const MatrixXd Jc = compiled->jacobian(qc, x), Jd = described->jacobian(qd, x);
    w.J = std::max(w.J, (Jc - Jd).norm() / Jc.norm());
    const Measures mc = compiled->measures(qc, x), md = described->measures(qd, x);
    if (mc.status == Status::Ok && md.status == Status::Ok) {
      const double ref = double(reference_cond(Jc));
      w.cond = std::max(w.cond, std::abs(md.values[0] - ref) / ref);
      w.compiled_cond = std::max(w.compiled_cond, std::abs(mc.values[0] - ref) / ref);
    }
    ++w.compared;
    // FK from a seed 2 % of the size away (every tenth pose: FK is the slow part).
    if (w.compared % 10 == 0) {
      FkOptions fo;
      fo.seed = x + 0.02 * size * VectorXd::NullaryExpr(3, [&] { return unit(rng); }) / std::sqrt(3.0);
      const FkResult fd = described->forward(qc, fo);
      EXPECT_EQ(fd.status, Status::Ok) << "FK at q = " << qc.transpose();
      if (fd.status == Status::Ok) {
        w.fk = std::max(w.fk, (fd.x - x).norm() / size);
        ++w.fk_compared;
      }
    }
  }
  expect_agreement("Delta", w);
}

// The window's "nearest singular" read-out: each leg's distance to its
// serial (type I) set, in cm, the same on both Deltas (their crank-and-rod
// legs' reach bounds are exact, and their boundary is that set).
TEST(DescribedDelta, EachLegsDistanceToItsSerialSetIsTheCompiledDeltas) {
  Preset linkage = load_preset("delta");
  linkage.checks.joint_limits = false;
  const auto compiled = make_mechanism(linkage);
  const auto described = make_mechanism(testing_support::without_stops(load_preset("delta-described")));
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> angle(-45.0 * M_PI / 180, 90.0 * M_PI / 180);
  IkOptions ik;
  ik.branch = 0;
  int compared = 0;
  double worst = 0;
  for (int attempt = 0; compared < 2000 && attempt < 10000; ++attempt) {
    const VectorXd q0 = VectorXd::NullaryExpr(3, [&] { return angle(rng); });
    const FkResult f = compiled->forward(q0, {});
    if (f.status != Status::Ok) continue;
    const IkResult d = described->inverse(f.x, ik);
    if (d.status != Status::Ok) continue;
    const SingularityReport c = compiled->nearest_singularity(q0, f.x);
    const SingularityReport e = described->nearest_singularity(d.solutions.front().q, f.x);
    for (std::size_t leg = 0; leg < 3; ++leg)
      worst = std::max(worst, std::abs(c.distances[leg] - e.distances[leg]) / compiled->size());
    ++compared;
  }
  EXPECT_GT(compared, 1000);
  EXPECT_LT(worst, 1e-9);
  std::printf("serial-set distances over %d poses: worst difference %.3g of the size\n", compared, worst);
}

// At the Delta's home two singular values of J meet; the compiled closed
// form of c(J) loses digits there and the described SVD does not
// (docs/described-internals.md quotes these figures).
TEST(DescribedDelta, AtHomeTheConditionNumberIsSettledByALongDoubleSvd) {
  const auto compiled = make_mechanism(load_preset("delta"));
  const auto described = make_mechanism(testing_support::without_stops(load_preset("delta-described")));
  const VectorXd x = compiled->home_task(), q = compiled->home_actuators();
  const long double ref = reference_cond(compiled->jacobian(q, x));
  const double c = compiled->measures(q, x).values[0], d = described->measures(q, x).values[0];
  std::printf("Delta home c(J): long-double SVD %.17Lg, described %.17g (%.1e), compiled closed form %.17g (%.1e)\n",
              ref, d, double(std::abs(d - ref) / ref), c, double(std::abs(c - ref) / ref));
  EXPECT_LE(std::abs(d - ref) / ref, 1e-13);
}

// A target nearer a leg's base than the leg's shortest reach (|La - Lb|:
// forearm folded back over the arm) is unreachable whatever the joints do;
// the solver says so before iterating that leg, with the miss through the
// shell |La - Lb| - distance, and the compiled Delta agrees it is
// unreachable, by the same leg, with a miss no smaller.
TEST(DescribedDelta, ALegNearerItsBaseThanItsShortestReachIsUnreachableBeforeIterating) {
  const Preset preset = testing_support::without_stops(load_preset("delta-described"));
  const described::Kinematics kinematics(
      described::build_model(preset.description, preset.parameters, preset.limits_deg, preset.length_unit));
  const auto compiled = make_mechanism(load_preset("delta"));
  const auto p = compiled->parameters();
  const double R = p.at("R"), r = p.at("r"), La = p.at("La"), Lb = p.at("Lb"), size = compiled->size();
  std::mt19937_64 rng(20261127);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0, 1);
  int checked = 0;
  for (int n = 0; n < 2000; ++n) {
    const int leg = n % 3, branch = (n / 3) % 8;
    const Eigen::Vector3d radial(std::cos(leg * 2 * M_PI / 3), std::sin(leg * 2 * M_PI / 3), 0);
    const Eigen::Vector3d u = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    // The anchor (platform point + r radial) within the shell, by 1e-6 of the size at least.
    const double distance = (std::abs(La - Lb) - 1e-6 * size) * std::cbrt(unit(rng));
    const VectorXd x = (R - r) * radial + distance * u;
    const described::PoseSolution s = kinematics.inverse(x, branch, 1e-10);
    const described::LegSolution& l = s.legs[std::size_t(leg)];
    ASSERT_EQ(l.status, Status::Unreachable) << x.transpose();
    EXPECT_EQ(l.iterations, 0) << x.transpose();
    EXPECT_NEAR(l.residual, std::abs(La - Lb) - distance, 1e-12 * size) << x.transpose();
    IkOptions o;
    o.branch = branch;
    const IkResult c = compiled->inverse(x, o);
    EXPECT_EQ(c.status, Status::Unreachable) << x.transpose();
    // The compiled reach margin is the signed distance to the leg's reach (a torus): outside by at least the shell's miss.
    EXPECT_LE(compiled->reach_margin(x, branch), -l.residual + 1e-12 * size) << x.transpose();
    ++checked;
  }
  EXPECT_EQ(checked, 2000);
}

TEST(DescribedPathos2, AgreesWithTheCompiledPathos2At1e5Poses) {
  // The described file states no stops: the compiled one's assumed stops off.
  Preset linkage = load_preset("pathos2");
  linkage.checks = {false, false};
  const auto compiled = make_mechanism(linkage);
  const auto described = make_mechanism(load_preset("pathos2-described"));
  ASSERT_EQ(described->info().task.size(), 7u);
  ASSERT_EQ(described->info().measures.size(), 2u);
  const double size = compiled->size();
  EXPECT_DOUBLE_EQ(described->size(), size);
  const VectorXd home = compiled->home_task();
  ASSERT_LE((described->home_task() - home).cwiseAbs().maxCoeff(), 1e-12);
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> unit(-1, 1);
  Worst w;
  int other_modes = 0;
  for (int attempt = 0; w.compared < 100000 && attempt < 400000; ++attempt) {
    VectorXd x = home;
    for (int k = 0; k < 3; ++k) x(k) += 5.0 * unit(rng);
    for (int k = 3; k < 6; ++k) x(k) += 0.35 * unit(rng);
    x(6) = home(6) * (1 + 0.3 * unit(rng));
    const IkResult c = compiled->inverse(x, {});
    const IkResult d = described->inverse(x, {});
    if (c.status != Status::Ok && c.status != Status::Unreachable) continue;  // singular bands differ by definition
    if (c.status == Status::Unreachable) {
      // The described solver must not claim a pose the device cannot reach.
      if (d.status == Status::Ok) {
        ++w.status_mismatch;
        ADD_FAILURE() << "described ok where compiled is unreachable at " << x.transpose();
      }
      continue;
    }
    const VectorXd& qc = c.solutions.front().q;
    const Measures mc = compiled->measures(qc, x);
    if (mc.status != Status::Ok) continue;
    if (d.status != Status::Ok) {
      ++w.status_mismatch;
      ADD_FAILURE() << "described " << to_string(d.status) << " where compiled is ok at " << x.transpose();
      continue;
    }
    const VectorXd& qd = d.solutions.front().q;
    w.q = std::max(w.q, (qc - qd).cwiseAbs().maxCoeff());
    const MatrixXd Jc = compiled->jacobian(qc, x), Jd = described->jacobian(qd, x);
    w.J = std::max(w.J, (Jc - Jd).norm() / Jc.norm());
    const Measures md = described->measures(qd, x);
    if (md.status == Status::Ok) {
      for (int k = 0; k < 2; ++k) {
        const double ref = double(reference_cond(k == 0 ? MatrixXd(Jc.topRows(3)) : MatrixXd(Jc.bottomRows(3))));
        w.cond = std::max(w.cond, std::abs(md.values[std::size_t(k)] - ref) / ref);
        w.compiled_cond = std::max(w.compiled_cond, std::abs(mc.values[std::size_t(k)] - ref) / ref);
      }
    }
    ++w.compared;
    // FK: the described and the compiled numerical FK from the same seed, 1 %
    // of the size and 0.01 rad away. Near a type II set two assembly modes
    // lie close together and either method may reach the other one; such a
    // pose is verified to be an assembly (the compiled closed-form IK gives q
    // back) and counted.
    if (w.compared % 20 == 0) {
      FkOptions fo;
      VectorXd seed = x;
      for (int k = 0; k < 3; ++k) seed(k) += 0.01 * size * unit(rng);
      for (int k = 3; k < 6; ++k) seed(k) += 0.01 * unit(rng);
      fo.seed = seed;
      const FkResult fd = described->forward(qc, fo), fc = compiled->forward(qc, fo);
      EXPECT_EQ(fd.status, Status::Ok) << "FK at x = " << x.transpose();
      if (fd.status == Status::Ok && fc.status == Status::Ok) {
        const double apart = (fd.x.head(6) - fc.x.head(6)).cwiseAbs().maxCoeff();
        if (apart <= 1e-6) {
          w.fk = std::max(w.fk, apart);
          ++w.fk_compared;
        } else {
          ++other_modes;
          for (const VectorXd& reached : {fd.x, fc.x}) {
            const IkResult back = compiled->inverse(reached, {});
            ASSERT_EQ(back.status, Status::Ok) << "FK reached " << reached.transpose() << ", not an assembly";
            EXPECT_LE((back.solutions.front().q - qc).cwiseAbs().maxCoeff(), 1e-9) << reached.transpose();
          }
        }
      }
    }
  }
  std::printf("PATHOS-II FK: %d seeds reached two different assembly modes (both verified)\n", other_modes);
  EXPECT_LE(other_modes, w.fk_compared / 100);
  expect_agreement("PATHOS-II", w);
}

}  // namespace
}  // namespace linkscape
