// A device's links at a pose (Mechanism::link_capsules, core/interference.h):
// the closest pair's points and gap against the capsules themselves, the
// Falcon's pair against a brute-force search over every pair its rule
// checks, and its links' ends against the skeleton the view draws.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

#include "core/interference.h"
#include "core/mechanism.h"
#include "core/preset.h"

namespace linkscape {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;
using interference::Capsule;
using interference::LinkCapsules;

TEST(LinkCapsules, TheGapSpansTheClosestPairsSurfaces) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), r(0.01, 0.4);
  auto point = [&] { return Vector3d(u(rng), u(rng), u(rng)); };
  int overlapping = 0;
  for (int trial = 0; trial < 500; ++trial) {
    LinkCapsules c;
    c.links = {{{point(), point(), r(rng)}, "a", 0, true}, {{point(), point(), r(rng)}, "b", 1, true}};
    interference::set_closest(c, 0, 1);
    const Capsule &p = c.links[0].capsule, &q = c.links[1].capsule;
    EXPECT_EQ(c.clearance, interference::clearance(p, q));
    const auto gap = c.gap();
    // Each end on its capsule's surface, as far from the other as the clearance says.
    EXPECT_NEAR((gap[0] - c.axes.on_a).norm(), p.radius, 1e-12);
    EXPECT_NEAR((gap[1] - c.axes.on_b).norm(), q.radius, 1e-12);
    EXPECT_NEAR((gap[1] - gap[0]).norm(), std::abs(c.clearance), 1e-12) << "trial " << trial;
    // Along the line between the axes' closest points (crossed where they overlap).
    const Vector3d along = c.axes.on_b - c.axes.on_a;
    EXPECT_NEAR((gap[1] - gap[0]).dot(along), c.clearance * along.norm(), 1e-12);
    overlapping += c.clearance < 0;
  }
  EXPECT_GT(overlapping, 10);  // both signs were tried
}

TEST(LinkCapsules, ThePairMustBeTwoLinks) {
  LinkCapsules c;
  c.links.resize(2);
  EXPECT_THROW(interference::set_closest(c, 0, 0), std::invalid_argument);
  EXPECT_THROW(interference::set_closest(c, 0, 2), std::invalid_argument);
  EXPECT_THROW(interference::set_closest(c, -1, 1), std::invalid_argument);
  EXPECT_THROW(c.gap(), std::logic_error);
}

// Poses over the Falcon's box that it reaches, the home first.
std::vector<std::pair<VectorXd, VectorXd>> falcon_poses(const Mechanism& m, int count, unsigned seed) {
  std::vector<std::pair<VectorXd, VectorXd>> out{{m.home_actuators(), m.home_task()}};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const Eigen::AlignedBox3d box = m.default_box();
  for (int tries = 0; tries < 400 && int(out.size()) < count; ++tries) {
    VectorXd x = m.home_task();
    x.head<3>() = box.min() + Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(box.sizes());
    const IkResult ik = m.inverse(x);
    if (ik.status == Status::Ok) out.push_back({ik.solutions.front().q, x});
  }
  return out;
}

TEST(LinkCapsules, FalconsPairIsTheClosestOfThePairsItChecks) {
  const auto falcon = make_mechanism(load_preset("falcon"));
  const auto poses = falcon_poses(*falcon, 25, 3);
  ASSERT_GE(poses.size(), 15u);
  for (const auto& [q, x] : poses) {
    const std::optional<LinkCapsules> c = falcon->link_capsules(q, x);
    ASSERT_TRUE(c);
    // Every leg's motor arm, four chain links and grip arm.
    ASSERT_EQ(c->links.size(), 18u);
    // Brute force: links of different legs, at least one a chain link (fixed
    // links meet their own body's other links by construction).
    double smallest = INFINITY;
    for (std::size_t i = 0; i < c->links.size(); ++i)
      for (std::size_t j = i + 1; j < c->links.size(); ++j) {
        const auto &a = c->links[i], &b = c->links[j];
        if (a.leg == b.leg || !(a.chain || b.chain)) continue;
        smallest = std::min(smallest, interference::clearance(a.capsule, b.capsule));
      }
    ASSERT_TRUE(c->has_pair());
    EXPECT_NEAR(c->clearance, smallest, 1e-12);
    EXPECT_NEAR(c->clearance, interference::clearance(c->links[std::size_t(c->closest[0])].capsule,
                                                      c->links[std::size_t(c->closest[1])].capsule),
                1e-15);
    // The window's read-out names the same gap.
    bool read = false;
    for (const auto& [name, text] : falcon->readouts(q, x))
      if (name == "clearance") read = text.find(c->links[std::size_t(c->closest[0])].name) != std::string::npos;
    EXPECT_TRUE(read);
  }
}

// A chain link's ends are joints of the drawn skeleton: the view puts the
// capsules round the tubes it draws.
TEST(LinkCapsules, FalconsChainLinksEndAtTheSkeletonsVertices) {
  const auto falcon = make_mechanism(load_preset("falcon"));
  const SkeletonModel model = falcon->skeleton_model();
  for (const auto& [q, x] : falcon_poses(*falcon, 6, 4)) {
    const SkeletonPose pose = falcon->skeleton_pose(q, x);
    std::vector<Vector3d> vertices;
    for (std::size_t b = 0; b < model.bodies.size(); ++b)
      for (const auto& line : model.bodies[b].polylines)
        for (const Vector3d& p : line) vertices.push_back(pose.X_world_body[b] * p);
    auto nearest = [&](const Vector3d& p) {
      double d = INFINITY;
      for (const Vector3d& v : vertices) d = std::min(d, (v - p).norm());
      return d;
    };
    int chain = 0;
    for (const interference::Link& l : falcon->link_capsules(q, x)->links) {
      if (!l.chain) continue;
      ++chain;
      EXPECT_LT(nearest(l.capsule.a), 1e-9) << l.name;
      EXPECT_LT(nearest(l.capsule.b), 1e-9) << l.name;
    }
    EXPECT_EQ(chain, 12);
  }
}

TEST(LinkCapsules, DevicesWithoutLinkRadiiHaveNone) {
  for (const char* name : {"parallel-12r", "delta", "five-bar", "delta-described"}) {
    const auto m = make_mechanism(load_preset(name));
    EXPECT_FALSE(m->link_capsules(m->home_actuators(), m->home_task())) << name;
  }
  // PATHOS-II's assumed radii switched off.
  Preset pathos2 = load_preset("pathos2");
  pathos2.checks.interference = false;
  const auto m = make_mechanism(pathos2);
  EXPECT_FALSE(m->link_capsules(m->home_actuators(), m->home_task()));
}

TEST(LinkCapsules, APoseThatDoesNotAssembleIsRefused) {
  const auto falcon = make_mechanism(load_preset("falcon"));
  VectorXd far = falcon->home_task();
  far(2) += 10 * falcon->size();
  EXPECT_THROW(falcon->link_capsules(falcon->home_actuators(), far), std::invalid_argument);
}

}  // namespace
}  // namespace linkscape
