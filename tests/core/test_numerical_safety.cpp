// Numerical safety: results that do not depend on the length scale, and
// condition numbers and statuses that are never a silent wrong answer.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/field.h"
#include "core/parallel12r.h"
#include "core/pathos2.h"

using namespace linkscape;
using Eigen::Vector3d;
using parallel12r::IkMethod;

namespace {


// Scales every decade from 1e-12 to 1e12: the sweep the kinematics must
// pass unchanged (c(J) is scale-invariant, angles are).
std::vector<double> decade_scales() {
  std::vector<double> s;
  for (int k = -12; k <= 12; ++k) s.push_back(std::pow(10.0, k));
  return s;
}

// Two floats that round the same double-precision value to within a few
// 1e-9 relative: equal to one unit in the last place of a float.
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


}  // namespace

// ---- Item: accepted scales ----------------------------------------------------

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
  EXPECT_NO_THROW(scaled_pathos2(2e-31));  // smallest length lp = 2 cm -> 4e-31 is allowed (an offset)
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
    for (IkMethod method : {IkMethod::Planar, IkMethod::Fallback})
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
