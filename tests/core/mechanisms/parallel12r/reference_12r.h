// Independent helpers for the 12R tests: the paper's Eqs. 11-13 written out
// literally, and seeded random configurations.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <random>

#include "core/mechanisms/parallel12r/parallel12r.h"

namespace linkscape::testing {

// The 12R model with link lengths L1, L2 and every other parameter at its default.
inline parallel12r::Model make_12r(double L1, double L2) {
  parallel12r::Model m;
  m.L1 = L1;
  m.L2 = L2;
  return m;
}

// Eqs. 11-13 exactly as printed (x, y, z of endpoint D).
// Evaluated in T (long double gives a reference for the double code).
template <class T>
Eigen::Vector3d paper_forward_in(double L1, double L2, double a_, double b_, double g_) {
  using std::cos, std::sin, std::sqrt;
  const T a = a_, b = b_, g = g_;
  const T sa = sin(a), ca = cos(a);
  const T db = sqrt(1 - sa * sa * sin(b) * sin(b));
  const T dg = sqrt(1 - sa * sa * sin(g) * sin(g));
  return {double(-(L1 * (sa * cos(b)) / db + L2 * (sa * cos(g)) / dg)),
          double(L1 * (ca * cos(b)) / db + L2 * (ca * cos(g)) / dg),
          double(L1 * (ca * sin(b)) / db + L2 * (ca * sin(g)) / dg)};
}
inline Eigen::Vector3d paper_forward(double L1, double L2, double a, double b, double g) {
  return paper_forward_in<double>(L1, L2, a, b, g);
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
