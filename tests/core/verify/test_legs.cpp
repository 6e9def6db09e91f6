// Certified verdicts for described devices whose legs are solved in closed
// form: the closed forms against the device's own evaluation, proofs
// against dense sampling, counterexamples confirmed, the described Delta
// against the compiled one, the spectrum bounds, and the refusals.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>

#include "core/verify/certifier.h"
#include "core/verify/legs.h"
#include "core/verify/matrix_bounds.h"
#include "core/verify/verify.h"
#include "tests/core/mechanisms/described/designs.h"
#include "tests/core/verify/verdict_checks.h"

namespace linkscape::verify {
namespace {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using namespace testing;

std::vector<task::Criterion> cond_below(double threshold) {
  return {task::parse_criterion("cond<" + std::to_string(threshold))};
}

// A task near each device's home, inside its workspace, and how far above
// (and below) the largest measure sampled there the thresholds are: the
// hexapods' measure (J's translational rows), from an enclosure of J = M^-1,
// needs smaller boxes to come as close.
struct Case {
  const char* name;
  const char* task;
  double margin;
};
const Case kCases[] = {
    {"delta-described", "sphere:diameter=6,centre=0,0,-20", 0.02},
    {"hexapod-rus", "sphere:diameter=1,centre=0,0,11.1", 0.03},
    {"stewart", "box:size=2,2,1.5,centre=0,0,10", 0.03},
    {"linear-delta", "sphere:diameter=10,centre=0,0,0", 0.02},
};

task::TaskVolume task_of(const Case& c) { return task::parse_task(c.task); }

// The closed forms in double give the device's own measure wherever the
// device assembles on the branch, and fail where it does not.
TEST(VerifyLegs, TheClosedFormsGiveTheDevicesMeasureAndReach) {
  for (const char* name : {"delta-described", "hexapod-rus", "stewart", "linear-delta"}) {
    const Preset preset = load_preset(name);
    const task::Device d = device_of(preset);
    const Certifier c = Certifier::from_preset(preset, 0, 1.0);
    const std::vector<task::Criterion> cond = task::resolve(d, cond_below(1e9));
    const Eigen::AlignedBox3d box = d.mechanism->default_box();
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> t(0, 1);
    int assembled = 0, failing = 0;
    for (int k = 0; k < 3000; ++k) {
      const Vector3d p = box.min() + Vector3d(t(rng), t(rng), t(rng)).cwiseProduct(box.max() - box.min());
      const task::PointValues device = task::evaluate_point(d, cond, p);
      const double kernel = c.badness(p);  // the measure itself: the bound is 1
      if (device.reachable && device.values[0] < 1e6) {
        ++assembled;
        EXPECT_NEAR(kernel, device.values[0], 1e-7 * device.values[0]) << name << " at " << p.transpose();
        EXPECT_NEAR(double(reference_condition(c, p)), device.values[0], 1e-7 * device.values[0]) << name;
      } else if (!device.reachable) {
        ++failing;
        if (std::isfinite(kernel) && kernel < 1e6) {
          // Where the closed forms assemble and the device does not, only its stops stop it.
          Eigen::VectorXd x = d.fixed_task;
          x.head<3>() = p;
          EXPECT_NE(d.mechanism->inverse(x, d.ik).status_text.find("out-of-limits"), std::string::npos)
              << name << " at " << p.transpose();
        }
      }
    }
    EXPECT_GT(failing, 30) << name;
    EXPECT_GT(assembled, 50) << name;
  }
}

// Proved with a threshold 2 % (hexapods 3 %) above the largest measure sampled over
// the task: dense samples of every proved box meet it for the device and in
// long double. Disproved as far below it: the counterexample is in the task
// and fails for the device and in long double.
TEST(VerifyLegs, ProofsHoldAtDenseSamplesAndCounterexamplesAreConfirmed) {
  for (const Case& k : kCases) {
    SCOPED_TRACE(k.name);
    const Preset preset = load_preset(k.name);
    task::TaskVolume task = task_of(k);
    const task::Device d = device_of(preset);
    const std::vector<task::Criterion> cond = task::resolve(d, cond_below(1e9));
    const task::TaskReport sampled = task::evaluate(d, cond, task, *task.centre, 24);
    const double worst = sampled.criteria[0].worst;
    ASSERT_TRUE(std::isfinite(worst)) << k.name;
    Options o;
    o.keep_boxes = true;
    const double above = worst * (1 + k.margin), below = worst * (1 - k.margin);
    const Result proved = verify(preset, task, cond_below(above), o);
    ASSERT_EQ(proved.verdict, Verdict::Proved) << k.name;
    EXPECT_EQ(proved.undecided_volume, 0) << k.name;
    EXPECT_GE(proved.proved_volume, task.volume()) << k.name;
    // Where the device states stops, the task is one they do not cut, so the device's verdict is the proof's.
    EXPECT_EQ(proved.stop_failures, 0) << k.name;
    expect_proved_boxes_hold(preset, proved, above, 0, 1 - 2 * k.margin, 1500);

    o.keep_boxes = false;
    o.search_samples = 0;  // subdivision alone finds it
    const Result disproved = verify(preset, task, cond_below(below), o);
    expect_confirmed(preset, task, disproved, below);
    if (disproved.counterexample) EXPECT_GE(disproved.counterexample->device_value, below);
  }
}

// The described Delta (delta-described.json) and the compiled one
// (delta.json) have the same geometry: on every branch the same measure,
// and the same verdicts with the same thresholds.
TEST(VerifyLegs, TheDescribedDeltaAgreesWithTheCompiledOne) {
  Preset described = load_preset("delta-described"), compiled = load_preset("delta");
  // Every branch within a whole turn of travel.
  for (Preset* p : {&described, &compiled})
    for (auto& [name, range] : p->limits_deg) range = {-180, 180};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> t(-1, 1);
  for (int branch = 0; branch < 8; ++branch) {
    const Certifier a = Certifier::from_preset(described, branch, 1.0), b = Certifier::from_preset(compiled, branch, 1.0);
    int both = 0;
    for (int k = 0; k < 400; ++k) {
      const Vector3d p = Vector3d(0, 0, -18) + 8 * Vector3d(t(rng), t(rng), t(rng));
      const long double x = reference_condition(a, p), y = reference_condition(b, p);
      ASSERT_EQ(std::isfinite(x), std::isfinite(y)) << branch << " at " << p.transpose();
      if (!std::isfinite(x)) continue;
      EXPECT_NEAR(double(x), double(y), 1e-9 * double(y)) << branch;
      ++both;
    }
    EXPECT_GT(both, 20) << branch;
  }
  for (const char* text : {"sphere:diameter=5,centre=0,0,-20", "box:size=8,8,4,centre=1,0,-18"}) {
    const task::TaskVolume task = task::parse_task(text);
    for (double threshold : {1.8, 2.5, 4.0}) {
      const Result r_described = verify(described, task, cond_below(threshold));
      const Result r_compiled = verify(compiled, task, cond_below(threshold));
      EXPECT_EQ(r_described.verdict, r_compiled.verdict) << text << " cond<" << threshold;
      if (r_described.counterexample) {
        // Each counterexample fails on the other device too.
        const Certifier c = Certifier::from_preset(compiled, 0, threshold);
        EXPECT_GE(reference_condition(c, r_described.counterexample->point), (long double)threshold);
      }
    }
  }
}

// The described Delta states ball-joint cones: the verdict says they are not
// covered and the device's own evaluation counts where they stop it.
TEST(VerifyLegs, StopsAreNamedAsNotCoveredAndSampledByTheDevice) {
  const Result inside = verify(load_preset("delta-described"), task::parse_task("sphere:diameter=5,centre=0,0,-20"),
                               cond_below(5));
  EXPECT_EQ(inside.verdict, Verdict::Proved);
  EXPECT_NE(inside.not_covered.find("passive-joint limits"), std::string::npos) << inside.not_covered;
  EXPECT_GT(inside.stop_samples, 1000);
  EXPECT_EQ(inside.stop_failures, 0);
  std::ostringstream report;
  write_report(report, inside);
  EXPECT_NE(report.str().find("not covered: its passive-joint limits"), std::string::npos) << report.str();
  // Out to the side, the cones stop the device where its closure, reach and travel hold.
  const Preset preset = load_preset("delta-described");
  const Result side = verify(preset, task::parse_task("sphere:diameter=3,centre=-11,0,-9"), {task::parse_criterion("reach")});
  EXPECT_GT(side.stop_failures, 100);
  EXPECT_NE(side.stop_example.find("cone"), std::string::npos) << side.stop_example;
  // The device the verdict is about (its stops removed) assembles there; the device as stated does not.
  const Vector3d stopped(-12, 0, -8);
  const std::vector<task::Criterion> reach = {task::parse_criterion("reach")};
  EXPECT_FALSE(task::evaluate_point(device_of(preset), reach, stopped).reachable);
  EXPECT_TRUE(task::evaluate_point(device_of(without_stops(preset)), reach, stopped).reachable);
  EXPECT_EQ(without_stops(preset).parameters, preset.parameters);
  EXPECT_EQ(make_mechanism(without_stops(preset))->home_actuators(), make_mechanism(preset)->home_actuators());
  // A device without stops has nothing uncovered.
  const Result hexapod = verify(load_preset("hexapod-rus"), task::parse_task("sphere:diameter=1,centre=0,0,11"),
                                cond_below(20));
  EXPECT_TRUE(hexapod.not_covered.empty());
  EXPECT_EQ(hexapod.stop_samples, 0);
}

TEST(VerifyLegs, DevicesWithOtherLegsOrCriteriaAreRefusedByName) {
  auto message_of = [](const Preset& preset) {
    try {
      Certifier::from_preset(preset, 0, 3);
    } catch (const Uncertifiable& e) {
      return std::string(e.what());
    }
    return std::string("certified");
  };
  auto message = [&](const char* name) { return message_of(load_preset(name)); };
  EXPECT_NE(message("pathos2-described").find("three-revolute"), std::string::npos) << message("pathos2-described");
  EXPECT_NE(message("five-bar").find("planar"), std::string::npos) << message("five-bar");
  EXPECT_NE(message("three-rrr").find("planar"), std::string::npos) << message("three-rrr");
  // Crank-rods whose rods end in a universal joint (the Omnid's arm with
  // universal knees and platform joints): their legs hold the orientation too.
  const Preset ruu = testing_support::omnid_with_universal_joints();
  EXPECT_NE(message_of(ruu).find("crank-rod ending in a universal joint"), std::string::npos) << message_of(ruu);
  EXPECT_EQ(message("omnid-delta"), "certified");
  EXPECT_THROW(verify(load_preset("delta-described"), task::parse_task("sphere:diameter=2,centre=0,0,-20"),
                      {task::parse_criterion("force_iso>1")}),
               Uncertifiable);
  EXPECT_THROW(Certifier::from_preset(load_preset("delta-described"), 8, 3), std::invalid_argument);
  EXPECT_THROW(Certifier::from_preset(load_preset("hexapod-rus"), 1, 3), std::invalid_argument);
}

// The spectrum bounds bracket the singular values of square and wide
// matrices (an SVD in long double) and are tight.
TEST(VerifyLegs, SpectrumBoundsBracketTheSingularValues) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> n(0, 1);
  for (int k = 0; k < 200; ++k) {
    const int rows = k % 2 ? 3 : 6, cols = 6;
    MatrixXd A(rows, cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) A(i, j) = n(rng) * (j == 0 ? (k < 100 ? 10.0 : 1e3) : 1.0);
    using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
    const auto s = Eigen::JacobiSVD<MatrixL>(A.cast<long double>()).singularValues();
    const SpectrumBounds b = spectrum_bounds(A);
    const long double largest = s(0), smallest = s(s.size() - 1);
    EXPECT_LE((long double)b.largest_lower, largest);
    EXPECT_GE((long double)b.largest_upper, largest);
    EXPECT_LE((long double)b.smallest_lower, smallest);
    EXPECT_GE((long double)b.smallest_upper, smallest);
    if (k < 100) {  // tight where the rounding of A A^T allows (c(A) about 10 to 100)
      EXPECT_NEAR(b.smallest_lower, double(smallest), 1e-6 * double(smallest));
      EXPECT_NEAR(b.largest_upper, double(largest), 1e-6 * double(largest));
    }
    // The bound on |I - A X| for an approximate inverse holds (square case).
    if (rows == cols) {
      const MatrixXd X = A.inverse();
      using MatrixL = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
      const MatrixL E = MatrixL::Identity(6, 6) - A.cast<long double>() * X.cast<long double>();
      const long double residual = Eigen::JacobiSVD<MatrixL>(E).singularValues()(0);
      EXPECT_GE((long double)inverse_residual_bound(A, X), residual);
    }
  }
}

}  // namespace
}  // namespace linkscape::verify
