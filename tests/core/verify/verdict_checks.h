// Checks of certified verdicts shared by the verify tests: a proof against
// dense samples of its boxes (the device and the long-double evaluation),
// a counterexample against independent evaluations.
#pragma once

#include <gtest/gtest.h>

#include <random>

#include "core/verify/certifier.h"
#include "core/verify/verify.h"

namespace linkscape::verify::testing {

using Eigen::Vector3d;

inline task::Device device_of(const Preset& preset, int branch = 0) {
  task::Device d;
  d.mechanism = make_mechanism(preset);
  d.ik.branch = branch;
  d.fixed_task = d.mechanism->home_task();
  return d;
}

inline std::vector<task::Criterion> criteria(std::initializer_list<const char*> texts) {
  std::vector<task::Criterion> out;
  for (const char* t : texts) out.push_back(task::parse_criterion(t));
  return out;
}

// Every proved box (at most `boxes` of them, evenly picked), sampled at its
// corners, centre and random points: the device and the long-double
// evaluation both meet the threshold there, and come within `close` of it.
inline void expect_proved_boxes_hold(const Preset& preset, const Result& r, double threshold, int branch = 0,
                                     double close = 0.95, std::size_t boxes = 4000) {
  ASSERT_EQ(r.verdict, Verdict::Proved);
  ASSERT_FALSE(r.proved_boxes.empty());
  const Certifier c = Certifier::from_preset(preset, branch, threshold);
  const task::Device d = device_of(preset, branch);
  const std::vector<task::Criterion> cond = task::resolve(d, criteria({"cond<1e9"}));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> t(0, 1);
  const std::size_t stride = std::max<std::size_t>(1, r.proved_boxes.size() / boxes);
  int samples = 0;
  double worst = 0;
  for (std::size_t i = 0; i < r.proved_boxes.size(); i += stride) {
    const Box& b = r.proved_boxes[i];
    for (int s = 0; s < 12; ++s) {
      const Vector3d f = s < 8 ? Vector3d(s & 1, (s >> 1) & 1, (s >> 2) & 1)
                               : s == 8 ? Vector3d::Constant(0.5) : Vector3d(t(rng), t(rng), t(rng));
      const Vector3d p = b.lo + f.cwiseProduct(b.hi - b.lo);
      const long double reference = reference_condition(c, p);
      ASSERT_LT(reference, (long double)threshold) << p.transpose();
      const task::PointValues device = task::evaluate_point(d, cond, p);
      ASSERT_TRUE(device.reachable) << p.transpose();
      ASSERT_LT(device.values[0], threshold) << p.transpose();
      worst = std::max(worst, double(reference));
      ++samples;
    }
  }
  EXPECT_GT(samples, int(std::min(boxes, r.proved_boxes.size())) * 10);
  // The proof is not a loose one far from the threshold: sampling comes close to it.
  EXPECT_GT(worst, close * threshold);
}

inline void expect_confirmed(const Preset& preset, const task::TaskVolume& task, const Result& r, double threshold,
                             int branch = 0) {
  ASSERT_EQ(r.verdict, Verdict::Disproved);
  ASSERT_TRUE(r.counterexample);
  const Counterexample& ce = *r.counterexample;
  EXPECT_TRUE(task.contains(ce.point, *task.centre));
  EXPECT_GE(ce.bound, threshold);
  // Independently: long double through the actuator angles, and the device.
  const Certifier c = Certifier::from_preset(preset, branch, threshold);
  EXPECT_GE(reference_condition(c, ce.point), (long double)threshold);
  EXPECT_NEAR(ce.long_double_value, double(reference_condition(c, ce.point)), 1e-12 * ce.long_double_value);
  const task::Device d = device_of(preset, branch);
  EXPECT_FALSE(task::evaluate_point(d, task::resolve(d, criteria({"cond<1e9"})), ce.point).values[0] < threshold);
  EXPECT_TRUE(r.proved_boxes.empty());
}

}  // namespace linkscape::verify::testing
