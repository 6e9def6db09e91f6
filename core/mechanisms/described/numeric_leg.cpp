// The numerical solver of one leg: Gauss-Newton from a seed (solve_leg),
// the seeds tried in turn and what decides without them (solve_leg_numeric),
// and the search of an actuator's travel for an assembly the seeds missed.
// (kinematics.cpp: the poses, the bounds and the closed forms around it.)
#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <vector>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/kinematics.h"

namespace linkscape::described {

using namespace internal;  // its Eigen names too

namespace {
struct ThreadSeeds {
  std::uint64_t id = 0;
  std::vector<std::vector<std::optional<LegState>>> legs;  // per leg, per combination
};
thread_local ThreadSeeds thread_seeds;

// The travel search's paths start from the seeds' assemblies, home, and this
// many spread seeds: on an arm with offset elbows, enough to find every
// assembly within the travel a finer scan finds (docs/described-internals.md).
constexpr int kTravelSearchSpreadSeeds = 2;
// The iterations a leg's travel searches take before its sampled reach is
// built to rule searches out: about what a grid costs (a few milliseconds),
// so that a field never pays much more than twice what the searches would.
constexpr int kSearchIterationsBeforeSampling = 20000;

}  // namespace

Kinematics::LegSolveResult Kinematics::solve_leg(int leg, const Isometry3d& anchor, LegState s, int max_iterations,
                                                 double crawl, int held) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  const double size = model_.size;
  // Scratch chains and states reused across iterations (no allocation in the loop).
  thread_local Chain c, tc;
  thread_local LegState trial;
  LegSolveResult out;
  walk_into(l, s, c);
  Rows e = rows_of(closure_error(c, anchor, size), model_.planar);
  double norm = e.norm();
  LegMatrix J(e.size(), l.variables);
  int it = 0;
  for (; it < max_iterations && norm > 1e-15; ++it) {
    for (int v = 0; v < l.variables; ++v) J.col(v) = rows_of(twist(c, v, c.end.translation(), size), model_.planar);
    if (held >= 0) J.col(held).setZero();
    auto d = damped_step(J, e, 1e-6);
    limit_step(d, c.sliding, size);
    bool accepted = false;
    for (int halving = 0; halving < 30 && !accepted; ++halving, d *= 0.5) {
      trial = s;
      apply(l, trial, d);
      walk_into(l, trial, tc);
      const Rows te = rows_of(closure_error(tc, anchor, size), model_.planar);
      if (te.norm() < norm) {
        accepted = true;
        // At the rounding floor, or crawling towards a least-squares minimum
        // off the target (an unreachable pose): either way, done.
        const bool floor = te.norm() > 0.5 * norm && norm < 1e-11;
        const bool crawling = te.norm() > (1 - crawl) * norm && norm > 1e-9;
        std::swap(s, trial);
        std::swap(c, tc);
        e = te;
        norm = te.norm();
        if (floor || crawling) it = max_iterations;
      }
    }
    if (!accepted) break;  // no decrease along the step: a least-squares minimum
  }
  for (int v = 0; v < l.variables; ++v) J.col(v) = rows_of(twist(c, v, c.end.translation(), size), model_.planar);
  if (held >= 0) J.col(held).setZero();
  const VectorXd gradient = MatrixXd(J).transpose() * VectorXd(e);
  out.stationary = gradient.norm() <= 1e-6 * J.norm() * norm;
  out.state = std::move(s);
  out.error = norm;
  out.iterations = std::min(it, max_iterations);
  return out;
}

LegSolution Kinematics::solve_leg_numeric(int leg, const Isometry3d& anchor, int branch, double tolerance,
                                          const LegState* extra_seed) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  LegSolution best;
  best.residual = kInf;
  const int combo = leg_combination(l, branch);
  ThreadSeeds& tls = thread_seeds;
  if (tls.id != id_) {
    tls.id = id_;
    tls.legs.assign(model_.legs.size(), {});
    for (std::size_t i = 0; i < model_.legs.size(); ++i)
      tls.legs[i].assign(std::size_t(1) << free_rules_of(model_.legs[i]), std::nullopt);
  }
  // Fast seeds first: the thread's last solution on this branch (a field's
  // neighbouring sample) and the caller's. Where they do not serve, fixed
  // seeds decide, so that an unreachable pose's miss distance does not depend
  // on what the thread solved before.
  std::vector<const LegState*> fast, fixed;
  if (aided_ && tls.legs[std::size_t(leg)][std::size_t(combo)])
    fast.push_back(&*tls.legs[std::size_t(leg)][std::size_t(combo)]);
  if (extra_seed) fast.push_back(extra_seed);
  // The leg at its turned reach's sample nearest the anchor first (a leg of
  // no known pattern); then at home on this branch turned towards the
  // anchor, at home on this branch, at home on its other branches: listed
  // only once the fast seeds have not served (each depends on the anchor alone).
  std::optional<TurnedReach::Nearby> nearby;
  const auto list_fixed = [&] {
    thread_local LegState nearest, toward;  // their storage reused
    if (aided_ && !closed_[std::size_t(leg)]) nearby = turned_reach(leg).nearby(anchor.translation(), combo, nearest);
    if (nearby && nearby->seeded) fixed.push_back(&nearest);
    const auto& homes = home_states_[std::size_t(leg)];
    if (home_toward(leg, combo, anchor, toward)) fixed.push_back(&toward);
    if (homes[std::size_t(combo)]) fixed.push_back(&*homes[std::size_t(combo)]);
    for (std::size_t other = 0; other < homes.size(); ++other)
      if (homes[other] && other != std::size_t(combo)) fixed.push_back(&*homes[other]);
    for (const LegState& s : spread_seeds_[std::size_t(leg)]) fixed.push_back(&s);
  };

  bool found_other_branch = false;
  // A solution on the branch whose actuator is outside its travel: the answer
  // only if the first fixed seed that closes the leg on the branch does not
  // find one within it, and then that seed's. (A leg may close the same
  // anchor twice on one branch, e.g. a prismatic leg at +d and, its universal
  // joint turned over, at -d; which one a seed finds must not decide the
  // status or the answer.)
  std::optional<LegSolution> outside_travel;
  bool outside_from_fixed = false;
  int stationary_misses = 0;
  int iterations = 0;
  for (const auto* seeds : {&fast, &fixed}) {
    if (seeds == &fixed) list_fixed();
    for (std::size_t i = 0; i < seeds->size(); ++i) {
      if (outside_from_fixed && seeds == &fixed) break;
      // Towards a least-squares minimum only while it gains 0.1 % per step:
      // enough for the verdict and for the miss distance near the boundary,
      // where the residual is small and Gauss-Newton converges fast.
      LegSolveResult r = solve_leg(leg, anchor, *(*seeds)[i], 40, 1e-3);
      iterations += r.iterations;
      const double residual = r.error * model_.size;
      if (residual <= tolerance * model_.size) {
        if (signs_match(leg, r.state, anchor, branch)) {
          LegSolution solved;
          solved.state = std::move(r.state);
          solved.status = Status::Ok;
          solved.residual = residual;
          solved.iterations = iterations;
          if (!within_travel(leg, solved.state)) {
            // A fixed seed's over a fast seed's: which solution the thread's
            // last one leads to must not decide the margin.
            if (!outside_travel || (seeds == &fixed && !outside_from_fixed)) outside_travel = std::move(solved);
            outside_from_fixed = outside_from_fixed || seeds == &fixed;
            continue;
          }
          tls.legs[std::size_t(leg)][std::size_t(combo)] = solved.state;
          return solved;
        }
        // Keep it only as a state to report (never empty), not as the answer.
        if (!found_other_branch && best.residual == kInf) best.state = r.state;
        found_other_branch = true;
        continue;
      }
      if (seeds == &fast) continue;
      if (residual < best.residual) {
        best.state = std::move(r.state);
        best.residual = residual;
      }
      // Two fixed seeds that both end at a least-squares minimum off the
      // target (not merely slow): the leg cannot reach it (more seeds would
      // repeat the verdict).
      if (r.stationary && ++stationary_misses >= 2 && !found_other_branch) break;
      // The seed at the nearest sample missed, and no seed has closed the
      // leg: near the reach's edge, where the seeds after it would crawl to
      // a least-squares minimum, the samples' boxes may prove that none can.
      if (i == 0 && nearby && nearby->seeded && !found_other_branch && !outside_travel) {
        const double outside = turned_reach(leg).outside_finely(anchor.translation(), refusal_cut(tolerance));
        if (outside > refusal_cut(tolerance)) {
          LegSolution refused;
          leave_unsolved(leg, Status::Unreachable, outside, refused);
          refused.iterations = iterations;
          return refused;
        }
      }
    }
  }
  // The seeds closed the leg, but not on the branch within its travel: that
  // tells nothing of the assemblies they did not find. The actuator swept
  // over its travel looks for one, where the bounds within the travel allow one.
  // The sampled reach only once the leg's searches have cost about what its
  // grid does (the answers are the same with it or without).
  std::atomic<int>& searched = sampled_->search_iterations[std::size_t(leg)];
  const auto ruled_out = [&] {
    if (!aided_) return false;
    const double cut = refusal_cut(tolerance);
    if (travel_outside(leg, anchor, branch, false) > cut) return true;
    // A leg of no known pattern: its turned reach's samples near the anchor,
    // finer than the sampled reach (not built then).
    if (nearby) return !nearby->within_travel;
    return searched.load(std::memory_order_relaxed) >= kSearchIterationsBeforeSampling &&
           sampled_outside(leg, anchor, branch) > cut;
  };
  if ((outside_travel || found_other_branch) && !ruled_out()) {
    thread_local std::vector<const LegState*> starts;
    starts.clear();
    if (outside_travel) starts.push_back(&outside_travel->state);
    if (found_other_branch) starts.push_back(&best.state);
    if (const auto& home = home_states_[std::size_t(leg)][std::size_t(combo)]) starts.push_back(&*home);
    for (int i = 0; i < kTravelSearchSpreadSeeds; ++i) starts.push_back(&spread_seeds_[std::size_t(leg)][std::size_t(i)]);
    LegSolution inside;
    const int before = iterations;
    const bool found = search_travel(leg, anchor, branch, tolerance, starts, inside, iterations);
    if (searched.load(std::memory_order_relaxed) < kSearchIterationsBeforeSampling)  // (no count past it)
      searched.fetch_add(iterations - before, std::memory_order_relaxed);
    if (found) {
      inside.iterations = iterations;
      tls.legs[std::size_t(leg)][std::size_t(combo)] = inside.state;
      return inside;
    }
  }
  if (outside_travel) {
    // The next sample starts from the fixed seeds, which decide such an
    // answer anyway: the thread's last solution, within the travel and now
    // behind, would mostly lead outside it again, for nothing.
    tls.legs[std::size_t(leg)][std::size_t(combo)].reset();
    outside_travel->iterations = iterations;
    return *outside_travel;
  }
  if (found_other_branch) best.residual = 0.0;  // the leg reaches the anchor, on another branch
  if (best.state.values.size() == 0) best.state = spread_seeds_[std::size_t(leg)].front();
  best.status = found_other_branch ? Status::NotConverged : Status::Unreachable;
  best.iterations = iterations;
  return best;
}

bool Kinematics::same_assembly(int leg, const LegState& a, const LegState& b) const {
  // By the joints' centres: a rod spinning about itself between two balls
  // (an idle freedom) leaves the assembly as it is.
  thread_local Chain ca, cb;
  const Leg& l = model_.legs[std::size_t(leg)];
  walk_into(l, a, ca);
  walk_into(l, b, cb);
  for (std::size_t i = 0; i < ca.step_centre.size(); ++i)
    if ((ca.step_centre[i] - cb.step_centre[i]).norm() > 1e-2 * model_.size) return false;
  return true;
}

bool Kinematics::search_travel(int leg, const Isometry3d& anchor, int branch, double tolerance,
                               const std::vector<const LegState*>& starts, LegSolution& out, int& iterations) const {
  const Leg& l = model_.legs[std::size_t(leg)];
  if (l.actuators.size() != 1) return false;
  const Actuator& act = model_.actuators[std::size_t(l.actuators.front())];
  if (!act.limited) return false;  // the seeds' assemblies are all within it
  const int variable = l.steps[std::size_t(act.step)].variable;
  // Steps over the travel, each from the last: the passive joints follow the
  // actuator as one branch of the leg's motion, by three iterations a step
  // (to follow, not to settle on the least error). Six steps and three
  // iterations find, on the arm with offset elbows, what eight and eight do.
  constexpr int kSteps = 6;
  thread_local std::vector<LegSolveResult> path;
  thread_local std::vector<LegState> taken;  // the paths' steps, path by path
  thread_local std::vector<int> minima;
  taken.clear();
  for (const LegState* start : starts) {
    path.clear();
    LegState s = *start;
    for (int i = 0; i < kSteps; ++i) {
      s.values(variable) = act.range.lo + (i + 0.5) / kSteps * (act.range.hi - act.range.lo);
      path.push_back(solve_leg(leg, anchor, s, 3, 1e-2, variable));
      iterations += path.back().iterations;
      s = path.back().state;
      // A path that joins one already taken would repeat it.
      bool joins = false;
      for (std::size_t t = std::size_t(i); t < taken.size() && !joins; t += std::size_t(kSteps))
        joins = same_assembly(leg, s, taken[t]);
      if (joins) break;
    }
    if (int(path.size()) < kSteps) continue;
    for (const LegSolveResult& r : path) taken.push_back(r.state);
    // Released where the error is least along the path (a local minimum; an
    // assembly within the travel is one), the least first.
    minima.clear();
    for (int i = 0; i < kSteps; ++i) {
      const double e = path[std::size_t(i)].error;
      if ((i == 0 || e <= path[std::size_t(i - 1)].error) && (i + 1 == kSteps || e <= path[std::size_t(i + 1)].error))
        minima.push_back(i);
    }
    std::sort(minima.begin(), minima.end(),
              [&](int a, int b) { return path[std::size_t(a)].error < path[std::size_t(b)].error; });
    for (int i : minima) {
      LegSolveResult r = solve_leg(leg, anchor, path[std::size_t(i)].state, 40, 1e-3);
      iterations += r.iterations;
      if (r.error > tolerance || !within_travel(leg, r.state) || !signs_match(leg, r.state, anchor, branch)) continue;
      out.state = std::move(r.state);
      out.status = Status::Ok;
      out.residual = r.error * model_.size;
      return true;
    }
  }
  return false;
}

}  // namespace linkscape::described
