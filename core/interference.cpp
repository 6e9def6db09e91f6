#include "core/interference.h"

#include <algorithm>

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

}  // namespace linkscape::interference
