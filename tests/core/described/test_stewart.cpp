// The 6-UPS Gough-Stewart platform of assets/mechanisms/stewart.json, solved
// by the generic solver for described devices, against the platform's own
// closed forms written here from the geometry alone (none of it calls the
// solver):
//
//   base joints b_i on a circle of radius rb, in pairs sb apart about 0, 120,
//   240 deg; platform joints a_i (platform frame) on a circle of radius rp,
//   in pairs sp apart about 60, 180, 300 deg; leg 2k+1 from the base joint at
//   120k - sb/2 to the platform joint at 120k - 60 + sp/2, leg 2k+2 from
//   120k + sb/2 to 120k + 60 - sp/2 (k = 0, 1, 2).
//   IK: l_i = |p + R a_i - b_i|, R = Rz(rz) Ry(ry) Rx(rx).
//   Inverse Jacobian: dl_i = u_i . v + ((R a_i) x u_i) . w, u_i the unit leg
//   vector, v the velocity of the platform origin, w the angular velocity in
//   the base frame: rows [u_i^T, ((R a_i) x u_i)^T], J = (J^-1)^-1.
//   cond_jp, cond_jo: 2-norm condition numbers of J's translational and
//   rotational rows (3 x 6 blocks), from an SVD.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/haptics.h"
#include "core/stability.h"
#include "described_devices_support.h"

using namespace linkscape;
using namespace linkscape::described_test;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

namespace {

struct Pose {
  Vector3d p;
  Vector3d angles;  // rx, ry, rz
  Matrix3d rotation() const {
    return (Eigen::AngleAxisd(angles(2), Vector3d::UnitZ()) * Eigen::AngleAxisd(angles(1), Vector3d::UnitY()) *
            Eigen::AngleAxisd(angles(0), Vector3d::UnitX()))
        .toRotationMatrix();
  }
};

struct Stewart {
  double rb = 0, rp = 0, sb = 0, sp = 0, lmin = 0, lmax = 0;
  std::array<Vector3d, 6> base{}, platform{};

  static Stewart from_file() {
    const auto j = read_asset("stewart.json").at("parameters");
    Stewart s;
    s.rb = j.at("rb").get<double>();
    s.rp = j.at("rp").get<double>();
    s.sb = j.at("sb").get<double>();
    s.sp = j.at("sp").get<double>();
    s.lmin = j.at("lmin").get<double>();
    s.lmax = j.at("lmax").get<double>();
    for (int k = 0; k < 3; ++k) {
      const double c = 120.0 * k;
      const std::array<double, 2> tb{c - s.sb / 2, c + s.sb / 2}, tp{c - 60 + s.sp / 2, c + 60 - s.sp / 2};
      for (int e = 0; e < 2; ++e) {
        const std::size_t i = std::size_t(2 * k + e);
        s.base[i] = s.rb * Vector3d(std::cos(tb[std::size_t(e)] * kDeg), std::sin(tb[std::size_t(e)] * kDeg), 0);
        s.platform[i] = s.rp * Vector3d(std::cos(tp[std::size_t(e)] * kDeg), std::sin(tp[std::size_t(e)] * kDeg), 0);
      }
    }
    return s;
  }

  Vector3d leg(int i, const Pose& x) const {
    return x.p + x.rotation() * platform[std::size_t(i)] - base[std::size_t(i)];
  }
  Vector6d ik(const Pose& x) const {
    Vector6d l;
    for (int i = 0; i < 6; ++i) l(i) = leg(i, x).norm();
    return l;
  }
  Matrix6d inverse_jacobian(const Pose& x) const {
    Matrix6d m;
    const Matrix3d r = x.rotation();
    for (int i = 0; i < 6; ++i) {
      const Vector3d u = leg(i, x).normalized();
      m.row(i) << u.transpose(), (r * platform[std::size_t(i)]).cross(u).transpose();
    }
    return m;
  }
  // The height at which every leg is at mid-travel with the platform level
  // and centred.
  double mid_height() const {
    const double l = (lmin + lmax) / 2;
    const double s2 = (platform[0] - base[0]).squaredNorm();
    return std::sqrt(l * l - s2);
  }
};

class StewartDevice : public ::testing::Test {
 protected:
  void SetUp() override {
    geometry = Stewart::from_file();
    m = load_device("stewart.json");
    const auto& task = m->info().task;
    for (const char* name : {"x", "y", "z", "rx", "ry", "rz"}) {
      const int i = index_of_name(task, name);
      ASSERT_GE(i, 0) << name;
      index.push_back(i);
    }
  }
  VectorXd task(const Pose& x) const {
    VectorXd v = m->home_task();
    for (int k = 0; k < 3; ++k) v(index[std::size_t(k)]) = x.p(k);
    for (int k = 0; k < 3; ++k) v(index[std::size_t(k + 3)]) = x.angles(k);
    return v;
  }
  Pose pose(const VectorXd& v) const {
    Pose x;
    for (int k = 0; k < 3; ++k) x.p(k) = v(index[std::size_t(k)]);
    for (int k = 0; k < 3; ++k) x.angles(k) = v(index[std::size_t(k + 3)]);
    return x;
  }
  // Poses about home: +-5 cm across, +-4 cm up and down, +-0.35 rad about
  // each axis (spread 1; about 15% of them lie inside the legs' travel), or
  // that box scaled by `spread`.
  Pose random_pose(std::mt19937_64& rng, double spread = 1.0) const {
    std::uniform_real_distribution<double> across(-5 * spread, 5 * spread), height(-4 * spread, 4 * spread),
        angle(-0.35 * spread, 0.35 * spread);
    Pose x;
    x.p = Vector3d(across(rng), across(rng), geometry.mid_height() + height(rng));
    x.angles = Vector3d(angle(rng), angle(rng), angle(rng));
    return x;
  }
  // The smallest distance of a leg length to the ends of the travel: > 0
  // when every leg is within it.
  double travel_margin(const Vector6d& l) const {
    return std::min((l.array() - geometry.lmin).minCoeff(), (geometry.lmax - l.array()).minCoeff());
  }

  Stewart geometry;
  std::shared_ptr<const Mechanism> m;
  std::vector<int> index;
};

// bench's accuracy table: a leg's IK error is its length difference in cm
// (an angle's would be wrapped by 2 pi and read in rad).
TEST(StewartBench, MeasuresItsLegsInItsLengthUnit) {
  const auto m = load_device("stewart.json");
  methods::HarnessOptions o;
  o.samples = 40;
  o.repeats = 1;
  o.include_field = false;
  int ik_rows = 0;
  for (const methods::MethodRow& row : m->measure_methods(o)) {
    if (row.family != "ik") continue;
    ++ik_rows;
    EXPECT_EQ(row.error_unit, "cm") << row.method;
    EXPECT_EQ(row.failures, 0u) << row.method;
    EXPECT_LE(row.error_max, 1e-9) << row.method;  // cm, legs of about 20 cm
  }
  EXPECT_GE(ik_rows, 2);
}

}  // namespace

// The description: l1..l6 in the length unit with the file's travel, the
// six task coordinates, cond_jp and cond_jo, one branch; home centred and
// level at the height where every leg is at mid-travel (z = 10.040 cm).
TEST_F(StewartDevice, DescriptionAndHomeAtMidTravel) {
  const MechanismInfo& info = m->info();
  ASSERT_EQ(info.actuators.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    const Quantity& a = info.actuators[std::size_t(i)];
    const std::string expected = std::string(1, 'l') + char('1' + i);
    EXPECT_EQ(a.name, expected);
    EXPECT_EQ(a.unit, "cm");
    EXPECT_DOUBLE_EQ(a.range.lo, geometry.lmin);
    EXPECT_DOUBLE_EQ(a.range.hi, geometry.lmax);
  }
  EXPECT_GE(measure_index(*m, "cond_jp"), 0);
  EXPECT_GE(measure_index(*m, "cond_jo"), 0);
  EXPECT_EQ(info.branches.size(), 1u);

  const Pose home = pose(m->home_task());
  EXPECT_NEAR(home.p.x(), 0.0, 1e-15);
  EXPECT_NEAR(home.p.y(), 0.0, 1e-15);
  EXPECT_NEAR(home.p.z(), geometry.mid_height(), 1e-12);
  EXPECT_NEAR(home.p.z(), 10.040, 1e-3);
  EXPECT_LT(home.angles.norm(), 1e-15);
  const Vector6d l = geometry.ik(home);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(l(i), (geometry.lmin + geometry.lmax) / 2, 1e-12);
  const VectorXd qh = m->home_actuators();
  ASSERT_EQ(qh.size(), 6);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(qh(i), l(i), 1e-9 * l(i));
}

// 1.4 x 10^4 random poses (half of them in a box 0.6 times as large, where
// most are inside the travel): where every leg length |p + R a_i - b_i| is
// inside the travel (by 1e-6 of the size, away from parallel singularities)
// IK is ok with those lengths to 1e-9 relative; where a leg is outside it,
// the leg exists but violates its actuator's travel: out-of-limits
// (core/status.h), never ok.
TEST_F(StewartDevice, InverseIsTheLegLengths) {
  std::mt19937_64 rng(15101);
  const double edge = 1e-6 * m->size();
  int ok = 0, refused = 0, shown = 0;
  double worst = 0;
  std::map<std::string, int> refusals;
  for (int n = 0; n < 14000; ++n) {
    const Pose x = random_pose(rng, n % 2 == 0 ? 0.6 : 1.0);
    const Vector6d l = geometry.ik(x);
    const double margin = travel_margin(l);
    const IkResult r = m->inverse(task(x));
    if (margin < -edge) {
      EXPECT_NE(r.status, Status::Ok) << "legs " << l.transpose();
      if (r.status != Status::OutOfLimits && shown++ < 5)
        ADD_FAILURE() << "pose " << x.p.transpose() << " " << x.angles.transpose() << ": legs " << l.transpose()
                      << " (travel " << geometry.lmin << " to " << geometry.lmax << "): status "
                      << to_string(r.status) << ", failing leg " << r.failing_part << ", expected out-of-limits";
      ++refusals[std::string(to_string(r.status))];
      ++refused;
      continue;
    }
    if (margin < edge) continue;
    if (!(svd_condition(geometry.inverse_jacobian(x)) < 1e3)) continue;
    ASSERT_EQ(r.status, Status::Ok) << "pose " << x.p.transpose() << " " << x.angles.transpose() << " legs "
                                    << l.transpose();
    const VectorXd& q = r.solutions.at(0).q;
    const double e = ((q - l).array().abs() / l.array()).maxCoeff();
    EXPECT_LT(e, 1e-9) << q.transpose() << " against " << l.transpose();
    worst = std::max(worst, e);
    ++ok;
  }
  RecordProperty("ok", ok);
  RecordProperty("refused", refused);
  RecordProperty("worst_relative", scientific(worst));
  EXPECT_GT(ok, 5000);
  EXPECT_GT(refused, 5000);
  EXPECT_EQ(refusals["out-of-limits"], refused);
  std::printf("Stewart IK: %d ok, %d refused (", ok, refused);
  for (const auto& [status, count] : refusals) std::printf(" %s %d", status.c_str(), count);
  std::printf(" ), worst %.3g relative\n", worst);
}

// J from the solver against the inverse of the closed-form inverse Jacobian
// (rows [u_i, (R a_i) x u_i]), and cond_jp, cond_jo against an SVD of its
// blocks, at 10^4 poses inside the travel: 1e-9 relative.
TEST_F(StewartDevice, JacobianIsTheInverseOfTheLegScrews) {
  std::mt19937_64 rng(15102);
  const int ijp = measure_index(*m, "cond_jp"), ijo = measure_index(*m, "cond_jo");
  ASSERT_GE(ijp, 0);
  ASSERT_GE(ijo, 0);
  int compared = 0;
  double worst_j = 0, worst_jp = 0, worst_jo = 0, worst_det = 0;
  while (compared < 10000) {
    const Pose x = random_pose(rng);
    const Vector6d l = geometry.ik(x);
    if (travel_margin(l) < 1e-3) continue;
    const Matrix6d inv = geometry.inverse_jacobian(x);
    if (!(svd_condition(inv) < 1e3)) continue;
    const Matrix6d j = inv.inverse();
    const VectorXd q = l, v = task(x);
    const Eigen::MatrixXd js = m->jacobian(q, v);
    ASSERT_EQ(js.rows(), 6);
    ASSERT_EQ(js.cols(), 6);
    // Rows in the order x, y, z, then the angular velocity about x, y, z.
    const double ej = (js - j).norm() / j.norm();
    EXPECT_LT(ej, 1e-9) << "pose " << x.p.transpose() << " " << x.angles.transpose() << "\n"
                        << js << "\nagainst\n"
                        << j;
    const double cjp = svd_condition(j.topRows(3)), cjo = svd_condition(j.bottomRows(3));
    const Measures ms = m->measures(q, v);
    ASSERT_EQ(ms.status, Status::Ok);
    const double ep = std::abs(ms.values.at(std::size_t(ijp)) - cjp) / cjp;
    const double eo = std::abs(ms.values.at(std::size_t(ijo)) - cjo) / cjo;
    EXPECT_LT(ep, 1e-9) << ms.values.at(std::size_t(ijp)) << " against " << cjp;
    EXPECT_LT(eo, 1e-9) << ms.values.at(std::size_t(ijo)) << " against " << cjo;
    const double det = j.determinant();
    const double ed = std::abs(ms.det - det) / std::abs(det);
    EXPECT_LT(ed, 1e-9) << ms.det << " against " << det;
    worst_j = std::max(worst_j, ej);
    worst_jp = std::max(worst_jp, ep);
    worst_jo = std::max(worst_jo, eo);
    worst_det = std::max(worst_det, ed);
    ++compared;
  }
  RecordProperty("worst_jacobian_relative", scientific(worst_j));
  RecordProperty("worst_cond_jp_relative", scientific(worst_jp));
  RecordProperty("worst_cond_jo_relative", scientific(worst_jo));
  std::printf("Stewart J: %d poses, worst J %.3g, cond_jp %.3g, cond_jo %.3g, det %.3g (relative)\n", compared,
              worst_j, worst_jp, worst_jo, worst_det);
}

// The conditioning at home from the closed form: cond(Jp) = 1.473 and
// cond(Jo) = 1.374 (rb = 15, rp = 10, pairs 20 deg apart, z = 10.04 cm).
TEST_F(StewartDevice, ConditioningAtHome) {
  const Pose home = pose(m->home_task());
  const Matrix6d j = geometry.inverse_jacobian(home).inverse();
  const double cjp = svd_condition(j.topRows(3)), cjo = svd_condition(j.bottomRows(3));
  std::printf("Stewart home: cond_jp %.6f cond_jo %.6f\n", cjp, cjo);
  const Measures ms = m->measures(m->home_actuators(), m->home_task());
  ASSERT_EQ(ms.status, Status::Ok);
  EXPECT_NEAR(ms.values.at(std::size_t(measure_index(*m, "cond_jp"))), cjp, 1e-9 * cjp);
  EXPECT_NEAR(ms.values.at(std::size_t(measure_index(*m, "cond_jo"))), cjo, 1e-9 * cjo);
  EXPECT_NEAR(cjp, 1.473, 1e-3);
  EXPECT_NEAR(cjo, 1.374, 1e-3);
}

// FK seeded near the answer (0.5 cm and 0.03 rad off in every coordinate)
// recovers 10^4 random poses inside the travel from their closed-form leg
// lengths: position to 1e-9 of the size, R = Rz Ry Rx to 1e-9. The poses are
// kept well away from parallel singularities (cond(J^-1) < 50; at home it is
// 14): nearer, a second assembly with the same leg lengths lies within the
// seed's reach (at cond(J^-1) = 100 to 230 one was 0.03 to 0.05 cm away), and
// FK may rightly find it; every pose FK reports has the given leg lengths.
TEST_F(StewartDevice, ForwardRecoversRandomPoses) {
  std::mt19937_64 rng(15103);
  std::uniform_real_distribution<double> noise(-1, 1);
  const double size = m->size();
  int solved = 0;
  long iterations = 0;
  double worst_p = 0, worst_r = 0, worst_l = 0;
  while (solved < 10000) {
    const Pose x = random_pose(rng);
    const Vector6d l = geometry.ik(x);
    if (travel_margin(l) < 1e-3) continue;
    if (!(svd_condition(geometry.inverse_jacobian(x)) < 50)) continue;
    Pose seed = x;
    for (int k = 0; k < 3; ++k) seed.p(k) += 0.5 * noise(rng);
    for (int k = 0; k < 3; ++k) seed.angles(k) += 0.03 * noise(rng);
    FkOptions options;
    options.seed = task(seed);
    const VectorXd q = l;
    const FkResult r = m->forward(q, options);
    ASSERT_EQ(r.status, Status::Ok) << "pose " << x.p.transpose() << " " << x.angles.transpose();
    const Pose found = pose(r.x);
    const double el = ((geometry.ik(found) - l).array().abs() / l.array()).maxCoeff();
    EXPECT_LT(el, 1e-9) << "the pose FK found has legs " << geometry.ik(found).transpose() << ", not "
                        << l.transpose();
    worst_l = std::max(worst_l, el);
    const double ep = (found.p - x.p).norm(), er = (found.rotation() - x.rotation()).norm();
    EXPECT_LT(ep, 1e-9 * size) << found.p.transpose() << " against " << x.p.transpose();
    EXPECT_LT(er, 1e-9) << found.angles.transpose() << " against " << x.angles.transpose();
    worst_p = std::max(worst_p, ep);
    worst_r = std::max(worst_r, er);
    iterations += r.iterations;
    ++solved;
  }
  RecordProperty("worst_position_over_size", scientific(worst_p / size));
  RecordProperty("worst_rotation", scientific(worst_r));
  std::printf("Stewart FK: %d poses, worst position %.3g of the size, rotation %.3g, leg lengths %.3g relative, "
              "mean %.2f iterations\n",
              solved, worst_p / size, worst_r, worst_l, double(iterations) / solved);
}

// FK from home (the default seed) finds poses near home; leg lengths outside
// the travel are reported out-of-limits (core/status.h; the compiled devices
// do so, e.g. DeltaForward.ReportsActuatorRanges), never ok.
TEST_F(StewartDevice, ForwardFromHomeAndOutsideTheTravel) {
  std::mt19937_64 rng(15104);
  std::uniform_real_distribution<double> small(-1, 1);
  const Pose home = pose(m->home_task());
  for (int n = 0; n < 300; ++n) {
    Pose x = home;
    x.p += 1.5 * Vector3d(small(rng), small(rng), small(rng));
    x.angles = 0.08 * Vector3d(small(rng), small(rng), small(rng));
    const VectorXd q = geometry.ik(x);
    const FkResult r = m->forward(q);
    ASSERT_EQ(r.status, Status::Ok);
    EXPECT_LT((pose(r.x).p - x.p).norm(), 1e-9 * m->size());
    EXPECT_LT((pose(r.x).rotation() - x.rotation()).norm(), 1e-9);
  }
  std::map<std::string, int> statuses;
  for (int n = 0; n < 300; ++n) {
    VectorXd q = geometry.ik(home);
    const int leg = n % 6;
    q(leg) = (n % 2 == 0) ? geometry.lmin - 1.0 - small(rng) * 0.5 : geometry.lmax + 1.0 + small(rng) * 0.5;
    const FkResult r = m->forward(q);
    if (r.status != Status::OutOfLimits && statuses[std::string(to_string(r.status))]++ < 3)
      ADD_FAILURE() << "legs " << q.transpose() << " (travel " << geometry.lmin << " to " << geometry.lmax
                    << "): FK status " << to_string(r.status) << ", expected out-of-limits";
  }
  for (const auto& [status, count] : statuses) std::printf("Stewart FK outside the travel: %d %s\n", count, status.c_str());
  EXPECT_TRUE(statuses.empty());
}

// A field over the default box at the home orientation: every sample is ok
// exactly where the closed-form leg lengths are within the travel, and
// out-of-limits elsewhere, whatever the thread solved before it. (A leg
// closes its anchor twice, at +l and, its universal joint turned over, at
// -l; the solver once reported out-of-limits where a seed led it to -l.)
TEST_F(StewartDevice, FieldStatusIsTheLegLengthsAgainstTheTravel) {
  const Eigen::AlignedBox3d box = m->default_box();
  const Grid g = Grid::box(box.min(), box.max(), {24, 24, 24});
  const VectorXd home = m->home_task();
  int wrong = 0, ok = 0;
  for (int threads : {1, 2}) {
    const Field f = *m->compute_field(g, home, {}, threads, {});
    for (int k = 0; k < g.dims[2]; ++k)
      for (int j = 0; j < g.dims[1]; ++j)
        for (int i = 0; i < g.dims[0]; ++i) {
          Pose x = pose(home);
          x.p = g.point(i, j, k);
          const double margin = travel_margin(geometry.ik(x));
          if (std::abs(margin) < 1e-9 * m->size()) continue;  // on the travel's end
          const Status want = margin > 0 ? Status::Ok : Status::OutOfLimits;
          const Status got = Status(f.status[g.index(i, j, k)]);
          ok += got == Status::Ok;
          if (got != want && wrong++ < 5)
            ADD_FAILURE() << threads << " thread(s), at " << x.p.transpose() << ": " << to_string(got) << ", expected "
                          << to_string(want) << " (travel margin " << margin << ")";
        }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(ok, 500);
}

// The reference itself, without the solver: the rows [u_i, (R a_i) x u_i]
// give the rate of the closed-form leg lengths along a platform twist (v, w),
// the pose moving as p + v t, exp([w] t) R.
// The haptic measures are in SI whatever the file's length unit: the
// platform described in mm (the file rewritten here: lengths times 10) has
// the force_iso, force_max, resolution and inertia of the platform in cm at
// the same poses, with the preset's actuator data and with Linkscape's
// defaults. Each slide is a motor driving it with lead_m_per_rev of travel
// per revolution: against the closed form from the leg screws (J_p, the
// velocity rows of J, in m/m; the motor's column J_p e_i lead / 2 pi):
//   force_iso = min_i tau / |J_p e_i| 2 pi / lead,
//   resolution = max_i |J_p e_i| lead / counts.
TEST_F(StewartDevice, HapticMeasuresInSiDoNotDependOnTheLengthUnit) {
  nlohmann::json cm = read_asset("stewart.json");
  nlohmann::json mm = cm;
  mm["length_unit"] = "mm";
  for (const char* length : {"rb", "rp", "lmin", "lmax"}) {
    mm["parameters"][length] = 10 * cm["parameters"][length].get<double>();
    nlohmann::json& info = mm["description"]["parameter_info"][length];
    info["range"] = {10 * info["range"][0].get<double>(), 10 * info["range"][1].get<double>()};
    info["unit"] = "mm";
  }
  const double tau = 0.5, counts = 4096, rotor = 2e-5, lead = 0.005;
  const nlohmann::json rated = {
      {"source", "test"},
      {"all", {{"peak_torque_Nm", 1.0}, {"continuous_torque_Nm", tau}, {"encoder_counts_per_rev", counts},
               {"rotor_inertia_kgm2", rotor}, {"lead_m_per_rev", lead}}}};
  std::mt19937_64 rng(16011);
  for (const bool defaults : {false, true}) {
    nlohmann::json cm_file = cm, mm_file = mm;
    if (!defaults) cm_file["actuator_data"] = mm_file["actuator_data"] = rated;
    const Preset cm_preset = parse_preset(cm_file.dump(), "stewart-cm.json");
    const Preset mm_preset = parse_preset(mm_file.dump(), "stewart-mm.json");
    const auto in_cm = make_mechanism(cm_preset), in_mm = make_mechanism(mm_preset);
    const haptics::DeviceData cm_data = haptics::device_data(cm_preset, in_cm->info());
    const haptics::DeviceData mm_data = haptics::device_data(mm_preset, in_mm->info());
    int checked = 0;
    while (checked < 20) {
      const Pose x = random_pose(rng, 0.6);
      if (!(travel_margin(geometry.ik(x)) > 0.1)) continue;
      Pose x_mm = x;
      x_mm.p *= 10;
      const VectorXd task_cm = task(x), task_mm = task(x_mm);
      const IkResult ik_cm = in_cm->inverse(task_cm), ik_mm = in_mm->inverse(task_mm);
      ASSERT_EQ(ik_cm.status, Status::Ok);
      ASSERT_EQ(ik_mm.status, Status::Ok);
      const haptics::Measures a = haptics::measures(in_cm->jacobian(ik_cm.solutions[0].q, task_cm), cm_data, {});
      const haptics::Measures b = haptics::measures(in_mm->jacobian(ik_mm.solutions[0].q, task_mm), mm_data, {});
      EXPECT_NEAR(b.force_iso_N, a.force_iso_N, 1e-9 * a.force_iso_N);
      EXPECT_NEAR(b.force_max_N, a.force_max_N, 1e-8 * a.force_max_N);
      EXPECT_NEAR(b.resolution_mm, a.resolution_mm, 1e-9 * a.resolution_mm);
      ASSERT_TRUE(a.inertia_kg && b.inertia_kg);
      EXPECT_NEAR(*b.inertia_kg, *a.inertia_kg, 1e-8 * *a.inertia_kg);
      if (!defaults) {
        const Eigen::MatrixXd Jp = geometry.inverse_jacobian(x).inverse().topRows(3);
        const double longest = Jp.colwise().norm().maxCoeff();
        EXPECT_NEAR(a.force_iso_N, tau * 2 * std::numbers::pi / lead / longest, 1e-9 * a.force_iso_N);
        EXPECT_NEAR(a.resolution_mm, 1e3 * longest * lead / counts, 1e-9 * a.resolution_mm);
      }
      ++checked;
    }
  }
}

TEST(StewartReference, InverseJacobianIsTheRateOfTheLegLengths) {
  const Stewart g = Stewart::from_file();
  std::mt19937_64 rng(15100);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n = 0; n < 2000; ++n) {
    Pose x;
    x.p = Vector3d(3 * u(rng), 3 * u(rng), g.mid_height() + 3 * u(rng));
    x.angles = 0.3 * Vector3d(u(rng), u(rng), u(rng));
    Vector6d twist;
    for (int k = 0; k < 6; ++k) twist(k) = u(rng);
    const double h = 1e-6;
    auto moved = [&](double t) {
      const Matrix3d r = Eigen::AngleAxisd(t * twist.tail<3>().norm(), twist.tail<3>().normalized()).toRotationMatrix() *
                         x.rotation();
      Vector6d l;
      for (int i = 0; i < 6; ++i)
        l(i) = (x.p + t * twist.head<3>() + r * g.platform[std::size_t(i)] - g.base[std::size_t(i)]).norm();
      return l;
    };
    const Vector6d rate = (moved(h) - moved(-h)) / (2 * h);
    const Vector6d closed = g.inverse_jacobian(x) * twist;
    EXPECT_LT((rate - closed).norm(), 1e-7 * closed.norm());
  }
  // The anchors: pairs on two circles, sb and sp apart.
  EXPECT_NEAR((g.base[0] - g.base[1]).norm(), 2 * g.rb * std::sin(g.sb / 2 * kDeg), 1e-12);
  EXPECT_NEAR((g.platform[1] - g.platform[2]).norm(), 2 * g.rp * std::sin(g.sp / 2 * kDeg), 1e-12);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(g.base[std::size_t(i)].norm(), g.rb, 1e-12);
    EXPECT_NEAR(g.platform[std::size_t(i)].norm(), g.rp, 1e-12);
  }
}

// The stability sweeps reach the platform's parallel (type II) set: where
// their path ends, the leg screws written here lose rank (their smallest
// singular value shrinking in proportion to eps along the path) and det
// changes sign across it; IK along the path stays ok with its legs closed
// until the set is near.
TEST_F(StewartDevice, StabilitySweepsApproachTheParallelSet) {
  const auto& sets = m->info().singular_sets;
  const int parallel = int(std::find_if(sets.begin(), sets.end(), [](const auto& s) { return s.name == "parallel"; }) -
                           sets.begin());
  ASSERT_LT(parallel, int(sets.size()));
  const auto screws = [&](const VectorXd& x) { return geometry.inverse_jacobian(pose(x)); };
  const auto smallest = [&](const VectorXd& x) { return Eigen::JacobiSVD<Matrix6d>(screws(x)).singularValues()(5); };
  const double home_det = screws(m->home_task()).determinant();
  int paths = 0;
  for (const SingularApproach& a : m->singular_approaches()) {
    if (a.set != parallel) continue;
    for (int k = 0; k < 3; ++k, ++paths) {
      const Pose end = pose(a.target(0, k));
      std::printf("parallel set at p = (%g, %g, %g), angles (%g, %g, %g) deg\n", end.p(0), end.p(1), end.p(2),
                  end.angles(0) / kDeg, end.angles(1) / kDeg, end.angles(2) / kDeg);
      const double far = smallest(a.target(1e-2, k));
      for (const double eps : {1e-4, 1e-6})
        EXPECT_NEAR(smallest(a.target(eps, k)) / far, eps / 1e-2, 0.05 * eps / 1e-2) << "path " << k << " eps " << eps;
      EXPECT_GT(screws(a.target(1e-2, k)).determinant() * home_det, 0.0) << "path " << k << " starts on home's side";
      EXPECT_LT(screws(a.target(-1e-3, k)).determinant() * home_det, 0.0) << "path " << k << " crosses the set";
      // Forward kinematics of the slides there, from a seed nearby: the
      // closure pins no pose to 1e-10 of the size, so never ok (a pose
      // 1e-7 off had been); 1e-2 of the way back, the pose itself (the
      // paths ignore the slides' travel).
      for (const double eps : {0.0, 1e-2}) {
        const IkResult ik = m->inverse(a.target(eps, k));
        ASSERT_FALSE(ik.solutions.empty()) << "path " << k;
        FkOptions o;
        o.seed = a.target(eps + 1e-3, k);
        const FkResult fk = m->forward(ik.solutions.front().q, o);
        if (eps == 0.0) {
          EXPECT_EQ(fk.status, Status::Singular) << "path " << k;
        } else {
          EXPECT_TRUE(fk.status == Status::Ok || fk.status == Status::OutOfLimits) << "path " << k;  // slides' travel
          EXPECT_LT((fk.x - a.target(eps, k)).norm(), 1e-9 * m->size()) << "path " << k;
        }
      }
    }
  }
  EXPECT_GE(paths, 3);

  stability::SweepOptions o;
  o.eps_min = 1e-8;
  o.base_points = 2;
  int ok_rows = 0;
  for (const stability::SweepRow& r : m->stability_sweeps(o)) {
    if (r.path_name != sets[std::size_t(parallel)].name) continue;
    if (r.eps >= 1e-2) EXPECT_EQ(r.status, Status::Ok) << r.method << " eps " << r.eps;
    if (r.status != Status::Ok) continue;
    ++ok_rows;
    EXPECT_LE(r.residual, 1e-9 * m->size()) << r.method << " eps " << r.eps;
    EXPECT_GT(r.cond, 1.0);
  }
  EXPECT_GT(ok_rows, 4);
}
