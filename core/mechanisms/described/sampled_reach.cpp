#include "core/mechanisms/described/sampled_reach.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/joint_grid.h"

namespace linkscape::described {

using namespace internal;
using namespace joint_grid;

namespace {
// Samples by the number of freedoms that move the end.
constexpr std::array<double, 3> kSamples{1 << 7, 1 << 15, 1 << 16};
// Voxels per grid, at most (in a plane, in space).
constexpr double kVoxelsInPlane = 1 << 16, kVoxels = 1 << 16, kSide = 256;
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

}  // namespace linkscape::described
