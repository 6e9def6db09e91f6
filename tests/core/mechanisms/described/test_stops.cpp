// Passive-joint limits and link interference of described devices
// (docs/described-mechanisms.md, "Joint limits" and "Link interference"):
// the joint angles and link positions Linkscape finds against hand geometry
// of the shipped Falcon and Delta, in IK, FK and fields, through both leg
// solvers; and the errors of malformed limits.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>

#include "core/field.h"
#include "core/interference.h"
#include "core/mechanism.h"
#include "core/preset.h"
#include "core/stability.h"
#include "tests/core/mechanisms/described/without_stops.h"

namespace linkscape {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;
using nlohmann::json;
constexpr double kDeg = M_PI / 180;

// A shipped preset after `edit` of its JSON.
Preset edited(const std::string& name, const std::function<void(json&)>& edit) {
  const Preset p = load_preset(name);
  json d = json::parse(p.description);
  edit(d);
  Preset out = p;
  out.description = d.dump();
  return out;
}

// Each leg's links without their radii (the joint limits kept).
Preset without_links(const std::string& name) {
  return edited(name, [](json& d) {
    for (json& leg : d["legs"])
      for (const char* list : {"base", "chain", "anchor"})
        for (json& step : leg[list]) step.erase("radius"), step.erase("link");
  });
}

// ---- The Falcon by hand (docs/mechanisms/falcon.md, "Model") ----------------------------

struct FalconLeg {
  double t1, t2, t3;           // thigh, shin and parallelogram angles (rad), Stamper's
  Vector3d M, K, U, L, A;      // motor axis, knee, upper and lower parallelogram joints, platform joint
};
constexpr double a = 60, b = 102.5, c = 14.43, d = 11.25, e = 11.25, f = -25, r = 40, s = -23.09;

// The design's branch (the knee bent outward); nullopt where the leg cannot reach.
std::optional<std::array<FalconLeg, 3>> falcon_by_hand(const Vector3d& p) {
  std::array<FalconLeg, 3> out;
  for (int k = 0; k < 3; ++k) {
    const double phi = (105 - 120 * k) * kDeg;
    const Vector3d u(std::cos(phi), std::sin(phi), 0), v(-std::sin(phi), std::cos(phi), 0), w(0, 0, 1);
    const double pu = u.dot(p) - r, pv = v.dot(p) - s, pw = p.z();
    const double ct3 = (pv + f) / b;
    if (std::abs(ct3) > 1) return std::nullopt;
    FalconLeg& l = out[std::size_t(k)];
    l.t3 = std::acos(ct3);
    const double K = d + e + b * std::sin(l.t3), A = pu + c, B = pw;
    const double rhs = (A * A + B * B + a * a - K * K) / (2 * a), R = std::hypot(A, B);
    if (std::abs(rhs) > R) return std::nullopt;
    l.t1 = std::atan2(B, A) - std::acos(rhs / R);
    l.t2 = std::atan2(pw - a * std::sin(l.t1), A - a * std::cos(l.t1));
    const Vector3d x1 = std::cos(l.t1) * u + std::sin(l.t1) * w, x2 = std::cos(l.t2) * u + std::sin(l.t2) * w;
    l.M = r * u + s * v;
    l.K = l.M + a * x1;
    l.U = l.K + e * x2;
    l.L = l.U + b * (std::sin(l.t3) * x2 + std::cos(l.t3) * v);
    l.A = l.L + d * x2;
    EXPECT_LT((l.A - (p + c * u + f * v)).norm(), 1e-9);  // the chain closes on the grip
  }
  return out;
}

double wrap_near(double angle_deg, double middle_deg) {
  return middle_deg + std::remainder(angle_deg - middle_deg, 360.0);
}

// The file's assumed stops: knee 10..170 deg, the parallelogram (upper joint
// -theta3) -150..-30 deg, the grip joint (theta2) 15..165 deg.
double falcon_joint_margin(const std::array<FalconLeg, 3>& legs) {
  double m = INFINITY;
  for (const FalconLeg& l : legs) {
    const double knee = wrap_near((l.t2 - l.t1) / kDeg, 90), upper = wrap_near(-l.t3 / kDeg, -90),
                 grip = wrap_near(l.t2 / kDeg, 90);
    m = std::min({m, knee - 10, 170 - knee, upper + 150, -30 - upper, grip - 15, 165 - grip});
  }
  return m;
}

bool falcon_within_travel(const std::array<FalconLeg, 3>& legs) {
  for (const FalconLeg& l : legs)
    if (const double q = std::remainder(l.t1, 2 * M_PI) / kDeg; q < -60 || q > 105) return false;
  return true;
}

// The smallest gap between a leg's links and another leg's links, motor
// arm (base origin to M, radius 12) or grip arm (p to A, radius 6); links:
// thigh 5, knee bar and ankle bar 4, the shin `shin` (mm, the file's: 4).
double falcon_clearance(const std::array<FalconLeg, 3>& legs, const Vector3d& p, double shin) {
  using interference::Capsule;
  auto chain = [shin](const FalconLeg& l) {
    return std::vector<Capsule>{{l.M, l.K, 5}, {l.K, l.U, 4}, {l.U, l.L, shin}, {l.L, l.A, 4}};
  };
  double gap = INFINITY;
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) {
      if (i == j) continue;
      std::vector<Capsule> other{{Vector3d::Zero(), legs[j].M, 12}, {p, legs[j].A, 6}};
      if (j > i) for (const Capsule& x : chain(legs[j])) other.push_back(x);
      for (const Capsule& x : chain(legs[i]))
        for (const Capsule& y : other) gap = std::min(gap, interference::clearance(x, y));
    }
  return gap;
}

const Field::NamedArray& extra(const Field& f, const std::string& name) {
  const Field::NamedArray* a = f.extra(name);
  if (!a) throw std::runtime_error("the field has no " + name);
  return *a;
}

Field field_of(const Mechanism& m, const Grid& g, const std::string& method) {
  IkOptions o;
  o.method = method;
  return *m.compute_field(g, m.home_task(), o, 2, {});
}

// ---- Joint limits -------------------------------------------------------------------------

// Over a box round the published cube, the Falcon's joint margin in the
// field is the hand geometry's, and a sample is ok exactly where the hand
// finds the legs closing within their travel and their stops.
TEST(DescribedStops, FalconJointMarginAndStatusesMatchHandGeometry) {
  const auto falcon = make_mechanism(without_links("falcon"));
  const Grid g = Grid::box({-70, -70, 50}, {70, 70, 190}, {14, 14, 14});
  const Field field = field_of(*falcon, g, "newton");
  const Field::NamedArray& margin = extra(field, "joint_margin");
  EXPECT_EQ(margin.unit, "deg");
  EXPECT_EQ(field.extra("clearance"), nullptr);  // no links given: no clearance array
  int compared = 0, beyond = 0, mismatches = 0;
  double worst = 0;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const std::size_t at = g.index(i, j, k);
        const auto legs = falcon_by_hand(g.point(i, j, k));
        if (!legs) {
          EXPECT_TRUE(std::isnan(margin.values[at])) << g.point(i, j, k).transpose();
          continue;
        }
        const double expected = falcon_joint_margin(*legs);
        if (Status(field.status[at]) == Status::NotConverged) continue;  // the numeric solver undecided
        ASSERT_TRUE(std::isfinite(margin.values[at])) << g.point(i, j, k).transpose();
        worst = std::max(worst, std::abs(margin.values[at] - expected));
        ++compared;
        beyond += expected < 0;
        if (std::abs(expected) > 1e-6) {
          const bool ok = expected > 0 && falcon_within_travel(*legs);
          mismatches += ok != (Status(field.status[at]) == Status::Ok);
          if (expected < 0) EXPECT_EQ(Status(field.status[at]), Status::OutOfLimits);
        }
      }
  std::printf("Falcon joint margin: %d samples, %d beyond a stop, worst difference %.2e deg\n", compared, beyond,
              worst);
  EXPECT_GT(compared, 800);
  EXPECT_GT(beyond, 50);
  EXPECT_LT(worst, 1e-4);  // float storage of values up to 180 deg
  EXPECT_EQ(mismatches, 0);
}

// IK names the leg and the joint beyond its stop; FK of those actuators is
// out-of-limits too, and the reach margin turns negative with it.
TEST(DescribedStops, FalconIkAndFkNameTheJointBeyondItsStop) {
  const auto falcon = make_mechanism(without_links("falcon"));
  const Vector3d p(0, 0, 60);  // every knee folded back beyond 170 deg (by hand)
  const auto legs = falcon_by_hand(p);
  ASSERT_TRUE(legs);
  ASSERT_LT(falcon_joint_margin(*legs), 0);
  ASSERT_TRUE(falcon_within_travel(*legs));
  const IkResult ik = falcon->inverse(p);
  EXPECT_EQ(ik.status, Status::OutOfLimits);
  ASSERT_EQ(ik.solutions.size(), 1u);
  EXPECT_EQ(ik.failing_part, "1");
  EXPECT_NE(ik.status_text.find("out-of-limits: leg 1 joint "), std::string::npos) << ik.status_text;
  EXPECT_NE(ik.status_text.find("beyond its range"), std::string::npos) << ik.status_text;
  EXPECT_LT(falcon->reach_margin(p), 0);
  FkOptions o;
  o.seed = VectorXd(p);
  const FkResult fk = falcon->forward(ik.solutions[0].q, o);
  EXPECT_EQ(fk.status, Status::OutOfLimits);
  EXPECT_LT((fk.x - p).norm(), 1e-8);
  EXPECT_TRUE(fk.status_text.empty()) << fk.status_text;  // eval's CSV keeps the status token
  // At home every stop holds: ok, with its margin in the readouts.
  const VectorXd home = falcon->home_task();
  EXPECT_EQ(falcon->inverse(home).status, Status::Ok);
  bool readout = false;
  for (const auto& [name, text] : falcon->readouts(falcon->home_actuators(), home))
    readout |= name == "joint margin" && text.find("° (leg ") != std::string::npos;
  EXPECT_TRUE(readout);
}

// The Delta's ball joints: the angle between each cone's axes by hand (the
// crank from the solution's actuator angles, the rod from elbow to platform
// joint), against the field of both leg solvers.
TEST(DescribedStops, DeltaBallJointConesMatchHandGeometryInBothSolvers) {
  const auto described = make_mechanism(load_preset("delta-described"));
  const auto prm = described->parameters();
  const double R = prm.at("R"), rp = prm.at("r"), La = prm.at("La");
  const Grid g = Grid::box({-12, -12, -28}, {12, 12, -4}, {10, 10, 10});
  const Field closed = field_of(*described, g, "closed"), numeric = field_of(*described, g, "newton");
  const Field bare = field_of(*make_mechanism(testing_support::without_stops(load_preset("delta-described"))), g, "closed");
  int compared = 0, beyond = 0;
  double worst = 0;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vector3d p = g.point(i, j, k);
        IkOptions o;
        o.branch = 0;
        const IkResult ik = described->inverse(p, o);
        if (ik.solutions.empty()) continue;
        const VectorXd& q = ik.solutions[0].q;
        double expected = INFINITY;
        for (int leg = 0; leg < 3; ++leg) {
          const Eigen::Matrix3d Rz = Eigen::AngleAxisd(leg * 120 * kDeg, Vector3d::UnitZ()).toRotationMatrix();
          const Vector3d crank = Rz * Vector3d(std::cos(q(leg)), 0, -std::sin(q(leg)));
          const Vector3d ydir = Rz * Vector3d::UnitY(), zdir = crank.cross(ydir).normalized();
          const Vector3d E = Rz * Vector3d(R, 0, 0) + La * crank, W = p + Rz * Vector3d(rp, 0, 0);
          const Vector3d rod = (W - E).normalized();
          // The elbow's socket: 104 deg from the crank towards -z of the crank's frame.
          const Vector3d socket = std::cos(104 * kDeg) * crank - std::sin(104 * kDeg) * zdir;
          const Vector3d platform_socket = Rz * Vector3d(-std::cos(49 * kDeg), 0, -std::sin(49 * kDeg));
          const double elbow = std::acos(std::clamp(socket.dot(rod), -1.0, 1.0)) / kDeg;
          const double wrist = std::acos(std::clamp(rod.dot(platform_socket), -1.0, 1.0)) / kDeg;
          expected = std::min({expected, 60 - elbow, 45 - wrist});
        }
        const std::size_t at = g.index(i, j, k);
        for (const Field* f : {&closed, &numeric}) {
          ASSERT_NEAR(extra(*f, "joint_margin").values[at], expected, 1e-4) << p.transpose();
          if (std::abs(expected) < 1e-6) continue;
          // Ok exactly where the device without cones is ok and every cone holds.
          const bool ok = Status(bare.status[at]) == Status::Ok && expected > 0;
          EXPECT_EQ(Status(f->status[at]) == Status::Ok, ok) << p.transpose();
        }
        ++compared;
        beyond += expected < 0;
        worst = std::max(worst, std::abs(extra(closed, "joint_margin").values[at] - expected));
      }
  std::printf("Delta cones: %d samples, %d beyond a cone, worst difference %.2e deg\n", compared, beyond, worst);
  EXPECT_GT(compared, 300);
  EXPECT_GT(beyond, 30);
}

// The cones are centred on the rods' directions at home: home stays ok.
TEST(DescribedStops, DeltaHomeIsWithinItsCones) {
  const auto described = make_mechanism(load_preset("delta-described"));
  EXPECT_EQ(described->inverse(described->home_task()).status, Status::Ok);
}

// A universal joint's two axis ranges: the Stewart platform's leg 1 with
// U1 limited to +-25 deg on each axis, against the angles that point the
// axis of its slide along the leg by hand (R_x(a) R_y(b) z = leg direction).
TEST(DescribedStops, UniversalJointRangesMatchHandGeometry) {
  const auto stewart = make_mechanism(edited("stewart", [](json& d) {
    d["legs"][0]["chain"][0]["ranges_deg"] = {{-25, 25}, {-25, 25}};
  }));
  const auto prm = stewart->parameters();
  const double rb = prm.at("rb"), rp = prm.at("rp"), sb = prm.at("sb"), sp = prm.at("sp");
  const Grid g = Grid::box({-15, -15, 5}, {15, 15, 22}, {8, 8, 8});
  const Field field = field_of(*stewart, g, "closed");
  const Field::NamedArray& margin = extra(field, "joint_margin");
  const Eigen::Matrix3d to_leg = Eigen::AngleAxisd(sb / 2 * kDeg, Vector3d::UnitZ()).toRotationMatrix();
  const Vector3d B = to_leg.transpose() * Vector3d(rb, 0, 0);
  int compared = 0, beyond = 0;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vector3d p = g.point(i, j, k);
        const std::size_t at = g.index(i, j, k);
        if (std::isnan(margin.values[at])) continue;  // does not assemble
        const Vector3d P = p + Eigen::AngleAxisd((-60 + sp / 2) * kDeg, Vector3d::UnitZ()) * Vector3d(rp, 0, 0);
        const Vector3d dir = (to_leg * (P - B)).normalized();
        const double alpha = std::atan2(-dir.y(), dir.z()) / kDeg, beta = std::asin(dir.x()) / kDeg;
        const double expected = std::min({alpha + 25, 25 - alpha, beta + 25, 25 - beta});
        ASSERT_NEAR(margin.values[at], expected, 1e-4) << p.transpose();
        if (expected < -1e-6) EXPECT_EQ(Status(field.status[at]), Status::OutOfLimits) << p.transpose();
        ++compared;
        beyond += expected < 0;
      }
  std::printf("Stewart U1 ranges: %d samples, %d beyond\n", compared, beyond);
  EXPECT_GT(compared, 100);
  EXPECT_GT(beyond, 10);
}

// The sweeps towards the singular sets follow the geometry: the cones that
// cut the described Delta's workspace do not cut them (the same rows as the
// Delta without cones).
TEST(DescribedStops, StabilitySweepsIgnoreTheStops) {
  stability::SweepOptions o;
  o.eps_min = 1e-4;
  o.base_points = 1;
  const auto with = make_mechanism(load_preset("delta-described"))->stability_sweeps(o);
  const auto without =
      make_mechanism(testing_support::without_stops(load_preset("delta-described")))->stability_sweeps(o);
  ASSERT_EQ(with.size(), without.size());
  ASSERT_FALSE(with.empty());
  for (std::size_t i = 0; i < with.size(); ++i) {
    EXPECT_EQ(with[i].distance, without[i].distance) << i;
    EXPECT_EQ(with[i].status, without[i].status) << i;
  }
}

// A planar device's field is one layer copied along z: its joint margin too.
TEST(DescribedStops, APlanarDevicesMarginIsExtrudedWithItsField) {
  const auto five_bar = make_mechanism(edited("five-bar", [](json& d) {
    d["legs"][0]["chain"][2]["range_deg"] = {20, 160};  // elbow1
  }));
  const Grid g = Grid::box({-12, 2, -1}, {12, 26, 1}, {16, 16, 3});
  const Field f = field_of(*five_bar, g, "closed");
  const Field::NamedArray& margin = extra(f, "joint_margin");
  ASSERT_EQ(margin.values.size(), g.size());
  int finite = 0, beyond = 0;
  for (int j = 0; j < g.dims[1]; ++j)
    for (int i = 0; i < g.dims[0]; ++i) {
      const float m0 = margin.values[g.index(i, j, 0)];
      for (int k = 1; k < g.dims[2]; ++k) {
        const float mk = margin.values[g.index(i, j, k)];
        EXPECT_TRUE(mk == m0 || (std::isnan(mk) && std::isnan(m0)));
      }
      finite += std::isfinite(m0);
      beyond += m0 < 0;
    }
  EXPECT_GT(finite, 50);
  EXPECT_GT(beyond, 5);
}

// ---- Link interference -----------------------------------------------------------------------

// The Falcon's clearance in the field is the hand geometry's smallest gap
// between its links' capsules; where it is negative the sample is
// out-of-limits and IK names the two links. With the file's radii the legs
// keep apart over the box; with shins of 16 mm radius they collide.
class FalconClearance : public ::testing::TestWithParam<double> {};

TEST_P(FalconClearance, MatchesHandGeometry) {
  const double shin = GetParam();
  const auto links_only = make_mechanism(edited("falcon", [shin](json& d) {
    for (json& leg : d["legs"])
      for (json& step : leg["chain"]) {
        if (!step.value("actuated", false)) step.erase("range_deg");
        if (step.value("link", "") == "shin") step["radius"] = shin;
      }
  }));
  const Grid g = Grid::box({-90, -90, 20}, {90, 90, 200}, {12, 12, 12});
  const Field field = field_of(*links_only, g, "newton");
  const Field::NamedArray& gap = extra(field, "clearance");
  EXPECT_EQ(gap.unit, "mm");
  EXPECT_EQ(field.extra("joint_margin"), nullptr);
  int compared = 0, colliding = 0;
  double worst = 0;
  Vector3d collision = Vector3d::Constant(NAN);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Vector3d p = g.point(i, j, k);
        const auto legs = falcon_by_hand(p);
        const std::size_t at = g.index(i, j, k);
        if (!legs || Status(field.status[at]) == Status::NotConverged) continue;
        const double expected = falcon_clearance(*legs, p, shin);
        worst = std::max(worst, std::abs(gap.values[at] - expected));
        ++compared;
        if (expected < -1e-6) {
          ++colliding;
          EXPECT_EQ(Status(field.status[at]), Status::OutOfLimits) << p.transpose();
          if (falcon_within_travel(*legs)) collision = p;
        }
      }
  std::printf("Falcon clearance (shin radius %g mm): %d samples, %d colliding, worst difference %.2e mm\n", shin,
              compared, colliding, worst);
  EXPECT_GT(compared, 500);
  EXPECT_LT(worst, 1e-4);
  if (shin == 4) return;
  EXPECT_GT(colliding, 10);
  ASSERT_TRUE(collision.allFinite()) << "no collision within the actuators' travel";
  // The window's readouts name the nearest pair at a pose that holds.
  bool readout = false;
  for (const auto& [name, text] : links_only->readouts(links_only->home_actuators(), links_only->home_task()))
    readout |= name == "clearance" && text.find(" mm (leg ") != std::string::npos && text.find(" to leg ") != std::string::npos;
  EXPECT_TRUE(readout);
  const IkResult ik = links_only->inverse(collision);
  EXPECT_EQ(ik.status, Status::OutOfLimits);
  EXPECT_NE(ik.status_text.find(" hits leg "), std::string::npos) << ik.status_text;
  std::printf("a collision: at (%g, %g, %g) mm: %s\n", collision.x(), collision.y(), collision.z(),
              ik.status_text.c_str());
}

INSTANTIATE_TEST_SUITE_P(DescribedStops, FalconClearance, ::testing::Values(4.0, 16.0));

// ---- Errors ----------------------------------------------------------------------------------

std::string error_of(const std::string& name, const std::function<void(json&)>& edit) {
  try {
    make_mechanism(edited(name, edit));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

void expect_error(const std::string& message, const std::vector<std::string>& parts) {
  for (const std::string& p : parts) EXPECT_NE(message.find(p), std::string::npos) << "'" << p << "' not in: " << message;
}

TEST(DescribedStops, MalformedLimitsAreRefusedNamingThePlace) {
  auto chain = [](int step) { return [step](json& d) -> json& { return d["legs"][0]["chain"][std::size_t(step)]; }; };
  const auto knee = chain(2), elbow = chain(2);
  expect_error(error_of("falcon", [&](json& d) { knee(d)["range_deg"] = {120, 30}; }),
               {"chain[2] (joint \"knee1\").range_deg", "needs lo < hi"});
  expect_error(error_of("falcon", [&](json& d) { knee(d)["range_deg"] = {-200, 200}; }),
               {"knee1", "spans at most 360 deg"});
  expect_error(error_of("delta-described", [&](json& d) { elbow(d)["cone"]["half_angle_deg"] = 180; }),
               {"chain[2] (joint \"elbow1\").cone.half_angle_deg", "must lie in (0, 180)"});
  expect_error(error_of("delta-described", [&](json& d) { elbow(d)["cone"]["half_angle_deg"] = 0; }),
               {"cone.half_angle_deg", "must lie in (0, 180)"});
  expect_error(error_of("delta-described", [&](json& d) { elbow(d)["cone"]["axis"] = {0, 0, 2}; }),
               {"cone.axis", "not a unit vector"});
  expect_error(error_of("delta-described", [&](json& d) { elbow(d)["cone"]["width"] = 3; }),
               {"cone", "unknown key 'width'"});
  expect_error(error_of("delta-described", [&](json& d) { elbow(d)["range_deg"] = {0, 10}; }),
               {"elbow1", "unknown key 'range_deg'"});
  expect_error(error_of("falcon", [&](json& d) { knee(d)["cone"] = {{"axis", {1, 0, 0}}, {"half_angle_deg", 30}}; }),
               {"knee1", "unknown key 'cone'"});
  expect_error(error_of("falcon", [&](json& d) { chain(1)(d)["radius"] = -1; }),
               {"chain[1].radius", "must be positive"});
  expect_error(error_of("falcon", [&](json& d) { d["legs"][0]["base"][0]["radius"] = 3; }),
               {"base[0]", "unknown key 'radius'"});
  expect_error(error_of("delta-described", [&](json& d) { chain(1)(d)["link"] = "crank"; }),
               {"chain[1]", "needs its \"radius\""});
  expect_error(error_of("hexapod-rus", [&](json& d) {
                 for (json& step : d["legs"][0]["chain"])
                   if (step.value("joint", "") == "universal") step["ranges_deg"] = {{0, 10}};
               }),
               {"ranges_deg", "must be two ranges"});
}

}  // namespace
}  // namespace linkscape
