// Numerical safety: results that do not depend on the length scale, and
// condition numbers and statuses that are never a silent wrong answer.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/conditioning.h"
#include "core/mechanisms/parallel12r/field.h"
#include "core/mechanisms/parallel12r/methods.h"
#include "core/mechanisms/parallel12r/parallel12r.h"
#include "core/mechanisms/pathos2/pathos2.h"
#include "core/mechanisms/pathos2/field.h"
#include "core/mechanisms/pathos2/methods.h"
#include "tests/core/mechanisms/parallel12r/reference_12r.h"

using namespace linkscape;
using Eigen::Vector3d;
using parallel12r::IkMethod;

namespace {

constexpr double kPi = std::numbers::pi;

// Scales every decade from 1e-12 to 1e12: the sweep the kinematics must
// pass unchanged (c(J) is scale-invariant, angles are).
std::vector<double> decade_scales() {
  std::vector<double> s;
  for (int k = -12; k <= 12; ++k) s.push_back(std::pow(10.0, k));
  return s;
}

// Float roundings of two doubles that agree to ~1e-9: equal, or a unit in
// the last place apart where the doubles straddle a rounding boundary.
bool float_close(float a, float b) {
  if (std::isinf(a) || std::isinf(b)) return a == b;
  return std::abs(a - b) <= 2.4e-7f * std::max(std::abs(a), std::abs(b));
}

bool any_nan(const Field& f) {
  for (std::size_t i = 0; i < f.grid.size(); ++i) {
    if (std::isnan(f.cond[i]) || std::isnan(f.reach_margin[i]) || std::isnan(f.residual[i])) return true;
    if (!f.cond_orientation.empty() && std::isnan(f.cond_orientation[i])) return true;
  }
  return false;
}

parallel12r::Model model_12r(double L1, double L2) {
  parallel12r::Model m;
  m.L1 = L1;
  m.L2 = L2;
  m.validate();
  return m;
}

// A slice through the model's workspace, scaled by s.
FieldRequest slice_at_scale(const parallel12r::Model& unit, IkMethod method, Axis normal, double position,
                            double s) {
  const double reach = unit.reach() * s;
  FieldRequest r;
  r.method = method;
  r.threads = 1;  // small fields: a team of threads costs more than it saves
  r.grid = Grid::slice(normal, position * reach, -1.1 * reach, 1.1 * reach, -1.1 * reach, 1.1 * reach, 20, 20);
  return r;
}

// Fields of the unit model and of the model scaled by s, on grids scaled
// alike: same statuses, and c(J) equal where the status is ok.
void expect_12r_field_scales(const parallel12r::Model& unit, const Field& f1, double s, IkMethod method,
                             Axis normal, double position) {
  const double reach = unit.reach();
  const parallel12r::Model scaled = model_12r(unit.L1 * s, unit.L2 * s);
  const Field fs = *compute_field(scaled, slice_at_scale(unit, method, normal, position, s));
  std::ostringstream where_text;
  where_text << "L1 " << scaled.L1 << " L2 " << scaled.L2 << " " << parallel12r::to_string(method);
  const std::string where = where_text.str();
  EXPECT_FALSE(any_nan(fs)) << where;
  int ok = 0, mismatches = 0;
  for (std::size_t i = 0; i < fs.grid.size(); ++i) {
    if (fs.status[i] != f1.status[i]) {
      ++mismatches;
      continue;
    }
    if (fs.status[i] != std::uint8_t(Status::Ok)) continue;
    ++ok;
    EXPECT_TRUE(std::isfinite(fs.cond[i])) << where << " sample " << i;
    if (!float_close(fs.cond[i], f1.cond[i])) ++mismatches;
    // Lengths scale with the model.
    if (!(std::abs(fs.reach_margin[i] - f1.reach_margin[i] * s) <= 1e-6 * reach * s)) ++mismatches;
    EXPECT_LE(fs.residual[i], 1e-10 * reach * s) << where;
  }
  EXPECT_EQ(mismatches, 0) << where;
  EXPECT_GT(ok, 100) << where;
}

pathos2::Model scaled_pathos2(double s) {
  pathos2::Model m;
  m.l0 *= s, m.lb *= s, m.l1 *= s, m.l2 *= s, m.l3 *= s, m.lp *= s, m.h0 *= s, m.db *= s, m.lx *= s;
  m.validate();
  return m;
}

pathos2::Pose scaled_pose(const pathos2::Pose& p, double s) {
  pathos2::Pose q = p;
  q.p_world_E *= s;
  q.h0 *= s;
  return q;
}

// ---- PATHOS-II end to end in long double ----------------------------------
using LD = long double;
using V3L = Eigen::Matrix<LD, 3, 1>;
using M3L = Eigen::Matrix<LD, 3, 3>;

// Eq. 3 and its Jacobian in long double: a = Rz(t1)(s2 w, -l3 s3, l1 + c2 w), w = l2 + l3 c3.
void leg_chain_ld(LD l1, LD l2, LD l3, const V3L& t, V3L& a, M3L& J) {
  const LD c1 = std::cos(t(0)), s1 = std::sin(t(0)), c2 = std::cos(t(1)), s2 = std::sin(t(1));
  const LD c3 = std::cos(t(2)), s3 = std::sin(t(2));
  const LD w = l2 + l3 * c3, bx = s2 * w, by = -l3 * s3, bz = l1 + c2 * w;
  a = V3L(c1 * bx - s1 * by, s1 * bx + c1 * by, bz);
  const LD d2x = c2 * w, d2z = -s2 * w, d3x = -s2 * l3 * s3, d3y = -l3 * c3, d3z = -c2 * l3 * s3;
  J << -s1 * bx - c1 * by, c1 * d2x, c1 * d3x - s1 * d3y, c1 * bx - s1 * by, s1 * d2x, s1 * d3x + c1 * d3y, 0, d2z,
      d3z;
}

struct Pathos2Reference {
  std::array<LD, 2> cond{};  // cond(Jp), cond(Jo)
  LD kappa = 0;              // 1-norm condition number of the dimensionless M (pathos2.h)
};

// From the pose to cond(Jp), cond(Jo) in long double: leg angles by Newton
// on Eq. 3 from the double IK, M from them, J = M^-1, Jacobi SVD of its blocks.
bool pathos2_reference(const pathos2::Geometry& g, const pathos2::Pose& pose, Pathos2Reference& out) {
  const pathos2::Model& m = g.model;
  const auto ik = pathos2::inverse(g, pose, pathos2::IkDetail::Full);
  if (ik.status != Status::Ok) return false;
  Eigen::Matrix<LD, 6, 6> M;
  const V3L p = pose.p_world_E.cast<LD>();
  const M3L R = pose.R_world_E.cast<LD>();
  for (int i = 0; i < pathos2::kLegCount; ++i) {
    V3L r_E = g.p_E_attach_plate[i].cast<LD>();
    r_E.z() += LD(g.grip_side[i]) * LD(pose.h0);
    const V3L pg = p + R * r_E;
    const V3L a = g.R_world_B[i].cast<LD>().transpose() * (pg - g.p_world_B[i].cast<LD>());
    V3L t(ik.legs[i].t1, ik.legs[i].t2, ik.legs[i].t3), at;
    M3L Jl;
    for (int k = 0; k < 6; ++k) {
      leg_chain_ld(m.l1, m.l2, m.l3, t, at, Jl);
      t += Jl.partialPivLu().solve(V3L(a - at));
    }
    leg_chain_ld(m.l1, m.l2, m.l3, t, at, Jl);
    const V3L grad = g.R_world_B[i].cast<LD>() * Jl.transpose().partialPivLu().solve(V3L::UnitX());
    M.block<1, 3>(i, 0) = grad.transpose();
    M.block<1, 3>(i, 3) = (pg - p).cross(grad).transpose();
  }
  M.leftCols<3>() *= std::ldexp(1.0L, std::ilogb(m.l2 + m.l3));
  const Eigen::Matrix<LD, 6, 6> J = M.fullPivLu().inverse();
  out.kappa = M.cwiseAbs().colwise().sum().maxCoeff() * J.cwiseAbs().colwise().sum().maxCoeff();
  for (int b = 0; b < 2; ++b) {
    const Eigen::JacobiSVD<Eigen::Matrix<LD, 3, 6>> svd(J.middleRows<3>(3 * b));
    out.cond[b] = svd.singularValues()(0) / svd.singularValues()(2);
  }
  return std::isfinite(out.kappa);
}

// Pose at s along d (1 cm : 0.1 rad) from `from`.
pathos2::Pose along(const pathos2::Pose& from, const pathos2::Vector6d& d, double s) {
  pathos2::Pose p = from;
  p.p_world_E += s * d.head<3>();
  const Vector3d w = s * d.tail<3>();
  if (w.norm() > 0) p.R_world_E = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * from.R_world_E;
  return p;
}

// First s along d where det M changes sign with every leg Ok (the J-singular
// set), by marching and bisection; 0 if a leg fails first.
double j_singular_crossing(const pathos2::Geometry& g, const pathos2::Pose& home, const pathos2::Vector6d& d) {
  auto det_at = [&](double s, double& det) {
    const pathos2::Pose p = along(home, d, s);
    const auto ik = pathos2::inverse(g, p, pathos2::IkDetail::ActiveOnly);
    if (ik.status != Status::Ok) return false;
    det = pathos2::jacobian(g, p, ik).J_qdot_from_twist.determinant();
    return std::isfinite(det);
  };
  double det0 = 0, det = 0, lo = 0, hi = 0;
  if (!det_at(0, det0)) return 0;
  for (double s = 0.25;; s += 0.25) {
    if (s > 40 || !det_at(s, det)) return 0;
    if (det * det0 < 0) {
      hi = s;
      break;
    }
    lo = s;
  }
  for (int k = 0; k < 200 && hi - lo > 4e-16 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    const bool before = det_at(mid, det) && det * det0 > 0;
    (before ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

// ---- Accepted scales ----------------------------------------------------

TEST(NumericalSafety, ModelsRejectLengthsOutsideTheAcceptedRangeNamingIt) {
  auto message = [](auto&& build) -> std::string {
    try {
      build();
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  for (double bad : {1e-100, 1e-31, 1e31, 1e70}) {
    const std::string m12 = message([&] { model_12r(1.0, bad); });
    EXPECT_NE(m12.find("L2"), std::string::npos) << bad << ": " << m12;
    EXPECT_NE(m12.find("1e-30"), std::string::npos) << m12;
    EXPECT_NE(m12.find("1e+30"), std::string::npos) << m12;
    pathos2::Model p;
    p.l3 = bad;
    const std::string mp = message([&] { p.validate(); });
    EXPECT_NE(mp.find("l3"), std::string::npos) << bad << ": " << mp;
    EXPECT_NE(mp.find("1e-30"), std::string::npos) << mp;
  }
  EXPECT_NO_THROW(model_12r(1e-30, 1e30));
  EXPECT_NO_THROW(scaled_pathos2(2e-31));  // l1 = h0 = 7 cm -> 1.4e-30; lp, an offset, may be smaller
  EXPECT_NO_THROW(scaled_pathos2(2e28));   // largest length l0 = 45 cm -> 9e29
}

TEST(NumericalSafety, Parallel12rFieldsAreScaleFreeAndNaNFree) {
  // Unit models with equal and unequal links; every decade 1e-12 .. 1e12 and
  // the ends of the accepted range. Slices through the workspace (z) and
  // next to the actuator plane (y = 1e-3 reach).
  const parallel12r::Model unit_models[] = {model_12r(1.0, 1.0), model_12r(1.0, 0.37), model_12r(0.29, 1.0)};
  struct Slice {
    Axis normal;
    double position;
  };
  for (const auto& unit : unit_models)
    for (IkMethod method : {IkMethod::Planar, IkMethod::Paper, IkMethod::Fallback})
      for (Slice slice : {Slice{Axis::Z, 0.3}, Slice{Axis::Y, 1e-3}}) {
        const Field f1 = *compute_field(unit, slice_at_scale(unit, method, slice.normal, slice.position, 1.0));
        for (double s : decade_scales()) expect_12r_field_scales(unit, f1, s, method, slice.normal, slice.position);
      }
  const parallel12r::Model unequal = model_12r(1.0, 2.0);
  for (IkMethod method : {IkMethod::Planar, IkMethod::Paper, IkMethod::Newton}) {
    const Field f1 = *compute_field(unequal, slice_at_scale(unequal, method, Axis::Z, 0.3, 1.0));
    for (double s : {1e-30, 5e29}) expect_12r_field_scales(unequal, f1, s, method, Axis::Z, 0.3);
  }
}

TEST(NumericalSafety, Parallel12rIkJacobianAndCondAreScaleFree) {
  // Targets of the unit models (seeded) where c(J) <= 1e4; at every scale
  // each method returns the unit-scale status and angles, meets its
  // tolerance, round-trips through forward(), and c(J) agrees to 1e-9.
  const parallel12r::Model unit_models[] = {model_12r(1.0, 1.0), model_12r(1.0, 0.37), model_12r(0.29, 1.0)};
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto& unit : unit_models) {
    std::vector<Vector3d> targets;
    while (targets.size() < 40) {
      const Vector3d p = unit.reach() * Vector3d(u(rng), u(rng), u(rng));
      const auto r = parallel12r::inverse(unit, p, IkMethod::Planar);
      if (r.status != Status::Ok) continue;
      if (parallel12r::conditioning(unit, r.solutions[0].q_actuated).cond > 1e4) continue;
      targets.push_back(p);
    }
    for (double s : decade_scales()) {
      const parallel12r::Model m = model_12r(unit.L1 * s, unit.L2 * s);
      for (IkMethod method : {IkMethod::Paper, IkMethod::Planar, IkMethod::Newton, IkMethod::Fallback})
        for (const Vector3d& p : targets) {
          const auto r1 = parallel12r::inverse(unit, p, method);
          const auto rs = parallel12r::inverse(m, p * s, method);
          ASSERT_EQ(rs.status, r1.status) << s << " " << parallel12r::to_string(method);
          ASSERT_EQ(rs.solutions.size(), r1.solutions.size());
          for (std::size_t k = 0; k < rs.solutions.size(); ++k) {
            const auto& a = rs.solutions[k];
            const auto& b = r1.solutions[k];
            if (a.status != Status::Ok) continue;
            EXPECT_LE((a.q_actuated - b.q_actuated).cwiseAbs().maxCoeff(), 1e-9);
            EXPECT_LE(a.residual, 1e-10 * m.reach());
            EXPECT_LE((parallel12r::forward(m, a.q_actuated) - p * s).norm(), 1e-10 * m.reach());
            const double c1 = parallel12r::conditioning(unit, b.q_actuated).cond;
            const double cs = parallel12r::conditioning(m, a.q_actuated).cond;
            EXPECT_NEAR(cs, c1, 1e-9 * c1) << s;
            // det J scales like length^3.
            const double d1 = parallel12r::conditioning(unit, b.q_actuated).det;
            EXPECT_NEAR(parallel12r::conditioning(m, a.q_actuated).det / (s * s * s), d1, 1e-8 * std::abs(d1));
          }
        }
    }
  }
}

TEST(NumericalSafety, Pathos2IsScaleFreeAndNaNFree) {
  // Every length parameter (l0, lb, l1, l2, l3, lp, h0, db, lx), pose
  // position and grip scaled together: IK angles, cond(Jp) and cond(Jo)
  // unchanged (to 1e-9), J's translation rows scaled, nine-sensor and
  // numerical FK recover the scaled pose, and fields have no NaN and the
  // unit-scale values.
  const pathos2::Model unit;
  const pathos2::Geometry g1 = pathos2::make_geometry(unit);
  const std::vector<pathos2::Pose> poses = pathos2_methods::workspace_poses(g1, 60, 41);
  std::vector<double> scales = decade_scales();
  scales.push_back(2e-31);
  scales.push_back(2e28);
  pathos2::FieldRequest r1;
  r1.grid = Grid::box({-12, -12, 10.5}, {12, 12, 34.5}, {10, 10, 10});
  r1.rpy = Vector3d(0, 0, kPi / 6);
  r1.h0 = unit.h0;
  r1.threads = 1;
  const Field f1 = *pathos2::compute_field(unit, r1);
  for (double s : scales) {
    const pathos2::Model m = scaled_pathos2(s);
    const pathos2::Geometry gs = pathos2::make_geometry(m);
    const double L = m.l2 + m.l3;
    int compared = 0, fk_ok = 0;
    for (const pathos2::Pose& P1 : poses) {
      const pathos2::Pose Ps = scaled_pose(P1, s);
      const auto ik1 = pathos2::inverse(g1, P1);
      const auto iks = pathos2::inverse(gs, Ps);
      ASSERT_EQ(iks.status, ik1.status) << s;
      EXPECT_LE((iks.q_active - ik1.q_active).cwiseAbs().maxCoeff(), 1e-9) << s;
      const auto j1 = pathos2::jacobian(g1, P1, ik1);
      const auto js = pathos2::jacobian(gs, Ps, iks);
      ASSERT_EQ(js.status, j1.status) << s;
      if (j1.status != Status::Ok) continue;
      ++compared;
      EXPECT_TRUE(std::isfinite(js.cond_p) && std::isfinite(js.cond_o)) << s;
      EXPECT_NEAR(js.cond_p, j1.cond_p, 1e-9 * j1.cond_p) << s;
      EXPECT_NEAR(js.cond_o, j1.cond_o, 1e-9 * j1.cond_o) << s;
      EXPECT_LE((js.J_twist_from_qdot.topRows<3>() / s - j1.J_twist_from_qdot.topRows<3>()).norm(),
                1e-9 * j1.J_twist_from_qdot.topRows<3>().norm());
      EXPECT_LE((js.J_twist_from_qdot.bottomRows<3>() - j1.J_twist_from_qdot.bottomRows<3>()).norm(),
                1e-9 * j1.J_twist_from_qdot.bottomRows<3>().norm());
      // FK round trips at scale.
      const auto nine = pathos2::forward_nine_sensors(gs, pathos2::sensors_of(iks));
      ASSERT_EQ(nine.status, Status::Ok) << s;
      EXPECT_LE((nine.pose.p_world_E - Ps.p_world_E).norm(), 1e-9 * L) << s;
      EXPECT_LE((nine.pose.R_world_E - Ps.R_world_E).norm(), 1e-9) << s;
      pathos2::FkOptions o;  // the trust region is a length: scale it with the model
      o.max_step_cm *= s;
      const Vector3d offset(0.03, -0.02, 0.01);  // cm at unit scale
      pathos2::Pose seed1 = P1, seed = Ps;
      seed1.p_world_E += offset;
      seed.p_world_E += offset * s;
      const auto num1 = pathos2::forward_numeric(g1, ik1.q_active, P1.h0, seed1);
      const auto num = pathos2::forward_numeric(gs, iks.q_active, Ps.h0, seed, o);
      ASSERT_EQ(num.status, num1.status) << s;
      if (num.status == Status::Ok) {
        ++fk_ok;
        EXPECT_LE((num.pose.p_world_E - Ps.p_world_E).norm(), 1e-8 * L) << s;
      }
    }
    EXPECT_GT(compared, 50);
    EXPECT_GT(fk_ok, 50);
    pathos2::FieldRequest rs = r1;
    rs.grid = Grid::box(Vector3d(-12, -12, 10.5) * s, Vector3d(12, 12, 34.5) * s, {10, 10, 10});
    rs.h0 = unit.h0 * s;
    const Field fs = *pathos2::compute_field(m, rs);
    EXPECT_FALSE(any_nan(fs)) << s;
    int ok = 0, mismatches = 0;
    for (std::size_t i = 0; i < fs.grid.size(); ++i) {
      if (fs.status[i] != f1.status[i]) {
        ++mismatches;
        continue;
      }
      if (fs.status[i] != std::uint8_t(Status::Ok)) continue;
      ++ok;
      if (!float_close(fs.cond[i], f1.cond[i]) || !float_close(fs.cond_orientation[i], f1.cond_orientation[i]))
        ++mismatches;
      if (!(std::abs(fs.reach_margin[i] - f1.reach_margin[i] * s) <= 1e-6 * L)) ++mismatches;
    }
    EXPECT_EQ(mismatches, 0) << s;
    EXPECT_GT(ok, 50) << s;
  }
}

// ---- PATHOS-II condition numbers are computed, not guessed -------------

TEST(NumericalSafety, Pathos2CondAtAPoseNearTheReachBoundaryIsFinite) {
  // Default design, 5e-6 cm inside the reach boundary (leg 4 almost
  // stretched): cond(Jp) ~ 3692, cond(Jo) ~ 4023, where a determinant
  // threshold on B B^T used to answer +inf with status ok.
  const pathos2::Geometry g = pathos2::make_geometry(pathos2::Model{});
  const auto pose = pathos2::Pose::from_xyz_rpy(-5.233051233618914, 2.3077145753855683, 22.45402265035826,
                                                -0.05058443175141523, -0.021291790722917644, 0.4966043687834863, 7);
  const auto jr = pathos2::jacobian(g, pose, pathos2::inverse(g, pose));
  ASSERT_EQ(jr.status, Status::Ok);
  Pathos2Reference ref;
  ASSERT_TRUE(pathos2_reference(g, pose, ref));
  EXPECT_NEAR(jr.cond_p, double(ref.cond[0]), 1e-8 * double(ref.cond[0]));
  EXPECT_NEAR(jr.cond_o, double(ref.cond[1]), 1e-8 * double(ref.cond[1]));
  // Central differences of the IK (the step must stay inside the 5e-6 cm
  // margin; at 3e-9 truncation and rounding are both below 1e-3).
  pathos2::Matrix6d J_fd;
  ASSERT_TRUE(pathos2_methods::jacobian_finite_difference(g, pose, 3e-9, true, J_fd));
  const auto c_fd = pathos2_methods::condition_numbers_svd(J_fd);
  EXPECT_NEAR(jr.cond_p, c_fd[0], 1e-2 * c_fd[0]);
  EXPECT_NEAR(jr.cond_o, c_fd[1], 1e-2 * c_fd[1]);
  EXPECT_GT(jr.cond_p, 3000);
  EXPECT_LT(jr.cond_p, 4500);
}

TEST(NumericalSafety, Pathos2CondMeetsItsAccuracyAndSingularMeansTheDocumentedBand) {
  // Random poses around home and poses 1e-14 .. 1e-1 (relative) from the
  // J-singular set along seeded directions. Against the long-double end-to-end
  // reference: an ok Jacobian has cond(Jp), cond(Jo) within 1e-6; `singular`
  // only where the reference kappa of M is within a factor 3 of the
  // documented 1e9 or above, and never below it by more.
  const pathos2::Model model;
  const pathos2::Geometry g = pathos2::make_geometry(model);
  std::vector<pathos2::Pose> poses = pathos2_methods::workspace_poses(g, 3000, 43);
  const pathos2::Pose home = pathos2::home_pose(model);
  std::mt19937_64 rng(44);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0, 1);
  for (int found = 0; found < 25;) {
    pathos2::Vector6d d;
    for (int k = 0; k < 6; ++k) d(k) = normal(rng);
    d.tail<3>() *= 0.1;
    d.normalize();
    const double s_star = j_singular_crossing(g, home, d);
    if (!(s_star > 0)) continue;
    ++found;
    for (int j = 0; j < 40; ++j) poses.push_back(along(home, d, s_star * (1 - std::pow(10.0, -14.0 + 13.0 * unit(rng)))));
  }
  int ok = 0, singular = 0, high_kappa_ok = 0, field_singular = 0;
  double worst = 0;
  for (const auto& pose : poses) {
    Pathos2Reference ref;
    if (!pathos2_reference(g, pose, ref)) continue;
    const auto jr = pathos2::jacobian(g, pose, pathos2::inverse(g, pose));
    // The field sample at this pose agrees: ok means finite conds.
    pathos2::FieldRequest req;
    req.rpy = pose.rpy();
    req.h0 = pose.h0;
    const FieldSample fs = pathos2::sample_position(g, pose.p_world_E, req);
    if (fs.status == std::uint8_t(Status::Ok)) {
      EXPECT_TRUE(std::isfinite(fs.cond) && std::isfinite(fs.cond_orientation));
    } else if (fs.status == std::uint8_t(Status::Singular)) {
      ++field_singular;
      EXPECT_TRUE(std::isinf(fs.cond) && std::isinf(fs.cond_orientation) && !fs.reachable);
    }
    if (jr.status == Status::Singular) {
      ++singular;
      EXPECT_GE(double(ref.kappa), 1e9 / 3) << "singular far from the documented band";
      EXPECT_TRUE(std::isinf(jr.cond_p) && std::isinf(jr.cond_o));
      continue;
    }
    ASSERT_EQ(jr.status, Status::Ok);
    EXPECT_LE(double(ref.kappa), 3e9) << "ok far beyond the documented band";
    ++ok;
    high_kappa_ok += ref.kappa > 1e8;
    for (int b = 0; b < 2; ++b) {
      const double c = b == 0 ? jr.cond_p : jr.cond_o;
      const double e = std::abs(c - double(ref.cond[b])) / double(ref.cond[b]);
      worst = std::max(worst, e);
      EXPECT_LE(e, 1e-6) << "kappa " << double(ref.kappa) << " cond " << double(ref.cond[b]);
    }
  }
  std::printf("PATHOS-II cond: %d ok (%d with kappa > 1e8), %d singular, worst relative error %.2g\n", ok,
              high_kappa_ok, singular, worst);
  EXPECT_GT(singular, 100);
  EXPECT_GT(high_kappa_ok, 20);
  EXPECT_GT(field_singular, 100);
}

TEST(NumericalSafety, BlockConditionNumberIsAccurateUpTo1e12) {
  // 3x6 blocks with prescribed singular values (random orthogonal factors),
  // c from 1 to 1e12 and any scale: relative error <= 100 u c against the
  // exact c; the previous test on det(B B^T) answered +inf from c ~ 3e6.
  std::mt19937_64 rng(45);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0, 1);
  for (int i = 0; i < 3000; ++i) {
    const double c = std::pow(10.0, 12.0 * unit(rng));
    const double mid = std::pow(c, unit(rng));  // sigma_mid anywhere in [1, c], incl. coinciding pairs
    Eigen::Matrix<double, 3, 3> A;
    Eigen::Matrix<double, 6, 6> B6;
    for (int k = 0; k < 9; ++k) A(k / 3, k % 3) = normal(rng);
    for (int k = 0; k < 36; ++k) B6(k / 6, k % 6) = normal(rng);
    const Eigen::Matrix3d U = Eigen::HouseholderQR<Eigen::Matrix3d>(A).householderQ();
    const Eigen::Matrix<double, 6, 6> V = Eigen::HouseholderQR<Eigen::Matrix<double, 6, 6>>(B6).householderQ();
    const double scale = std::pow(10.0, -20.0 + 40.0 * unit(rng));
    const Eigen::Vector3d sigma(c * scale, mid * scale, scale);
    const Eigen::Matrix<double, 3, 6> block = U * sigma.asDiagonal() * V.leftCols<3>().transpose();
    // The exact c of the double block, from a long-double SVD (the rounding of
    // the product above moves it by ~u c).
    const Eigen::JacobiSVD<Eigen::Matrix<LD, 3, 6>> svd(block.cast<LD>());
    const double exact = double(svd.singularValues()(0) / svd.singularValues()(2));
    EXPECT_NEAR(pathos2::block_condition_number(block), exact, 100 * 1.1e-16 * exact * exact + 1e-14 * exact)
        << "c " << c;
  }
}

// ---- The singular status within the documented band -----------------------

TEST(NumericalSafety, TargetsWithinTheSingularBandAreSingularForEveryMethod) {
  // kSingularTolerance (1e-12 of the reach) around each singular set: every
  // method says `singular`, and any solution it gives meets the tolerance
  // (before, (0.3, 1e-13, 0.3) with L1 = L2 = 1 was not-converged for all
  // closed forms, planar's residual 8e-5).
  const IkMethod all_methods[] = {IkMethod::Paper, IkMethod::Planar, IkMethod::Newton, IkMethod::DampedLeastSquares,
                                  IkMethod::Fallback};
  auto check = [&](const parallel12r::Model& m, const Vector3d& p, const std::string& where) {
    for (IkMethod method : all_methods) {
      const auto r = parallel12r::inverse(m, p, method);
      EXPECT_EQ(r.status, Status::Singular) << where << " " << parallel12r::to_string(method);
      for (const auto& s : r.solutions) {
        EXPECT_EQ(s.status, Status::Singular) << where;
        EXPECT_LE(s.residual, 1e-10 * m.reach()) << where << " " << parallel12r::to_string(method);
        EXPECT_LE((parallel12r::forward(m, s.q_actuated) - p).norm(), 1e-10 * m.reach()) << where;
      }
      FieldRequest req;
      req.method = method;
      const FieldSample f = sample_point(m, p, req);
      EXPECT_EQ(f.status, std::uint8_t(Status::Singular)) << where << " " << parallel12r::to_string(method);
      EXPECT_TRUE(std::isinf(f.cond) && !f.reachable) << where;
    }
  };
  check(model_12r(1.0, 1.0), Vector3d(0.3, 1e-13, 0.3), "the reported target");
  std::mt19937_64 rng(51);
  std::uniform_real_distribution<double> u(-1.0, 1.0), band(0.0, 0.99e-12);
  for (const auto& m : {model_12r(1.0, 1.0), model_12r(1.0, 0.7), model_12r(0.4, 1.3)}) {
    const double reach = m.reach();
    for (int i = 0; i < 30; ++i) {
      // A generic direction and radius inside the workspace.
      Vector3d dir(u(rng), std::abs(u(rng)) + 0.1, u(rng));
      dir.normalize();
      const double radius = m.inner_reach() + (0.2 + 0.6 * (u(rng) + 1) / 2) * (reach - m.inner_reach());
      const double d = band(rng) * reach;
      // |y| = d: the actuator plane, at the same radius.
      const Eigen::Vector2d xz = Eigen::Vector2d(dir.x(), dir.z()).normalized() * std::sqrt(radius * radius - d * d);
      check(m, Vector3d(xz.x(), i % 2 ? d : -d, xz.y()), "actuator plane");
      const Vector3d axis(d * 0.6, d * 0.8, (i % 2 ? 1 : -1) * radius);  // sqrt(x^2 + y^2) = d: the z axis
      check(m, axis, "z axis");
      check(m, (reach - d) * dir, "outer sphere");
      if (m.L1 != m.L2) check(m, (m.inner_reach() + d) * dir, "inner sphere");
    }
  }
}

// ---- The paper method meets its tolerance ------------------------------------

TEST(NumericalSafety, PaperMethodMeetsItsToleranceAtTheIsotropicPointAndGenerally) {
  // The README's example: (0, 15, 15) with L1 = L2 = 15, branch 0 is
  // (0, pi/2, 0), where Eq. 16's cos^2(gamma) is stationary; it was
  // not-converged with residual 7.45e-9 (L1 + L2).
  const parallel12r::Model iso = model_12r(15.0, 15.0);
  const auto r = parallel12r::inverse(iso, Vector3d(0, 15, 15), IkMethod::Paper);
  ASSERT_EQ(r.status, Status::Ok);
  ASSERT_EQ(r.solutions.size(), 2u);
  for (const auto& s : r.solutions) {
    EXPECT_EQ(s.status, Status::Ok) << "branch " << s.branch;
    EXPECT_LE(s.residual, 1e-10 * iso.reach());
    EXPECT_LE(s.iterations, 1);  // the polishing Newton step, counted
  }
  EXPECT_LE((r.solutions[0].q_actuated - parallel12r::home_pose(0)).norm(), 1e-12);

  // Generally: uniform targets, and targets whose beta or gamma sits at or
  // within 1e-9 rad of 0, pi/2 or pi (where the squared equations lose
  // half the digits): every branch planar solves, paper solves too, within
  // the tolerance.
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double stationary[] = {0.0, kPi / 2, kPi, -kPi / 2};
  for (const auto& m : {model_12r(1.0, 1.0), model_12r(1.0, 0.7), model_12r(0.3, 1.0)}) {
    int compared = 0;
    for (int i = 0; i < 20000; ++i) {
      Vector3d p;
      if (i % 2 == 0) {
        p = m.reach() * Vector3d(u(rng), u(rng), u(rng));
      } else {
        Vector3d q(0.5 * kPi * u(rng), kPi * u(rng), kPi * u(rng));
        const int which = 1 + (i / 2) % 2;
        q(which) = stationary[(i / 4) % 4] + (i % 8 == 1 ? 0.0 : 1e-9 * u(rng));
        p = parallel12r::forward(m, q);
      }
      const auto planar = parallel12r::inverse(m, p, IkMethod::Planar);
      if (planar.status != Status::Ok) continue;
      const auto paper = parallel12r::inverse(m, p, IkMethod::Paper);
      for (const auto& ps : planar.solutions) {
        if (ps.status != Status::Ok) continue;
        ++compared;
        const parallel12r::IkSolution* match = nullptr;
        for (const auto& s : paper.solutions)
          if (s.branch == ps.branch) match = &s;
        ASSERT_NE(match, nullptr) << p.transpose();
        EXPECT_EQ(match->status, Status::Ok) << p.transpose() << " residual " << match->residual;
        EXPECT_LE(match->residual, 1e-10 * m.reach());
      }
    }
    EXPECT_GT(compared, 15000);
  }
}

// ---- The range where the 12R c(J) is trustworthy ----------------------------

namespace {

// J of Eqs. 11-13 in long double from a configuration taken as exact.
Eigen::Matrix<LD, 3, 3> jacobian_12r_ld(LD L1, LD L2, LD a, LD b, LD g) {
  const LD sa = std::sin(a), ca = std::cos(a);
  auto columns = [&](LD t, V3L& du_da, V3L& du_dt) {
    const LD st = std::sin(t), ct = std::cos(t), d2 = ca * ca + sa * sa * ct * ct, d3 = d2 * std::sqrt(d2);
    du_da = V3L(-ca * ct, -sa * ct * ct * ct, -sa * st * ct * ct) / d3;
    du_dt = ca * V3L(sa * ca * st, -ca * ca * st, ct) / d3;
  };
  V3L b_da, b_dt, g_da, g_dt;
  columns(b, b_da, b_dt);
  columns(g, g_da, g_dt);
  Eigen::Matrix<LD, 3, 3> J;
  J.col(0) = L1 * b_da + L2 * g_da;
  J.col(1) = L1 * b_dt;
  J.col(2) = L2 * g_dt;
  return J;
}

// Configurations approaching every singular set: the actuator plane
// (alpha -> +-pi/2, also with beta -> +-pi/2), stretched (gamma -> beta),
// folded (gamma -> beta - pi), both at once, and the z axis.
Vector3d configuration_near_singular_sets(const parallel12r::Model& m, int mode, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  for (;;) {
    double a = -1.5 + 3.0 * u(rng), b = -kPi + 2 * kPi * u(rng), g = -kPi + 2 * kPi * u(rng);
    const double s = u(rng) < 0.5 ? -1 : 1;
    const double e = std::pow(10.0, -10.0 * u(rng));
    switch (mode % 6) {
      case 0: a = s * (kPi / 2 - e); break;
      case 1: a = s * (kPi / 2 - e), b = (u(rng) < 0.5 ? -1 : 1) * (kPi / 2 - std::pow(10.0, -9.0 * u(rng))); break;
      case 2: g = b - s * e; break;
      case 3: g = b - kPi + s * e; break;
      case 4: a = s * (kPi / 2 - std::pow(10.0, -6.0 * u(rng))), g = b - s * std::pow(10.0, -6.0 * u(rng)); break;
      default: {  // L1 cb/db + L2 cg/dg = 0
        const double sa = std::sin(a), ca = std::cos(a), cb = std::cos(b);
        const double t = -(m.L1 / m.L2) * cb / std::sqrt(ca * ca + sa * sa * cb * cb);
        if (std::abs(t) >= 1) continue;
        const double c2 = std::min(1.0, t * t * ca * ca / (1 - t * t * sa * sa));
        g = std::acos((t >= 0 ? 1 : -1) * std::sqrt(c2)) * (u(rng) < 0.5 ? 1 : -1) + s * e;
      }
    }
    return Vector3d(a, b, g);
  }
}

}  // namespace

TEST(NumericalSafety, Parallel12rCondIsTrustedUpToTheThresholdAndSingularBeyond) {
  // Against c(J) and det J of the same configuration in long double: below
  // kMaxTrustedCondition (with a 1.5x margin for the reference and the
  // threshold test) conditioning() is ok and within 1e-6; above it, singular
  // with cond = +inf and det = 0, never a wrong finite number. (Long double
  // resolves c to ~90 u_ld c, 1e-5 at c = 1e14, the top of the check.)
  const double c_max = parallel12r::kMaxTrustedCondition;
  int below_near = 0, above_near = 0;
  double worst = 0;
  std::mt19937_64 rng(71);
  for (const auto& m : {model_12r(1.0, 1.0), model_12r(1.0, 0.7), model_12r(0.3, 1.0)})
    for (int i = 0; i < 30000; ++i) {
      const Vector3d q = configuration_near_singular_sets(m, i, rng);
      const Eigen::Matrix<LD, 3, 3> J_ref = jacobian_12r_ld(m.L1, m.L2, q.x(), q.y(), q.z());
      const Eigen::JacobiSVD<Eigen::Matrix<LD, 3, 3>> svd(J_ref);
      const double c_ref = double(svd.singularValues()(0) / svd.singularValues()(2));
      const auto c = parallel12r::conditioning(m, q);
      if (c_ref <= c_max / 1.5) {
        ASSERT_EQ(c.status, Status::Ok) << "c " << c_ref;
        const double e = std::abs(c.cond - c_ref) / c_ref;
        worst = std::max(worst, e);
        EXPECT_LE(e, 1e-6) << "c " << c_ref << " q " << q.transpose();
        const double det_ref = double(J_ref.determinant());
        EXPECT_LE(std::abs(c.det - det_ref), 1e-6 * std::abs(det_ref)) << "c " << c_ref;
        below_near += c_ref > c_max / 10;
      } else if (c_ref >= 1.5 * c_max && c_ref <= 1e14) {
        EXPECT_EQ(c.status, Status::Singular) << "c " << c_ref;
        EXPECT_TRUE(std::isinf(c.cond) && c.det == 0.0) << "c " << c_ref;
        above_near += c_ref < 10 * c_max;
      }
      if (!std::isfinite(c.cond)) {
        EXPECT_EQ(c.status, Status::Singular);
      }
    }
  std::printf("12R c(J) below the threshold: worst relative error %.2g; %d samples within 10x below, %d within 10x above\n",
              worst, below_near, above_near);
  EXPECT_GT(below_near, 200);
  EXPECT_GT(above_near, 200);
  // At alpha = pi/2 - 1e-9, beta, gamma on opposite sides of +-pi/2
  // (c ~ 1e26 by mpmath) double gave c half the true value and det J -2x:
  // singular now.
  const auto far = parallel12r::conditioning(model_12r(1.0, 1.0), Vector3d(kPi / 2 - 1e-9, -2.8, 1.05));
  EXPECT_EQ(far.status, Status::Singular);
  EXPECT_TRUE(std::isinf(far.cond));
}

TEST(NumericalSafety, Parallel12rFieldsReportUntrustedCondAsSingular) {
  // Targets of configurations near the singular sets: a field sample is
  // never ok with c(J) above the threshold; above it the sample is singular
  // (cond +inf, not reachable, no method recorded).
  std::mt19937_64 rng(72);
  int singular = 0, ok = 0;
  for (const auto& m : {model_12r(1.0, 1.0), model_12r(1.0, 0.7)})
    for (IkMethod method : {IkMethod::Planar, IkMethod::Fallback, IkMethod::Paper})
      for (int i = 0; i < 3000; ++i) {
        const Vector3d q = configuration_near_singular_sets(m, i, rng);
        FieldRequest req;
        req.method = method;
        req.branch = parallel12r::branch_of(q);
        const FieldSample s = sample_point(m, parallel12r::forward(m, q), req);
        if (s.status == std::uint8_t(Status::Ok)) {
          ++ok;
          EXPECT_LE(s.cond, parallel12r::kMaxTrustedCondition);
          EXPECT_TRUE(s.reachable);
        } else if (s.status == std::uint8_t(Status::Singular)) {
          ++singular;
          EXPECT_TRUE(std::isinf(s.cond) && !s.reachable && s.method_used == Field::kNoMethod);
        }
      }
  EXPECT_GT(ok, 1000);
  EXPECT_GT(singular, 1000);
}

// ---- The conditioning error table of docs/mechanisms/parallel-12r.md ----------

TEST(NumericalSafety, Parallel12rConditioningErrorEndToEnd) {
  // Prints the table of docs/mechanisms/parallel-12r.md (run this test alone
  // to see it). 200,000 configurations uniform over the workspace
  // (ConfigurationSampler(13, 0)); the target is forward(q). End to end: the
  // planar IK of the target (its branch), J, c in double; reference: the
  // long-double IK of the same target (methods::reference_inverse), J and a
  // Jacobi SVD in long double. "Same J": the c forms on the double J of the
  // end-to-end chain against a long-double SVD of that J (the algorithm
  // alone, what the table showed before). Bounds per sample: end to end
  // 100 u c^2 (the target fixes the distance to the outer sphere only to
  // ~u (L1 + L2), and c ~ 1 / sqrt(distance) there), same J 100 u c.
  const parallel12r::Model m;
  constexpr double kU = 1.1102230246251565e-16;
  constexpr int kSamples = 200000;
  std::vector<Vector3d> configurations;
  linkscape::testing::ConfigurationSampler sample(13, 0.0);
  for (int i = 0; i < kSamples; ++i) configurations.push_back(sample());
  struct Decade {
    int samples = 0;
    std::array<double, 4> worst{};  // end to end closed form, end to end SVD, same J closed form, same J SVD
  };
  std::map<int, Decade> decades;
  int violations = 0, no_reference = 0;
#pragma omp parallel
  {
    std::map<int, Decade> local;
    int local_violations = 0, local_no_reference = 0;
#pragma omp for schedule(dynamic, 1024)
    for (int i = 0; i < kSamples; ++i) {
      const Vector3d& q = configurations[std::size_t(i)];
      const Vector3d p = parallel12r::forward(m, q);
      const auto ref = methods::reference_inverse(m, p, q);
      if (!ref.converged) {
        ++local_no_reference;
        continue;
      }
      const Eigen::JacobiSVD<Eigen::Matrix<LD, 3, 3>> ref_svd(jacobian_12r_ld(m.L1, m.L2, ref.q[0], ref.q[1], ref.q[2]));
      const double c_ref = double(ref_svd.singularValues()(0) / ref_svd.singularValues()(2));
      if (!(c_ref < 1e7)) continue;
      const auto planar = parallel12r::inverse(m, p, IkMethod::Planar);
      const parallel12r::IkSolution* s = nullptr;
      for (const auto& candidate : planar.solutions)
        if (candidate.branch == ref.branch && candidate.status == Status::Ok) s = &candidate;
      if (!s) {
        ++local_violations;  // planar serves every target of the open workspace
        continue;
      }
      const Eigen::Matrix3d J = parallel12r::jacobian(m, s->q_actuated);
      const Eigen::JacobiSVD<Eigen::Matrix<LD, 3, 3>> same_svd(J.cast<LD>());
      const double c_same = double(same_svd.singularValues()(0) / same_svd.singularValues()(2));
      const double closed = condition_number_closed_form(J), svd = condition_number_svd(J);
      const std::array<double, 4> e{std::abs(closed - c_ref) / c_ref, std::abs(svd - c_ref) / c_ref,
                                    std::abs(closed - c_same) / c_same, std::abs(svd - c_same) / c_same};
      Decade& d = local[int(std::floor(std::log10(c_ref)))];
      ++d.samples;
      for (int k = 0; k < 4; ++k) d.worst[k] = std::max(d.worst[k], e[k]);
      if (!(e[0] <= 100 * kU * c_ref * c_ref) || !(e[2] <= 100 * kU * c_ref)) ++local_violations;
    }
#pragma omp critical
    {
      for (const auto& [k, d] : local) {
        Decade& total = decades[k];
        total.samples += d.samples;
        for (int j = 0; j < 4; ++j) total.worst[j] = std::max(total.worst[j], d.worst[j]);
      }
      violations += local_violations;
      no_reference += local_no_reference;
    }
  }
  std::printf("| c(J) | samples | end to end, closed form | end to end, double Jacobi SVD | same J, closed form | same J, double Jacobi SVD |\n|---|---|---|---|---|---|\n");
  for (const auto& [k, d] : decades)
    std::printf("| 1e%d–1e%d | %d | %.2g | %.2g | %.2g | %.2g |\n", k, k + 1, d.samples, d.worst[0], d.worst[1], d.worst[2],
                d.worst[3]);
  std::printf("(%d targets without a long-double reference)\n", no_reference);
  EXPECT_EQ(violations, 0);
  EXPECT_LT(no_reference, kSamples / 1000);
  EXPECT_GE(decades.size(), 7u);  // 1 .. 1e7
}
