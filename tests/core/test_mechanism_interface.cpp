// Every registered device keeps the promises of core/mechanism.h: a
// consistent description, IK and FK that invert each other, a Jacobian that
// matches finite differences of FK, fields that agree with point-wise
// evaluation, and a skeleton that fits its model.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <random>
#include <set>

#include "core/mechanism.h"
#include "core/preset.h"

using namespace linkscape;
using Eigen::VectorXd;

namespace {

std::shared_ptr<const Mechanism> shipped(const std::string& name) { return make_mechanism(load_preset(name)); }

class EveryDevice : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(EveryDevice, DescriptionIsConsistent) {
  const auto m = shipped(GetParam());
  const MechanismInfo& info = m->info();
  EXPECT_EQ(info.name, GetParam());
  EXPECT_GE(info.task.size(), 3u);
  EXPECT_EQ(info.task[0].name, "x");
  EXPECT_EQ(info.task[1].name, "y");
  EXPECT_EQ(info.task[2].name, "z");
  for (const auto* list : {&info.parameters, &info.actuators, &info.task}) {
    std::set<std::string> names;
    for (const Quantity& q : *list) {
      EXPECT_TRUE(names.insert(q.name).second) << "repeated name " << q.name;
      EXPECT_LE(q.range.lo, q.range.hi) << q.name;
    }
  }
  EXPECT_FALSE(info.ik_methods.empty());
  EXPECT_FALSE(info.fk_methods.empty());
  EXPECT_FALSE(info.measures.empty());
  EXPECT_FALSE(info.branches.empty());
  EXPECT_FALSE(info.singular_sets.empty());
  for (const auto& [name, value] : m->parameters()) EXPECT_TRUE(std::isfinite(value)) << name;
  // The preset's parameters are the description's.
  std::set<std::string> described;
  for (const Quantity& q : info.parameters) described.insert(q.name);
  for (const auto& [name, value] : m->parameters()) EXPECT_TRUE(described.count(name)) << name;
}

TEST_P(EveryDevice, HomeIsReachableAndForwardInvertsInverse) {
  const auto m = shipped(GetParam());
  const VectorXd x = m->home_task(), q = m->home_actuators();
  FkOptions fo;
  fo.seed = x;
  const FkResult fk = m->forward(q, fo);
  ASSERT_EQ(fk.status, Status::Ok);
  EXPECT_LT((fk.x - x).norm(), 1e-9 * m->size());
  EXPECT_GT(m->reach_margin(x), 0.0);
  for (const NamedItem& method : m->info().ik_methods) {
    IkOptions io;
    io.method = method.name;
    const IkResult ik = m->inverse(x, io);
    ASSERT_EQ(ik.status, Status::Ok) << method.name;
    double best = INFINITY;
    for (const IkSolution& s : ik.solutions) best = std::min(best, (s.q - q).cwiseAbs().maxCoeff());
    EXPECT_LT(best, 1e-9) << method.name;
  }
}

TEST_P(EveryDevice, RefusesNonFiniteCoordinatesByEveryMethod) {
  const auto m = shipped(GetParam());
  for (const double bad : {INFINITY, -INFINITY, NAN}) {
    for (Eigen::Index k = 0; k < m->home_actuators().size(); ++k) {
      VectorXd q = m->home_actuators();
      q(k) = bad;
      for (const NamedItem& method : m->info().fk_methods) {
        FkOptions fo;
        fo.method = method.name;
        EXPECT_THROW(m->forward(q, fo), std::invalid_argument) << method.name << " q" << k + 1 << " = " << bad;
      }
    }
    for (Eigen::Index k = 0; k < m->home_task().size(); ++k) {
      VectorXd x = m->home_task();
      x(k) = bad;
      for (const NamedItem& method : m->info().ik_methods) {
        IkOptions io;
        io.method = method.name;
        EXPECT_THROW(m->inverse(x, io), std::invalid_argument) << method.name << " " << m->info().task[std::size_t(k)].name << " = " << bad;
      }
    }
  }
}

TEST_P(EveryDevice, RandomPosesRoundTripAndJacobianMatchesFiniteDifferences) {
  const auto m = shipped(GetParam());
  const MechanismInfo& info = m->info();
  std::mt19937_64 rng(11);
  int checked = 0;
  for (int trial = 0; trial < 400 && checked < 50; ++trial) {
    // Near home, so that every device's pose stays assembled.
    VectorXd q = m->home_actuators();
    for (Eigen::Index k = 0; k < q.size(); ++k) q(k) += std::uniform_real_distribution<double>(-0.15, 0.15)(rng);
    FkOptions fo;
    fo.seed = m->home_task();
    const FkResult fk = m->forward(q, fo);
    if (fk.status != Status::Ok) continue;
    const Measures meas = m->measures(q, fk.x);
    if (meas.status != Status::Ok || !(meas.values[0] < 100)) continue;
    ++checked;
    const IkResult ik = m->inverse(fk.x, {});
    ASSERT_EQ(ik.status, Status::Ok);
    double best = INFINITY;
    for (const IkSolution& s : ik.solutions) best = std::min(best, (s.q - q).cwiseAbs().maxCoeff());
    EXPECT_LT(best, 1e-8) << "trial " << trial;
    // J = dx/dq where every task coordinate is driven (3-DOF devices, and
    // 6-DOF ones whose rotation rows are the angular velocity in the base
    // frame: the differences of R = Rz(rz) Ry(ry) Rx(rx) give it as the
    // axial vector of dR R^T).
    if (info.task.size() != info.actuators.size()) continue;
    std::array<int, 3> rotation = {-1, -1, -1};
    for (std::size_t t = 0; t < info.task.size(); ++t)
      for (int a = 0; a < 3; ++a)
        if (info.task[t].name == std::string("r") + "xyz"[a]) rotation[std::size_t(a)] = int(t);
    const bool turns = rotation[0] >= 0 && rotation[1] >= 0 && rotation[2] >= 0;
    auto rotation_of = [&](const VectorXd& x) {
      return (Eigen::AngleAxisd(x(rotation[2]), Eigen::Vector3d::UnitZ()) *
              Eigen::AngleAxisd(x(rotation[1]), Eigen::Vector3d::UnitY()) *
              Eigen::AngleAxisd(x(rotation[0]), Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
    };
    const Eigen::MatrixXd J = m->jacobian(q, fk.x);
    const double h = 1e-6;
    for (Eigen::Index k = 0; k < q.size(); ++k) {
      VectorXd qp = q, qm = q;
      qp(k) += h;
      qm(k) -= h;
      fo.seed = fk.x;
      const VectorXd xp = m->forward(qp, fo).x, xm = m->forward(qm, fo).x;
      VectorXd column = (xp - xm) / (2 * h);
      if (turns) {
        const Eigen::Matrix3d w = (rotation_of(xp) - rotation_of(xm)) / (2 * h) * rotation_of(fk.x).transpose();
        const Eigen::Vector3d omega(w(2, 1), w(0, 2), w(1, 0));
        for (int a = 0; a < 3; ++a) column(rotation[std::size_t(a)]) = omega(a);
      }
      EXPECT_LT((J.col(k) - column).norm(), 1e-6 * J.norm()) << "column " << k;
    }
  }
  EXPECT_GE(checked, 20);
}

TEST_P(EveryDevice, FieldAgreesWithPointwiseEvaluation) {
  const auto m = shipped(GetParam());
  const VectorXd home = m->home_task();
  const auto [normal, position] = m->default_slice_plane(home);
  const Eigen::AlignedBox3d box = m->default_box();
  EXPECT_TRUE(box.contains(home.head<3>()));
  const auto [u, v] = Grid::slice_axes(normal);
  const Grid grid = Grid::slice(normal, position, box.min()(int(u)), box.max()(int(u)), box.min()(int(v)),
                                box.max()(int(v)), 24, 24);
  const std::optional<Field> field = m->compute_field(grid, home, {}, 1, {});
  ASSERT_TRUE(field.has_value());
  int reachable = 0;
  for (int k = 0; k < grid.dims[2]; ++k)
    for (int j = 0; j < grid.dims[1]; ++j)
      for (int i = 0; i < grid.dims[0]; ++i) {
        const std::size_t s = grid.index(i, j, k);
        VectorXd x = home;
        x.head<3>() = grid.point(i, j, k);
        ASSERT_FALSE(std::isnan(field->cond[s]));
        ASSERT_FALSE(std::isnan(field->reach_margin[s]));
        EXPECT_NEAR(field->reach_margin[s], m->reach_margin(x), 1e-5 * m->size());
        if (!field->reachable[s]) continue;
        ++reachable;
        const IkResult ik = m->inverse(x, {});
        ASSERT_EQ(ik.status, Status::Ok);
        const Measures meas = m->measures(ik.solutions.front().q, x);
        EXPECT_NEAR(field->cond[s], meas.values[0], 1e-5 * meas.values[0]);
      }
  EXPECT_GT(reachable, 20);
}

TEST_P(EveryDevice, SkeletonFitsItsModel) {
  const auto m = shipped(GetParam());
  const SkeletonModel model = m->skeleton_model();
  const SkeletonPose pose = m->skeleton_pose(m->home_actuators(), m->home_task());
  ASSERT_EQ(pose.X_world_body.size(), model.bodies.size());
  ASSERT_EQ(pose.states.size(), model.bodies.size());
  for (const Joint& j : model.joints) {
    ASSERT_GE(j.body, 0);
    ASSERT_LT(j.body, int(model.bodies.size()));
  }
  EXPECT_LT((pose.p_world_endpoint - m->home_task().head<3>()).norm(), 1e-9 * m->size());
  EXPECT_GT(model.scale, 0);
}

// "singular" wherever J is reported singular: along seeded rays from home
// on every branch, each sign change of det J (through 0 at a serial
// singularity, through infinity at a parallel one) is bisected to the
// floating-point edge of the singular set; where measures() says singular
// there, IK (the solution on that branch) and FK of its actuators are never
// "ok".
TEST_P(EveryDevice, StatusesAreSingularWhereJIsReportedSingular) {
  const auto m = shipped(GetParam());
  const MechanismInfo& info = m->info();
  const VectorXd home = m->home_task();
  std::mt19937_64 rng(29);
  std::normal_distribution<double> normal;
  int singular = 0;
  for (int ray = 0; ray < 150; ++ray) {
    IkOptions io;
    io.branch = ray % int(info.branches.size());
    VectorXd direction = VectorXd::Zero(home.size());
    for (int k = 0; k < 3; ++k) direction(k) = normal(rng);
    if (info.plane_z) direction(2) = 0;
    direction.normalize();
    // det J of the branch's solution at home + t size direction (NaN where none assembles).
    auto det_at = [&](double t, IkSolution* solution) {
      const VectorXd x = home + t * m->size() * direction;
      for (const IkSolution& s : m->inverse(x, io).solutions)
        if (s.branch == *io.branch && s.status != Status::Unreachable && s.status != Status::NotConverged) {
          if (solution) *solution = s;
          const Eigen::MatrixXd J = m->jacobian(s.q, x);
          return J.rows() == J.cols() ? J.determinant() : NAN;
        }
      return double(NAN);
    };
    double t0 = 0, d0 = det_at(0, nullptr);
    for (double t = 0.02; t < 1.5 && std::isfinite(d0); t += 0.02) {
      const double d1 = det_at(t, nullptr);
      if (!std::isfinite(d1)) break;
      if (d0 * d1 < 0) {
        double lo = t0, hi = t;
        for (int i = 0; i < 80; ++i) {
          const double mid = 0.5 * (lo + hi), dm = det_at(mid, nullptr);
          if (!std::isfinite(dm)) break;
          (dm * d0 > 0 ? lo : hi) = mid;
        }
        IkSolution s;
        if (!std::isfinite(det_at(lo, &s))) break;
        const VectorXd x = home + lo * m->size() * direction;
        if (m->measures(s.q, x).status != Status::Singular) break;
        ++singular;
        EXPECT_NE(s.status, Status::Ok) << "IK at " << x.transpose() << ", branch " << s.branch;
        FkOptions fo;
        fo.seed = x;
        const FkResult fk = m->forward(s.q, fo);
        EXPECT_NE(fk.status, Status::Ok) << "FK of " << s.q.transpose() << " seeded at " << x.transpose();
        break;
      }
      t0 = t;
      d0 = d1;
    }
  }
  RecordProperty("singular_points", singular);
}

// The compiled Delta with its ranges opened to the full circle reaches its
// parallel (type II) set, where the forearms are coplanar and the two
// assembly modes merge: found by bisecting q3 between actuator values that
// assemble and values that do not. Each leg's inverse is regular there, but
// J is singular, and so is the IK the device reports.
TEST(DeltaDevice, InverseIsSingularOnTheParallelSet) {
  Preset full_circle = load_preset("delta");
  for (const char* name : {"q1", "q2", "q3"}) full_circle.limits_deg[name] = {-180, 180};
  full_circle.checks.joint_limits = false;  // the linkage's own set: its ball joints' cones cut it first
  const auto m = make_mechanism(full_circle);
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> angle(-0.5, 1.2);
  int tested = 0;
  for (int attempt = 0; attempt < 2000 && tested < 20; ++attempt) {
    VectorXd q(3);
    q << angle(rng), angle(rng), -3.1;
    auto assembles = [&](double q3) {
      VectorXd qq = q;
      qq(2) = q3;
      const Status s = m->forward(qq).status;
      return s == Status::Ok || s == Status::Singular;
    };
    double lo = -3.1, hi = lo;  // an edge of the values of q3 that assemble
    for (double t = -3.1; t < 3.1 && assembles(lo) == assembles(hi); t += 0.05) hi = t;
    if (assembles(lo) == assembles(hi)) continue;
    const bool lo_assembles = assembles(lo);
    for (int k = 0; k < 100; ++k) {
      const double mid = 0.5 * (lo + hi);
      (assembles(mid) == lo_assembles ? lo : hi) = mid;
    }
    q(2) = lo_assembles ? lo : hi;
    const FkResult fk = m->forward(q);
    if (fk.status != Status::Singular || m->measures(q, fk.x).status != Status::Singular) continue;
    ++tested;
    bool found = false;
    for (int branch = 0; branch < int(m->info().branches.size()); ++branch) {
      IkOptions io;
      io.branch = branch;
      const IkResult ik = m->inverse(fk.x, io);
      for (const IkSolution& s : ik.solutions)
        if ((s.q - q).unaryExpr([](double d) { return std::remainder(d, 2 * M_PI); }).cwiseAbs().maxCoeff() < 1e-6) {
          found = true;
          EXPECT_EQ(s.status, Status::Singular) << "q " << q.transpose() << ", branch " << branch;
          EXPECT_EQ(ik.status, Status::Singular);
        }
    }
    EXPECT_TRUE(found) << q.transpose();
  }
  EXPECT_GE(tested, 10);
}

INSTANTIATE_TEST_SUITE_P(Registered, EveryDevice, ::testing::ValuesIn(registered_mechanisms()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

// The described devices shipped as files (assets/mechanisms/*.json with
// "mechanism": "described") keep the same promises.
INSTANTIATE_TEST_SUITE_P(Described, EveryDevice, ::testing::ValuesIn(described_presets()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

TEST(Registry, UnknownMechanismsListTheKnownOnes) {
  Preset p;
  p.mechanism = "stewart";
  try {
    make_mechanism(p);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("delta"), std::string::npos) << e.what();
  }
}
