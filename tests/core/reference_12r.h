// Independent helpers for the 12R tests: the paper's Eqs. 11-13 written out
// literally, and seeded random configurations.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <random>

#include "core/parallel12r.h"

namespace linkscape::testing {

// Eqs. 11-13 exactly as printed (x, y, z of endpoint D).
inline Eigen::Vector3d paper_forward(double L1, double L2, double a, double b, double g) {
  const double sa = std::sin(a), ca = std::cos(a);
  const double db = std::sqrt(1 - sa * sa * std::sin(b) * std::sin(b));
  const double dg = std::sqrt(1 - sa * sa * std::sin(g) * std::sin(g));
  return {-(L1 * (sa * std::cos(b)) / db + L2 * (sa * std::cos(g)) / dg),
          L1 * (ca * std::cos(b)) / db + L2 * (ca * std::cos(g)) / dg,
          L1 * (ca * std::sin(b)) / db + L2 * (ca * std::sin(g)) / dg};
}

// Configurations with alpha in (-pi/2, pi/2) kept `margin` rad away from the
// actuator plane and |sin(beta - gamma)| >= sin(margin) (away from the outer
// and inner spheres), so that every point has a well-defined IK.
class ConfigurationSampler {
 public:
  explicit ConfigurationSampler(unsigned seed, double margin = 0.05) : rng_(seed), margin_(margin) {}
  Eigen::Vector3d operator()() {
    constexpr double pi = std::numbers::pi;
    std::uniform_real_distribution<double> alpha(-pi / 2 + margin_, pi / 2 - margin_);
    std::uniform_real_distribution<double> angle(-pi, pi);
    for (;;) {
      Eigen::Vector3d q(alpha(rng_), angle(rng_), angle(rng_));
      if (std::abs(std::sin(q.y() - q.z())) >= std::sin(margin_)) return q;
    }
  }

 private:
  std::mt19937_64 rng_;
  double margin_;
};

}  // namespace linkscape::testing
