// The enclosures of one device: the kernels are the devices' own Jacobians,
// a box's bound holds at every point of the box (long double, independent
// evaluation), boxes that leave the workspace are never bounded, and certain
// failures are failures for the device too.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <sstream>

#include "core/haptics.h"
#include "core/mechanisms/delta/delta.h"
#include "core/mechanisms/parallel12r/mechanism.h"
#include "core/preset.h"
#include "core/task.h"
#include "core/verify/certifier.h"
#include "core/verify/verify.h"

namespace linkscape::verify {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

Preset preset_12r(double L1, double L2) {
  Preset p = load_preset("parallel-12r");
  p.parameters["L1"] = L1, p.parameters["L2"] = L2;
  return p;
}

Matrix3d to_matrix(const Matrix3<double>& m) {
  Matrix3d out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out(i, j) = m[i][j];
  return out;
}

// The device without its stated stops: the certifier bounds the linkage
// (verify reports the stops as not covered).
task::Device device_of(Preset preset, int branch) {
  preset.checks = {false, false};
  task::Device d;
  d.mechanism = make_mechanism(preset);
  d.ik.branch = branch;
  d.fixed_task = d.mechanism->home_task();
  return d;
}

// Whether the device itself reaches p in its branch (IK Ok, within ranges, J regular).
bool device_reaches(const task::Device& d, const Vector3d& p) {
  return task::evaluate_point(d, {task::parse_criterion("reach")}, p).reachable;
}

TEST(VerifyKernels, The12rMatrixIsTheDevicesJacobian) {
  const parallel12r::Model m = make_parallel12r(preset_12r(15, 11));
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-26, 26);
  int compared = 0;
  for (int n = 0; n < 4000; ++n) {
    const Vector3d p(u(rng), u(rng), u(rng));
    const parallel12r::IkResult ik = parallel12r::inverse(m, p, parallel12r::IkMethod::Planar);
    for (const parallel12r::IkSolution& s : ik.solutions) {
      if (s.status != Status::Ok) continue;
      const KernelResult<double> k = kernel_12r(m.L1, m.L2, s.branch, p.x(), p.y(), p.z());
      ASSERT_EQ(k.failure, KernelFailure::None) << p.transpose();
      const Matrix3d J = parallel12r::jacobian(m, s.q_actuated);
      ASSERT_LT((to_matrix(k.M) - J).norm(), 1e-9 * J.norm()) << p.transpose();
      ++compared;
    }
  }
  EXPECT_GT(compared, 3000);
}

TEST(VerifyKernels, TheDeltaMatrixIsTheInverseOfTheDevicesJacobian) {
  const Preset preset = load_preset("delta");
  delta::Model m;  // the preset's dimensions without ranges: every branch reaches
  for (auto& r : m.q_limits) r = {-3.14159, 3.14159};
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-12, 12), h(-24, -4);
  int compared = 0;
  for (int n = 0; n < 4000; ++n) {
    const Vector3d p(u(rng), u(rng), h(rng));
    for (int branch : {0, 5, 7}) {
      delta::IkOptions o;
      o.branch = branch;
      const delta::IkResult ik = delta::inverse(m, p, delta::IkMethod::Closed, o);
      if (ik.status != Status::Ok) continue;
      const DeltaGeometry g{m.R, m.r, m.La, m.Lb, branch};
      const KernelResult<double> k = kernel_delta(g, p.x(), p.y(), p.z());
      ASSERT_EQ(k.failure, KernelFailure::None) << p.transpose();
      const Matrix3d K = delta::jacobian(m, ik.q_actuated, p).J_actuated_from_task;
      ASSERT_LT((to_matrix(k.M) - K).norm(), 1e-8 * K.norm()) << p.transpose() << " branch " << branch;
      for (int i = 0; i < 3; ++i) {
        ASSERT_NEAR(std::atan2(k.sin_q[i], k.cos_q[i]), ik.q_actuated(i), 1e-9);
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, 3000);
}

// Random boxes of many sizes around the workspace: where a box gets a bound,
// every sampled point of it is reached by the device and has c(J) at most
// the bound in long double (an evaluation through the actuator angles, not
// the kernel); boxes holding a point the device does not reach get none.
void check_boxes(const Preset& preset, int branch, const Vector3d& lo, const Vector3d& hi, double cond_bound,
                 int seed) {
  const Certifier c = Certifier::from_preset(preset, branch, cond_bound);
  const task::Device device = device_of(preset, branch);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> t(0, 1), w(-12, -3);
  int bounded = 0, unbounded_with_unreachable = 0;
  for (int n = 0; n < 3000; ++n) {
    const Vector3d corner = lo + Vector3d(t(rng), t(rng), t(rng)).cwiseProduct(hi - lo);
    const Vector3d size = (hi - lo).maxCoeff() * Vector3d(std::exp2(w(rng)), std::exp2(w(rng)), std::exp2(w(rng)));
    const std::optional<double> bound = c.condition_bound(corner, corner + size);
    bool all_reached = true;
    for (int s = 0; s < 27; ++s) {
      const Vector3d f = s < 8 ? Vector3d(s & 1, (s >> 1) & 1, (s >> 2) & 1) : Vector3d(t(rng), t(rng), t(rng));
      const Vector3d p = corner + f.cwiseProduct(size);
      const bool reached = device_reaches(device, p);
      all_reached = all_reached && reached;
      if (!bound) continue;
      ASSERT_TRUE(reached) << "a bounded box holds an unreachable point " << p.transpose();
      ASSERT_LE(reference_condition(c, p), (long double)*bound) << p.transpose();
    }
    bounded += bound.has_value();
    unbounded_with_unreachable += !bound && !all_reached;
  }
  // Both kinds occur, so the checks above are not vacuous.
  EXPECT_GT(bounded, 200);
  EXPECT_GT(unbounded_with_unreachable, 200);
}

TEST(VerifyCertifier, The12rBoxBoundsHoldAtEveryPointAndNeverSpanTheWorkspaceEdge) {
  check_boxes(preset_12r(15, 12), 0, Vector3d(-28, -28, -28), Vector3d(28, 28, 28), 1e6, 3);
  check_boxes(preset_12r(15, 15), 1, Vector3d(-30, -30, -30), Vector3d(30, 30, 30), 1e6, 4);
}

TEST(VerifyCertifier, The12rActuatorRangesAreNeverCrossedByABoundedBox) {
  Preset p = preset_12r(15, 15);
  p.limits_deg["beta"] = {-30, 120};
  p.limits_deg["gamma"] = {-100, 60};
  check_boxes(p, 0, Vector3d(-30, -30, -30), Vector3d(30, 30, 30), 1e6, 5);
}

TEST(VerifyCertifier, TheDeltaBoxBoundsHoldAtEveryPointAndNeverSpanTheWorkspaceEdge) {
  const Preset preset = load_preset("delta");  // its ranges (-45 to 90 deg) cut the workspace
  check_boxes(preset, 0, Vector3d(-16, -16, -27), Vector3d(16, 16, 2), 1e6, 6);
  // Elbows in: the preset's ranges leave little of it, so over full turns.
  Preset full = preset;
  for (const char* q : {"q1", "q2", "q3"}) full.limits_deg[q] = {-180, 180};
  check_boxes(full, 6, Vector3d(-16, -16, -27), Vector3d(16, 16, 2), 1e6, 7);
}

// The Delta counts an angle inside a range if some turn of it is: ranges a
// turns away (675 to 810 deg for -45 to 90) certify the same boxes.
TEST(VerifyCertifier, TheDeltaRangesAreTheSameWholeTurnsAway) {
  const Preset preset = load_preset("delta");
  Preset turned = preset;
  for (auto& [name, range] : turned.limits_deg) range = {range.lo + 720, range.hi + 720};
  const Certifier a = Certifier::from_preset(preset, 0, 1e6), b = Certifier::from_preset(turned, 0, 1e6);
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-10, 10), h(-22, -8), w(-9, -4);
  int bounded = 0;
  for (int n = 0; n < 3000; ++n) {
    const Vector3d lo(u(rng), u(rng), h(rng));
    const Vector3d hi = lo + 25 * Vector3d(std::exp2(w(rng)), std::exp2(w(rng)), std::exp2(w(rng)));
    const std::optional<double> x = a.condition_bound(lo, hi), y = b.condition_bound(lo, hi);
    ASSERT_EQ(x.has_value(), y.has_value()) << lo.transpose();
    bounded += x.has_value();
    const Vector3d p = 0.5 * (lo + hi);
    ASSERT_EQ(a.certain_failure(p).has_value(), b.certain_failure(p).has_value()) << p.transpose();
  }
  EXPECT_GT(bounded, 1000);
}

// A force_iso or resolution bound on J's columns, with the threshold at the
// median over random boxes near the home: bounded boxes meet it at every
// sampled point, for the device and in long double; both outcomes occur.
TEST(VerifyCertifier, HapticBoxBoundsHoldAtEveryPoint) {
  for (const char* name : {"parallel-12r", "delta"})
    for (bool force : {true, false}) {
      const Preset preset = load_preset(name);
      task::Device d = device_of(preset, 0);
      d.data = haptics::device_data(preset, d.mechanism->info());
      Certifier c = Certifier::from_preset(preset, 0, 1e5);
      Certifier::ColumnCriterion column{force ? "force_iso>F" : "resolution<R", force, 0, {}};
      for (std::size_t i = 0; i < 3; ++i) {
        const haptics::Rating& r = d.data->actuators[i];
        const Interval metres(d.data->metres_per_motor_radian(i));
        column.scale[i] = force ? Interval(r.continuous_torque_Nm) / metres
                                : Interval(1000.0) * Interval(6.283185307179586, 6.283185307179587) /
                                      Interval(r.encoder_counts_per_rev) * metres;
      }
      std::mt19937_64 rng(12);
      std::uniform_real_distribution<double> u(-0.2, 0.2), t(0, 1), w(-10, -3);
      const Vector3d home = d.mechanism->home_task();
      std::vector<Vector3d> corners, sizes;
      std::vector<double> values;
      for (int n = 0; n < 1500; ++n) {
        corners.push_back(home + d.mechanism->size() * Vector3d(u(rng), u(rng), u(rng)));
        sizes.push_back(d.mechanism->size() * Vector3d(std::exp2(w(rng)), std::exp2(w(rng)), std::exp2(w(rng))));
        values.push_back(double(reference_value(c, column, corners.back() + sizes.back() / 2)));
      }
      // The median where the device reaches (force 0 and resolution +inf elsewhere).
      std::vector<double> sorted;
      for (double v : values)
        if (v > 0 && std::isfinite(v)) sorted.push_back(v);
      std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(sorted.size() / 2), sorted.end());
      column.threshold = sorted[sorted.size() / 2];
      c.columns = {column};
      std::ostringstream text;
      text.precision(17);
      text << (force ? "force_iso>" : "resolution<") << column.threshold;
      const std::vector<task::Criterion> criterion = task::resolve(d, {task::parse_criterion(text.str())});
      int bounded = 0, unbounded = 0;
      for (std::size_t n = 0; n < corners.size(); ++n) {
        if (!c.condition_bound(corners[n], corners[n] + sizes[n])) {
          ++unbounded;
          continue;
        }
        ++bounded;
        for (int k = 0; k < 16; ++k) {
          const Vector3d p = corners[n] + Vector3d(t(rng), t(rng), t(rng)).cwiseProduct(sizes[n]);
          const long double v = reference_value(c, column, p);
          ASSERT_TRUE(force ? v > column.threshold : v < column.threshold) << name << " " << p.transpose();
          ASSERT_TRUE(task::evaluate_point(d, criterion, p).meets) << name << " " << p.transpose();
        }
      }
      EXPECT_GT(bounded, 200) << name;
      EXPECT_GT(unbounded, 200) << name;
    }
}

TEST(VerifyCertifier, CertainFailuresFailForTheDeviceAndInLongDouble) {
  for (const char* name : {"parallel-12r", "delta"}) {
    const Preset preset = load_preset(name);
    const double threshold = 2.5;
    const Certifier c = Certifier::from_preset(preset, 0, threshold);
    const task::Device d = device_of(preset, 0);
    const std::vector<task::Criterion> criteria = task::resolve(d, {task::parse_criterion("cond<2.5")});
    std::mt19937_64 rng(8);
    const Vector3d home = d.mechanism->home_task();
    std::uniform_real_distribution<double> u(-1, 1);
    int failures = 0, meeting = 0;
    for (int n = 0; n < 20000; ++n) {
      const Vector3d p = home + 0.9 * d.mechanism->size() * Vector3d(u(rng), u(rng), u(rng));
      const task::PointValues device = task::evaluate_point(d, criteria, p);
      if (const auto f = c.certain_failure(p)) {
        ASSERT_FALSE(device.meets) << name << " " << p.transpose();
        ASSERT_GE(reference_condition(c, p), (long double)f->bound) << name << " " << p.transpose();
        ++failures;
      } else if (device.meets) {
        ++meeting;
      }
    }
    EXPECT_GT(failures, 1000) << name;
    EXPECT_GT(meeting, 100) << name;
  }
}

TEST(VerifyCertifier, OtherDevicesCannotBeCertified) {
  for (const char* name : {"pathos2", "five-bar", "pathos2-described"})
    EXPECT_THROW(Certifier::from_preset(load_preset(name), 0, 3), Uncertifiable) << name;
  EXPECT_THROW(Certifier::from_preset(load_preset("parallel-12r"), 2, 3), std::invalid_argument);
  EXPECT_THROW(Certifier::from_preset(load_preset("delta"), 8, 3), std::invalid_argument);
}

}  // namespace
}  // namespace linkscape::verify
