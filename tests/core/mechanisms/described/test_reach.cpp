// The reach bounds (reach.h): sound (a chain at any joint values, and an
// anchor the closed form reaches, lie within them), exact for a crank and a
// rod, and what the numerical solver leaves out because of them.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/closed_form.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/reach.h"
#include "core/mechanisms/described/sampled_reach.h"
#include "core/mechanisms/described/turned_reach.h"
#include "tests/core/mechanisms/described/designs.h"

namespace linkscape::described {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;
using testing_support::load_described;
using testing_support::random_designs;
using testing_support::shipped_descriptions;

// The shipped description and four random designs of it.
std::vector<Kinematics> designs_of(const std::string& name, std::mt19937_64& rng) {
  std::vector<Kinematics> out = random_designs(name, 4, rng);
  out.push_back(load_described(name));
  return out;
}

// An anchor about the leg's base, up to 1.5 sizes away (in the plane for a
// planar device), the platform unturned.
Isometry3d anchor_near(const Model& m, const Leg& l, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1, 1);
  Isometry3d anchor = Isometry3d::Identity();
  anchor.translation() = l.base.translation() + 1.5 * m.size * Vector3d(unit(rng), unit(rng), m.planar ? 0.0 : unit(rng));
  anchor.linear() = l.anchor.linear();
  return anchor;
}

// A leg's state at random joint values (lengths up to the size).
LegState random_state(const Model& m, const Leg& l, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1, 1);
  LegState s;
  s.values.resize(l.variables);
  for (int v = 0; v < l.variables; ++v) s.values(v) = 4 * unit(rng) * (v % 2 ? 1.0 : m.size / 4);
  for (int b = 0; b < l.spheres; ++b)
    s.spheres.push_back(internal::rotation_of(Vector3d(unit(rng), unit(rng), unit(rng)) * 2.0));
  return s;
}

// The same with the actuators within their travel.
LegState random_state_within_travel(const Model& m, const Leg& l, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  LegState s = random_state(m, l, rng);
  for (int a : l.actuators) {
    const Actuator& act = m.actuators[std::size_t(a)];
    if (act.limited) s.values(l.steps[std::size_t(act.step)].variable) = act.range.lo + unit(rng) * (act.range.hi - act.range.lo);
  }
  return s;
}

TEST(DescribedReach, ChainsAtRandomJointValuesLieWithinTheirBounds) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> unit(-1, 1);
  int bounded = 0, checked = 0;
  for (const std::string& name : shipped_descriptions())
    for (const Kinematics& k : designs_of(name, rng)) {
      const Model& m = k.model();
      const double tolerance = 1e-9 * m.size;
      for (std::size_t leg = 0; leg < m.legs.size(); ++leg) {
        const Leg& l = m.legs[leg];
        const FirstJointReach& about = k.reach_about_first_joint(int(leg));
        bounded += about.motion != FirstJointReach::Motion::None;
        for (int i = 0; i < 3000; ++i, ++checked) {
          const LegState s = random_state(m, l, rng);
          const Vector3d end = internal::walk(l, s).end.translation();
          const double distance = (end - l.base.translation()).norm();
          EXPECT_LE(distance, k.reach(int(leg)).hi + tolerance) << name << " leg " << l.name;
          EXPECT_GE(distance, k.reach(int(leg)).lo - tolerance) << name << " leg " << l.name;
          EXPECT_LE(about.outside(end), tolerance) << name << " leg " << l.name;
        }
      }
    }
  std::printf("first-joint bounds on %d legs; %d chain states checked\n", bounded, checked);
  EXPECT_GT(bounded, 100);
}

// Anchors round each leg's base: where the bound about the first joint
// refuses one, the closed form (exact) finds no solution and misses it by
// at least as much as the bound says.
TEST(DescribedReach, BoundsNeverRefuseAnAnchorTheClosedFormReaches) {
  std::mt19937_64 rng(23);
  int refused = 0;
  for (const std::string& name : shipped_descriptions())
    for (const Kinematics& k : designs_of(name, rng)) {
      const Model& m = k.model();
      for (std::size_t leg = 0; leg < m.legs.size(); ++leg) {
        const Leg& l = m.legs[leg];
        if (!k.closed_form(int(leg))) continue;  // a random design whose leg is no longer a known pattern
        for (int i = 0; i < 2000; ++i) {
          const Isometry3d anchor = anchor_near(m, l, rng);
          const double outside = k.reach_about_first_joint(int(leg)).outside(anchor.translation());
          if (!(outside > 1e-9 * m.size)) continue;
          LegCandidates c;
          solve_closed(*k.closed_form(int(leg)), m, l, anchor, c);
          if (c.undecided) continue;
          ++refused;
          EXPECT_EQ(c.count, 0) << name << " leg " << l.name;
          EXPECT_GE(c.miss, outside - 1e-12 * m.size) << name << " leg " << l.name;
        }
      }
    }
  std::printf("first-joint bounds: %d anchors refused, each confirmed\n", refused);
  EXPECT_GT(refused, 50000);
}

// A crank and a rod reach exactly the shell round the crank's circle: the
// bound is the closed form's miss.
TEST(DescribedReach, ACrankAndARodAreBoundExactly) {
  std::mt19937_64 rng(25);
  int compared = 0;
  for (const char* name : {"delta-described", "hexapod-rus"})
    for (const Kinematics& k : designs_of(name, rng)) {
      const Model& m = k.model();
      for (std::size_t leg = 0; leg < m.legs.size(); ++leg) {
        const Leg& l = m.legs[leg];
        ASSERT_EQ(k.reach_about_first_joint(int(leg)).motion, FirstJointReach::Motion::Turn) << name;
        ASSERT_NE(k.closed_form(int(leg)), nullptr) << name;
        for (int i = 0; i < 2000; ++i) {
          const Isometry3d anchor = anchor_near(m, l, rng);
          LegCandidates c;
          solve_closed(*k.closed_form(int(leg)), m, l, anchor, c);
          const double outside = k.reach_about_first_joint(int(leg)).outside(anchor.translation());
          if (c.undecided) continue;
          if (c.count == 0) {
            ++compared;
            EXPECT_NEAR(outside, c.miss, 1e-9 * m.size) << name << " leg " << l.name;
          } else {
            EXPECT_LE(outside, 1e-9 * m.size) << name << " leg " << l.name;
          }
        }
      }
    }
  EXPECT_GT(compared, 20000);
}

// Whether a state's actuators lie within their travel (a revolute's: some turn of it).
bool within_travel(const Model& m, const Leg& l, const LegState& s) {
  for (int a : l.actuators) {
    const Actuator& act = m.actuators[std::size_t(a)];
    const double v = s.values(l.steps[std::size_t(act.step)].variable);
    const bool inside = act.prismatic ? act.range.contains(v)
                                      : act.range.contains(act.range.lo + std::fmod(std::fmod(v - act.range.lo, 2 * M_PI) + 2 * M_PI, 2 * M_PI));
    if (act.limited && !inside) return false;
  }
  return true;
}

// The combination of the leg's free rules a state takes (leg_combination),
// or -1 where a rule's sign is zero or a fixed rule's is not the design's.
int combination_of(const Leg& l, const LegState& s) {
  const internal::Chain c = internal::walk(l, s);
  int combo = 0, bit = 0;
  for (const BranchRule& r : l.rules) {
    const int sign = internal::rule_sign(r, l, c, s, c.end);
    if (sign == 0 || (r.free_index < 0 && sign != r.fixed_sign)) return -1;
    if (r.free_index >= 0) combo |= int(sign < 0) << bit++;
  }
  return combo;
}

// No closed-form candidate within the travel on combination `combo`.
void expect_none_within_travel(const Model& m, const Leg& l, const LegCandidates& c, int combo, const std::string& name) {
  for (int j = 0; j < c.count; ++j) {
    const LegState& s = c.states[std::size_t(j)];
    EXPECT_FALSE(within_travel(m, l, s) && combination_of(l, s) == combo)
        << name << " leg " << l.name << " combination " << combo;
  }
}

// Where a grid tells branches apart least: each passive revolute of the
// state (or ball, about a random axis) turned to just either side of where
// the state changes branch; `at(state, combination)` for each.
template <class At>
void beside_branch_edges(const Leg& l, const LegState& s, std::mt19937_64& rng, At&& at) {
  if (l.rules.empty()) return;
  std::uniform_real_distribution<double> unit(-1, 1);
  int sphere = 0;
  for (const Step& step : l.steps) {
    const bool ball = step.kind == Step::Kind::Spherical;
    sphere += ball;
    if (!(ball || step.kind == Step::Kind::Revolute) || step.actuator >= 0) continue;
    const Vector3d axis = Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    LegState t = s;
    const auto turn = [&](double angle) {
      if (ball) t.spheres[std::size_t(sphere - 1)] = s.spheres[std::size_t(sphere - 1)] * Eigen::AngleAxisd(angle, axis);
      else t.values(step.variable) = angle;
      return combination_of(l, t);
    };
    for (int j = 0; j < 64; ++j) {
      double lo = -M_PI + j * 2 * M_PI / 64, hi = lo + 2 * M_PI / 64;
      const int from = turn(lo), to = turn(hi);
      if (from < 0 || to < 0 || from == to) continue;
      for (int b = 0; b < 50; ++b) (turn(0.5 * (lo + hi)) == from ? lo : hi) = 0.5 * (lo + hi);
      for (const double side : {lo, hi})
        if (const int c = turn(side); c >= 0) at(t, c);
    }
  }
}

// Each leg of every shipped description and of four random designs of it:
// at(name, kinematics, leg).
template <class At>
void for_each_leg(std::mt19937_64& rng, At&& at) {
  for (const std::string& name : shipped_descriptions())
    for (const Kinematics& k : designs_of(name, rng))
      for (std::size_t leg = 0; leg < k.model().legs.size(); ++leg) at(name, k, int(leg));
}

// A thousand anchors about a leg's base, each the closed form decides:
// at(anchor, its candidates).
template <class At>
void closed_form_anchors(const Kinematics& k, int leg, std::mt19937_64& rng, At&& at) {
  const Model& m = k.model();
  const Leg& l = m.legs[std::size_t(leg)];
  for (int i = 0; i < 1000; ++i) {
    const Isometry3d anchor = anchor_near(m, l, rng);
    LegCandidates c;
    solve_closed(*k.closed_form(leg), m, l, anchor, c);
    if (!c.undecided) at(anchor, c);
  }
}

// The bounds with the actuators within their travel, which decide whether
// the numerical solver searches the travel for an assembly its seeds did
// not find: a chain whose actuators are within their travel lies within
// them, and where they refuse an anchor no closed-form solution is within
// the travel. For a crank and a rod, or a slide and a rod, they are exact.
TEST(DescribedReach, TheTravelBoundsHoldEveryAssemblyWithinTheTravel) {
  std::mt19937_64 rng(27);
  int chains = 0, refused = 0, admitted_exactly = 0;
  for_each_leg(rng, [&](const std::string& name, const Kinematics& k, int leg) {
    const Model& m = k.model();
    const Leg& l = m.legs[std::size_t(leg)];
    const double tolerance = 1e-9 * m.size;
    for (int i = 0; i < 1000; ++i) {
      const LegState s = random_state_within_travel(m, l, rng);
      const Isometry3d end = internal::walk(l, s).end;
      const int combo = combination_of(l, s);
      // Not on a branch the design takes: the bounds without the sampled reach.
      const int branch = combo < 0 ? 0 : internal::device_branch(l, combo);
      EXPECT_LE(k.travel_outside(leg, end, branch, combo >= 0), tolerance) << name << " leg " << l.name;
      ++chains;
    }
    if (!k.closed_form(leg)) return;
    const LegPattern pattern = k.closed_form(leg)->pattern;
    const bool exact = pattern == LegPattern::CrankRod || pattern == LegPattern::SlideRod;
    closed_form_anchors(k, leg, rng, [&](const Isometry3d& anchor, const LegCandidates& c) {
      bool any_within = false;
      for (int j = 0; j < c.count; ++j) any_within = any_within || within_travel(m, l, c.states[std::size_t(j)]);
      const double outside = k.travel_outside(leg, anchor, 0, false);
      if (outside > tolerance) {
        ++refused;
        EXPECT_FALSE(any_within) << name << " leg " << l.name << " refused by " << outside;
      } else if (exact && outside < -tolerance) {
        ++admitted_exactly;
        EXPECT_TRUE(any_within) << name << " leg " << l.name << " within by " << -outside;
      }
    });
  });
  std::printf("travel bounds: %d chains within them, %d anchors refused, %d admitted exactly\n", chains, refused,
              admitted_exactly);
  EXPECT_GT(refused, 20000);
  EXPECT_GT(admitted_exactly, 1000);
}

// The sampled reach (sampled_reach.h) on each branch: every assembly within
// the travel on a branch lies within the branch's bound, and where the bound
// refuses an anchor the closed form (independent of the sampling) finds no
// assembly within the travel on that branch. It refuses anchors the shells
// admit: it follows the chain's shape.
TEST(DescribedReach, TheSampledReachHoldsEveryAssemblyOnItsBranch) {
  std::mt19937_64 rng(31);
  int legs = 0, chains = 0, edges = 0, refused = 0, refused_beyond_shells = 0;
  for_each_leg(rng, [&](const std::string& name, const Kinematics& k, int leg) {
    const Model& m = k.model();
    const Leg& l = m.legs[std::size_t(leg)];
    const double tolerance = 1e-9 * m.size;
    const SampledReach& sampled = k.sampled_reach(leg);
    if (!sampled.built) return;
    ++legs;
    for (int i = 0; i < 2000; ++i) {
      const LegState s = random_state_within_travel(m, l, rng);
      const int combo = combination_of(l, s);
      if (combo < 0) continue;
      const Vector3d end = internal::walk(l, s).end.translation();
      EXPECT_LE(sampled.travel[std::size_t(combo)].outside(end), tolerance) << name << " leg " << l.name;
      ++chains;
      if (i % 20 == 0)
        beside_branch_edges(l, s, rng, [&](const LegState& t, int c) {
          EXPECT_LE(sampled.travel[std::size_t(c)].outside(internal::walk(l, t).end.translation()), tolerance)
              << name << " leg " << l.name << " next to a branch's edge";
          ++edges;
        });
    }
    if (!k.closed_form(leg)) return;
    closed_form_anchors(k, leg, rng, [&](const Isometry3d& anchor, const LegCandidates& c) {
      for (std::size_t combo = 0; combo < sampled.travel.size(); ++combo) {
        const int branch = internal::device_branch(l, int(combo));
        if (!(k.travel_outside(leg, anchor, branch) > tolerance)) continue;
        ++refused;
        refused_beyond_shells += !(k.travel_outside(leg, anchor, branch, false) > tolerance);
        expect_none_within_travel(m, l, c, int(combo), name);
      }
    });
  });
  std::printf("sampled reach on %d legs: %d chains within it (%d next to a branch's edge), %d anchors refused (%d the "
              "shells admit)\n",
              legs, chains, edges, refused, refused_beyond_shells);
  EXPECT_GT(legs, 100);
  EXPECT_GT(edges, 1000);
  EXPECT_GT(refused_beyond_shells, 1000);
}

// The turned reach (turned_reach.h) about each leg's first revolute: every
// chain's end within it, and, where its first joint has a travel, no chain
// within the travel (nor one turned to either side of a branch's edge) ruled
// out on its branch; where it rules an anchor out within the travel on a
// branch, the closed form (independent of the sampling) finds no assembly
// within the travel on it. Its finer bound near the reach's edge never
// refuses a chain's end, nor an anchor the closed form reaches.
TEST(DescribedReach, TheTurnedReachHoldsEveryChainAndEveryOneWithinTheTravel) {
  std::mt19937_64 rng(37);
  int legs = 0, limited = 0, edges = 0, refused = 0, refused_beyond_bounds = 0, finely = 0;
  for_each_leg(rng, [&](const std::string& name, const Kinematics& k, int leg) {
    const Model& m = k.model();
    const Leg& l = m.legs[std::size_t(leg)];
    const double tolerance = 1e-9 * m.size;
    const TurnedReach& turned = k.turned_reach(leg);
    if (!turned.built) return;
    ++legs;
    for (int i = 0; i < 1000; ++i) {
      const LegState s = random_state(m, l, rng);
      const Vector3d end = internal::walk(l, s).end.translation();
      EXPECT_LE(turned.outside(end), tolerance) << name << " leg " << l.name;
      if (i % 10 == 0) EXPECT_LE(turned.outside_finely(end, 0), tolerance) << name << " leg " << l.name;
    }
    if (!turned.nearest || !turned.limited) return;
    ++limited;
    LegState seed;
    const auto held = [&](const LegState& s, int combo) {
      EXPECT_TRUE(turned.nearby(internal::walk(l, s).end.translation(), combo, seed).within_travel)
          << name << " leg " << l.name << " combination " << combo;
    };
    for (int i = 0; i < 2000; ++i) {
      const LegState s = random_state_within_travel(m, l, rng);
      if (const int combo = combination_of(l, s); combo >= 0) held(s, combo);
      if (i % 20 == 0) beside_branch_edges(l, s, rng, [&](const LegState& t, int c) { held(t, c), ++edges; });
    }
    if (!k.closed_form(leg)) return;
    closed_form_anchors(k, leg, rng, [&](const Isometry3d& anchor, const LegCandidates& c) {
      if (c.count > 0) {
        EXPECT_LE(turned.outside_finely(anchor.translation(), 0), tolerance) << name << " leg " << l.name;
        ++finely;
      }
      for (int combo = 0; combo < 1 << internal::free_rules_of(l); ++combo) {
        if (turned.nearby(anchor.translation(), combo, seed).within_travel) continue;
        ++refused;
        const int branch = internal::device_branch(l, combo);
        refused_beyond_bounds += !(k.travel_outside(leg, anchor, branch) > tolerance);
        expect_none_within_travel(m, l, c, combo, name);
      }
    });
  });
  std::printf("turned reach on %d legs, %d with a travel: %d chains next to a branch's edge held, %d anchors ruled out "
              "within the travel (%d the other bounds admit), %d anchors reached held finely\n",
              legs, limited, edges, refused, refused_beyond_bounds, finely);
  EXPECT_GT(legs, 100);
  EXPECT_GT(limited, 50);
  EXPECT_GT(edges, 1000);
  EXPECT_GT(refused_beyond_bounds, 1000);
  EXPECT_GT(finely, 10000);
}

// The turned reach's nearest sample as the numerical solver's seed, for an
// anchor that a chain within the travel reaches on a combination: some
// sample lies within the margin m of the chain's end (in distance and
// height; in azimuth within w, the angle m subtends at the anchor's distance
// from the axis), so the seed, the nearest such, ends within m of the anchor
// and turns within w of the travel.
TEST(DescribedReach, TheTurnedReachSeedsALegNearEveryAnchorWithinItsTravel) {
  std::mt19937_64 rng(41);
  int legs = 0, seeded = 0;
  double worst = 0;  // the seed's end from the anchor, in margins
  for_each_leg(rng, [&](const std::string& name, const Kinematics& k, int leg) {
    const Model& m = k.model();
    const Leg& l = m.legs[std::size_t(leg)];
    const TurnedReach& turned = k.turned_reach(leg);
    if (!turned.nearest) return;
    ++legs;
    const double margin = turned.rest.margin();
    const int turned_variable = l.steps[first_joint(l).step].variable;
    LegState seed;
    for (int i = 0; i < 500; ++i) {
      const LegState s = random_state_within_travel(m, l, rng);
      const int combo = combination_of(l, s);
      if (combo < 0) continue;
      const Vector3d anchor = internal::walk(l, s).end.translation();
      ASSERT_TRUE(turned.nearby(anchor, combo, seed).seeded) << name << " leg " << l.name;
      ++seeded;
      const double off = (internal::walk(l, seed).end.translation() - anchor).norm();
      worst = std::max(worst, off / margin);
      EXPECT_LE(off, margin + 1e-5 * m.size) << name << " leg " << l.name;
      if (!turned.limited) continue;
      const Vector3d d = anchor - turned.centre;
      const double r = (d - turned.axis.dot(d) * turned.axis).norm();
      const double w = r > margin ? std::asin(margin / r) : internal::kPi;
      const double turn = seed.values(turned_variable);
      EXPECT_GE(turn, turned.travel.lo - w - 1e-5) << name << " leg " << l.name;
      EXPECT_LE(turn, turned.travel.hi + w + 1e-5) << name << " leg " << l.name;
    }
  });
  std::printf("turned reach's seeds on %d legs: %d anchors, the worst seed's end %.2f margins away\n", legs,
              seeded, worst);
  EXPECT_GT(legs, 100);
  EXPECT_GT(seeded, 20000);
}

// A sample whose neighbour is on the other side of a rule's zero stands for
// both branches. One revolute turning a link of 10 cm, its branch the sign
// of the end along a direction turned so that the zero lies just past a
// sample: an end just across the zero lies farther than the margin from
// every sample on its own side, within it of that sample.
TEST(DescribedReach, ASampleNextToARulesZeroCountsOnBothBranches) {
  Leg leg;
  leg.variables = 1;
  Step turn;
  turn.kind = Step::Kind::Revolute;
  turn.actuator = 0;
  Step link;
  link.transform = Isometry3d(Eigen::Translation3d(10, 0, 0));
  leg.steps = {turn, link};
  leg.actuators = {0};
  Actuator motor;  // a full turn
  const int samples = 128;
  const double half_step = M_PI / samples;
  // The samples' angles: -pi + (i + 0.5) 2 pi / samples; the one at pi/2 + half_step,
  // the zero 0.05 half steps past it.
  const double zero = M_PI / 2 + 1.05 * half_step;
  BranchRule along;
  along.kind = BranchRule::Kind::Along;
  along.steps = {0, -2, -1};
  along.direction = Vector3d(std::cos(zero - M_PI / 2), std::sin(zero - M_PI / 2), 0);
  along.free_index = 0;
  leg.rules = {along};
  LegState seed;
  seed.values = Eigen::VectorXd::Zero(1);
  const SampledReach sampled = sample_reach(leg, {motor}, false, seed);
  ASSERT_TRUE(sampled.built);
  ASSERT_EQ(sampled.samples, samples);
  ASSERT_EQ(sampled.travel.size(), 2u);
  for (const double side : {-1.0, 1.0}) {
    const double angle = zero + side * 1e-9;
    const Vector3d end(10 * std::cos(angle), 10 * std::sin(angle), 0);
    const int combo = end.dot(along.direction) < 0;
    EXPECT_LE(sampled.travel[std::size_t(combo)].outside(end), 1e-9) << "the side " << side;
  }
}

// What a grid cannot sample is said, not sampled: a passive slide after an
// actuated revolute (no range), four freedoms.
TEST(DescribedReach, TheSampledReachSaysWhatItCannotSample) {
  Leg leg;
  Step turn, slide, link;
  turn.kind = Step::Kind::Revolute;
  turn.actuator = 0;
  slide.kind = Step::Kind::Prismatic;
  slide.axis = Vector3d::UnitX();
  slide.variable = 1;
  link.transform = Isometry3d(Eigen::Translation3d(10, 0, 0));
  leg.steps = {turn, slide, link};
  leg.variables = 2;
  LegState seed;
  seed.values = Eigen::VectorXd::Zero(2);
  const SampledReach passive = sample_reach(leg, {Actuator{}}, false, seed);
  EXPECT_FALSE(passive.built);
  EXPECT_EQ(passive.why_not, "a slide without travel moves its end");
  leg.steps = {turn, link, turn, link, turn, link, turn, link};
  for (int i = 0; i < 4; ++i) leg.steps[std::size_t(2 * i)].variable = i;
  leg.variables = 4;
  seed.values = Eigen::VectorXd::Zero(4);
  const SampledReach four = sample_reach(leg, {Actuator{}}, false, seed);
  EXPECT_FALSE(four.built);
  EXPECT_EQ(four.why_not, "4 freedoms move its end; a grid samples three at most");
}

// The numerical solver: a pose a bound rules out costs no iteration, its
// status is the closed forms' and, where the legs' bounds are exact (cranks
// and rods, three-revolute legs), its miss is the largest of the legs'
// exact misses (a leg within its bound closes there).
TEST(DescribedReach, TheNumericalSolverDoesNotSolveWhatTheBoundsRuleOut) {
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (const char* name : {"delta-described", "hexapod-rus", "pathos2-described", "falcon"}) {
    const Kinematics k = load_described(name);
    const Model& m = k.model();
    const bool exact = std::string(name) != "falcon";
    int ruled_out = 0;
    for (int i = 0; i < 3000; ++i) {
      Eigen::VectorXd x = m.home;
      for (int c = 0; c < 3; ++c) x(c) += 0.8 * m.size * unit(rng);
      const PlatformPose p = k.pose(x);
      PoseSolution numeric, closed;
      k.inverse_into(p, 0, 1e-10, LegSolver::Numeric, numeric);
      k.inverse_into(p, 0, 1e-10, LegSolver::Fastest, closed);
      // Off the design's branch the closed form decides (unreachable), the
      // numerical solver cannot (not-converged).
      if (!(closed.status == Status::Unreachable && numeric.status == Status::NotConverged)) {
        ASSERT_EQ(numeric.status, closed.status) << name << " at " << x.transpose();
      }
      if (numeric.status != Status::Unreachable || numeric.iterations > 0) continue;
      ++ruled_out;
      // The leg named is one the bounds refused, not one left unsolved.
      ASSERT_GE(numeric.failing_leg, 0) << name;
      EXPECT_EQ(numeric.legs[std::size_t(numeric.failing_leg)].status, Status::Unreachable) << name;
      EXPECT_GT(numeric.legs[std::size_t(numeric.failing_leg)].residual, 1e-9 * m.size) << name;
      double miss = 0;
      for (std::size_t leg = 0; leg < m.legs.size(); ++leg) {
        LegCandidates c;
        solve_closed(*k.closed_form(int(leg)), m, m.legs[leg], k.anchor(int(leg), p), c);
        if (c.count == 0) miss = std::max(miss, c.miss);
      }
      if (exact) EXPECT_NEAR(numeric.residual, miss, 1e-9 * m.size) << name << " at " << x.transpose();
      else EXPECT_LE(numeric.residual, miss + 1e-9 * m.size) << name << " at " << x.transpose();
    }
    std::printf("%s: %d of 3000 poses ruled out without iterating\n", name, ruled_out);
    EXPECT_GT(ruled_out, 1000) << name;
  }
}

// A leg that closes its anchor only outside its travel reports the same
// solution whatever the thread solved before (the Gough-Stewart platform's
// legs close an anchor at +d and, turned over, at -d).
TEST(DescribedReach, AnOutOfLimitsAnswerDoesNotDependOnTheSampleBefore) {
  const Kinematics k = load_described("stewart");
  const Model& m = k.model();
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> unit(-1, 1);
  Eigen::VectorXd elsewhere = m.home;
  elsewhere(0) += 0.3 * m.size;
  int compared = 0;
  for (int i = 0; i < 400; ++i) {
    Eigen::VectorXd x = m.home;
    for (int c = 0; c < 3; ++c) x(c) += 0.6 * m.size * unit(rng);
    k.inverse(m.home, 0, 1e-10, LegSolver::Numeric);
    const PoseSolution after_home = k.inverse(x, 0, 1e-10, LegSolver::Numeric);
    if (after_home.status != Status::OutOfLimits) continue;
    k.inverse(elsewhere, 0, 1e-10, LegSolver::Numeric);
    Eigen::VectorXd near = x;
    for (int c = 0; c < 3; ++c) near(c) += 0.01 * m.size;
    k.inverse(near, 0, 1e-10, LegSolver::Numeric);
    const PoseSolution after_other = k.inverse(x, 0, 1e-10, LegSolver::Numeric);
    ++compared;
    ASSERT_EQ(after_other.status, Status::OutOfLimits);
    EXPECT_LE((after_home.q - after_other.q).norm(), 1e-9) << "at " << x.transpose();
    EXPECT_NEAR(k.limits_margin(after_home.q), k.limits_margin(after_other.q), 1e-9 * m.size);
  }
  EXPECT_GT(compared, 100);
}

// The reach bounds and row seeding only save work: with them and without
// (LINKSCAPE_NUMERIC_AIDS=off, the fixed seeds deciding every leg), the
// numerical solver's verdicts are the same, pose for pose, along rows
// through the home of every shipped description and of a random design of
// each (the thread's last solution the next pose's seed, as in a field).
TEST(DescribedReach, BoundsAndRowSeedingLeaveEveryVerdictAsItIs) {
  for (const std::string& name : shipped_descriptions()) {
    // The same designs twice: unaided, then aided.
    std::vector<Kinematics> unaided, aided;
    for (std::vector<Kinematics>* designs : {&unaided, &aided}) {
      if (designs == &unaided) setenv("LINKSCAPE_NUMERIC_AIDS", "off", 1);
      std::mt19937_64 rng(31);
      *designs = random_designs(name, 1, rng);
      designs->push_back(load_described(name));
      unsetenv("LINKSCAPE_NUMERIC_AIDS");
    }
    for (std::size_t design = 0; design < aided.size(); ++design) {
      const Model& m = aided[design].model();
      const std::string what = name + (design + 1 < aided.size() ? " (random design)" : "");
      const int n = design + 1 < aided.size() ? 20 : 36;
      int differ = 0, assembled = 0;
      for (int row = 0; row < n; ++row)
        for (int column = 0; column < n; ++column) {
          Eigen::VectorXd x = m.home;
          x(0) += 0.8 * m.size * (2.0 * (column + 0.5) / n - 1);
          x(1) += 0.8 * m.size * (2.0 * (row + 0.5) / n - 1);
          const PoseSolution with = aided[design].inverse(x, 0, 1e-10, LegSolver::Numeric);
          const PoseSolution without = unaided[design].inverse(x, 0, 1e-10, LegSolver::Numeric);
          assembled += with.status == Status::Ok || with.status == Status::OutOfLimits;
          if (with.status != without.status && differ++ < 5)
            ADD_FAILURE() << what << " at " << x.transpose() << ": " << to_string(with.status) << " with the aids, "
                          << to_string(without.status) << " without";
        }
      std::printf("%s: %d of %d poses assemble\n", what.c_str(), assembled, n * n);
      EXPECT_EQ(differ, 0) << what;
      EXPECT_GT(assembled, 0) << what;
    }
  }
}

}  // namespace
}  // namespace linkscape::described
