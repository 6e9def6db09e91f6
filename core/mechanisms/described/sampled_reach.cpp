#include "core/mechanisms/described/sampled_reach.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/mechanisms/described/chain.h"

namespace linkscape::described {

using namespace internal;

namespace {
// Samples by the number of joints that move the end.
constexpr std::array<double, 3> kSamples{1 << 12, 1 << 15, 1 << 16};
// Voxels per grid, at most (in a plane, in space).
constexpr double kVoxelsInPlane = 1 << 16, kVoxels = 1 << 16;
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

// One joint that moves the end point, sampled over [lo, hi] in `count`
// steps (their centres); `turn`: a full turn, whose ends are neighbours.
struct SampledJoint {
  int step = 0;
  bool sliding = false;
  double lever = 0;  // a revolute's: the most its later links reach
  double lo = 0, hi = 0;
  bool turn = false;
  int count = 1;
  double half_step() const { return 0.5 * (hi - lo) / count; }
  double value(int i) const { return lo + (i + 0.5) * (hi - lo) / count; }
};

// Counts per joint for about `budget` samples, each joint's half step times
// its lever alike; returns the margin (the sum of those).
double allot(std::vector<SampledJoint>& joints, double budget) {
  const auto weight = [](const SampledJoint& j) { return (j.hi - j.lo) * (j.sliding ? 1.0 : j.lever); };
  double product = 1;
  for (const SampledJoint& j : joints) product *= std::max(weight(j), 1e-300);
  const double per = std::pow(product / budget, 1.0 / double(joints.size()));
  double margin = 0;
  for (SampledJoint& j : joints) {
    j.count = std::clamp(int(std::ceil(weight(j) / per)), 1, int(budget));
    margin += j.half_step() * (j.sliding ? 1.0 : j.lever);
  }
  return margin;
}

// The leg as the frames its sampled joints move: the frame after joint j
// is frame j times lead[j] times the joint's motion; every step's frame
// (before it) is one of those times a fixed offset. The joints it does not
// sample keep the seed's values.
struct Frames {
  std::vector<Eigen::Isometry3d> lead;      // per sampled joint
  std::vector<int> frame_of_step;           // per step: the frame it follows (0: the base's, j + 1: joint j's)
  std::vector<Eigen::Isometry3d> offset;    // per step: from that frame to the step
  Eigen::Isometry3d tail = Eigen::Isometry3d::Identity();  // from the last frame to the end
};

Frames frames_of(const Leg& leg, const std::vector<SampledJoint>& joints, const LegState& seed) {
  Frames f;
  Eigen::Isometry3d acc = leg.base;
  int frame = 0, sphere = 0;
  std::size_t next = 0;
  for (std::size_t i = 0; i < leg.steps.size(); ++i) {
    const Step& step = leg.steps[i];
    f.frame_of_step.push_back(frame);
    f.offset.push_back(acc);
    if (next < joints.size() && joints[next].step == int(i)) {
      f.lead.push_back(acc);
      acc.setIdentity();
      ++frame;
      ++next;
      continue;
    }
    switch (step.kind) {
      case Step::Kind::Fixed: acc = acc * step.transform; break;
      case Step::Kind::Revolute: acc.rotate(Eigen::AngleAxisd(seed.values(step.variable), step.axis)); break;
      case Step::Kind::Prismatic: acc.translate(step.axis * seed.values(step.variable)); break;
      case Step::Kind::Spherical: acc.rotate(seed.spheres[std::size_t(sphere)]); break;
    }
    sphere += step.kind == Step::Kind::Spherical;
  }
  f.tail = acc;
  return f;
}

// The end's point and every rule's sign at each sample, the last joint
// fastest; each frame recomputed only where a joint before it moved.
struct Samples {
  std::vector<Eigen::Vector3d> ends;
  std::vector<std::int8_t> signs;  // per sample, per rule
};

Samples walk_samples(const Leg& leg, const std::vector<SampledJoint>& joints, const Frames& f) {
  const std::size_t k = joints.size();
  std::vector<std::vector<Eigen::Isometry3d>> moved(k);  // per joint, per value: lead times motion
  std::size_t total = 1;
  for (std::size_t j = 0; j < k; ++j) {
    const Step& step = leg.steps[std::size_t(joints[j].step)];
    for (int i = 0; i < joints[j].count; ++i) {
      Eigen::Isometry3d m = f.lead[j];
      if (joints[j].sliding) m.translate(step.axis * joints[j].value(i));
      else m.rotate(Eigen::AngleAxisd(joints[j].value(i), step.axis));
      moved[j].push_back(m);
    }
    total *= std::size_t(joints[j].count);
  }
  const std::size_t rules = leg.rules.size();
  Samples out;
  out.ends.resize(total);
  out.signs.resize(total * rules);
  std::array<Eigen::Isometry3d, 4> frame;
  frame[0].setIdentity();
  std::array<int, 3> at{0, 0, 0};
  std::size_t changed = 0;  // the first joint whose value changed
  for (std::size_t index = 0; index < total; ++index) {
    for (std::size_t j = changed; j < k; ++j) frame[j + 1] = frame[j] * moved[j][std::size_t(at[j])];
    const Eigen::Vector3d end = frame[k] * f.tail.translation();
    out.ends[index] = end;
    const auto centre = [&](int step) {
      return step == -2 ? end : Eigen::Vector3d(frame[std::size_t(f.frame_of_step[std::size_t(step)])] *
                                                f.offset[std::size_t(step)].translation());
    };
    for (std::size_t r = 0; r < rules; ++r) {
      const BranchRule& rule = leg.rules[r];
      double value = 0;
      if (rule.kind == BranchRule::Kind::Angle) {
        for (std::size_t j = 0; j < k; ++j)
          if (joints[j].step == rule.steps[0]) value = sine_sign(joints[j].value(at[j]));
      } else if (rule.kind == BranchRule::Kind::Along) {
        value = (centre(rule.steps[1]) - centre(rule.steps[0])).dot(rule.direction);
      } else {
        const int a = rule.steps[0];
        const Eigen::Vector3d axis = frame[std::size_t(f.frame_of_step[std::size_t(a)])].linear() *
                                     (f.offset[std::size_t(a)].linear() * leg.steps[std::size_t(a)].axis);
        const Eigen::Vector3d b = centre(rule.steps[1]);
        value = (b - centre(a)).cross(centre(rule.steps[2]) - b).dot(axis);
      }
      out.signs[index * rules + r] = std::int8_t(value > 0 ? 1 : value < 0 ? -1 : 0);
    }
    // The next sample: the last joint fastest.
    changed = k;
    while (changed > 0) {
      --changed;
      if (++at[changed] < joints[changed].count) break;
      at[changed] = 0;
    }
  }
  return out;
}
}  // namespace

BallSetDistance::BallSetDistance(const std::vector<Eigen::Vector3d>& points, double margin, bool in_plane)
    : margin_(margin), in_plane_(in_plane) {
  if (points.empty()) return;
  lo_ = hi_ = points.front();
  for (const Eigen::Vector3d& p : points) {
    lo_ = lo_.cwiseMin(p);
    hi_ = hi_.cwiseMax(p);
  }
  if (in_plane) hi_.z() = lo_.z();
  // A quarter of the margin, where the voxels allow: the slack below adds
  // to the margin.
  const Eigen::Vector3d extent = (hi_ - lo_).cwiseMax(1e-12 * std::max(1.0, (hi_ - lo_).maxCoeff()));
  const double volume = in_plane ? extent.x() * extent.y() : extent.prod();
  voxel_ = std::max(0.25 * margin, in_plane ? std::sqrt(volume / kVoxelsInPlane) : std::cbrt(volume / kVoxels));
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
  const double within = std::max(0.0, double(distance_[index]) - slack_);
  return std::sqrt((q - near).squaredNorm() + within * within) - margin_;
}

SampledReach sample_reach(const Leg& leg, const std::vector<Actuator>& actuators, bool planar, const LegState& seed) {
  SampledReach out;
  const auto length = [&](const Eigen::Vector3d& v) { return planar ? v.head<2>().norm() : v.norm(); };
  // The last step that moves the end point: the joints after it only turn it.
  int last = -1;
  for (std::size_t i = 0; i < leg.steps.size(); ++i) {
    const Step& step = leg.steps[i];
    if ((step.kind == Step::Kind::Fixed && length(step.transform.translation()) > 0) ||
        step.kind == Step::Kind::Prismatic)
      last = int(i);
  }
  // The joints up to it, each over a full turn or its actuator's travel.
  std::vector<SampledJoint> joints;
  for (int i = 0; i <= last; ++i) {
    const Step& step = leg.steps[std::size_t(i)];
    if (step.kind == Step::Kind::Fixed) continue;
    if (step.kind == Step::Kind::Spherical) {
      out.why_not = "a spherical joint moves its end";
      return out;
    }
    const Actuator* act = step.actuator >= 0 ? &actuators[std::size_t(step.actuator)] : nullptr;
    SampledJoint j;
    j.step = i;
    j.sliding = step.kind == Step::Kind::Prismatic;
    if (j.sliding && !(act && act->limited)) {
      out.why_not = "a slide without travel moves its end";
      return out;
    }
    j.turn = !(act && act->limited);
    j.lo = j.turn ? -kPi : act->range.lo;
    j.hi = j.turn ? kPi : act->range.hi;
    // A revolute's lever: what the links after it reach at most.
    for (int after = i + 1; after <= last; ++after) {
      const Step& s = leg.steps[std::size_t(after)];
      if (s.kind == Step::Kind::Fixed) j.lever += length(s.transform.translation());
      if (s.kind == Step::Kind::Prismatic) {
        const Range& r = actuators[std::size_t(s.actuator)].range;
        j.lever += length(s.axis) * std::max(std::abs(r.lo), std::abs(r.hi));
      }
    }
    joints.push_back(j);
  }
  out.joints = int(joints.size());
  if (joints.empty() || joints.size() > 3) {
    out.why_not = joints.empty() ? "no joint moves its end"
                                 : std::to_string(joints.size()) + " joints move its end (a grid samples three at most)";
    return out;
  }
  const double margin = allot(joints, kSamples[joints.size() - 1]);
  const Samples samples = walk_samples(leg, joints, frames_of(leg, joints, seed));
  out.samples = int(samples.ends.size());

  // Which rules a sample tells: not an angle of a joint it does not sample,
  // nor a triple about an axis that a joint it does not sample turns.
  const std::size_t rules = leg.rules.size();
  std::vector<bool> told(rules, true);
  for (std::size_t r = 0; r < rules; ++r) {
    const BranchRule& rule = leg.rules[r];
    const auto sampled = [&](int step) {
      return std::any_of(joints.begin(), joints.end(), [&](const SampledJoint& j) { return j.step == step; });
    };
    if (rule.kind == BranchRule::Kind::Angle) told[r] = sampled(rule.steps[0]);
    if (rule.kind == BranchRule::Kind::Triple)
      for (int i = last + 1; i < rule.steps[0]; ++i)
        told[r] = told[r] && leg.steps[std::size_t(i)].kind == Step::Kind::Fixed;
  }
  // Where a rule's sign changes between two neighbouring samples, its zero
  // lies between them: both stand for assemblies of either sign.
  const std::size_t k = joints.size(), total = samples.ends.size();
  std::vector<std::uint8_t> both(total * rules, 0);
  for (std::size_t r = 0; r < rules; ++r)
    for (std::size_t index = 0; index < total; ++index)
      both[index * rules + r] = !told[r] || samples.signs[index * rules + r] == 0;
  std::size_t stride = 1;  // the last joint fastest
  for (std::size_t j = k; j-- > 0;) {
    const std::size_t count = std::size_t(joints[j].count), block = stride * count;
    for (std::size_t outer = 0; outer < total; outer += block)
      for (std::size_t a = 0; a < count; ++a) {
        if (a + 1 == count && !(joints[j].turn && count > 1)) break;
        const std::size_t b = a + 1 == count ? 0 : a + 1;
        for (std::size_t inner = 0; inner < stride; ++inner) {
          const std::size_t p = (outer + a * stride + inner) * rules, q = (outer + b * stride + inner) * rules;
          for (std::size_t r = 0; r < rules; ++r)
            if (samples.signs[p + r] != samples.signs[q + r]) both[p + r] = both[q + r] = 1;
        }
      }
    stride = block;
  }
  const int combos = 1 << free_rules_of(leg);
  std::vector<std::vector<Eigen::Vector3d>> points;
  points.resize(std::size_t(combos));
  for (std::size_t index = 0; index < total; ++index) {
    std::uint32_t allowed = (std::uint32_t(1) << combos) - 1;
    int bit = 0;
    for (std::size_t r = 0; r < rules; ++r) {
      const BranchRule& rule = leg.rules[r];
      const int free_bit = rule.free_index >= 0 ? bit++ : -1;
      const int sign = samples.signs[index * rules + r];
      if (both[index * rules + r]) continue;
      if (free_bit < 0) {
        if (sign != rule.fixed_sign) allowed = 0;
        continue;
      }
      for (int combo = 0; combo < combos; ++combo)
        if ((((combo >> free_bit) & 1) != 0) != (sign < 0)) allowed &= ~(std::uint32_t(1) << combo);
    }
    for (int combo = 0; combo < combos; ++combo)
      if (allowed >> combo & 1) points[std::size_t(combo)].push_back(samples.ends[index]);
  }
  for (const auto& p : points) out.travel.emplace_back(p, margin, planar);
  out.built = true;
  return out;
}

}  // namespace linkscape::described
