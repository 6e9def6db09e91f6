// Certified verdicts: proofs checked against dense sampling with independent
// long-double and device evaluations, counterexamples confirmed, unreachable
// parts never proved, bad input refused, and the exit statuses.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>

#include "core/verify/certifier.h"
#include "core/verify/verify.h"
#include "tests/core/verify/verdict_checks.h"

namespace linkscape::verify {
namespace {

using Eigen::Vector3d;
using namespace testing;

Preset preset_12r(double L) {
  Preset p = load_preset("parallel-12r");
  p.parameters["L1"] = p.parameters["L2"] = L;
  return p;
}


// Seed 001's 15 cm sphere scaled to the 12R at L1 = L2 = 1 (c(J) at p
// depends on p / L only), at the centre `linkscape fit` gives for it.
const Vector3d kSeedCentrePerL = Vector3d(-0.16876895597201358, -12.826372702528483, -8.295677424641113) / 12.268798828125;

// The seed's 15 cm sphere in units of the design fit answers (L = 12.27 cm
// becomes 1), placed for the design L (the placement scales with it).
task::TaskVolume seed_task(double L) {
  task::TaskVolume t = task::parse_task("sphere:diameter=" + std::to_string(15 / 12.268798828125));
  t.centre = kSeedCentrePerL * L;
  return t;
}

TEST(Verify, TheSeedSphereIsProvedAtASizeAboveTheAnswerAndNoProvedBoxHoldsAFailingPoint) {
  const double L = 1.01;  // 1 % above the size fit answers
  Options o;
  o.keep_boxes = true;
  const Preset preset = preset_12r(L);
  const task::TaskVolume task = seed_task(L);
  const Result proved = verify(preset, task, criteria({"cond<3"}), o);
  expect_proved_boxes_hold(preset, proved, 3);
  EXPECT_EQ(proved.undecided_volume, 0);
  EXPECT_GE(proved.proved_volume, task.volume());
  ASSERT_TRUE(proved.largest_box_bound);
  EXPECT_LT(*proved.largest_box_bound, 3);
}

TEST(Verify, TheSeedSphereIsDisprovedBelowTheAnswerWithAConfirmedCounterexample) {
  const double L = 0.99;
  const task::TaskVolume task = seed_task(L);
  const Preset preset = preset_12r(L);
  expect_confirmed(preset, task, verify(preset, task, criteria({"cond<3"})), 3);
  // Without the search, subdivision alone finds one.
  Options o;
  o.search_samples = 0;
  const Result r = verify(preset, task, criteria({"cond<3"}), o);
  expect_confirmed(preset, task, r, 3);
  EXPECT_GT(r.boxes, 0);
}

// The Delta: a box around its home, with a threshold above and below the
// largest c(J) sampled there.
TEST(Verify, TheDeltaIsProvedAndDisprovedAroundTheLargestSampledCondition) {
  const Preset preset = load_preset("delta");
  task::TaskVolume task = task::parse_task("box:size=6,6,4");
  const task::Device d = device_of(preset);
  task.centre = d.mechanism->home_task();
  const task::TaskReport sampled = task::evaluate(d, task::resolve(d, criteria({"cond<1e9"})), task, *task.centre, 24);
  const double worst = sampled.criteria[0].worst;
  ASSERT_TRUE(std::isfinite(worst));
  Options o;
  o.keep_boxes = true;
  const std::string above = "cond<" + std::to_string(worst * 1.02), below = "cond<" + std::to_string(worst * 0.98);
  expect_proved_boxes_hold(preset, verify(preset, task, {task::parse_criterion(above)}, o), worst * 1.02);
  o.search_samples = 0;
  expect_confirmed(preset, task, verify(preset, task, {task::parse_criterion(below)}, o), worst * 0.98);
}

// force_iso and resolution, with a threshold either side of the worst
// value sampled over a task at the home: proved (the device meets them at
// dense samples of every proved box, and so does the long-double
// evaluation) and disproved (a confirmed counterexample).
TEST(Verify, HapticCriteriaAreProvedAndDisprovedAroundTheSampledWorst) {
  for (const char* name : {"parallel-12r", "delta"}) {
    const Preset preset = load_preset(name);
    task::Device d = device_of(preset);
    d.data = haptics::device_data(preset, d.mechanism->info());
    task::TaskVolume task = task::parse_task("sphere:diameter=4");
    task.centre = d.mechanism->home_task();
    for (const char* measure : {"force_iso", "resolution"}) {
      const bool force = std::string(measure) == "force_iso";
      const std::vector<task::Criterion> probe = task::resolve(d, {task::parse_criterion(std::string(measure) + (force ? ">1e-9" : "<1e9"))});
      const double worst = task::evaluate(d, probe, task, *task.centre, 24).criteria[0].worst;
      const double meets = force ? worst * 0.97 : worst * 1.03, fails = force ? worst * 1.01 : worst * 0.99;
      const auto text = [&](double v) { return std::string(measure) + (force ? ">" : "<") + std::to_string(v); };
      Options o;
      o.keep_boxes = true;
      const Result proved = verify(preset, task, {task::parse_criterion(text(meets))}, o);
      ASSERT_EQ(proved.verdict, Verdict::Proved) << name << " " << measure;
      EXPECT_FALSE(proved.largest_box_bound);  // a bound on c(J) only where c(J) was asked
      const std::vector<task::Criterion> check = task::resolve(d, {task::parse_criterion(text(meets))});
      std::mt19937_64 rng(9);
      std::uniform_real_distribution<double> t(0, 1);
      const std::size_t stride = std::max<std::size_t>(1, proved.proved_boxes.size() / 1000);
      for (std::size_t i = 0; i < proved.proved_boxes.size(); i += stride) {
        const Box& b = proved.proved_boxes[i];
        for (int k = 0; k < 4; ++k) {
          const Vector3d p = b.lo + Vector3d(t(rng), t(rng), t(rng)).cwiseProduct(b.hi - b.lo);
          ASSERT_TRUE(task::evaluate_point(d, check, p).meets) << name << " " << measure << " " << p.transpose();
        }
      }
      const Result disproved = verify(preset, task, {task::parse_criterion(text(fails))});
      ASSERT_EQ(disproved.verdict, Verdict::Disproved) << name << " " << measure;
      const Counterexample& ce = *disproved.counterexample;
      EXPECT_TRUE(task.contains(ce.point, *task.centre));
      EXPECT_FALSE(task::evaluate_point(d, task::resolve(d, {task::parse_criterion(text(fails))}), ce.point).meets);
      EXPECT_TRUE(force ? ce.bound <= fails && ce.long_double_value <= fails && ce.device_value <= fails
                        : ce.bound >= fails && ce.long_double_value >= fails && ce.device_value >= fails)
          << name << " " << measure << " " << ce.bound << " " << ce.long_double_value << " " << ce.device_value;
      EXPECT_NEAR(ce.long_double_value, ce.device_value, 1e-9 * ce.device_value);
    }
  }
}

TEST(Verify, APartOutOfReachIsNeverProved) {
  // 12R: a sphere through the outer reach sphere |p| = L1 + L2; Delta: a box
  // through the edge its actuator ranges cut.
  struct Case {
    Preset preset;
    const char* task;
  };
  const std::vector<Case> cases = {{preset_12r(15), "sphere:diameter=8,centre=0,20,18"},
                                   {load_preset("delta"), "box:size=30,4,4,centre=0,0,-20"}};
  for (const Case& c : cases) {
    const task::TaskVolume task = task::parse_task(c.task);
    for (int samples : {6000, 0}) {
      Options o;
      o.search_samples = samples;
      o.keep_boxes = true;
      o.max_depth = 30;
      const Result r = verify(c.preset, task, criteria({"reach"}), o);
      EXPECT_EQ(r.verdict, Verdict::Disproved) << c.task;
      ASSERT_TRUE(r.counterexample);
      EXPECT_FALSE(std::isfinite(r.counterexample->bound));
      EXPECT_TRUE(task.contains(r.counterexample->point, *task.centre));
      const task::Device d = device_of(c.preset);
      EXPECT_FALSE(task::evaluate_point(d, task::resolve(d, criteria({"reach"})), r.counterexample->point).reachable);
    }
  }
}

// The 12R's angles are in (-pi, pi] and its ranges do not wrap: with beta's
// travel 100 to 200 deg, a beta just past -180 deg is outside it. A sphere
// whose boxes' beta enclosures cross pi holds such points (a cap about 1e-5
// deep) and is never proved; a range that holds every angle (gamma's, and
// beta's once opened) is not checked, so that a small sphere about the same
// place is proved with alpha's travel cut.
TEST(Verify, The12rRangesAreHeldAsTheDeviceHoldsItsAnglesAcrossPi) {
  Preset wrapped = load_preset("parallel-12r");
  wrapped.limits_deg["alpha"] = Range{-90, 90};
  wrapped.limits_deg["beta"] = Range{100, 200};
  wrapped.limits_deg["gamma"] = Range{-180, 180};
  const task::TaskVolume sphere = task::parse_task("sphere:diameter=2,centre=3.74512453603,-3.89025038154,12.7999879042");
  const Vector3d inside(4.16125344013357, -4.32250328021764, 11.9999927999929);  // beta = -179.99994 deg
  ASSERT_TRUE(sphere.contains(inside, *sphere.centre));
  const task::Device d = device_of(wrapped);
  ASSERT_FALSE(task::evaluate_point(d, task::resolve(d, criteria({"reach"})), inside).reachable);
  Options o;
  o.time_limit_seconds = 20;
  const Result r = verify(wrapped, sphere, criteria({"reach"}), o);
  EXPECT_NE(r.verdict, Verdict::Proved);
  if (r.counterexample)
    EXPECT_FALSE(task::evaluate_point(d, task::resolve(d, criteria({"reach"})), r.counterexample->point).reachable);

  Preset cut = load_preset("parallel-12r");
  cut.limits_deg["alpha"] = Range{-80, 80};
  const task::TaskVolume small = task::parse_task("sphere:diameter=0.2,centre=4.16125,-4.3225,12");
  o.time_limit_seconds = 60;
  const Result proved = verify(cut, small, criteria({"reach"}), o);
  EXPECT_EQ(proved.verdict, Verdict::Proved);
  EXPECT_LT(proved.boxes, 100);
}

TEST(Verify, BoxesOpenAtTheDepthLimitAreAnUndecidedVolume) {
  const double L = 1.01;
  const task::TaskVolume task = seed_task(L);
  Options o;
  o.max_depth = 6;
  o.search_samples = 0;
  const Result r = verify(preset_12r(L), task, criteria({"cond<3"}), o);
  EXPECT_EQ(r.verdict, Verdict::Undecided);
  EXPECT_GT(r.undecided_fraction(), 0);
  EXPECT_FALSE(r.counterexample);
  EXPECT_EQ(r.deepest, 6);
  EXPECT_EQ(exit_status(r.verdict), kExitUndecided);
  // And at the time limit: what is still open is undecided.
  o.max_depth = 48;
  o.time_limit_seconds = 0.05;
  const Result timed = verify(preset_12r(L), task, criteria({"cond<3"}), o);
  EXPECT_EQ(timed.verdict, Verdict::Undecided);
  EXPECT_TRUE(timed.timed_out);
  EXPECT_GT(timed.undecided_fraction(), 0);
  EXPECT_LT(timed.seconds, 1.0);
  // And where a generation outgrows the open-box limit.
  o.time_limit_seconds = 120;
  o.max_open_boxes = 1000;
  const Result crowded = verify(preset_12r(L), task, criteria({"cond<3"}), o);
  EXPECT_EQ(crowded.verdict, Verdict::Undecided);
  EXPECT_TRUE(crowded.box_limit);
  EXPECT_GT(crowded.undecided_fraction(), 0);
  EXPECT_LT(crowded.boxes, 3000);
}

TEST(Verify, OneThreadAndTwoGiveTheSameVerdict) {
  const double L = 1.02;
  const task::TaskVolume task = seed_task(L);
  Options one, two;
  one.threads = 1, two.threads = 2;
  const Result a = verify(preset_12r(L), task, criteria({"cond<3"}), one);
  const Result b = verify(preset_12r(L), task, criteria({"cond<3"}), two);
  EXPECT_EQ(a.verdict, Verdict::Proved);
  EXPECT_EQ(b.verdict, Verdict::Proved);
  EXPECT_EQ(a.boxes, b.boxes);  // the same subdivision: each box's outcome depends on it alone
}

TEST(Verify, BadInputIsRefused) {
  const Preset preset = preset_12r(15);
  const task::TaskVolume placed = task::parse_task("sphere:diameter=5,centre=0,15,15");
  EXPECT_THROW(verify(preset, task::parse_task("sphere:diameter=5"), criteria({"cond<3"})), std::invalid_argument);
  EXPECT_THROW(verify(preset, placed, {}), std::invalid_argument);
  EXPECT_THROW(verify(preset, placed, criteria({"cond_jo<3"})), std::invalid_argument);  // unknown measure
  EXPECT_THROW(verify(preset, placed, criteria({"cond<3"}), {}, 2), std::invalid_argument);
  Options o;
  o.max_depth = 0;
  EXPECT_THROW(verify(preset, placed, criteria({"cond<3"}), o), std::invalid_argument);
  o = {};
  o.threads = -1;
  EXPECT_THROW(verify(preset, placed, criteria({"cond<3"}), o), std::invalid_argument);
  o = {};
  o.max_open_boxes = 0;
  EXPECT_THROW(verify(preset, placed, criteria({"cond<3"}), o), std::invalid_argument);
  // What has no enclosure says so: a haptic criterion, another device.
  EXPECT_THROW(verify(preset, placed, criteria({"force_max>1"})), Uncertifiable);
  EXPECT_THROW(verify(preset, placed, criteria({"inertia<1"})), Uncertifiable);
  EXPECT_THROW(verify(load_preset("pathos2"), placed, criteria({"cond<3"})), Uncertifiable);
  // Sizing: bounds, tolerance.
  SizingProblem s;
  s.preset = preset;
  s.variable = {{"L1", "L2"}, 12, 12};
  s.task = placed;
  s.criteria = criteria({"cond<3"});
  EXPECT_THROW(size(s), std::invalid_argument);
  s.variable.hi = 13;
  s.tolerance = 0;
  EXPECT_THROW(size(s), std::invalid_argument);
  s.tolerance = 0.1;
  s.centre_scales_from = -1;
  EXPECT_THROW(size(s), std::invalid_argument);
  fit::Problem placement;
  placement.preset = preset;
  placement.variables = {s.variable, {{"L2"}, 1, 2}};
  placement.task = task::parse_task("sphere:diameter=5");
  EXPECT_THROW(placement_by_fit(placement), std::invalid_argument);  // two variables
  placement.variables.pop_back();
  placement.task = placed;
  EXPECT_THROW(placement_by_fit(placement), std::invalid_argument);  // a centre given
}

TEST(Verify, EachVerdictHasItsOwnExitStatus) {
  const std::set<int> statuses = {exit_status(Verdict::Proved), exit_status(Verdict::Disproved),
                                  exit_status(Verdict::Undecided)};
  EXPECT_EQ(statuses.size(), 3u);
  EXPECT_EQ(exit_status(Verdict::Proved), 0);
  EXPECT_FALSE(statuses.count(1));  // a failed write
  EXPECT_FALSE(statuses.count(2));  // bad input
}

TEST(Verify, TheReportAndTheJsonSayTheVerdictAndTheCounterexample) {
  const double L = 0.99;
  const task::TaskVolume task = seed_task(L);
  const Result r = verify(preset_12r(L), task, criteria({"cond<3"}));
  std::ostringstream text, json;
  write_report(text, r);
  write_json(json, r);
  EXPECT_NE(text.str().find("disproved"), std::string::npos);
  EXPECT_NE(text.str().find("long double"), std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(json.str());
  EXPECT_EQ(j["verdict"], "disproved");
  EXPECT_EQ(j["counterexample"]["point"][1].get<double>(), r.counterexample->point.y());
  EXPECT_GE(j["counterexample"]["bound"].get<double>(), 3);
}

// Sizing the 12R for the seed's sphere scaled to L = 1: the bracket holds
// the answer within the tolerance, its ends re-verify as reported, and the
// disproved end's counterexample fails for the device at that design.
TEST(CertifiedSizing, BracketsTheSmallestDesignBetweenAProvedAndADisprovedOne) {
  SizingProblem s;
  s.preset = preset_12r(1);
  s.variable = {{"L1", "L2"}, 0.9, 1.1};
  s.task = seed_task(1);
  s.centre_scales_from = 1;
  s.criteria = criteria({"cond<3"});
  s.tolerance = 0.01;
  const SizingResult r = size(s);
  ASSERT_TRUE(r.bracketed());
  ASSERT_TRUE(r.proved_at && r.disproved_at);
  EXPECT_LE(*r.proved_at - *r.disproved_at, s.tolerance);
  EXPECT_EQ(r.proved->verdict, Verdict::Proved);
  // The answer fit finds by sampling (1 in these units) lies in the bracket, give or take its sampling.
  EXPECT_GT(*r.proved_at, 0.98);
  EXPECT_LT(*r.disproved_at, 1.02);
  task::TaskVolume at_disproved = s.task;
  at_disproved.centre = *s.task.centre * *r.disproved_at;
  expect_confirmed(preset_12r(*r.disproved_at), at_disproved, *r.disproved, 3);
  EXPECT_EQ(exit_status(r), kExitProved);
  std::ostringstream text;
  write_report(text, r);
  EXPECT_NE(text.str().find("proved at"), std::string::npos);
  // Placed by fit at each design instead: the bracket holds, and each
  // design's task sits where fit::evaluate places it.
  fit::Problem placement;
  placement.preset = s.preset;
  placement.variables = {s.variable};
  placement.task = task::parse_task("sphere:diameter=" + std::to_string(15 / 12.268798828125));
  placement.criteria = s.criteria;
  placement.inscribed.resolution = 32;
  SizingProblem placed = s;
  placed.centre_at = placement_by_fit(placement);
  placed.variable.lo = 0.9, placed.variable.hi = 1.2;
  placed.tolerance = 0.05;
  const SizingResult by_fit = size(placed);
  ASSERT_TRUE(by_fit.bracketed());
  for (const SizingStep& step : by_fit.steps) {
    task::TaskVolume expected = placement.task;
    expected.centre = fit::evaluate(placement, {step.value})->centre;
    EXPECT_EQ(step.result.task, task::to_text(expected));
  }
  // Too small an upper bound: disproved throughout.
  s.variable = {{"L1", "L2"}, 0.8, 0.9};
  const SizingResult none = size(s);
  EXPECT_FALSE(none.proved_at);
  EXPECT_EQ(exit_status(none), kExitDisproved);
}

}  // namespace
}  // namespace linkscape::verify
