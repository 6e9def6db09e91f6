// Shared pieces of the Delta tests: seeded samplers and a long-double
// reference built without the code under test.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include "core/mechanisms/delta/delta.h"

namespace linkscape::delta::test_support {

// Actuator angles uniform in the model's ranges.
class ConfigurationSampler {
 public:
  ConfigurationSampler(const Model& model, unsigned seed) : model_(model), rng_(seed) {}
  Eigen::Vector3d operator()() {
    Eigen::Vector3d q;
    for (int i = 0; i < kLegCount; ++i) {
      std::uniform_real_distribution<double> d(model_.q_limits[i].lo, model_.q_limits[i].hi);
      q(i) = d(rng_);
    }
    return q;
  }
  std::mt19937_64& rng() { return rng_; }

 private:
  Model model_;
  std::mt19937_64 rng_;
};

// Actuator angles (over the full circle) for which no platform position
// exists: the three sphere centres lie farther apart than Lb allows.
inline Eigen::Vector3d unassemblable_configuration(const Model& model, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  for (;;) {
    const Eigen::Vector3d q(angle(rng), angle(rng), angle(rng));
    if (forward(model, q).status == Status::Unreachable) return q;
  }
}

// A measured number for RecordProperty, in scientific notation.
inline std::string scientific(double value) {
  std::ostringstream out;
  out.precision(3);
  out << std::scientific << value;
  return out.str();
}

inline double angle_distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  Eigen::Vector3d d = a - b;
  for (int k = 0; k < 3; ++k) d(k) = std::remainder(d(k), 2 * std::numbers::pi);
  return d.lpNorm<Eigen::Infinity>();
}

using Vector3ld = Eigen::Matrix<long double, 3, 1>;

// Sphere centre B_i - r e_i built by rotating La e_i about the motor axis
// t_i by q_i (right-handed, which turns the arm downward), in long double.
inline Vector3ld reference_sphere_centre(const Model& m, int leg, long double q) {
  const long double phi = leg * (2.0L * std::numbers::pi_v<long double> / 3.0L);
  const Vector3ld e(std::cos(phi), std::sin(phi), 0.0L), t(-std::sin(phi), std::cos(phi), 0.0L);
  const Vector3ld arm = Eigen::AngleAxis<long double>(q, t) * (static_cast<long double>(m.La) * e);
  return static_cast<long double>(m.R) * e + arm - static_cast<long double>(m.r) * e;
}

// Trilateration in the frame of the three centres (x towards c1, y in their
// plane): both points at distance Lb from all three, or nothing.
inline bool reference_forward(const Model& m, const Eigen::Vector3d& q, std::array<Vector3ld, 2>& points) {
  std::array<Vector3ld, 3> c;
  for (int i = 0; i < 3; ++i) c[i] = reference_sphere_centre(m, i, q(i));
  const long double d = (c[1] - c[0]).norm();
  const Vector3ld ex = (c[1] - c[0]) / d;
  const long double i = ex.dot(c[2] - c[0]);
  const Vector3ld ey = (c[2] - c[0] - i * ex).normalized();
  const Vector3ld ez = ex.cross(ey);
  const long double j = ey.dot(c[2] - c[0]);
  const long double L = m.Lb;
  const long double x = d / 2.0L;  // equal radii
  const long double y = (i * i + j * j) / (2.0L * j) - i * x / j;
  const long double z2 = L * L - x * x - y * y;
  if (z2 < 0.0L) return false;
  const long double z = std::sqrt(z2);
  points[0] = c[0] + x * ex + y * ey + z * ez;
  points[1] = c[0] + x * ex + y * ey - z * ez;
  return true;
}

}  // namespace linkscape::delta::test_support
