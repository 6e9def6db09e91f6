#include "core/mechanisms/described/turned_reach.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/joint_grid.h"
#include "core/mechanisms/described/reach.h"

namespace linkscape::described {

using namespace internal;
using namespace joint_grid;

namespace {
// Samples of the joints after the first, by their number (the margin: joint_grid.h's allot).
constexpr std::array<double, 3> kTurnedSamples{1 << 12, 1 << 18, 1 << 18};
// Voxels of the distance transform, cells of the samples' grid; the
// transform's grid grown by a quarter of the samples' extent each way.
constexpr double kTurnedVoxels = 1 << 18, kTurnedPad = 0.25, kCells = 1 << 16;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// p as (distance from the axis, height along it, 0): in a plane, the distance alone.
Eigen::Vector3d turned_coordinates(const TurnedReach& t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - t.centre;
  if (t.in_plane) return {d.head<2>().norm(), 0, 0};
  const double height = t.axis.dot(d);
  return {(d - height * t.axis).norm(), height, 0};
}

// Azimuths about the axis from `zero`.
double azimuth_of(const TurnedReach& t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - t.centre;
  return std::atan2(t.onwards.dot(d), t.zero.dot(d));
}

// The grid of cells over the samples' (distance, height), padded by the
// margin's cells and their rounding each way.
int margin_cells(const TurnedReach& t) { return int(std::ceil(t.rest.margin() / t.cell + std::sqrt(2.0))); }
void place_grid(TurnedReach& out, const std::vector<Eigen::Vector3d>& at) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(kInfinity), hi = -lo;
  for (const Eigen::Vector3d& p : at) {
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  const Eigen::Vector2d extent = (hi - lo).cwiseMax(1e-12);
  out.cell = std::max({0.25 * out.rest.margin(), std::sqrt(extent.prod() / kCells), extent.maxCoeff() / 256});
  const int reach = margin_cells(out);
  out.grid_lo = lo - Eigen::Vector2d::Constant((reach + 1) * out.cell);
  out.columns = int(extent.x() / out.cell) + 2 * reach + 4;
  out.rows = int(extent.y() / out.cell) + 2 * reach + 4;
}
std::size_t cell_of(const TurnedReach& t, const Eigen::Vector3d& turned) {
  const std::size_t column = std::size_t(std::lround((turned.x() - t.grid_lo.x()) / t.cell));
  const std::size_t row = std::size_t(std::lround((turned.y() - t.grid_lo.y()) / t.cell));
  return row * std::size_t(t.columns) + column;
}

}  // namespace

// The samples sorted by cell: a cell's are entries[first[cell], first[cell + 1]).
struct TurnedReach::Nearest {
  struct Entry {
    float distance, height, azimuth;  // the end's, the first joint at the seed's value
    std::uint32_t sample;
    std::uint64_t combinations;
  };
  std::vector<std::uint32_t> first;
  std::vector<Entry> entries;
  // A sample's state: the seed with the sampled joints at its values (a
  // ball's rotation from the link's direction as written, `written`).
  std::vector<Freedom> freedoms;
  LegState seed;
  int turned_variable = 0;
  std::vector<int> variable_of, sphere_of;  // per freedom: its joint's variable, or its ball's sphere (else -1)
  Eigen::Matrix3d written = Eigen::Matrix3d::Identity();
  // The sample's state, its first joint at `first`.
  void state_of(std::uint32_t sample, double first, LegState& out) const;
  // outside_finely's: the leg sampled, and its first joint; a bound on the
  // end's second-order rest over a box (in three dimensions); none where a
  // ball joint moves the end.
  Leg leg;
  Eigen::Vector3d centre, axis;
  bool refinable = false;
  double second_order = 0;
};

void TurnedReach::Nearest::state_of(std::uint32_t sample, double first, LegState& out) const {
  out = seed;
  out.values(turned_variable) = first;
  std::size_t index = sample;
  thread_local std::vector<int> at;
  at.resize(freedoms.size());
  for (std::size_t j = at.size(); j-- > 0;) {
    at[j] = int(index % std::size_t(freedoms[j].count));
    index /= std::size_t(freedoms[j].count);
  }
  for (std::size_t j = 0; j < at.size(); ++j) {
    const Freedom& f = freedoms[j];
    if (sphere_of[j] < 0) {
      out.values(variable_of[j]) = f.value(at[j]);
    } else if (f.kind == Freedom::Kind::Polar) {  // (its azimuth: the next)
      const double polar = f.value(at[j]), spin = freedoms[j + 1].value(at[j + 1]);
      const Eigen::Vector3d d =
          written * Eigen::Vector3d(std::cos(polar), std::sin(polar) * std::cos(spin), std::sin(polar) * std::sin(spin));
      out.spheres[std::size_t(sphere_of[j])] = basis_along(d) * written.transpose();
    }
  }
}

namespace {

std::shared_ptr<const TurnedReach::Nearest> sort_nearest(const TurnedReach& t, const Leg& leg, const Samples& samples,
                                                         const std::vector<Eigen::Vector3d>& at,
                                                         const std::vector<std::uint64_t>& combinations,
                                                         const std::vector<Freedom>& freedoms, const Frames& frames,
                                                         const LegState& seed, int turned_variable) {
  auto n = std::make_shared<TurnedReach::Nearest>();
  const std::size_t cells = std::size_t(t.columns) * std::size_t(t.rows);
  n->first.assign(cells + 1, 0);
  for (const Eigen::Vector3d& p : at) ++n->first[cell_of(t, p) + 1];
  for (std::size_t c = 0; c < cells; ++c) n->first[c + 1] += n->first[c];
  n->entries.resize(at.size());
  std::vector<std::uint32_t> next(n->first.begin(), n->first.end() - 1);
  for (std::size_t i = 0; i < at.size(); ++i)
    n->entries[next[cell_of(t, at[i])]++] = {float(at[i].x()), float(at[i].y()), float(azimuth_of(t, samples.ends[i])),
                                             std::uint32_t(i), combinations[i]};
  n->freedoms = freedoms;
  n->seed = seed;
  n->turned_variable = turned_variable;
  int sphere = 0;
  for (std::size_t s = 0, f = 0; s < leg.steps.size(); ++s) {
    const bool ball = leg.steps[s].kind == Step::Kind::Spherical;
    sphere += ball;
    for (; f < freedoms.size() && freedoms[f].step == int(s); ++f) {
      n->sphere_of.push_back(ball ? sphere - 1 : -1);
      n->variable_of.push_back(ball ? -1 : leg.steps[s].variable);
    }
  }
  n->written = basis_along(frames.tail.translation().normalized());
  // Within a box of half steps h, the end's second derivative along joints
  // i <= j is w_i x (w_j x (end - c_j)) (revolutes), w_i x a_j (a slide
  // after a revolute) or 0 (after a slide): at most joint j's lever.
  n->leg = leg;
  n->centre = t.centre;
  n->axis = t.axis;
  n->refinable = std::all_of(freedoms.begin(), freedoms.end(), [](const Freedom& f) {
    return f.kind == Freedom::Kind::Turn || f.kind == Freedom::Kind::Slide;
  });
  for (std::size_t i = 0; i < freedoms.size(); ++i)
    for (std::size_t j = 0; j < freedoms.size(); ++j)
      n->second_order += 0.5 * freedoms[i].half_step() * freedoms[j].half_step() * freedoms[std::max(i, j)].lever;
  return n;
}

// Calls f(entry) for each sample in the cells within `around` of t's (in
// turned coordinates) until f returns false; returns the distance within
// which every sample was visited (0 where f stopped it).
template <class F>
double scan_near(const TurnedReach& reach, const Eigen::Vector3d& t, long around, F f) {
  const long column = std::lround((t.x() - reach.grid_lo.x()) / reach.cell);
  const long row = std::lround((t.y() - reach.grid_lo.y()) / reach.cell);
  const TurnedReach::Nearest& n = *reach.nearest;
  for (long r = std::max(0L, row - around); r <= std::min(long(reach.rows) - 1, row + around); ++r)
    for (long c = std::max(0L, column - around); c <= std::min(long(reach.columns) - 1, column + around); ++c) {
      const std::size_t cell = std::size_t(r) * std::size_t(reach.columns) + std::size_t(c);
      for (std::uint32_t e = n.first[cell]; e < n.first[cell + 1]; ++e)
        if (!f(n.entries[e])) return 0;
    }
  return double(around - 1) * reach.cell;
}

// Of the joint values a full turn apart from `turn`, the nearest `middle`.
double nearest_to(double turn, double middle) {
  while (turn - middle > kPi) turn -= 2 * kPi;
  while (turn - middle < -kPi) turn += 2 * kPi;
  return turn;
}

// The stored samples' rounding (floats), generously: their azimuths', and
// their distances' and heights' about t.
constexpr double kAngleRounding = 1e-6;
double rounding_at(const Eigen::Vector3d& t) { return 1e-6 * (1 + t.head<2>().lpNorm<Eigen::Infinity>()); }

// The distance from q to the zonogon of generators g (about the origin).
double zonogon_distance(const Eigen::Vector2d& q, const std::vector<Eigen::Vector2d>& g) {
  const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
  // Inside where it has an area and q lies within its extent across every edge.
  bool area = false, inside = true;
  for (const Eigen::Vector2d& edge : g) {
    double extent = 0;
    for (const Eigen::Vector2d& other : g) {
      extent += std::abs(cross(edge, other));
      area = area || cross(edge, other) != 0;
    }
    inside = inside && std::abs(cross(edge, q)) <= extent;
  }
  if (area && inside) return 0;
  // Else the nearest of its edges (and the segments within it: never nearer).
  double nearest = kInfinity;
  const std::size_t k = g.size();
  for (std::size_t j = 0; j < k; ++j)
    for (std::size_t signs = 0; signs < (std::size_t(1) << k); ++signs) {
      if (signs >> j & 1) continue;
      Eigen::Vector2d a = Eigen::Vector2d::Zero();
      for (std::size_t i = 0; i < k; ++i)
        if (i != j) a += (signs >> i & 1 ? 1.0 : -1.0) * g[i];
      const Eigen::Vector2d along = 2 * g[j], from = a - g[j];
      const double length = along.squaredNorm();
      const double at = length > 0 ? std::clamp((q - from).dot(along) / length, 0.0, 1.0) : 0.0;
      nearest = std::min(nearest, (q - from - at * along).norm());
    }
  return nearest;
}

}  // namespace

double TurnedReach::outside(const Eigen::Vector3d& p) const {
  return built ? rest.outside(turned_coordinates(*this, p)) : -std::numeric_limits<double>::infinity();
}

bool same_from_first_joint(const Leg& a, const Leg& b, const std::vector<Actuator>& actuators) {
  const FirstJoint first_a = first_joint(a), first_b = first_joint(b);
  const std::size_t from_a = first_a.step, from_b = first_b.step;
  if (a.steps.size() - from_a != b.steps.size() - from_b || a.rules.size() != b.rules.size()) return false;
  const auto limited = [&](const Step& s) { return s.actuator >= 0 && actuators[std::size_t(s.actuator)].limited; };
  for (std::size_t i = 0; i < a.steps.size() - from_a; ++i) {
    const Step &sa = a.steps[from_a + i], &sb = b.steps[from_b + i];
    if (sa.kind != sb.kind || sa.axis != sb.axis || sa.variable != sb.variable ||
        !(sa.transform.matrix() == sb.transform.matrix()) || (i > 0 && limited(sa) != limited(sb)))
      return false;
  }
  // The same branch rules, on the same steps, an `along` rule's direction
  // the same in the first joint's frame (the first joint's travel may differ).
  for (std::size_t r = 0; r < a.rules.size(); ++r) {
    const BranchRule &ra = a.rules[r], &rb = b.rules[r];
    const auto from_first = [](const BranchRule& rule, std::size_t from) {
      std::array<int, 3> steps = rule.steps;
      for (int& step : steps) step = step >= 0 ? step - int(from) : step;
      return steps;
    };
    const Eigen::Vector3d along_a = first_a.frame.linear().transpose() * ra.direction,
                          along_b = first_b.frame.linear().transpose() * rb.direction;
    if (ra.kind != rb.kind || from_first(ra, from_a) != from_first(rb, from_b) ||
        (ra.kind == BranchRule::Kind::Along && !along_a.isApprox(along_b, 1e-12)) ||
        ra.fixed_sign != rb.fixed_sign || (ra.free_index >= 0) != (rb.free_index >= 0))
      return false;
  }
  return true;
}

TurnedReach sample_turned_reach(const Leg& leg, const std::vector<Actuator>& actuators, bool planar,
                                const LegState& seed, const TurnedReach* like) {
  TurnedReach out;
  const FirstJoint first = first_joint(leg);
  // About this leg's first joint (a copy's samples: at the same distances,
  // heights and azimuths about it).
  const auto place = [&] {
    const Eigen::Vector3d local = leg.steps[first.step].axis.normalized();
    out.axis = first.frame.linear() * local;
    out.zero = first.frame.linear() * local.unitOrthogonal();
    // A turn of the joint moves an end round the axis one way in its own
    // frame; a mirrored leg's frame sees it go the other way.
    out.onwards = first.frame.linear() * local.cross(local.unitOrthogonal());
    out.centre = first.frame.translation();
  };
  const Step& joint = leg.steps[first.step];
  const bool limited = joint.actuator >= 0 && actuators[std::size_t(joint.actuator)].limited;
  if (like) {
    out = *like;
    if (!out.built) return out;
    place();
    out.limited = limited;
    if (limited) out.travel = actuators[std::size_t(joint.actuator)].range;
    return out;
  }
  const EndFreedoms end = end_freedoms(leg, actuators, planar, false);
  out.why_not = end.why_not;
  if (end.freedoms.empty()) return out;
  if (end.freedoms.front().kind != Freedom::Kind::Turn || end.freedoms.front().step != int(first.step)) {
    out.why_not = "its first joint does not turn";
    return out;
  }
  const std::vector<Freedom> rest(end.freedoms.begin() + 1, end.freedoms.end());
  if (rest.empty() || rest.size() > 3) {
    out.why_not = rest.empty() ? "its first joint alone moves its end" : "more than three freedoms after its first joint";
    return out;
  }
  place();
  out.in_plane = planar;
  if (planar && std::abs(std::abs(out.axis.z()) - 1) > 1e-12) {
    out.why_not = "its first joint leaves the plane";
    return out;
  }
  std::vector<Freedom> sampled = rest;
  const double margin = allot(sampled, kTurnedSamples[sampled.size() - 1]);
  const Frames frames = frames_of(leg, sampled, seed);
  const Samples samples = walk_samples(leg, sampled, frames);
  std::vector<Eigen::Vector3d> points;
  points.reserve(samples.ends.size());
  for (const Eigen::Vector3d& p : samples.ends) points.push_back(turned_coordinates(out, p));
  out.rest = BallSetDistance(points, margin, true, kTurnedVoxels, kTurnedPad);
  out.samples = int(points.size());
  out.built = true;
  out.seed_value = seed.values(joint.variable);
  out.limited = limited;
  if (limited) out.travel = actuators[std::size_t(joint.actuator)].range;
  if (free_rules_of(leg) > 6) return out;
  place_grid(out, points);
  const std::vector<std::uint64_t> combinations =
      combinations_of(leg, sampled, samples, end.last, end.ball, &out.axis);
  out.nearest = sort_nearest(out, leg, samples, points, combinations, sampled, frames, seed, joint.variable);
  return out;
}

double TurnedReach::outside_finely(const Eigen::Vector3d& p, double cut) const {
  if (!nearest || !nearest->refinable) return -kInfinity;
  const Nearest& n = *nearest;
  const Eigen::Vector3d t = turned_coordinates(*this, p);
  const double margin = rest.margin(), rounding = rounding_at(t);
  thread_local LegState state;
  thread_local internal::Chain chain;
  thread_local std::vector<Eigen::Vector2d> generators;
  double least = kInfinity;
  const double covered = scan_near(*this, t, margin_cells(*this), [&](const Nearest::Entry& entry) {
    const double coarse = (Eigen::Vector2d(entry.distance, entry.height) - t.head<2>()).norm() - margin - rounding;
    if (coarse > cut) return least = std::min(least, coarse), true;
    // The box's first-order image about its sample, in (distance, height).
    n.state_of(entry.sample, seed_value, state);
    internal::walk_into(n.leg, state, chain);
    const Eigen::Vector3d end = chain.end.translation(), from = end - n.centre;
    const double height = n.axis.dot(from);
    const Eigen::Vector3d radial = from - height * n.axis;
    const double distance = radial.norm();
    if (distance <= margin) return least = std::min(least, coarse), false;  // (on the axis: no curvature bound)
    const Eigen::Vector3d unit = radial / distance;
    generators.clear();
    for (const Freedom& f : n.freedoms) {
      const int v = n.leg.steps[std::size_t(f.step)].variable;
      const Eigen::Vector3d move = chain.sliding[std::size_t(v)]
                                       ? chain.axis[std::size_t(v)]
                                       : Eigen::Vector3d(chain.axis[std::size_t(v)].cross(end - chain.centre[std::size_t(v)]));
      generators.emplace_back(f.half_step() * unit.dot(move), in_plane ? 0.0 : f.half_step() * n.axis.dot(move));
    }
    const Eigen::Vector2d q = t.head<2>() - Eigen::Vector2d(distance, in_plane ? 0.0 : height);
    // The second-order rest: the end's, and the distance's own curvature
    // over the box (|first-order move|^2 / 2r, r at least distance - margin).
    const double rest_bound = n.second_order + 0.5 * margin * margin / (distance - margin);
    const double fine = std::max(coarse, zonogon_distance(q, generators) - rest_bound - rounding);
    least = std::min(least, fine);
    return fine > cut;
  });
  return std::min(least, covered - margin - rounding);
}

TurnedReach::Nearby TurnedReach::nearby(const Eigen::Vector3d& p, int combo, LegState& seed) const {
  Nearby out;
  if (!nearest) return out;
  const Eigen::Vector3d t = turned_coordinates(*this, p);
  const double azimuth = azimuth_of(*this, p), middle = 0.5 * (travel.lo + travel.hi);
  const double margin = rest.margin(), rounding = rounding_at(t);
  const double widen = t.x() > margin ? std::asin(margin / t.x()) : kPi;
  const double close = (margin + rounding) * (margin + rounding);
  // The nearest sample that turns onto p within the (widened) travel, of
  // those within the margin; and the nearest of all.
  const Nearest::Entry *within = nullptr, *any = nullptr;
  double within_squared = kInfinity, any_squared = kInfinity, within_turn = 0, any_turn = 0;
  scan_near(*this, t, margin_cells(*this), [&](const Nearest::Entry& entry) {
    const double squared = (Eigen::Vector2d(entry.distance, entry.height) - t.head<2>()).squaredNorm();
    if (!(entry.combinations >> combo & 1) || !(squared < any_squared || (squared <= close && squared < within_squared)))
      return true;
    const double turn = nearest_to(seed_value + azimuth - entry.azimuth, middle);
    if (squared < any_squared) any_squared = squared, any = &entry, any_turn = turn;
    const bool in_travel = !limited || std::max({0.0, travel.lo - turn, turn - travel.hi}) <= widen + kAngleRounding;
    if (in_travel && squared <= close && squared < within_squared) within_squared = squared, within = &entry, within_turn = turn;
    return true;
  });
  out.within_travel = within || !limited;
  out.seeded = any;
  if (within) nearest->state_of(within->sample, within_turn, seed);
  else if (any) nearest->state_of(any->sample, any_turn, seed);
  return out;
}

}  // namespace linkscape::described
