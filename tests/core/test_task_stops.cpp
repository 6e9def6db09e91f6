// Criteria on a device's stops (core/task.h) and the switches that turn the
// stops off (Preset::checks): the Falcon's joint margin and clearance are
// criteria bounded from below; a point's value is the field's at that
// sample; field and point verdicts agree; a task's worst margin decides its
// verdict; and with a switch off no sample is out of limits for that reason.
#include <gtest/gtest.h>

#include "expect_error.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/preset.h"
#include "core/task.h"

using namespace linkscape;
using namespace linkscape::task;
using Eigen::Vector3d;

namespace {

// The Falcon, or with shins of 16 mm radius (the file's: 4), whose legs
// collide over part of the box (with the file's radii they keep apart).
Device falcon(StopChecks checks = {}, bool thick_shins = false) {
  Preset preset = load_preset("falcon");
  if (thick_shins) {
    nlohmann::json d = nlohmann::json::parse(preset.description);
    for (nlohmann::json& leg : d["legs"])
      for (nlohmann::json& step : leg["chain"])
        if (step.value("link", "") == "shin") step["radius"] = 16;
    preset.description = d.dump();
  }
  preset.checks = checks;
  Device d;
  d.mechanism = make_mechanism(preset);
  d.fixed_task = d.mechanism->home_task();
  d.threads = 2;
  return d;
}

// The Falcon's box, coarsely.
Grid falcon_grid(const Device& d, int n) {
  const Eigen::AlignedBox3d box = d.mechanism->default_box();
  return Grid::box(box.min(), box.max(), {n, n, n});
}

std::vector<Criterion> criteria_on(const Device& d, const std::vector<std::string>& texts) {
  std::vector<Criterion> c;
  for (const std::string& t : texts) c.push_back(parse_criterion(t));
  return resolve(d, c);
}

}  // namespace

TEST(TaskStops, ExtraFieldsAreCriteriaBoundedFromBelow) {
  const Device d = falcon();
  const std::vector<Criterion> c = criteria_on(d, {"joint_margin>5", "clearance>0.5"});
  for (const Criterion& k : c) {
    EXPECT_TRUE(k.extra) << k.text;
    EXPECT_TRUE(k.above) << k.text;
    EXPECT_EQ(k.measure_index, -1) << k.text;  // never read as a conditioning measure (verify refuses it)
  }
  EXPECT_EQ(c[0].threshold, 5);
  EXPECT_EQ(c[1].threshold, 0.5);
  expect_error([&] { criteria_on(d, {"joint_margin<5"}); }, "joint_margin is bounded from below (joint_margin>VALUE)");
  expect_error([&] { criteria_on(d, {"clearance>0"}); }, "the threshold must be positive");
  expect_error([&] { criteria_on(d, {"clearance>-1"}); }, "the threshold must be positive");
}

// The error lists what the device has: a compiled Delta states no stops,
// and a Falcon with its joint limits switched off has none to bound.
TEST(TaskStops, AFieldTheDeviceLacksIsRefusedListingItsFields) {
  Preset delta = load_preset("delta");
  delta.checks.joint_limits = false;  // its cones off: no joint_margin
  Device d;
  d.mechanism = make_mechanism(delta);
  expect_error([&] { criteria_on(d, {"joint_margin>5"}); },
               "unknown measure 'joint_margin' for delta (known: reach, cond, force_iso");
  expect_error([&] { criteria_on(falcon(), {"margin>5"}); }, "(known: reach, cond, joint_margin, clearance, force_iso");
  const Device off = falcon({.joint_limits = false, .interference = true});
  expect_error([&] { criteria_on(off, {"joint_margin>5"}); }, "(known: reach, cond, clearance, force_iso");
  EXPECT_NO_THROW(criteria_on(off, {"clearance>0.5"}));
}

// evaluate_point reads an extra field from the device's kernel at the one
// sample: the same number as the whole field's at that sample, and the
// same verdict as good_mask's. Each bound is the median of its field over
// the reachable samples, so it holds at some and fails at others.
TEST(TaskStops, PointwiseMarginsAreTheFieldsAtTheSameSample) {
  const Device d = falcon({}, true);
  const int n = 9;
  const Grid grid = falcon_grid(d, n);
  const std::optional<Field> all = d.mechanism->compute_field(grid, d.fixed_task, {}, 2, {});
  ASSERT_TRUE(all);
  std::vector<std::string> texts;
  for (const char* name : {"joint_margin", "clearance"}) {
    std::vector<float> reached;
    for (std::size_t s = 0; s < grid.size(); ++s)
      if (all->reachable[s]) reached.push_back(all->extra(name)->values[s]);
    ASSERT_GT(reached.size(), 20u);
    std::nth_element(reached.begin(), reached.begin() + std::ptrdiff_t(reached.size() / 2), reached.end());
    texts.push_back(std::string(name) + ">" + std::to_string(reached[reached.size() / 2]));
  }
  const std::vector<Criterion> c = criteria_on(d, texts);
  const std::optional<Field> field = sample(d, c, grid);
  ASSERT_TRUE(field);
  const std::vector<std::uint8_t> good = good_mask(*field, c);
  int reachable = 0, meeting = 0, cut[2] = {0, 0};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::size_t s = grid.index(i, j, k);
        const PointValues v = evaluate_point(d, c, grid.point(i, j, k));
        ASSERT_EQ(v.reachable, field->reachable[s] != 0) << grid.point(i, j, k).transpose();
        ASSERT_EQ(v.meets, bool(good[s])) << grid.point(i, j, k).transpose();
        if (!v.reachable) continue;
        ++reachable;
        meeting += v.meets;
        for (std::size_t m = 0; m < c.size(); ++m) {
          const float expected = field->extra(c[m].measure)->values[s];
          EXPECT_EQ(float(v.values[m]), expected) << c[m].text << " at " << grid.point(i, j, k).transpose();
          EXPECT_GE(v.values[m], 0) << c[m].text;  // reachable: within every stop
          cut[m] += v.values[m] <= c[m].threshold;
        }
      }
  EXPECT_GT(meeting, 0);
  EXPECT_LT(meeting, reachable);
  EXPECT_GT(cut[0], 0);  // each bound fails somewhere the device reaches
  EXPECT_GT(cut[1], 0);
}

// A small sphere at home: its worst joint margin over the samples decides
// the verdict of a bound just below it (met) and just above it (failed).
TEST(TaskStops, ATaskMeetsAMarginJustBelowItsWorstAndFailsJustAbove) {
  const Device d = falcon();
  const Vector3d home = d.mechanism->home_task().head<3>();
  const TaskVolume sphere = parse_task("sphere:diameter=10");
  const TaskReport probe = evaluate(d, criteria_on(d, {"joint_margin>1"}), sphere, home, 8);
  ASSERT_TRUE(probe.meets()) << verdict_text(probe);
  const double worst = probe.criteria[0].worst;
  ASSERT_GT(worst, 1.5);
  const TaskReport below = evaluate(d, criteria_on(d, {"joint_margin>" + std::to_string(worst - 0.5)}), sphere, home, 8);
  EXPECT_TRUE(below.meets()) << verdict_text(below);
  EXPECT_NEAR(below.criteria[0].margin(), 0.5, 1e-6);
  const TaskReport above = evaluate(d, criteria_on(d, {"joint_margin>" + std::to_string(worst + 0.5)}), sphere, home, 8);
  EXPECT_FALSE(above.meets());
  EXPECT_GE(above.criteria[0].failing, 1);
  EXPECT_NEAR(above.criteria[0].margin(), -0.5, 1e-6);
}

// The thick-shinned Falcon, a stop switched off (the links with its joint
// limits already off: the collisions lie beyond the joints' stops too): the
// field of the stop is gone, no sample is out of limits for its reason
// (IK's status text names it: "... beyond its ..." for a joint, "... hits
// ..." for two links), and samples it held back become reachable.
TEST(StopChecks, ASwitchedOffStopHoldsNoSampleBack) {
  struct Case {
    StopChecks before, after;
    const char* removed;  // the field it drops
    const char* reason;   // the words of its status text
  };
  for (const Case& c : {Case{{}, {.joint_limits = false, .interference = true}, "joint_margin", " beyond its "},
                        Case{{.joint_limits = false, .interference = true}, {.joint_limits = false, .interference = false},
                             "clearance", " hits "}}) {
    const Device on = falcon(c.before, true), off = falcon(c.after, true);
    const Grid grid = falcon_grid(on, 8);
    const std::optional<Field> all = on.mechanism->compute_field(grid, on.fixed_task, {}, 2, {});
    const std::optional<Field> f = off.mechanism->compute_field(grid, off.fixed_task, {}, 2, {});
    ASSERT_TRUE(all && f);
    ASSERT_TRUE(all->extra(c.removed)) << c.removed;
    EXPECT_EQ(f->extra(c.removed), nullptr) << c.removed;
    const SampleArray<float>& margin = all->extra(c.removed)->values;
    int freed = 0, still_out = 0;
    for (std::size_t s = 0; s < grid.size(); ++s) {
      const bool held_back = all->status[s] == std::uint8_t(Status::OutOfLimits) && margin[s] < 0;
      if (f->status[s] != std::uint8_t(Status::OutOfLimits)) {
        freed += held_back;
        continue;
      }
      ++still_out;
      ASSERT_EQ(all->status[s], std::uint8_t(Status::OutOfLimits)) << "off adds no stop";
      Eigen::VectorXd x = off.fixed_task;
      x.head<3>() = grid.point(int(s % 8), int(s / 8 % 8), int(s / 64));
      IkOptions branch0;
      branch0.branch = 0;
      const IkResult ik = off.mechanism->inverse(x, branch0);
      EXPECT_EQ(ik.status_text.find(c.reason), std::string::npos) << ik.status_text;
    }
    EXPECT_GT(freed, 0) << c.removed << ": the switch frees samples its stop held back";
    std::printf("%s off: %d samples freed, %d still out of limits for another reason\n", c.removed, freed, still_out);
  }
}
