// Sizing a device to a task (core/fit.h): free variables from options, the
// size measure each device states, and the search's answer against the
// task evaluated directly (the 12R's c(J) is scale-free, so the smallest L
// of an --equal L1, L2 search must be the task's diameter over the largest
// sphere at L = 1).
#include <gtest/gtest.h>

#include "expect_error.h"

#include <sstream>

#include "core/fit.h"

using namespace linkscape;
using Eigen::Vector3d;

namespace {

// Coarse settings: these tests check the search, not the sampling's accuracy.
fit::Problem problem_12r(const std::string& task, const std::vector<std::string>& equal) {
  fit::Problem p;
  p.preset = load_preset("parallel-12r");
  p.variables = fit::variables(*make_mechanism(p.preset), {}, equal, {});
  p.task = task::parse_task(task);
  p.criteria = {task::parse_criterion("reach"), task::parse_criterion("cond<3")};
  p.inscribed = {24, 1, 1};
  p.task_resolution = 8;
  p.tolerance = 2e-3;
  return p;
}

task::Device device_12r(double L1, double L2) {
  Preset preset = load_preset("parallel-12r");
  preset.parameters["L1"] = L1;
  preset.parameters["L2"] = L2;
  task::Device d;
  d.mechanism = make_mechanism(preset);
  d.fixed_task = d.mechanism->home_task();
  return d;
}

}  // namespace

TEST(FitVariables, FromFreeEqualAndBounds) {
  const auto m = make_mechanism(load_preset("parallel-12r"));
  const auto both = fit::variables(*m, {}, {}, {});
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both[0].name(), "L1");
  EXPECT_EQ(both[0].lo, 1.5);  // the design panel's range, 0.1 to 3 times 15 cm
  EXPECT_EQ(both[0].hi, 45);
  const auto tied = fit::variables(*m, {}, {"L1,L2"}, {"L2=5:30"});
  ASSERT_EQ(tied.size(), 1u);
  EXPECT_EQ(tied[0].name(), "L1=L2");
  EXPECT_EQ(tied[0].lo, 5);
  EXPECT_EQ(tied[0].hi, 30);
  EXPECT_EQ(fit::variables(*m, {"L2"}, {}, {}).size(), 1u);
  expect_error([&] { fit::variables(*m, {"L3"}, {}, {}); }, "unknown parameter 'L3'");
  expect_error([&] { fit::variables(*m, {"L1"}, {}, {"L2=1:2"}); }, "not free");
  expect_error([&] { fit::variables(*m, {}, {"L1"}, {}); }, "two or more");
  expect_error([&] { fit::variables(*m, {}, {}, {"L1=1"}); }, "NAME=lo:hi");
}

// The size fit minimises is what each device says it is: the sum of the
// parameters its description names.
TEST(FitVariables, EverySizeIsTheSumItDescribes) {
  for (const std::string& name : registered_mechanisms()) {
    const auto m = make_mechanism(load_preset(name));
    const std::string text = m->info().size_description;
    ASSERT_FALSE(text.empty()) << name;
    double sum = 0;
    std::stringstream ss(text);
    for (std::string term; std::getline(ss, term, '+');) {
      term.erase(0, term.find_first_not_of(' '));
      term.erase(term.find_last_not_of(' ') + 1);
      sum += m->parameters().at(term);
    }
    EXPECT_NEAR(m->size(), sum, 1e-12 * sum) << name << ": " << text;
  }
}

TEST(FitSearch, EqualLinksGiveTheDiameterOverTheUnitSphere) {
  const fit::Problem p = problem_12r("sphere:diameter=15", {"L1,L2"});
  const fit::Result r = fit::solve(p);
  ASSERT_TRUE(r.best);
  const fit::Row& best = r.rows[*r.best];
  EXPECT_TRUE(best.meets);
  EXPECT_EQ(best.parameters.at("L1"), best.parameters.at("L2"));
  EXPECT_GE(best.fit, 1.0);
  // c(J) is scale-free and the default box scales with L: the largest
  // sphere at L is L times the one at L = 1, sampled on the same grid.
  const task::Device unit = device_12r(1, 1);
  const auto criteria = task::resolve(unit, p.criteria);
  const auto d1 = task::largest_inscribed(unit, criteria, p.task, unit.mechanism->default_box(), p.inscribed);
  ASSERT_TRUE(d1 && d1->found);
  const double L = best.parameters.at("L1");
  EXPECT_NEAR(L, 15.0 / d1->size, 2 * p.tolerance * L);
  // Every meeting design is at least as large; every smaller one fails.
  for (const fit::Row& row : r.rows) {
    if (!row.invalid.empty()) continue;
    if (row.meets) EXPECT_GE(row.size, best.size);
    if (row.size < best.size * (1 - 1e-12)) EXPECT_FALSE(row.meets) << row.size;
  }
  EXPECT_FALSE(r.at_lower_bounds);
}

// A fixed centre: the smallest L1 = L2 whose c(J) < 3 covers a 4 cm sphere at
// (0, 12, 10); the task evaluated there meets it, 1 % smaller it does not.
TEST(FitSearch, FixedCentreIsCoveredByTheSmallestDesignAndNotBelow) {
  fit::Problem p = problem_12r("sphere:diameter=4,centre=0,12,10", {"L1,L2"});
  p.task_resolution = 12;
  const fit::Result r = fit::solve(p);
  ASSERT_TRUE(r.best);
  const double L = r.rows[*r.best].parameters.at("L1");
  EXPECT_EQ(r.rows[*r.best].centre, Vector3d(0, 12, 10));
  auto meets = [&](double length) {
    const task::Device d = device_12r(length, length);
    return task::evaluate(d, task::resolve(d, p.criteria), p.task, *p.task.centre, p.task_resolution).meets();
  };
  EXPECT_TRUE(meets(L));
  EXPECT_FALSE(meets(L * 0.99));
}

TEST(FitSearch, NoDesignIsAResultAndExcludingBoundsAnError) {
  fit::Problem p = problem_12r("sphere:diameter=15", {"L1,L2"});
  p.variables[0].lo = 1;
  p.variables[0].hi = 4;
  const fit::Result r = fit::solve(p);
  EXPECT_FALSE(r.best);
  ASSERT_TRUE(r.closest);
  EXPECT_EQ(r.rows[*r.closest].parameters.at("L1"), 4);  // the largest comes closest
  EXPECT_LT(r.rows[*r.closest].fit, 1);

  p.variables[0].lo = -4;
  p.variables[0].hi = -1;
  expect_error([&] { fit::solve(p); }, "bounds exclude every design");
  p.variables[0].lo = 5;
  p.variables[0].hi = 2;
  expect_error([&] { fit::solve(p); }, "lo <= hi");
  p.variables.clear();
  expect_error([&] { fit::solve(p); }, "no free design parameter");
}
