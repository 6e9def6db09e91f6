// The compiled Delta's ball-joint cones (core/mechanisms/delta/stops.h): the
// same as the described Delta's, in IK, FK, fields, the switch, the preset
// reader and verify.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <map>
#include <sstream>

#include "core/mechanism.h"
#include "core/mechanisms/delta/delta.h"
#include "core/mechanisms/delta/field.h"
#include "core/mechanisms/delta/mechanism.h"
#include "core/mechanisms/delta/stops.h"
#include "core/preset.h"
#include "core/simd.h"
#include "core/stability.h"
#include "core/task.h"
#include "core/verify/verify.h"
#include "tests/core/simd_targets.h"

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

// The window's read-out of the nearest cone: the described Delta's, word for
// word, at poses within and beyond the cones; none with the cones off.
TEST(DeltaStops, ReadoutIsTheDescribedDeltas) {
  const auto compiled = linkscape::make_mechanism(delta_preset(true));
  const auto described = linkscape::make_mechanism(load_preset("delta-described"));
  const Vector3d home = compiled->home_task();
  int compared = 0, beyond = 0;
  for (int i = -4; i <= 4; i += 2)
    for (int j = -4; j <= 4; j += 2)
      for (int k = -4; k <= 4; k += 2) {
        // Off the device's mirror planes, where two legs' cones tie and either may be named.
        const VectorXd x = home + Vector3d(i, j, k) * 1.5 + Vector3d(0.37, 0.23, 0);
        const linkscape::IkResult ik = compiled->inverse(x, {});
        if (ik.solutions.empty()) continue;
        const VectorXd q = ik.solutions[0].q;
        const auto mine = compiled->readouts(q, x);
        auto theirs = described->readouts(q, x);
        std::erase_if(theirs, [](const auto& r) { return r.first == "mobility"; });
        ASSERT_FALSE(mine.empty()) << x.transpose();
        EXPECT_EQ(mine, theirs) << x.transpose();
        EXPECT_EQ(mine[0].first, "joint margin");
        ++compared;
        beyond += ik.status == Status::OutOfLimits && mine.size() == 2;
      }
  EXPECT_GE(compared, 20);
  EXPECT_GE(beyond, 3);
  const auto plain = linkscape::make_mechanism(delta_preset(false));
  EXPECT_TRUE(plain->readouts(plain->home_actuators(), home).empty());
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
          if (f->status[n] == std::uint8_t(Status::Ok)) {
            EXPECT_EQ(ik.status, Status::Ok) << n;
          }
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

// The vector kernels' cones (field_simd.cpp) against the scalar kernel's
// (cones_of_sample, the reference), on the best target and the portable
// baseline (the last of simd::available_targets): random designs, branches
// and cones (some narrow enough to cut most of the workspace, some on one
// joint type only), boxes over the workspace and rows across a cone's
// boundary in steps of 1e-12 of the size and of a few ulps. Statuses
// identical, joint margins and the reach margins the cones decide equal or
// one float step apart, or near 0 within 1e-14 size / Lb rad (the rounding
// of the angles, here and in the reference alike); the other reach margins
// within the kernel's own tolerance (tests/core/mechanisms/delta/test_field.cpp).
using ConeCase = simd_test::FieldCase<Model, FieldRequest>;

Model random_coned_model(std::mt19937_64& rng, int c) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Model m;
  m.R = 4 + 8 * unit(rng);
  m.r = 6 * unit(rng);
  m.La = 4 + 8 * unit(rng);
  m.Lb = m.La * (0.8 + 1.5 * unit(rng));
  for (auto& range : m.q_limits) range = c % 3 == 0 ? Interval{-std::numbers::pi, std::numbers::pi} : Interval{-2 * unit(rng), 2 * unit(rng)};
  if (c % 2 == 0) m.q_limits[2] = m.q_limits[1];  // the mirror in y holds with branches 0, 1, 6, 7
  const bool narrow = c % 4 == 0;
  m.elbow_axis = std::numbers::pi * unit(rng);
  m.wrist_axis = std::numbers::pi * unit(rng);
  m.elbow_cone = (narrow ? 15 + 20 * unit(rng) : 40 + 80 * unit(rng)) * kDeg;
  m.wrist_cone = (narrow ? 15 + 20 * unit(rng) : 40 + 80 * unit(rng)) * kDeg;
  if (c % 5 == 1) m.elbow_cone = std::numbers::pi;  // no elbow cone
  if (c % 5 == 2) m.wrist_cone = std::numbers::pi;  // no wrist cone
  return m;
}

// The reference's cone outcome at p: NaN margin (no pose), within or beyond.
int cone_side(const Model& m, const FieldRequest& r, const Vector3d& p) {
  FieldSample s = sample_point(m, p, r);
  const float margin = cones_of_sample(m, p, r, s);
  return std::isnan(margin) ? 0 : margin < 0 ? 1 : 2;
}

std::vector<ConeCase> cone_cases(int& beyond_rows) {
  std::vector<ConeCase> out;
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  beyond_rows = 0;
  for (int c = 0; c < 16; ++c) {
    const Model m = random_coned_model(rng, c);
    FieldRequest r;
    // Even designs have legs 1 and 2 alike: branches with their elbows alike too, where the mirror holds.
    r.ik.branch = c % 2 == 0 ? std::array{0, 1, 6, 7}[c / 2 % 4] : c % kBranchCount;
    const double s = m.size();
    const Vector3d centre(0, 0, -0.5 * s), half(0.8 * s, 0.8 * s, 0.8 * s);
    const int n = 15 + c % 3;
    r.grid = Grid::box(centre - half, centre + half, {n, n, n});
    // y = -+y_j exactly (a spacing of 40 bits): the mirrored kernel's rows.
    r.grid.spacing.y() = std::ldexp(std::round(std::ldexp(2 * half.y() / n, 40)), -40);
    r.grid.origin.y() = -0.5 * n * r.grid.spacing.y();
    out.push_back({"design " + std::to_string(c), m, r});
    int rows = 0;
    for (int k = 0; k < 3000 && rows < 3; ++k) {
      const auto random = [&] { return Vector3d(2 * unit(rng) - 1, 2 * unit(rng) - 1, 2 * unit(rng) - 1); };
      Vector3d a = centre + half.cwiseProduct(random()), b = a + 0.3 * s * random();
      const int sa = cone_side(m, r, a), sb = cone_side(m, r, b);
      if (sa == 0 || sb == 0 || sa == sb) continue;
      const auto same_as_a = [&](const Vector3d& p) { return cone_side(m, r, p) == sa; };
      simd_test::bisect(a, b, same_as_a, 200, 1e-14 * s);
      ConeCase row{"design " + std::to_string(c) + " cone boundary " + std::to_string(k), m, r};
      row.request.grid = simd_test::row_through(0.5 * (a + b), 0, 1e-12 * s, 41);
      out.push_back(row);
      simd_test::bisect(a, b, same_as_a, 80);
      row.name += ", ulp steps";
      row.request.grid = simd_test::row_through(0.5 * (a + b), 0, 4 * simd_test::kUlp * std::max(std::abs(a.x()), 1e-3 * s), 41);
      out.push_back(row);
      ++rows;
    }
    beyond_rows += rows;
  }
  return out;
}

bool same_or_next(float a, float b) { return a == b || std::nextafter(a, b) == b || (std::isnan(a) && std::isnan(b)); }

// Equal or one float step apart, or near 0 within an absolute `slack` (the
// kernel's angles and the reference's differ by rounding: about 1e-15 size
// / Lb rad).
bool same_to(float a, float b, double slack) { return same_or_next(a, b) || std::abs(double(a) - double(b)) <= slack; }

// Compares f with the reference field `want`; returns the number of failures (the first few reported).
int compare_cones(const ConeCase& c, const Field& f, const Field& want, const std::string& label, long& beyond) {
  const Field::NamedArray *joint = f.extra("joint_margin"), *joint_want = want.extra("joint_margin");
  if (!joint || !joint_want) {
    ADD_FAILURE() << label << ", " << c.name << ": no joint margin";
    return 1;
  }
  const double size = c.model.size();
  const double slack_rad = 1e-14 * size / c.model.Lb;  // a hundredth of the band where the reference decides
  int failures = 0;
  for (std::size_t i = 0; i < f.status.size(); ++i) {
    const float jm = joint_want->values[i], rm = want.reach_margin[i];
    beyond += jm < 0;
    // Where the cone decides the reach margin, one float step; elsewhere the kernel's own tolerance.
    const bool cone_decides = !std::isnan(jm) && float(size * jm * std::numbers::pi / 180) == rm;
    const bool reach_ok = same_to(f.reach_margin[i], rm, size * slack_rad) ||
                          (!cone_decides && simd_test::rounds_within(f.reach_margin[i], rm, 1e-13 * size + std::abs(rm) * 0x1p-24));
    const bool ok = f.status[i] == want.status[i] && f.reachable[i] == want.reachable[i] &&
                    std::isinf(f.cond[i]) == std::isinf(want.cond[i]) &&
                    same_to(joint->values[i], jm, slack_rad * 180 / std::numbers::pi) && reach_ok;
    const auto& dims = c.request.grid.dims;
    const int x = int(i % dims[0]), y = int(i / dims[0] % dims[1]), z = int(i / dims[0] / dims[1]);
    if (!ok && ++failures <= 5)
      ADD_FAILURE() << label << ", " << c.name << ": sample " << i << " at " << c.request.grid.point(x, y, z).transpose()
                    << ": status " << int(f.status[i]) << " vs " << int(want.status[i]) << ", joint margin "
                    << joint->values[i] << " vs " << jm << ", reach margin " << f.reach_margin[i] << " vs " << rm;
  }
  return failures;
}

TEST(DeltaStops, VectorKernelsConesAreTheReferences) {
  int boundary_rows = 0;
  const std::vector<ConeCase> all = cone_cases(boundary_rows);
  EXPECT_GT(boundary_rows, 20);
  RecordProperty("rows across a cone's boundary", std::to_string(boundary_rows));
  std::vector<Field> reference;
  for (const ConeCase& c : all) reference.push_back(simd_test::field_of(c, FieldKernel::Scalar));
  const std::vector<std::string> targets = simd::available_targets();
  ASSERT_FALSE(targets.empty());
  std::vector<std::string> chosen{targets.front()};
  if (targets.back() != targets.front()) chosen.push_back(targets.back());  // the portable baseline (EMU128 or SCALAR)
  RecordProperty("targets", chosen.size() == 2 ? chosen[0] + " " + chosen[1] : chosen[0]);
  for (const std::string& target : chosen) {
    const simd_test::TargetLimit limit(target);
    long beyond = 0, samples = 0, narrow_beyond = 0, narrow_samples = 0;
    int mirrored = 0;
    for (std::size_t k = 0; k < all.size(); ++k) {
      const ConeCase& c = all[k];
      const long before = beyond;
      EXPECT_EQ(compare_cones(c, simd_test::field_of(c, FieldKernel::Vector), reference[k], target, beyond), 0);
      samples += long(reference[k].status.size());
      // The design boxes with narrow cones: most solved samples beyond one.
      if (c.name == "design 0" || c.name == "design 4" || c.name == "design 8" || c.name == "design 12") {
        narrow_beyond += beyond - before;
        narrow_samples += std::count_if(reference[k].status.begin(), reference[k].status.end(),
                                        [](std::uint8_t s) { return s != std::uint8_t(Status::Unreachable); });
      }
      if (!mirror_holds(c.model, c.request)) continue;
      ++mirrored;
      long ignored = 0;
      EXPECT_EQ(compare_cones(c, simd_test::field_of(c, FieldKernel::VectorMirrored), reference[k], target + " mirrored", ignored), 0);
    }
    EXPECT_GE(mirrored, 4) << target;
    EXPECT_GT(beyond, samples / 20) << target;
    EXPECT_GT(narrow_beyond, narrow_samples / 2) << target;
    RecordProperty(target + " samples", std::to_string(samples));
    RecordProperty(target + " beyond a cone", std::to_string(beyond));
  }
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
      parse_preset(R"({"mechanism": "delta", "length_unit": "cm", "parameters": {"R": 9.5, "r": 5.445, "La": 8, "Lb": 17},
                       "stops": )" + stops + "}",
                   "test");
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

// The stability sweeps approach the legs' singular sets on the linkage
// alone: with the shipped cones every sample was out of limits and the
// bench measured nothing. Each set's sweep must reach down to small eps.
TEST(DeltaStops, StabilitySweepsMeasureTheLinkageNotItsStops) {
  const auto device = linkscape::make_mechanism(linkscape::load_preset("delta"));
  ASSERT_TRUE(device->info().extra_fields.size() > 0);  // the preset states its cones
  const std::vector<linkscape::stability::SweepRow> rows = device->stability_sweeps({});
  std::map<std::string, double> smallest_ok;
  for (const linkscape::stability::SweepRow& r : rows) {
    if (r.status != linkscape::Status::Ok) continue;
    auto [it, added] = smallest_ok.emplace(linkscape::stability::path_label(r), r.eps);
    if (!added) it->second = std::min(it->second, r.eps);
  }
  ASSERT_EQ(smallest_ok.size(), 3u);  // leg-1, leg-2, leg-3
  for (const auto& [path, eps] : smallest_ok) EXPECT_LE(eps, 1e-8) << path;
}
