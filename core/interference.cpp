#include "core/interference.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace linkscape::interference {

using Eigen::Vector3d;

SegmentPair closest_points(const Vector3d& a0, const Vector3d& a1, const Vector3d& b0, const Vector3d& b1) {
  const Vector3d d1 = a1 - a0, d2 = b1 - b0, r = a0 - b0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  // Below this a segment is a point (relative to the longer one, squared).
  const double tiny = 1e-30 * std::max({a, e, r.squaredNorm(), 1e-300});
  double s = 0, t = 0;
  if (a <= tiny && e <= tiny) {
    s = t = 0;
  } else if (a <= tiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= tiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      // Parallel segments (denom 0): any s serves; take 0 and let t follow.
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      // t outside [0, 1]: clamp it and take the s nearest the clamped point.
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  SegmentPair out;
  out.on_a = a0 + s * d1;
  out.on_b = b0 + t * d2;
  out.distance = (out.on_a - out.on_b).norm();
  return out;
}

double clearance(const Capsule& p, const Capsule& q) {
  return closest_points(p.a, p.b, q.a, q.b).distance - p.radius - q.radius;
}

void set_closest(LinkCapsules& c, int a, int b) {
  const int n = int(c.links.size());
  if (a < 0 || b < 0 || a >= n || b >= n || a == b)
    throw std::invalid_argument("link capsules: the closest pair must be two different links of 0.." +
                                std::to_string(n - 1) + ", got " + std::to_string(a) + " and " + std::to_string(b));
  const Capsule &p = c.links[std::size_t(a)].capsule, &q = c.links[std::size_t(b)].capsule;
  c.closest = {a, b};
  c.axes = closest_points(p.a, p.b, q.a, q.b);
  c.clearance = c.axes.distance - p.radius - q.radius;
}

std::array<Vector3d, 2> LinkCapsules::gap() const {
  if (!has_pair()) throw std::logic_error("link capsules: no closest pair");
  const Vector3d along = axes.on_b - axes.on_a;
  // Axes that meet: any direction serves; both points are then that point.
  const Vector3d u = axes.distance > 0 ? Vector3d(along / axes.distance) : Vector3d::Zero();
  return {axes.on_a + links[std::size_t(closest[0])].capsule.radius * u,
          axes.on_b - links[std::size_t(closest[1])].capsule.radius * u};
}

}  // namespace linkscape::interference
