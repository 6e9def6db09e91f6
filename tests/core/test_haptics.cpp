// The haptic measures (core/haptics.h) against brute force on random poses
// of every registered device: the force limits against a search over
// directions, the resolution against forward kinematics one count away, the
// reflected inertia against a search over directions, the statics (units
// included) against finite differences of forward kinematics; and the
// preset's actuator data.
#include <gtest/gtest.h>

#include <random>

#include "core/haptics.h"
#include "core/preset.h"

using namespace linkscape;
using Eigen::Matrix3Xd;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {

// The linkage as shipped, its assumed stops off: they do not change J, and the
// poses drawn stay the ones these brute-force checks were tuned on.
std::shared_ptr<const Mechanism> shipped(const std::string& name) {
  Preset preset = load_preset(name);
  preset.checks = {false, false};
  return make_mechanism(preset);
}

// Largest (sign = +1) or smallest (sign = -1) of f over unit vectors: the
// best 10 of 4000 Fibonacci-sphere directions, each refined by exhaustive
// 21 x 21 grids on the tangent plane, halving the patch until it is below
// 1e-10 rad (a grid, unlike a coordinate or gradient search, finds the sharp
// vertex of a polytope). Independent of the closed forms it checks.
template <class F>
double search_directions(F f, double sign) {
  std::vector<std::pair<double, Vector3d>> coarse;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    const double z = 1 - (2 * k + 1.0) / n, r = std::sqrt(1 - z * z), phi = k * 2.399963229728653;
    const Vector3d u(r * std::cos(phi), r * std::sin(phi), z);
    coarse.push_back({sign * f(u), u});
  }
  std::partial_sort(coarse.begin(), coarse.begin() + 10, coarse.end(),
                    [](const auto& a, const auto& b) { return a.first > b.first; });
  double best = -INFINITY;
  for (int start = 0; start < 10; ++start) {
    auto [value, u] = coarse[std::size_t(start)];
    for (double patch = 0.1; patch > 1e-10; patch *= 0.5) {
      const Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
      Vector3d centre = u;
      for (int i = -10; i <= 10; ++i)
        for (int j = -10; j <= 10; ++j) {
          const Vector3d w = (centre + patch / 10 * (i * e1 + j * e2)).normalized();
          const double v = sign * f(w);
          if (v > value) value = v, u = w;
        }
    }
    best = std::max(best, value);
  }
  return sign * best;
}

struct Pose {
  VectorXd q, x;
};

// Seeded poses near home, reachable and well away from singular sets.
std::vector<Pose> random_poses(const Mechanism& m, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Pose> out;
  for (int trial = 0; trial < 50 * count && int(out.size()) < count; ++trial) {
    VectorXd q = m.home_actuators();
    for (Eigen::Index k = 0; k < q.size(); ++k) q(k) += std::uniform_real_distribution<double>(-0.25, 0.25)(rng);
    FkOptions fo;
    fo.seed = m.home_task();
    const FkResult fk = m.forward(q, fo);
    if (fk.status != Status::Ok) continue;
    const Measures meas = m.measures(q, fk.x);
    if (meas.status != Status::Ok || !(meas.values[0] < 50)) continue;
    out.push_back({q, fk.x});
  }
  return out;
}

class HapticsOfEveryDevice : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(HapticsOfEveryDevice, ForcesResolutionAndInertiaAgreeWithBruteForce) {
  const auto m = shipped(GetParam());
  const haptics::DeviceData data = haptics::device_data(load_preset(GetParam()), m->info());
  ASSERT_TRUE(data.has_inertia());
  const double unit = data.metres_per_length_unit;
  const auto poses = random_poses(*m, 8, 3);
  ASSERT_GE(poses.size(), 8u);
  for (const haptics::TorqueRating rating : {haptics::TorqueRating::Continuous, haptics::TorqueRating::Peak}) {
    for (const Pose& p : poses) {
      const MatrixXd J = m->jacobian(p.q, p.x);
      const haptics::Measures h = haptics::measures(J, data, rating);
      const Eigen::Index n = J.cols();
      const Matrix3Xd Jp = J.topRows(3) * unit;
      VectorXd tau(n), inertia(n), count(n);
      for (Eigen::Index i = 0; i < n; ++i) {
        const auto& r = data.actuators[std::size_t(i)];
        tau(i) = rating == haptics::TorqueRating::Peak ? r.peak_torque_Nm : r.continuous_torque_Nm;
        inertia(i) = *r.rotor_inertia_kgm2;
        count(i) = 2 * M_PI / r.encoder_counts_per_rev;
      }
      // Along u, the force grows until the first actuator reaches its limit.
      auto force_along = [&](const Vector3d& u) { return 1.0 / (Jp.transpose() * u).cwiseQuotient(tau).cwiseAbs().maxCoeff(); };
      EXPECT_NEAR(h.force_iso_N, search_directions(force_along, -1), 1e-7 * h.force_iso_N);
      EXPECT_NEAR(h.force_max_N, search_directions(force_along, +1), 1e-6 * h.force_max_N);
      EXPECT_LT(h.force_iso_N, h.force_max_N);
      // Apparent mass along u: 1 / (u^T J_p M^-1 J_p^T u).
      const MatrixXd inverse_mass = Jp * inertia.cwiseInverse().asDiagonal() * Jp.transpose();
      auto mass_along = [&](const Vector3d& u) { return 1.0 / u.dot(inverse_mass * u); };
      EXPECT_NEAR(*h.inertia_kg, search_directions(mass_along, +1), 1e-7 * *h.inertia_kg);

      // The statics and the units from forward kinematics alone: a force of
      // force_iso along the binding actuator's column puts that actuator
      // exactly at its limit (tau = J^T F with J from central differences).
      MatrixXd J_fd(3, n);
      FkOptions fo;
      fo.seed = p.x;
      double largest_step_mm = 0;
      for (Eigen::Index i = 0; i < n; ++i) {
        VectorXd qp = p.q, qm = p.q;
        qp(i) += 1e-6;
        qm(i) -= 1e-6;
        J_fd.col(i) = (m->forward(qp, fo).x - m->forward(qm, fo).x).head<3>() / 2e-6 * unit;
        // One count, centred on the pose: the displacement to O(count^3).
        qp = p.q, qm = p.q;
        qp(i) += count(i) / 2;
        qm(i) -= count(i) / 2;
        const Vector3d step = (m->forward(qp, fo).x - m->forward(qm, fo).x).head<3>() * unit;
        largest_step_mm = std::max(largest_step_mm, 1e3 * step.norm());
      }
      EXPECT_NEAR(h.resolution_mm, largest_step_mm, 1e-4 * h.resolution_mm);
      Eigen::Index binding = 0;
      (J_fd.colwise().norm().transpose().cwiseQuotient(tau)).maxCoeff(&binding);
      const Vector3d F = h.force_iso_N * J_fd.col(binding).normalized();
      const VectorXd torque = J_fd.transpose() * F;
      EXPECT_NEAR(std::abs(torque(binding)), tau(binding), 1e-5 * tau(binding));
      EXPECT_LE(torque.cwiseAbs().cwiseQuotient(tau).maxCoeff(), 1 + 1e-5);
    }
  }
}

// Every haptic array of a sampled slice equals the point-wise measures; the
// samples outside the workspace fail every criterion.
TEST_P(HapticsOfEveryDevice, FieldsAgreeWithPointwiseMeasures) {
  const auto m = shipped(GetParam());
  const haptics::DeviceData data = haptics::device_data(load_preset(GetParam()), m->info());
  const VectorXd home = m->home_task();
  const auto [normal, position] = m->default_slice_plane(home);
  const Eigen::AlignedBox3d box = m->default_box();
  const auto [u, v] = Grid::slice_axes(normal);
  const Grid grid = Grid::slice(normal, position, box.min()(int(u)), box.max()(int(u)), box.min()(int(v)),
                                box.max()(int(v)), 20, 20);
  const auto field = haptics::sample_field(*m, grid, home, {}, 2, {}, &data);
  ASSERT_TRUE(field.has_value());
  const auto* iso = field->extra("force_iso");
  const auto* max = field->extra("force_max");
  const auto* res = field->extra("resolution");
  const auto* inertia = field->extra("inertia");
  ASSERT_TRUE(iso && max && res && inertia);
  EXPECT_EQ(iso->unit, "N");
  EXPECT_EQ(res->unit, "mm");
  int reachable = 0, unreachable = 0;
  for (std::size_t s = 0; s < grid.size(); ++s) {
    if (!field->reachable[s]) {
      ++unreachable;
      EXPECT_EQ(iso->values[s], 0.0f);
      EXPECT_EQ(res->values[s], INFINITY);
      continue;
    }
    ++reachable;
    VectorXd x = home;
    const int nx = grid.dims[0], ny = grid.dims[1];
    x.head<3>() = grid.point(int(s % nx), int((s / nx) % ny), int(s / (std::size_t(nx) * ny)));
    const IkResult ik = m->inverse(x, {});
    ASSERT_EQ(ik.status, Status::Ok);
    const haptics::Measures h = haptics::measures(m->jacobian(ik.solutions.front().q, x), data, {});
    EXPECT_FLOAT_EQ(iso->values[s], float(h.force_iso_N));
    EXPECT_FLOAT_EQ(max->values[s], float(h.force_max_N));
    EXPECT_FLOAT_EQ(res->values[s], float(h.resolution_mm));
    EXPECT_FLOAT_EQ(inertia->values[s], float(*h.inertia_kg));
  }
  EXPECT_GT(reachable, 20);
  EXPECT_GT(unreachable, 0);
}

INSTANTIATE_TEST_SUITE_P(Registered, HapticsOfEveryDevice, ::testing::ValuesIn(registered_mechanisms()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

// A diagonal J has every measure in closed form.
TEST(HapticMeasures, DiagonalJacobianInClosedForm) {
  haptics::DeviceData d;
  d.metres_per_length_unit = 0.01;
  for (double inertia : {1e-5, 2e-5, 4e-5}) {
    haptics::Rating r;
    r.continuous_torque_Nm = 0.2;
    r.peak_torque_Nm = 1.0;
    r.encoder_counts_per_rev = 1000;
    r.rotor_inertia_kgm2 = inertia;
    d.actuators.push_back(r);
  }
  MatrixXd J = Vector3d(10, 20, 40).asDiagonal();  // cm per rad
  const auto h = haptics::measures(J, d, haptics::TorqueRating::Continuous);
  // Actuator i alone balances F_i: F_i = tau / (J_ii in m).
  EXPECT_NEAR(h.force_iso_N, 0.2 / 0.40, 1e-12);
  EXPECT_NEAR(h.force_max_N, std::sqrt(std::pow(0.2 / 0.1, 2) + std::pow(0.2 / 0.2, 2) + std::pow(0.2 / 0.4, 2)), 1e-12);
  EXPECT_NEAR(h.resolution_mm, 1e3 * 2 * M_PI / 1000 * 0.40, 1e-12);
  // Mass along axis i: I_i / J_ii^2; largest 1e-5 / 0.01 = 1e-3 kg.
  EXPECT_NEAR(*h.inertia_kg, std::max({1e-5 / 0.01, 2e-5 / 0.04, 4e-5 / 0.16}), 1e-15);
  EXPECT_NEAR(haptics::measures(J, d, haptics::TorqueRating::Peak).force_iso_N, 1.0 / 0.40, 1e-12);
}

// Where J_p loses rank the structure holds forces along its null space:
// force_max and inertia are infinite, force_iso and resolution stay finite.
TEST(HapticMeasures, RankDeficientJacobianHoldsForcesWithoutTorque) {
  haptics::DeviceData d;
  d.actuators.assign(3, haptics::default_rating());
  MatrixXd J(3, 3);
  J << 1, 0, 1, 0, 1, 1, 0, 0, 0;  // nothing moves along z
  const auto h = haptics::measures(J, d, haptics::TorqueRating::Continuous);
  EXPECT_EQ(h.force_max_N, INFINITY);
  EXPECT_EQ(*h.inertia_kg, INFINITY);
  EXPECT_NEAR(h.force_iso_N, 0.18 / (std::sqrt(2.0) * 0.01), 1e-9);
  EXPECT_TRUE(std::isfinite(h.resolution_mm));
  EXPECT_THROW(haptics::measures(MatrixXd::Identity(3, 2), d, {}), std::invalid_argument);
}

TEST(ActuatorData, PresetsOverrideAllPerActuatorAndNameTheirProblems) {
  const std::string head = R"({"mechanism": "parallel-12r", "length_unit": "cm", "parameters": {"L1": 15, "L2": 15},)";
  Preset p = parse_preset(head + R"("actuator_data": {"source": "bench measurement",
      "all": {"peak_torque_Nm": 1, "continuous_torque_Nm": 0.5, "encoder_counts_per_rev": 4096},
      "beta": {"continuous_torque_Nm": 0.25, "rotor_inertia_kgm2": 1e-5}}})", "test");
  const auto m = make_mechanism(p);
  const haptics::DeviceData d = haptics::device_data(p, m->info());
  ASSERT_EQ(d.actuators.size(), 3u);
  EXPECT_EQ(d.actuators[0].continuous_torque_Nm, 0.5);
  EXPECT_EQ(d.actuators[1].continuous_torque_Nm, 0.25);
  EXPECT_EQ(d.actuators[2].encoder_counts_per_rev, 4096);
  EXPECT_FALSE(d.has_inertia());  // only beta's is given
  EXPECT_FALSE(d.defaults);
  EXPECT_EQ(d.source, "bench measurement");
  EXPECT_EQ(haptics::field_infos(d).size(), 3u);  // no inertia field

  auto fails = [&](const std::string& data, const std::string& expected) {
    try {
      const Preset bad = parse_preset(head + R"("actuator_data": )" + data + "}", "bad.json");
      haptics::device_data(bad, make_mechanism(bad)->info());
      ADD_FAILURE() << "accepted " << data;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  fails(R"({"all": {"peak_torque_Nm": 1, "encoder_counts_per_rev": 10}})", "no continuous_torque_Nm for actuator alpha");
  fails(R"({"delta": {"peak_torque_Nm": 1}})", "'delta' is not an actuator of parallel-12r");
  fails(R"({"all": {"peak_torque_Nm": -1}})", "actuator_data.all.peak_torque_Nm must be a positive");
  fails(R"({"all": {"torque": 1}})", "unknown key actuator_data.all.torque");
  fails(R"({"all": {"peak_torque_Nm": 1, "continuous_torque_Nm": 2, "encoder_counts_per_rev": 10}})",
        "exceeds its peak_torque_Nm");

  // No actuator data: Linkscape's defaults, labelled as such.
  const Preset bare = parse_preset(head + R"("title": "t"})", "bare");
  const haptics::DeviceData defaults = haptics::device_data(bare, m->info());
  EXPECT_TRUE(defaults.defaults);
  EXPECT_NE(defaults.source.find("Linkscape defaults"), std::string::npos);
  EXPECT_EQ(defaults.actuators.size(), 3u);
  // Every shipped preset says where its numbers come from.
  for (const std::string& name : registered_mechanisms()) {
    const Preset shipped_preset = load_preset(name);
    EXPECT_TRUE(shipped_preset.actuator_data.given) << name;
    EXPECT_TRUE(haptics::device_data(shipped_preset, make_mechanism(shipped_preset)->info()).defaults) << name;
  }
  EXPECT_THROW(haptics::metres_per("unit"), std::invalid_argument);
  // A lead is for prismatic actuators: named on a revolute one it is refused.
  fails(R"({"all": {"peak_torque_Nm": 1, "continuous_torque_Nm": 0.5, "encoder_counts_per_rev": 10},
            "beta": {"lead_m_per_rev": 0.005}})",
        "lead_m_per_rev is for prismatic actuators; beta is revolute");
}

// A prismatic actuator (the described Stewart platform's legs) is a motor
// driving its slide: with actuator data it needs the lead; without, the
// default motor drives it by a capstan of 1 cm radius, which the source says.
TEST(ActuatorData, PrismaticActuatorsAreMotorsDrivingTheirSlideByALead) {
  Preset stewart = load_preset("stewart");
  stewart.actuator_data = {};
  const auto m = make_mechanism(stewart);
  const haptics::DeviceData defaults = haptics::device_data(stewart, m->info());
  ASSERT_EQ(defaults.actuators.size(), 6u);
  EXPECT_NE(defaults.source.find("capstan of 1 cm radius"), std::string::npos) << defaults.source;
  EXPECT_DOUBLE_EQ(*defaults.actuators[0].lead_m_per_rev, 2 * M_PI * 0.01);
  EXPECT_DOUBLE_EQ(defaults.metres_per_motor_radian(0), 0.01);
  stewart.actuator_data.given = true;
  stewart.actuator_data.all = {1.0, 0.5, 4096.0, std::nullopt, std::nullopt};
  try {
    haptics::device_data(stewart, m->info());
    ADD_FAILURE() << "a prismatic actuator without a lead accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no lead_m_per_rev for actuator l1"), std::string::npos) << e.what();
  }
  stewart.actuator_data.per_actuator["l2"].lead_m_per_rev = 0.004;
  stewart.actuator_data.all.lead_m_per_rev = 0.005;
  const haptics::DeviceData rated = haptics::device_data(stewart, m->info());
  EXPECT_DOUBLE_EQ(rated.metres_per_motor_radian(0), 0.005 / (2 * M_PI));
  EXPECT_DOUBLE_EQ(rated.metres_per_motor_radian(1), 0.004 / (2 * M_PI));
  // A slide of unit column: force 2 pi tau / lead, one count lead / counts, mass I (2 pi / lead)^2.
  MatrixXd J = MatrixXd::Zero(6, 6);
  J.topLeftCorner(3, 3).setIdentity();
  J.block(3, 3, 3, 3).setIdentity();
  haptics::DeviceData one = rated;
  for (haptics::Rating& r : one.actuators) {
    r.lead_m_per_rev = 0.005;
    r.rotor_inertia_kgm2 = 2e-5;
  }
  const haptics::Measures h = haptics::measures(J, one, haptics::TorqueRating::Continuous);
  EXPECT_NEAR(h.force_iso_N, 2 * M_PI * 0.5 / 0.005, 1e-9 * h.force_iso_N);
  EXPECT_NEAR(h.resolution_mm, 1e3 * 0.005 / 4096, 1e-12);
  EXPECT_NEAR(*h.inertia_kg, 2e-5 * std::pow(2 * M_PI / 0.005, 2), 1e-9 * *h.inertia_kg);
}

// Motor ratings are design parameters too (--param, sessions, sweep): one
// given as a parameter holds for every actuator, over the file's
// actuator_data; a gear ratio n gives the joint n times the motor's torques
// and counts and n^2 its inertia; the linkage never sees them.
TEST(ActuatorData, RatingsAsParametersHoldForEveryActuatorOverTheFile) {
  Preset p = load_preset("parallel-12r");
  const auto m = make_mechanism(p);
  const haptics::DeviceData file = haptics::device_data(p, m->info());
  apply_overrides(p, {"continuous_torque_Nm=0.3", "gear_ratio=4"});
  EXPECT_EQ(make_mechanism(p)->parameters(), m->parameters());  // the linkage is unchanged
  const haptics::DeviceData d = haptics::device_data(p, m->info());
  ASSERT_EQ(d.actuators.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(d.actuators[i].continuous_torque_Nm, 4 * 0.3);
    EXPECT_DOUBLE_EQ(d.actuators[i].peak_torque_Nm, 4 * file.actuators[i].peak_torque_Nm);
    EXPECT_DOUBLE_EQ(d.actuators[i].encoder_counts_per_rev, 4 * file.actuators[i].encoder_counts_per_rev);
    EXPECT_DOUBLE_EQ(*d.actuators[i].rotor_inertia_kgm2, 16 * *file.actuators[i].rotor_inertia_kgm2);
  }
  EXPECT_NE(d.source.find("set as parameters: continuous_torque_Nm 0.3, gear_ratio 4"), std::string::npos) << d.source;
  EXPECT_FALSE(d.defaults);

  // The forces follow the torque: twice the torque, twice force_iso.
  const VectorXd x = m->home_task(), q = m->home_actuators();
  Preset doubled = p;
  apply_overrides(doubled, {"continuous_torque_Nm=0.6"});
  const MatrixXd J = m->jacobian(q, x);
  const double f1 = haptics::measures(J, d, haptics::TorqueRating::Continuous).force_iso_N;
  const double f2 = haptics::measures(J, haptics::device_data(doubled, m->info()), haptics::TorqueRating::Continuous).force_iso_N;
  EXPECT_NEAR(f2, 2 * f1, 1e-12 * f2);

  // Refused: a rating that is not positive, a name that is neither.
  for (const std::string bad : {"gear_ratio=0", "peak_torque_Nm=-1", "continuous_torque_Nm=nan"})
    EXPECT_THROW(apply_overrides(p, {bad}), std::invalid_argument) << bad;
  try {
    apply_overrides(p, {"torque=1"});
    ADD_FAILURE() << "accepted torque=1";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("motor ratings: continuous_torque_Nm"), std::string::npos) << e.what();
  }
  // A continuous rating above the peak is refused as it is given, in every
  // command (it was refused only where a haptic measure read the ratings).
  Preset over = load_preset("parallel-12r");
  EXPECT_THROW(apply_overrides(over, {"continuous_torque_Nm=100"}), std::invalid_argument);
}

// A preset without actuator_data gets the defaults, then the parameters over them.
TEST(ActuatorData, RatingsAsParametersOverTheDefaults) {
  Preset p = load_preset("stewart");
  p.actuator_data = {};
  apply_overrides(p, {"peak_torque_Nm=2", "lead_m_per_rev=0.004"});
  const haptics::DeviceData d = haptics::device_data(p, make_mechanism(p)->info());
  for (const haptics::Rating& r : d.actuators) {
    EXPECT_DOUBLE_EQ(r.peak_torque_Nm, 2);
    EXPECT_DOUBLE_EQ(r.continuous_torque_Nm, haptics::default_rating(true).continuous_torque_Nm);
    EXPECT_DOUBLE_EQ(*r.lead_m_per_rev, 0.004);
  }
  EXPECT_FALSE(d.defaults);
  EXPECT_NE(d.source.find("Linkscape defaults"), std::string::npos);
  EXPECT_NE(d.source.find("peak_torque_Nm 2"), std::string::npos) << d.source;
}

// A gear ratio in the file is the motor's side of the reduction, as a parameter is.
TEST(ActuatorData, AGearRatioInTheFileScalesTheMotorToTheJoint) {
  const Preset p = parse_preset(R"({"mechanism": "parallel-12r", "length_unit": "cm", "parameters": {"L1": 15, "L2": 15},
      "actuator_data": {"all": {"peak_torque_Nm": 0.1, "continuous_torque_Nm": 0.05, "encoder_counts_per_rev": 1000,
                                "rotor_inertia_kgm2": 1e-6, "gear_ratio": 10}}})", "geared");
  const haptics::DeviceData d = haptics::device_data(p, make_mechanism(p)->info());
  EXPECT_DOUBLE_EQ(d.actuators[0].peak_torque_Nm, 1.0);
  EXPECT_DOUBLE_EQ(d.actuators[0].continuous_torque_Nm, 0.5);
  EXPECT_DOUBLE_EQ(d.actuators[0].encoder_counts_per_rev, 10000);
  EXPECT_DOUBLE_EQ(*d.actuators[0].rotor_inertia_kgm2, 1e-4);
}
