#include "core/mechanisms/described/turned_reach.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
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
// Voxels of the distance transform, cells of the azimuths' grid; the
// transform's grid grown by a quarter of the samples' extent each way.
constexpr double kTurnedVoxels = 1 << 18, kTurnedPad = 0.25, kBinnedCells = 1 << 16;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// p as (distance from the axis, height along it, 0): in a plane, the distance alone.
Eigen::Vector3d turned_coordinates(const TurnedReach& t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - t.centre;
  if (t.in_plane) return {d.head<2>().norm(), 0, 0};
  const double height = t.axis.dot(d);
  return {(d - height * t.axis).norm(), height, 0};
}

// Azimuths about the axis from `zero`, in kBins bins.
constexpr int kBins = 64;
constexpr double kBinWidth = 2 * kPi / kBins;
double azimuth_of(const TurnedReach& t, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - t.centre;
  return std::atan2(t.onwards.dot(d), t.zero.dot(d));
}
int azimuth_bin(double azimuth) {
  const double turns = (azimuth + kPi) / (2 * kPi);
  return std::clamp(int((turns - std::floor(turns)) * kBins), 0, kBins - 1);
}

// Each sample's azimuth bin in its cell of (distance, height), per
// combination it stands for, spread to every cell within the margin and the
// cells' rounding (a square: more than needed, never less).
// (`at`: the samples' ends in turned coordinates.)
void bin_azimuths(TurnedReach& out, const Samples& samples, const std::vector<Eigen::Vector3d>& at,
                  const std::vector<std::uint64_t>& combinations, std::size_t combos) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(kInfinity), hi = -lo;
  for (const Eigen::Vector3d& p : at) {
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  const Eigen::Vector2d extent = (hi - lo).cwiseMax(1e-12);
  out.cell = std::max({0.25 * out.rest.margin(), std::sqrt(extent.prod() / kBinnedCells), extent.maxCoeff() / 256});
  const int reach = int(std::ceil(out.rest.margin() / out.cell + std::sqrt(2.0)));  // cells
  out.grid_lo = lo - Eigen::Vector2d::Constant((reach + 1) * out.cell);
  out.columns = int(extent.x() / out.cell) + 2 * reach + 4;
  out.rows = int(extent.y() / out.cell) + 2 * reach + 4;
  const std::size_t columns = std::size_t(out.columns), rows = std::size_t(out.rows);
  out.azimuths.assign(combos, std::vector<std::uint64_t>(columns * rows, 0));
  for (std::size_t i = 0; i < at.size(); ++i) {
    const std::size_t column = std::size_t(std::lround((at[i].x() - out.grid_lo.x()) / out.cell));
    const std::size_t row = std::size_t(std::lround((at[i].y() - out.grid_lo.y()) / out.cell));
    const std::uint64_t bit = std::uint64_t(1) << azimuth_bin(azimuth_of(out, samples.ends[i]));
    for (std::size_t combo = 0; combo < combos; ++combo)
      if (combinations[i] >> combo & 1) out.azimuths[combo][row * columns + column] |= bit;
  }
  // Spread along rows, then along columns.
  std::vector<std::uint64_t> line;
  for (std::vector<std::uint64_t>& grid : out.azimuths)
    for (const auto [count, stride, lines, step] : {std::array<std::size_t, 4>{columns, 1, rows, columns},
                                                    std::array<std::size_t, 4>{rows, columns, columns, 1}})
      for (std::size_t l = 0; l < lines; ++l) {
        std::uint64_t* first = &grid[l * step];
        line.assign(count, 0);
        for (std::size_t i = 0; i < count; ++i)
          for (std::size_t j = i >= std::size_t(reach) ? i - std::size_t(reach) : 0; j <= std::min(count - 1, i + reach); ++j)
            line[i] |= first[j * stride];
        for (std::size_t i = 0; i < count; ++i) first[i * stride] = line[i];
      }
  out.binned = true;
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
    out.binned = out.binned && limited;
    if (out.binned) out.travel = actuators[std::size_t(joint.actuator)].range;
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
  const Samples samples = walk_samples(leg, sampled, frames_of(leg, sampled, seed));
  std::vector<Eigen::Vector3d> points;
  points.reserve(samples.ends.size());
  for (const Eigen::Vector3d& p : samples.ends) points.push_back(turned_coordinates(out, p));
  out.rest = BallSetDistance(points, margin, true, kTurnedVoxels, kTurnedPad);
  out.samples = int(points.size());
  out.built = true;
  // The azimuths within the first joint's travel: where its actuator has
  // one, and no joint after it does (they are sampled over full turns).
  const bool rest_free = std::none_of(rest.begin(), rest.end(), [&](const Freedom& f) {
    const Step& step = leg.steps[std::size_t(f.step)];
    return step.actuator >= 0 && actuators[std::size_t(step.actuator)].limited;
  });
  if (limited && rest_free && free_rules_of(leg) <= 6) {
    out.travel = actuators[std::size_t(joint.actuator)].range;
    out.seed_value = seed.values(joint.variable);
    bin_azimuths(out, samples, points, combinations_of(leg, sampled, samples, end.last, end.ball, &out.axis),
                 std::size_t(1) << free_rules_of(leg));
  }
  return out;
}

bool TurnedReach::rules_out_within_travel(const Eigen::Vector3d& p, int combo) const {
  if (!binned) return false;
  const Eigen::Vector3d t = turned_coordinates(*this, p);
  const int column = int(std::lround((t.x() - grid_lo.x()) / cell)), row = int(std::lround((t.y() - grid_lo.y()) / cell));
  if (column < 0 || row < 0 || column >= columns || row >= rows) return true;  // no sample within the margin
  // The azimuths that turn onto p's within the travel, widened by the angle
  // the margin subtends at p's distance from the axis.
  const double margin = rest.margin(), widen = t.x() > margin ? std::asin(margin / t.x()) : kPi;
  const double from = azimuth_of(*this, p) + seed_value - travel.hi - widen;
  const double span = travel.hi - travel.lo + 2 * widen;
  std::uint64_t window = ~std::uint64_t(0);
  if (span < 2 * kPi - 2 * kBinWidth) {
    window = 0;
    const int first_bin = azimuth_bin(from), bins = int(std::ceil(span / kBinWidth)) + 1;
    for (int b = 0; b <= bins; ++b) window |= std::uint64_t(1) << ((first_bin + b) % kBins);
  }
  return (azimuths[std::size_t(combo)][std::size_t(row) * std::size_t(columns) + std::size_t(column)] & window) == 0;
}

}  // namespace linkscape::described
