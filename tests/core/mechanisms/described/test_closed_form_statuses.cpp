// Honest statuses from the closed-form legs: the Falcon's crank-parallelogram
// miss is the distance from the anchor to the leg's reach (against a search
// over the chain itself), its field has no not-converged sample, and the
// described Delta calls unreachable exactly what the compiled Delta does.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/field.h"
#include "core/mechanism.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/preset.h"

namespace linkscape::described {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;
using Eigen::VectorXd;

Kinematics load(const std::string& name) {
  const Preset p = load_preset(name);
  return Kinematics(build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
}

// The distance from `anchor` to the Falcon leg's reach, searched over its
// chain as walked (crank, knee and parallelogram angles; the lower joint and
// the grip keep the grip level): a grid, then a pattern search from its best
// points.
double searched_miss(const Kinematics& k, int leg, const Vector3d& anchor) {
  const Leg& l = k.model().legs[std::size_t(leg)];
  auto distance = [&](const Vector3d& t) {
    LegState s;
    s.values = VectorXd::Zero(l.variables);
    s.values << t(0), t(1), t(2), -t(2), t(0) + t(1);  // q, knee, upper, lower, grip
    return (k.draw_leg(leg, s).frames.back().translation() - anchor).norm();
  };
  const int n = 40;
  std::vector<std::pair<double, Vector3d>> grid;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int m = 0; m < n; ++m) {
        const Vector3d t = 2 * M_PI / n * Vector3d(i, j, m) - Vector3d::Constant(M_PI);
        grid.push_back({distance(t), t});
      }
  std::partial_sort(grid.begin(), grid.begin() + 8, grid.end(),
                    [](const auto& a, const auto& b) { return a.first < b.first; });
  double best = grid.front().first;
  for (int start = 0; start < 8; ++start) {
    auto [d, t] = grid[std::size_t(start)];
    for (double step = 2 * M_PI / n; step > 1e-11; step *= 0.5)
      for (bool moved = true; moved;) {
        moved = false;
        for (int axis = 0; axis < 3; ++axis)
          for (double sign : {1.0, -1.0}) {
            const Vector3d trial = t + sign * step * Vector3d::Unit(axis);
            if (const double e = distance(trial); e < d) d = e, t = trial, moved = true;
          }
      }
    best = std::min(best, d);
  }
  return best;
}

TEST(DescribedClosedForm, FalconMissIsTheDistanceToTheLegsReach) {
  const Kinematics k = load("falcon");
  const Model& m = k.model();
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> unit(-1, 1);
  int checked = 0;
  double worst = 0;
  for (int i = 0; i < 4000 && checked < 24; ++i) {
    const int leg = i % 3;
    const Leg& l = m.legs[std::size_t(leg)];
    Isometry3d anchor = Isometry3d::Identity();
    anchor.linear() = l.anchor.linear();  // the grip level
    anchor.translation() = l.base.translation() + 1.3 * m.size * Vector3d(unit(rng), unit(rng), unit(rng));
    LegCandidates c;
    solve_closed(*k.closed_form(leg), m, l, anchor, c);
    if (c.count > 0 || c.undecided) continue;
    const double searched = searched_miss(k, leg, anchor.translation());
    EXPECT_NEAR(c.miss, searched, 1e-7 * m.size) << "leg " << l.name << " at " << anchor.translation().transpose();
    worst = std::max(worst, std::abs(c.miss - searched));
    ++checked;
  }
  std::printf("Falcon miss: %d anchors out of reach, worst difference from the search %.2e mm\n", checked, worst);
  EXPECT_EQ(checked, 24);
}

// Where a crank-parallelogram leg has a continuum of solutions (or its end
// is turned so that it closes only by luck), the closed form does not
// decide: the numerical solver does.
TEST(DescribedClosedForm, CrankParallelogramHandsDegeneratePosesToTheNumericalSolver) {
  const Kinematics k = load("falcon");
  const Leg& l = k.model().legs[0];
  const ClosedFormLeg& f = *k.closed_form(0);
  const ClosedFormLeg::Parallelogram& g = f.parallelogram;
  const Vector3d A = f.actuator_axis, across = g.across;
  const double r1 = g.thigh.norm();
  auto undecided = [&](const Vector3d& local, const Eigen::Matrix3d& turn) {
    Isometry3d anchor = f.base * Isometry3d(turn);
    anchor.translation() = f.base * local;
    LegCandidates c;
    solve_closed(f, k.model(), l, anchor, c);
    return c.undecided && c.miss == 0;
  };
  const Eigen::Matrix3d level = Eigen::Matrix3d::Identity();
  // On the crank's axis, where the parallelogram's reach equals the thigh: every crank angle.
  const double on_axis = std::sqrt(g.side * g.side - (r1 - g.bar) * (r1 - g.bar));
  EXPECT_TRUE(undecided(A * (g.height + on_axis), level));
  // The parallelogram's reach across A zero, the end at the thigh's length: every knee angle.
  const double s = g.bar / g.side, h = g.side * std::sqrt(1 - s * s);
  EXPECT_TRUE(undecided(A * (g.height + h) + r1 * across, level));
  // A reachable point, the end level, is decided; turned off the crank's axis, it is not.
  EXPECT_FALSE(undecided(A * (g.height + h) + 0.9 * r1 * across, level));
  EXPECT_TRUE(undecided(A * (g.height + h) + 0.9 * r1 * across,
                        Eigen::AngleAxisd(0.1, across).toRotationMatrix()));
}

// The default box at a moderate resolution: every sample decided; where the
// closed form says unreachable, the numerical reference does not close the
// pose on the design's branch either.
TEST(DescribedClosedForm, FalconFieldHasNoNotConvergedSample) {
  const auto falcon = make_mechanism(load_preset("falcon"));
  const Eigen::AlignedBox3d box = falcon->default_box();
  const Grid g = Grid::box(box.min(), box.max(), {16, 16, 16});
  const auto field = falcon->compute_field(g, falcon->home_task(), {}, 2, {});
  IkOptions newton;
  newton.method = "newton";
  int unreachable = 0, reference_open = 0;
  for (int kk = 0; kk < g.dims[2]; ++kk)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const Status s = Status(field->status[g.index(i, j, kk)]);
        EXPECT_NE(s, Status::NotConverged) << g.point(i, j, kk).transpose();
        if (s != Status::Unreachable) continue;
        ++unreachable;
        const Status reference = falcon->inverse(g.point(i, j, kk), newton).status;
        EXPECT_TRUE(reference == Status::Unreachable || reference == Status::NotConverged)
            << g.point(i, j, kk).transpose() << ": the reference says " << to_string(reference);
        reference_open += reference == Status::NotConverged;
      }
  std::printf("Falcon field 16^3: %d unreachable, %d of them left not-converged by the reference\n", unreachable,
              reference_open);
  EXPECT_GT(reference_open, 0);  // the samples the closed form decides
}

// The closed form fills in every passive joint, so the stops see the same
// assembly: over the default box, the joint margin and the clearance of the
// closed-form field are the numerical solver's, and so are the statuses but
// where the closed form decides what the solver leaves open.
TEST(DescribedClosedForm, FalconStopsAgreeWithTheNumericalSolver) {
  const auto falcon = make_mechanism(load_preset("falcon"));
  const Eigen::AlignedBox3d box = falcon->default_box();
  const Grid g = Grid::box(box.min(), box.max(), {14, 14, 14});
  IkOptions newton;
  newton.method = "newton";
  const auto closed = falcon->compute_field(g, falcon->home_task(), {}, 2, {});
  const auto reference = falcon->compute_field(g, falcon->home_task(), newton, 2, {});
  int compared = 0, stopped = 0;
  double worst_margin = 0, worst_clearance = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const Status a = Status(closed->status[i]), b = Status(reference->status[i]);
    if (!(a == Status::Unreachable && b == Status::NotConverged)) {
      EXPECT_EQ(a, b) << "sample " << i;
    }
    const float m = closed->extra("joint_margin")->values[i], c = closed->extra("clearance")->values[i];
    if (std::isnan(m) || a != b) continue;
    worst_margin = std::max(worst_margin, double(std::abs(m - reference->extra("joint_margin")->values[i])));
    worst_clearance = std::max(worst_clearance, double(std::abs(c - reference->extra("clearance")->values[i])));
    ++compared;
    stopped += a == Status::OutOfLimits && m < 0;
  }
  std::printf("Falcon stops: %d assemblies, %d beyond a passive joint's stop; worst joint margin %.2e deg, "
              "clearance %.2e mm\n", compared, stopped, worst_margin, worst_clearance);
  EXPECT_GT(compared, 1000);
  EXPECT_GT(stopped, 20);
  EXPECT_LT(worst_margin, 1e-4);     // float storage
  EXPECT_LT(worst_clearance, 1e-4);
}

// Targets within 2 % of the size of the compiled Delta's reach boundary
// (found by bisection along random rays from home): the described Delta
// calls unreachable exactly those the compiled one does. (Out-of-limits may
// differ: the described Delta's ball joints have assumed cones.)
TEST(DescribedClosedForm, DeltaNearItsReachIsUnreachableWhereTheCompiledDeltaIs) {
  const auto compiled = make_mechanism(load_preset("delta"));
  const auto described = make_mechanism(load_preset("delta-described"));
  const double size = compiled->size();
  const VectorXd home = compiled->home_task();
  IkOptions ik;
  ik.branch = 0;
  IkOptions newton = ik;
  newton.method = "newton";
  auto unreachable = [&](const Mechanism& m, const VectorXd& x) { return m.inverse(x, ik).status == Status::Unreachable; };
  std::mt19937_64 rng(29);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> band(-0.02, 0.02);
  int compared = 0, outside = 0;
  for (int ray = 0; ray < 400; ++ray) {
    const Vector3d d = Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    double in = 0, out = 3 * size;
    if (!unreachable(*compiled, home + out * d)) continue;
    while (out - in > 1e-9 * size) {
      const double mid = 0.5 * (in + out);
      (unreachable(*compiled, home + mid * d) ? out : in) = mid;
    }
    for (int t = 0; t < 10; ++t) {
      const VectorXd x = home + (in + band(rng) * size) * d;
      if (std::abs(compiled->reach_margin(x, 0)) < 1e-6 * size) continue;  // rounding of the boundary
      const bool c = unreachable(*compiled, x);
      EXPECT_EQ(unreachable(*described, x), c) << "at " << x.transpose() << ": compiled "
                                               << to_string(compiled->inverse(x, ik).status) << ", described "
                                               << to_string(described->inverse(x, ik).status);
      // The numerical reference too.
      EXPECT_EQ(described->inverse(x, newton).status == Status::Unreachable, c) << "newton at " << x.transpose();
      ++compared;
      outside += c;
    }
  }
  std::printf("Delta near its reach: %d targets, %d unreachable on both\n", compared, outside);
  EXPECT_GT(compared, 3000);
  EXPECT_GT(outside, 1000);
}

// The five-bar's left leg folded at (-3, -4) (|P - A1| = b - a): both
// solvers call every branch that assembles there singular, and eval's rows
// (IkResult::solutions) keep each such assembly with its actuators. The
// numerical solver stops about sqrt(residual) short of the folded leg,
// where J is still finite; it is the pose, not that stop, that is singular.
TEST(DescribedStatuses, AFoldedLegIsSingularForBothSolversAndKeepsItsRows) {
  const auto m = make_mechanism(load_preset("five-bar"));
  const VectorXd x = (VectorXd(3) << -3, -4, 0).finished();
  for (const char* method : {"closed", "newton"}) {
    IkOptions o;
    o.method = method;
    const IkResult r = m->inverse(x, o);
    ASSERT_EQ(r.solutions.size(), 4u) << method;
    int singular = 0;
    for (const IkSolution& s : r.solutions) {
      EXPECT_NE(s.status, Status::Ok) << method << " branch " << s.branch;
      if (s.status != Status::Singular) continue;
      ++singular;
      EXPECT_EQ(s.failing_part, "left") << method;
      EXPECT_NEAR(s.q(0), M_PI / 2, 1e-6) << method;  // the crank up, P below its base: folded
      EXPECT_TRUE(std::isinf(m->measures(s.q, x).values.at(0))) << method;
    }
    EXPECT_EQ(singular, 2) << method;
  }
  // A hair past the fold (4e-10 and 1e-9 cm, within the tolerance) no leg closes
  // exactly: the closed form says unreachable, and the numerical solver,
  // closing within its tolerance, singular, never ok with c(J) = inf.
  IkOptions newton;
  newton.method = "newton";
  for (double past : {4e-10, 1e-9}) {
    const VectorXd beyond = (VectorXd(3) << -3, -4 + past, 0).finished();
    EXPECT_EQ(m->inverse(beyond).status, Status::Unreachable) << past;
    const IkResult r = m->inverse(beyond, newton);
    int singular = 0;
    for (const IkSolution& s : r.solutions) {
      EXPECT_NE(s.status, Status::Ok) << past << " branch " << s.branch;
      singular += s.status == Status::Singular;
    }
    EXPECT_EQ(singular, 2) << past;
  }
}

}  // namespace
}  // namespace linkscape::described
