#include "core/mechanisms/described/sampled_reach.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/reach.h"

namespace linkscape::described {

using namespace internal;

namespace {
// Samples by the number of freedoms that move the end.
constexpr std::array<double, 3> kSamples{1 << 7, 1 << 15, 1 << 16};
// Voxels per grid, at most (in a plane, in space).
constexpr double kVoxelsInPlane = 1 << 16, kVoxels = 1 << 16, kSide = 256;
// The same for the turned reach's two coordinates, by the number of freedoms after the first joint.
constexpr std::array<double, 3> kTurnedSamples{1 << 12, 1 << 18, 1 << 18};
constexpr double kTurnedVoxels = 1 << 18, kTurnedPad = 0.25, kBinnedCells = 1 << 16;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kFar = 1e30;  // a voxel's squared distance before any point is near

// The squared distance transform of f along one line of n values, `stride`
// apart (Felzenszwalb and Huttenlocher's lower envelope of parabolas).
void transform_line(float* f, int n, int stride, std::vector<double>& in, std::vector<double>& out,
                    std::vector<int>& v, std::vector<double>& z) {
  in.resize(std::size_t(n));
  out.resize(std::size_t(n));
  v.resize(std::size_t(n));
  z.resize(std::size_t(n) + 1);
  for (int q = 0; q < n; ++q) in[std::size_t(q)] = f[std::size_t(q) * std::size_t(stride)];
  int k = 0;
  v[0] = 0;
  z[0] = -kFar;
  z[1] = kFar;
  const auto meet = [&](int q, int p) {
    return ((in[std::size_t(q)] + double(q) * q) - (in[std::size_t(p)] + double(p) * p)) / (2.0 * (q - p));
  };
  for (int q = 1; q < n; ++q) {
    double s = meet(q, v[std::size_t(k)]);
    while (k > 0 && s <= z[std::size_t(k)]) s = meet(q, v[std::size_t(--k)]);
    v[std::size_t(++k)] = q;
    z[std::size_t(k)] = s;
    z[std::size_t(k) + 1] = kFar;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[std::size_t(k) + 1] < q) ++k;
    const double d = q - v[std::size_t(k)];
    out[std::size_t(q)] = d * d + in[std::size_t(v[std::size_t(k)])];
  }
  for (int q = 0; q < n; ++q) f[std::size_t(q) * std::size_t(stride)] = float(std::min(out[std::size_t(q)], kFar));
}

// One freedom (a dimension of the grid) over [lo, hi] in `count` steps
// (their centres): a revolute's angle, a slide's travel, or a ball joint's
// direction for the link after it (polar angle from the link's direction
// as written, then azimuth; its spin about the link moves nothing sampled).
// `wraps`: a full turn, whose ends are neighbours.
struct Freedom {
  enum class Kind { Turn, Slide, Polar, Azimuth };
  Kind kind = Kind::Turn;
  int step = 0;
  double lever = 0;  // how far a unit of it moves the end, at most
  double lo = 0, hi = 0;
  bool wraps = false;
  int count = 1;
  double half_step() const { return 0.5 * (hi - lo) / count; }
  double value(int i) const { return lo + (i + 0.5) * (hi - lo) / count; }
};

// Counts per dimension for about `budget` samples, each one's half step
// times its lever alike; returns the margin (the sum of those).
double allot(std::vector<Freedom>& freedoms, double budget) {
  const auto weight = [](const Freedom& j) { return (j.hi - j.lo) * j.lever; };
  double product = 1;
  for (const Freedom& j : freedoms) product *= std::max(weight(j), 1e-300);
  const double per = std::pow(product / budget, 1.0 / double(freedoms.size()));
  double margin = 0;
  for (Freedom& j : freedoms) {
    j.count = std::clamp(int(std::ceil(weight(j) / per)), 1, int(budget));
    margin += j.half_step() * j.lever;
  }
  return margin;
}

// An orthonormal basis whose first column is the unit u.
Eigen::Matrix3d basis_along(const Eigen::Vector3d& u) {
  Eigen::Matrix3d b;
  b.col(0) = u;
  b.col(1) = u.unitOrthogonal();
  b.col(2) = u.cross(b.col(1));
  return b;
}

// The leg as the frames its sampled joints move: the frame after motion m
// is frame m times lead[m] times its motion; every step's frame (before
// it) is one of those times a fixed offset. The joints it does not sample
// keep the seed's values.
struct Frames {
  std::vector<Eigen::Isometry3d> lead;    // per motion (a revolute, a slide, a ball)
  std::vector<int> frame_of_step;         // per step: the frame it follows (0: the base's, m + 1: motion m's)
  std::vector<Eigen::Isometry3d> offset;  // per step: from that frame to the step
  Eigen::Isometry3d tail = Eigen::Isometry3d::Identity();  // from the last frame to the end
};

Frames frames_of(const Leg& leg, const std::vector<Freedom>& freedoms, const LegState& seed) {
  Frames f;
  Eigen::Isometry3d acc = leg.base;
  int frame = 0, sphere = 0;
  std::size_t next = 0;
  for (std::size_t i = 0; i < leg.steps.size(); ++i) {
    const Step& step = leg.steps[i];
    f.frame_of_step.push_back(frame);
    f.offset.push_back(acc);
    sphere += step.kind == Step::Kind::Spherical;
    if (next < freedoms.size() && freedoms[next].step == int(i)) {
      f.lead.push_back(acc);
      acc.setIdentity();
      ++frame;
      while (next < freedoms.size() && freedoms[next].step == int(i)) ++next;  // a ball's two dimensions
      continue;
    }
    switch (step.kind) {
      case Step::Kind::Fixed: acc = acc * step.transform; break;
      case Step::Kind::Revolute: acc.rotate(Eigen::AngleAxisd(seed.values(step.variable), step.axis)); break;
      case Step::Kind::Prismatic: acc.translate(step.axis * seed.values(step.variable)); break;
      case Step::Kind::Spherical: acc.rotate(seed.spheres[std::size_t(sphere - 1)]); break;
    }
  }
  f.tail = acc;
  return f;
}

// The end's point and every rule's sign at each sample, the last dimension
// fastest; each frame recomputed only where a motion before it moved.
struct Samples {
  std::vector<Eigen::Vector3d> ends;
  std::vector<std::int8_t> signs;  // per sample, per rule
};

Samples walk_samples(const Leg& leg, const std::vector<Freedom>& freedoms, const Frames& f) {
  const std::size_t k = freedoms.size();
  // Per motion: its first dimension and, per value (a ball's per pair of
  // values, the azimuth fastest), its lead times its motion.
  std::vector<std::size_t> motion_of(k), first;
  std::vector<std::vector<Eigen::Isometry3d>> moved;
  std::size_t total = 1;
  for (std::size_t j = 0; j < k; ++j) {
    total *= std::size_t(freedoms[j].count);
    if (freedoms[j].kind == Freedom::Kind::Azimuth) {
      motion_of[j] = motion_of[j - 1];
      continue;
    }
    motion_of[j] = moved.size();
    first.push_back(j);
    const std::size_t m = moved.size();
    const Step& step = leg.steps[std::size_t(freedoms[j].step)];
    moved.emplace_back();
    for (int i = 0; i < freedoms[j].count; ++i) {
      if (freedoms[j].kind == Freedom::Kind::Polar) {
        // The link after the ball (the tail: a ball is the last motion)
        // turned from its direction as written to the sampled direction.
        const Eigen::Vector3d link = f.tail.translation().normalized();
        const Eigen::Matrix3d written = basis_along(link);
        const double polar = freedoms[j].value(i);
        for (int az = 0; az < freedoms[j + 1].count; ++az) {
          const double azimuth = freedoms[j + 1].value(az);
          const Eigen::Vector3d d = written * Eigen::Vector3d(std::cos(polar), std::sin(polar) * std::cos(azimuth),
                                                              std::sin(polar) * std::sin(azimuth));
          Eigen::Isometry3d mm = f.lead[m];
          mm.linear() = mm.linear() * (basis_along(d) * written.transpose());
          moved[m].push_back(mm);
        }
        continue;
      }
      Eigen::Isometry3d mm = f.lead[m];
      if (freedoms[j].kind == Freedom::Kind::Slide) mm.translate(step.axis * freedoms[j].value(i));
      else mm.rotate(Eigen::AngleAxisd(freedoms[j].value(i), step.axis));
      moved[m].push_back(mm);
    }
  }
  const std::size_t motions = moved.size(), rules = leg.rules.size();
  Samples out;
  out.ends.resize(total);
  out.signs.resize(total * rules);
  std::array<Eigen::Isometry3d, 4> frame;
  frame[0].setIdentity();
  std::array<int, 3> at{0, 0, 0};
  std::size_t changed = 0;  // the first dimension whose value changed
  for (std::size_t index = 0; index < total; ++index) {
    for (std::size_t m = motion_of[std::min(changed, k - 1)]; m < motions; ++m) {
      const std::size_t j = first[m];
      const std::size_t value = freedoms[j].kind == Freedom::Kind::Polar
                                    ? std::size_t(at[j]) * std::size_t(freedoms[j + 1].count) + std::size_t(at[j + 1])
                                    : std::size_t(at[j]);
      frame[m + 1] = frame[m] * moved[m][value];
    }
    const Eigen::Vector3d end = frame[motions] * f.tail.translation();
    out.ends[index] = end;
    const auto centre = [&](int step) -> Eigen::Vector3d {
      return step == -2 ? end : frame[std::size_t(f.frame_of_step[std::size_t(step)])] * f.offset[std::size_t(step)].translation();
    };
    const auto axis = [&](int step) -> Eigen::Vector3d {
      return frame[std::size_t(f.frame_of_step[std::size_t(step)])].linear() *
             (f.offset[std::size_t(step)].linear() * leg.steps[std::size_t(step)].axis);
    };
    for (std::size_t r = 0; r < rules; ++r) {
      const BranchRule& rule = leg.rules[r];
      double value = 0;
      if (rule.kind != BranchRule::Kind::Angle) value = rule_value_from(rule, centre, axis);
      else
        for (std::size_t j = 0; j < k; ++j)
          if (freedoms[j].step == rule.steps[0]) value = sine_sign(freedoms[j].value(at[j]));
      out.signs[index * rules + r] = std::int8_t(value > 0 ? 1 : value < 0 ? -1 : 0);
    }
    // The next sample: the last dimension fastest.
    changed = k;
    while (changed > 0) {
      --changed;
      if (++at[changed] < freedoms[changed].count) break;
      at[changed] = 0;
    }
  }
  return out;
}
// The joints that move a leg's end point, as the freedoms a grid samples:
// up to its last link or slide (the joints after it only turn the end),
// each revolute over its actuator's travel (where `within_travel` and it has
// one) or a full turn, a slide over its actuator's travel, a ball joint (the
// last of them) over every direction of its link. None, and why not, where
// they cannot be sampled so.
struct EndFreedoms {
  std::vector<Freedom> freedoms;
  int last = -1;  // the last step that moves the end
  int ball = -1;  // the ball joint's step
  std::string why_not;
};

EndFreedoms end_freedoms(const Leg& leg, const std::vector<Actuator>& actuators, bool planar, bool within_travel) {
  EndFreedoms out;
  const auto length = [&](const Eigen::Vector3d& v) { return planar ? v.head<2>().norm() : v.norm(); };
  const auto fail = [&](std::string why) {
    out.freedoms.clear();
    out.why_not = std::move(why);
    return out;
  };
  int& last = out.last;
  for (std::size_t i = 0; i < leg.steps.size(); ++i) {
    const Step& step = leg.steps[i];
    if ((step.kind == Step::Kind::Fixed && length(step.transform.translation()) > 0) ||
        step.kind == Step::Kind::Prismatic)
      last = int(i);
  }
  // A slide has a range only as an actuator with a travel, and only within it.
  for (int i = 0; i <= last; ++i) {
    const Step& step = leg.steps[std::size_t(i)];
    if (step.kind != Step::Kind::Prismatic) continue;
    if (!(step.actuator >= 0 && actuators[std::size_t(step.actuator)].limited))
      return fail("a slide without travel moves its end");
    if (!within_travel) return fail("a slide moves its end, beyond its travel too");
  }
  for (int i = 0; i <= last; ++i) {
    const Step& step = leg.steps[std::size_t(i)];
    if (step.kind == Step::Kind::Fixed) continue;
    if (out.ball >= 0 || (step.kind == Step::Kind::Spherical && planar))
      return fail(planar ? "a spherical joint in a planar device" : "a spherical joint moves its end before another joint");
    const Actuator* act = step.actuator >= 0 ? &actuators[std::size_t(step.actuator)] : nullptr;
    // Its lever: what the links after it reach at most.
    double lever = step.kind == Step::Kind::Prismatic ? length(step.axis) : 0.0;
    for (int after = i + 1; after <= last && step.kind != Step::Kind::Prismatic; ++after) {
      const Step& s = leg.steps[std::size_t(after)];
      if (s.kind == Step::Kind::Fixed) lever += length(s.transform.translation());
      if (s.kind == Step::Kind::Prismatic) {
        const Range& r = actuators[std::size_t(s.actuator)].range;
        lever += length(s.axis) * std::max(std::abs(r.lo), std::abs(r.hi));
      }
    }
    if (step.kind == Step::Kind::Spherical) {
      out.ball = i;
      out.freedoms.push_back({Freedom::Kind::Polar, i, lever, 0.0, kPi, false});
      out.freedoms.push_back({Freedom::Kind::Azimuth, i, lever, -kPi, kPi, true});
      continue;
    }
    const bool sliding = step.kind == Step::Kind::Prismatic;
    const bool limited = act && act->limited && (within_travel || sliding);
    out.freedoms.push_back({sliding ? Freedom::Kind::Slide : Freedom::Kind::Turn, i, lever,
                            limited ? act->range.lo : -kPi, limited ? act->range.hi : kPi, !limited});
  }
  if (out.freedoms.empty()) return fail("no joint moves its end");
  return out;
}
// Per sample, the combinations of the leg's free rules (at most six) it
// stands for: bit c set for combination c. From its signs, where it tells
// them; a sample next to where a rule's sign changes stands for both signs.
// `turned_about`: the samples leave the first joint as the seed has it (the
// turned reach), and a rule along a direction not that joint's axis changes
// as it turns (a triple of the leg's centres and axes turns with them).
std::vector<std::uint64_t> combinations_of(const Leg& leg, const std::vector<Freedom>& freedoms, const Samples& samples,
                                           int last, int ball, const Eigen::Vector3d* turned_about) {
  // Which rules a sample tells: an angle of a revolute it samples; a centre
  // the ball's spin does not move (not one between the ball and the end);
  // an axis that no joint turns that it does not sample in full (a ball's
  // spin, a joint after the last link).
  int turned_from = ball >= 0 ? ball + 1 : int(leg.steps.size());
  for (int i = last + 1; i < int(leg.steps.size()); ++i)
    if (leg.steps[std::size_t(i)].kind != Step::Kind::Fixed) turned_from = std::min(turned_from, i + 1);
  const auto centre_told = [&](int step) { return step == -2 || step > last || ball < 0 || step <= ball; };
  const std::size_t rules = leg.rules.size();
  std::vector<bool> told(rules, true);
  for (std::size_t r = 0; r < rules; ++r) {
    const BranchRule& rule = leg.rules[r];
    if (rule.kind == BranchRule::Kind::Angle)
      told[r] = std::any_of(freedoms.begin(), freedoms.end(), [&](const Freedom& j) {
        return j.step == rule.steps[0] && j.kind == Freedom::Kind::Turn;
      });
    if (rule.kind == BranchRule::Kind::Along)
      told[r] = centre_told(rule.steps[0]) && centre_told(rule.steps[1]) &&
                (!turned_about || rule.direction.cross(*turned_about).norm() < 1e-12);
    if (rule.kind == BranchRule::Kind::Triple)
      told[r] = rule.steps[0] < turned_from &&
                std::all_of(rule.steps.begin(), rule.steps.end(), [&](int step) { return centre_told(step); });
  }
  // Where a rule's sign differs between two neighbouring samples its zero
  // passes between them: they and every sample next to them (diagonally
  // too) stand for assemblies of either sign. The samples next to a ball's
  // poles are all neighbours of one another.
  const std::size_t k = freedoms.size(), total = samples.ends.size();
  std::array<std::size_t, 3> strides{1, 1, 1};  // the last dimension fastest
  for (std::size_t j = k - 1; j > 0; --j) strides[j - 1] = strides[j] * std::size_t(freedoms[j].count);
  // Calls pair(a, b) for each two samples next to each other along dimension j.
  const auto for_each_pair = [&](std::size_t j, auto&& pair) {
    const std::size_t count = std::size_t(freedoms[j].count), stride = strides[j], block = stride * count;
    const std::size_t pairs = freedoms[j].wraps && count > 2 ? count : count - 1;
    for (std::size_t outer = 0; outer < total; outer += block)
      for (std::size_t a = 0; a < pairs; ++a)
        for (std::size_t inner = 0; inner < stride; ++inner)
          pair(outer + a * stride + inner, outer + (a + 1) % count * stride + inner);
  };
  const auto sign = [&](std::size_t sample, std::size_t r) { return samples.signs[sample * rules + r]; };
  std::vector<std::uint8_t> near_zero(total * rules, 0);
  const auto mark = [&](std::size_t sample, std::size_t r) { near_zero[sample * rules + r] = 1; };
  for (std::size_t j = 0; j < k; ++j)
    for_each_pair(j, [&](std::size_t a, std::size_t b) {
      for (std::size_t r = 0; r < rules; ++r)
        if (sign(a, r) != sign(b, r)) mark(a, r), mark(b, r);
    });
  // A ball is the last motion: its polar angle the second last dimension.
  if (ball >= 0) {
    const std::size_t polar = k - 2, azimuths = std::size_t(freedoms[k - 1].count);
    for (std::size_t row = 0; row < total; row += azimuths) {
      const int at = int(row / azimuths % std::size_t(freedoms[polar].count));
      if (at != 0 && at + 1 != freedoms[polar].count) continue;
      for (std::size_t r = 0; r < rules; ++r) {
        bool differs = false;
        for (std::size_t az = 1; az < azimuths; ++az) differs = differs || sign(row + az, r) != sign(row, r);
        for (std::size_t az = 0; az < azimuths && differs; ++az) mark(row + az, r);
      }
    }
  }
  // Spread by one sample along each dimension in turn: to the diagonal
  // neighbours too.
  for (std::size_t j = 0; j < k; ++j) {
    const std::vector<std::uint8_t> before = near_zero;
    for_each_pair(j, [&](std::size_t a, std::size_t b) {
      for (std::size_t r = 0; r < rules; ++r) {
        near_zero[a * rules + r] |= before[b * rules + r];
        near_zero[b * rules + r] |= before[a * rules + r];
      }
    });
  }
  std::vector<std::uint8_t> both(total * rules, 0);
  for (std::size_t index = 0; index < total; ++index)
    for (std::size_t r = 0; r < rules; ++r)
      both[index * rules + r] = !told[r] || samples.signs[index * rules + r] == 0 || near_zero[index * rules + r];
  const int combos = 1 << free_rules_of(leg);
  std::vector<std::uint64_t> out(total, 0);
  for (std::size_t index = 0; index < total; ++index) {
    // The combinations its signs allow: a combination's bit b set where its
    // free rule b is negative.
    int negative = 0, positive = 0, bit = 0;
    bool off_design = false;
    for (std::size_t r = 0; r < rules; ++r) {
      const BranchRule& rule = leg.rules[r];
      const int free_bit = rule.free_index >= 0 ? bit++ : -1;
      if (both[index * rules + r]) continue;
      const int s = sign(index, r);
      if (free_bit < 0) off_design = off_design || s != rule.fixed_sign;
      else (s < 0 ? negative : positive) |= 1 << free_bit;
    }
    for (int combo = 0; combo < combos && !off_design; ++combo)
      if ((combo & negative) == negative && (combo & positive) == 0) out[index] |= std::uint64_t(1) << combo;
  }
  return out;
}
}  // namespace

BallSetDistance::BallSetDistance(const std::vector<Eigen::Vector3d>& points, double margin, bool in_plane,
                                 double voxels, double pad)
    : margin_(margin), in_plane_(in_plane) {
  if (voxels <= 0) voxels = in_plane ? kVoxelsInPlane : kVoxels;
  const double side = in_plane ? std::sqrt(voxels) : kSide;
  if (points.empty()) return;
  lo_ = hi_ = points.front();
  for (const Eigen::Vector3d& p : points) {
    lo_ = lo_.cwiseMin(p);
    hi_ = hi_.cwiseMax(p);
  }
  const Eigen::Vector3d grown = pad * (hi_ - lo_);
  lo_ -= grown;
  hi_ += grown;
  if (in_plane) hi_.z() = lo_.z();
  // A quarter of the margin, where the voxels allow: the slack below adds
  // to the margin.
  const Eigen::Vector3d extent = (hi_ - lo_).cwiseMax(1e-12 * std::max(1.0, (hi_ - lo_).maxCoeff()));
  const double volume = in_plane ? extent.x() * extent.y() : extent.prod();
  // (At most kVoxels, and a flat or thin set of points at most kSide along its longest side.)
  voxel_ = std::max({0.25 * margin, in_plane ? std::sqrt(volume / voxels) : std::cbrt(volume / voxels),
                     extent.maxCoeff() / side});
  for (int d = 0; d < 3; ++d) n_[std::size_t(d)] = int((hi_(d) - lo_(d)) / voxel_) + 2;
  if (in_plane) n_[2] = 1;
  // A point and the centre of its voxel are at most half a diagonal apart,
  // and so are the query and its voxel's centre.
  slack_ = voxel_ * std::sqrt(in_plane ? 2.0 : 3.0);
  distance_.assign(std::size_t(n_[0]) * std::size_t(n_[1]) * std::size_t(n_[2]), float(kFar));
  for (const Eigen::Vector3d& p : points) {
    std::size_t index = 0, stride = 1;
    for (int d = 0; d < 3; ++d) {
      const int i = in_plane && d == 2 ? 0 : int((p(d) - lo_(d)) / voxel_ + 0.5);  // p >= lo_: rounds
      index += std::size_t(std::clamp(i, 0, n_[std::size_t(d)] - 1)) * stride;
      stride *= std::size_t(n_[std::size_t(d)]);
    }
    distance_[index] = 0;
  }
  std::vector<double> in, out, z;
  std::vector<int> v;
  const std::size_t nx = std::size_t(n_[0]), ny = std::size_t(n_[1]), nz = std::size_t(n_[2]);
  for (std::size_t k = 0; k < nz; ++k)
    for (std::size_t j = 0; j < ny; ++j) transform_line(&distance_[(k * ny + j) * nx], n_[0], 1, in, out, v, z);
  for (std::size_t k = 0; k < nz; ++k)
    for (std::size_t i = 0; i < nx; ++i) transform_line(&distance_[k * ny * nx + i], n_[1], int(nx), in, out, v, z);
  if (nz > 1)
    for (std::size_t j = 0; j < ny; ++j)
      for (std::size_t i = 0; i < nx; ++i) transform_line(&distance_[j * nx + i], n_[2], int(nx * ny), in, out, v, z);
  for (float& d : distance_) d = float(std::sqrt(double(d)) * voxel_);
}

double BallSetDistance::outside(const Eigen::Vector3d& p) const {
  if (distance_.empty()) return std::numeric_limits<double>::infinity();
  // Beyond the points' box, the distance to a point in it is at least the
  // hypotenuse of the distance to the box and that from the box's nearest point.
  Eigen::Vector3d q = p;
  if (in_plane_) q.z() = lo_.z();
  const Eigen::Vector3d near = q.cwiseMax(lo_).cwiseMin(hi_);
  std::size_t index = 0, stride = 1;
  for (int d = 0; d < 3; ++d) {
    const int i = int(std::lround((near(d) - lo_(d)) / voxel_));
    index += std::size_t(std::clamp(i, 0, n_[std::size_t(d)] - 1)) * stride;
    stride *= std::size_t(n_[std::size_t(d)]);
  }
  // (The distance rounded to float: taken a little short.)
  const double within = std::max(0.0, double(distance_[index]) * (1 - 1e-6) - slack_);
  return std::sqrt((q - near).squaredNorm() + within * within) - margin_;
}

SampledReach sample_reach(const Leg& leg, const std::vector<Actuator>& actuators, bool planar, const LegState& seed) {
  SampledReach out;
  EndFreedoms end = end_freedoms(leg, actuators, planar, true);
  std::vector<Freedom>& freedoms = end.freedoms;
  const int last = end.last, ball = end.ball;
  out.why_not = end.why_not;
  if (freedoms.empty()) return out;
  out.joints = int(freedoms.size()) - (ball >= 0);
  if (free_rules_of(leg) > 6) {
    out.why_not = "more than six free branch rules";
    return out;
  }
  if (freedoms.size() > 3) {
    out.why_not = std::to_string(freedoms.size()) + " freedoms move its end; a grid samples three at most";
    return out;
  }
  const double margin = allot(freedoms, kSamples[freedoms.size() - 1]);
  const Samples samples = walk_samples(leg, freedoms, frames_of(leg, freedoms, seed));
  out.samples = int(samples.ends.size());

  const std::vector<std::uint64_t> combinations = combinations_of(leg, freedoms, samples, last, ball, nullptr);
  std::vector<std::vector<Eigen::Vector3d>> points(std::size_t(1) << free_rules_of(leg));
  for (std::size_t index = 0; index < samples.ends.size(); ++index)
    for (std::size_t combo = 0; combo < points.size(); ++combo)
      if (combinations[index] >> combo & 1) points[combo].push_back(samples.ends[index]);
  for (const auto& p : points) out.travel.emplace_back(p, margin, planar);
  out.built = true;
  return out;
}

namespace {
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
  out.cell = std::max({0.25 * out.margin, std::sqrt(extent.prod() / kBinnedCells), extent.maxCoeff() / 256});
  const int reach = int(std::ceil(out.margin / out.cell + std::sqrt(2.0)));  // cells
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
  const std::size_t from_a = first_joint(a).step, from_b = first_joint(b).step;
  if (a.steps.size() - from_a != b.steps.size() - from_b || a.rules.size() != b.rules.size()) return false;
  const auto limited = [&](const Step& s) { return s.actuator >= 0 && actuators[std::size_t(s.actuator)].limited; };
  for (std::size_t i = 0; i < a.steps.size() - from_a; ++i) {
    const Step &sa = a.steps[from_a + i], &sb = b.steps[from_b + i];
    if (sa.kind != sb.kind || sa.axis != sb.axis || sa.variable != sb.variable ||
        !(sa.transform.matrix() == sb.transform.matrix()) || (i > 0 && limited(sa) != limited(sb)))
      return false;
  }
  // The same branch rules, on the same steps (the first joint's travel may differ).
  for (std::size_t r = 0; r < a.rules.size(); ++r) {
    const BranchRule &ra = a.rules[r], &rb = b.rules[r];
    const auto from_first = [](const BranchRule& rule, std::size_t from) {
      std::array<int, 3> steps = rule.steps;
      for (int& step : steps) step = step >= 0 ? step - int(from) : step;
      return steps;
    };
    if (ra.kind != rb.kind || from_first(ra, from_a) != from_first(rb, from_b) || ra.direction != rb.direction ||
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
    out.margin = margin;
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
  const double widen = t.x() > margin ? std::asin(margin / t.x()) : kPi;
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
