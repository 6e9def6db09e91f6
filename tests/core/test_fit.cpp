// Sizing a device to a task (core/fit.h): free variables from options, the
// size measure each device states, and the search's answer against the
// task evaluated directly (the 12R's c(J) is scale-free, so the smallest L
// of an --equal L1, L2 search must be the task's diameter over the largest
// sphere at L = 1).
#include <gtest/gtest.h>

#include "expect_error.h"


#include <nlohmann/json.hpp>

#include "core/csv.h"
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
  // Bounds given twice for one variable, by one name or by two names of a group.
  expect_error([&] { fit::variables(*m, {}, {}, {"L1=5:30", "L1=6:20"}); }, "--bounds given twice for L1");
  expect_error([&] { fit::variables(*m, {}, {"L1,L2"}, {"L1=5:30", "L2=6:20"}); }, "--bounds given twice for L1=L2");
}

// Motor ratings are variables (they need bounds); free with lengths, or
// held at a size, they are refused; a design's row carries the rating it was given.
TEST(FitVariables, MotorRatingsAreVariablesWithBounds) {
  const auto m = make_mechanism(load_preset("parallel-12r"));
  const auto torque = fit::variables(*m, {"continuous_torque_Nm"}, {}, {"continuous_torque_Nm=0.1:1"});
  ASSERT_EQ(torque.size(), 1u);
  EXPECT_EQ(torque[0].lo, 0.1);
  expect_error([&] { fit::variables(*m, {"continuous_torque_Nm"}, {}, {}); }, "needs --bounds continuous_torque_Nm");
  expect_error([&] { fit::variables(*m, {}, {"L1,gear_ratio"}, {"L1=1:2"}); }, "cannot hold a motor rating equal to a length");
  fit::Problem p = problem_12r("sphere:diameter=10", {});
  p.variables = torque;
  fit::Problem mixed = p;
  mixed.variables.push_back(fit::variables(*m, {"L1"}, {}, {})[0]);
  expect_error([&] { fit::solve(mixed); }, "free motor ratings and free lengths together");
  fit::Problem at_size = p;
  at_size.size = 30;
  expect_error([&] { fit::solve(at_size); }, "motor ratings do not change");
  const std::optional<fit::Row> row = fit::evaluate(p, {0.25});
  ASSERT_TRUE(row);
  EXPECT_EQ(row->parameters.at("continuous_torque_Nm"), 0.25);
  EXPECT_EQ(row->parameters.at("L1"), 15);
}

// The size fit minimises is what each device says it is: the sum of the
// parameters its description names.
TEST(FitVariables, EverySizeIsTheSumItDescribes) {
  for (const std::string& name : registered_mechanisms()) {
    const auto m = make_mechanism(load_preset(name));
    const std::string text = m->info().size_description;
    ASSERT_FALSE(text.empty()) << name;
    double sum = 0;
    for (const std::string& term : fit::size_terms(m->info())) sum += m->parameters().at(term);
    EXPECT_NEAR(m->size(), sum, 1e-12 * sum) << name << ": " << text;
  }
}

TEST(FitSearch, EqualLinksGiveTheDiameterOverTheUnitSphere) {
  const fit::Problem p = problem_12r("sphere:diameter=15", {"L1,L2"});
  const fit::Result r = fit::solve(p);
  ASSERT_TRUE(r.best);
  const fit::Row& best = r.rows[*r.best];
  EXPECT_TRUE(best.meets);
  EXPECT_TRUE(best.report.meets());
  EXPECT_EQ(best.parameters.at("L1"), best.parameters.at("L2"));
  // c(J) is scale-free and the default box scales with L: the largest
  // sphere at L is L times the one at L = 1, sampled on the same grid.
  const task::Device unit = device_12r(1, 1);
  const auto criteria = task::resolve(unit, p.criteria);
  const auto d1 = task::largest_inscribed(unit, criteria, p.task, unit.mechanism->default_box(), p.inscribed);
  ASSERT_TRUE(d1 && d1->found);
  const double L = best.parameters.at("L1");
  // The verdict is the task's samples', the inscribed sphere an estimate to
  // about its grid's spacing (1 to 3 % here).
  EXPECT_NEAR(L, 15.0 / d1->size, (2 * d1->spacing / d1->size + 2 * p.tolerance) * L);
  // Every meeting design is at least as large, to the round step the answer
  // is rounded up to (0.01 on each link); every smaller one fails.
  constexpr double kRounding = 0.02;
  for (const fit::Row& row : r.rows) {
    if (!row.invalid.empty()) continue;
    if (row.meets) {
      EXPECT_GE(row.size, best.size - kRounding - 1e-9);
    }
    if (row.size < best.size - kRounding - 1e-9) {
      EXPECT_FALSE(row.meets) << row.size;
    }
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
  // Bounds past the searches' range: refused, not "no design meets".
  p.variables[0].lo = 1;
  p.variables[0].hi = 1e31;
  expect_error([&] { fit::solve(p); }, "must lie within -1e+06 to 1e+06");
  p.variables[0].hi = fit::kLargestBound;
  EXPECT_NO_THROW(fit::check_bounds(p.variables, "fit"));
  p.variables.clear();
  expect_error([&] { fit::solve(p); }, "no free design parameter");
}

// At the widest bounds allowed the search still finds the 12R's smallest
// design to its tolerance (the size along the ray resolves 1e-12 of the
// bounds: 1e-6 cm here).
TEST(FitSearch, TheWidestBoundsGiveTheSameSmallestDesign) {
  fit::Problem p = problem_12r("sphere:diameter=15", {"L1,L2"});
  const fit::Result narrow = fit::solve(p);
  p.variables[0].hi = fit::kLargestBound;
  const fit::Result wide = fit::solve(p);
  ASSERT_TRUE(narrow.best && wide.best);
  EXPECT_NEAR(wide.rows[*wide.best].size, narrow.rows[*narrow.best].size,
              2 * p.tolerance * narrow.rows[*narrow.best].size);
}

// ---- The largest ratio at a given size ---------------------------------------------

namespace {

// The ratio of the 12R at L1, L2 for problem p (centre free: the largest
// sphere over the task's diameter, sampled as the search samples it).
double margin_12r(const fit::Problem& p, double L1, double L2) {
  const task::Device d = device_12r(L1, L2);
  const auto criteria = task::resolve(d, p.criteria);
  const auto found = task::largest_inscribed(d, criteria, p.task, d.mechanism->default_box(), p.inscribed);
  return found && found->found ? found->size / p.task.diameter() : 0.0;
}

// A design's ratio as the search evaluates it (at the place nearest home
// that meets the task, else the largest).
double ratio_12r(const fit::Problem& p, double L1, double L2) {
  fit::Problem q = p;
  q.size.reset();
  q.variables = fit::variables(*make_mechanism(q.preset), {"L1", "L2"}, {}, {"L1=1:40", "L2=1:40"});
  return fit::evaluate(q, {L1, L2})->ratio;
}

}  // namespace

// Among designs L1 + L2 = S, the search's answer is at least as good as
// every design of a brute-force scan along the size (41 designs), within
// the sampling's noise: the inscribed sphere moves in steps of the grid's
// spacing, about one cell of 24 across the default box (3 L), 0.125 L
// over a task of about 1.2 L: 10 %. A scan point finer than the search's
// step may land on a lucky step, hence the tolerance.
TEST(FitMargin, AtASizeNoScannedDesignIsClearlyBetter) {
  fit::Problem p = problem_12r("sphere:diameter=15", {});
  p.size = 30;
  const fit::Result r = fit::solve(p);
  ASSERT_TRUE(r.best);
  const fit::Row& best = r.rows[*r.best];
  for (const fit::Row& row : r.rows) {
    if (!row.invalid.empty()) continue;
    EXPECT_NEAR(row.size, 30, 1e-9) << "every design evaluated has the size asked for";
    EXPECT_LE(row.ratio, best.ratio) << "the answer is the best evaluated";
  }
  EXPECT_NEAR(best.ratio, ratio_12r(p, best.parameters.at("L1"), best.parameters.at("L2")), 1e-12);
  constexpr double kSamplingNoise = 0.10;
  double brute = 0;
  for (int i = 0; i <= 40; ++i) {
    const double L1 = 3 + 24 * i / 40.0;
    brute = std::max(brute, margin_12r(p, L1, 30 - L1));
  }
  EXPECT_GE(best.ratio, brute - kSamplingNoise) << "brute force " << brute;
  // The 12R's reachable region and c(J) are best with equal links, as the scan shows.
  EXPECT_NEAR(best.parameters.at("L1"), 15, 0.1 * 15);
}

// Both modes agree: at the smallest size the size mode finds, the largest
// margin is about 1 (the task just fits), and the margin grows with the
// size as c(J) is scale-free (margin at S = S / S_min within the noise).
TEST(FitMargin, AtTheSmallestSizeTheMarginIsAboutOne) {
  fit::Problem p = problem_12r("sphere:diameter=15", {});
  p.inscribed = {32, 1, 2};
  const fit::Result smallest = fit::solve(p);
  ASSERT_TRUE(smallest.best);
  const double s_min = smallest.rows[*smallest.best].size;
  p.size = s_min;
  const fit::Result at_min = fit::solve(p);
  const auto chosen = at_min.best ? at_min.best : at_min.closest;
  ASSERT_TRUE(chosen);
  // One cell of 32 across 3 L, over a sphere of about 1.2 L: 8 %.
  constexpr double kSamplingNoise = 0.08;
  EXPECT_NEAR(at_min.rows[*chosen].ratio, 1.0, kSamplingNoise) << "S_min = " << s_min;
  p.size = 1.5 * s_min;
  const fit::Result larger = fit::solve(p);
  ASSERT_TRUE(larger.best);
  EXPECT_NEAR(larger.rows[*larger.best].ratio, 1.5, 1.5 * kSamplingNoise);
}

// Centre fixed: the margin is the smallest bound / worst ratio, checked
// against the task evaluated directly at the chosen design.
TEST(FitMargin, FixedCentreMarginIsTheSmallestBoundOverWorstRatio) {
  fit::Problem p = problem_12r("sphere:diameter=4,centre=0,12,10", {});
  p.criteria.push_back(task::parse_criterion("force_iso>0.5"));
  p.task_resolution = 10;
  p.size = 30;
  const fit::Result r = fit::solve(p);
  ASSERT_TRUE(r.best);
  const fit::Row& best = r.rows[*r.best];
  task::Device d = device_12r(best.parameters.at("L1"), best.parameters.at("L2"));
  d.data = haptics::device_data(load_preset("parallel-12r"), d.mechanism->info());
  const task::TaskReport report = task::evaluate(d, task::resolve(d, p.criteria), p.task, *p.task.centre, p.task_resolution);
  ASSERT_EQ(report.criteria.size(), 3u);
  const double cond_ratio = 3 / report.criteria[1].worst, force_ratio = report.criteria[2].worst / 0.5;
  EXPECT_NEAR(best.ratio, std::min(cond_ratio, force_ratio), 1e-12);
  EXPECT_GE(best.ratio, 1.0);
  EXPECT_TRUE(best.meets);
}

TEST(FitMargin, SizesNoDesignHasAreErrors) {
  fit::Problem p = problem_12r("sphere:diameter=15", {});
  p.size = 100;  // L1 + L2 within [1.5, 45] each: 3 to 90
  expect_error([&] { fit::solve(p); }, "no design within the bounds has size L1 + L2 = 100");
  p.size = -1;
  expect_error([&] { fit::solve(p); }, "positive and finite");
  p.size = 30;
  p.variables = fit::variables(*make_mechanism(p.preset), {}, {}, {"L1=20:25", "L2=20:25"});
  expect_error([&] { fit::solve(p); }, "they span 40 to 50");
  // The Delta's R is not in its size (La + Lb): holding the size leaves nothing to choose.
  p.preset = load_preset("delta");
  p.variables = fit::variables(*make_mechanism(p.preset), {"R"}, {}, {});
  p.size = 20;
  expect_error([&] { fit::solve(p); }, "needs a free parameter the size counts (La + Lb)");
}

// Three free parameters (PATHOS-II's l0, l2, l3; the size is l2 + l3): the
// answer is the best of the shortened scan designs, not a full
// optimisation, so check it is sensible: a two-variable search (the finer
// search over l2, l3) with l0 held where the three-variable answer put it
// finds no design clearly smaller. "Clearly": the bisection's 1 % tolerance
// and the coarse sampling's noise, 3 % in all.
TEST(FitSearch, ThreeFreeParametersGiveADesignTheTwoVariableSearchCannotClearlyBeat) {
  fit::Problem p;
  p.preset = load_preset("pathos2");
  p.variables = fit::variables(*make_mechanism(p.preset), {"l0", "l2", "l3"}, {}, {});
  p.task = task::parse_task("sphere:diameter=4");
  p.criteria = {task::parse_criterion("reach"), task::parse_criterion("cond<5")};
  p.inscribed = {24, 1, 1};
  p.task_resolution = 8;
  p.tolerance = 1e-2;
  const fit::Result three = fit::solve(p);
  ASSERT_TRUE(three.best);
  const fit::Row& best = three.rows[*three.best];
  EXPECT_LE(three.rows.size(), 80u) << "cost: 12 scan designs per variable, the corners and three bisections";

  fit::Problem held = p;
  held.preset.parameters["l0"] = best.parameters.at("l0");
  held.variables = fit::variables(*make_mechanism(held.preset), {"l2", "l3"}, {}, {});
  const fit::Result two = fit::solve(held);
  ASSERT_TRUE(two.best);
  EXPECT_GE(two.rows[*two.best].size, best.size * (1 - 0.03))
      << "three free: " << best.size << ", l0 held at " << best.parameters.at("l0");
}

// A described device's size is its description's expression: the Delta
// described (size La + Lb) is held at the size asked for like the compiled
// one, every design evaluated having it.
TEST(FitMargin, ADescribedDeviceIsHeldAtTheSizeAsked) {
  fit::Problem p;
  p.preset = load_preset("delta-described");
  p.variables = fit::variables(*make_mechanism(p.preset), {"La", "Lb"}, {}, {});
  p.task = task::parse_task("sphere:diameter=5");
  p.criteria = {task::parse_criterion("reach")};
  p.inscribed = {8, 0, 1};  // coarse: the described solver is slow, and this checks the sizes only
  p.task_resolution = 2;
  p.tolerance = 0.1;
  p.size = 30;
  const fit::Result r = fit::solve(p);
  ASSERT_TRUE(r.best || r.closest);
  std::size_t valid = 0;
  for (const fit::Row& row : r.rows) {
    if (!row.invalid.empty()) continue;
    ++valid;
    EXPECT_NEAR(row.size, 30, 1e-9);
    EXPECT_NEAR(row.parameters.at("La") + row.parameters.at("Lb"), 30, 1e-9);
  }
  EXPECT_GT(valid, 5u);
}

// A size the description makes no sum of parameters (a * b / 10 for the
// five-bar) cannot be held by moving along a line: refused, naming why.
TEST(FitMargin, ASizeNotInProportionToTheParametersIsRefused) {
  fit::Problem p;
  p.preset = load_preset("five-bar");
  nlohmann::json description = nlohmann::json::parse(p.preset.description);
  description["size"] = "a * b / 10";
  p.preset.description = description.dump();
  p.variables = fit::variables(*make_mechanism(p.preset), {"a", "b"}, {}, {});
  p.task = task::parse_task("sphere:diameter=5");
  p.criteria = {task::parse_criterion("reach")};
  p.size = 20;
  expect_error([&] { fit::solve(p); }, "--size needs a size that changes in proportion to the free parameters");
}

// One verdict: a design meets the task exactly when every sample of the
// evaluation it reports meets every criterion, and that evaluation is
// reproducible from what the report prints: the design (round numbers)
// evaluated again with its task fixed at the printed centre gives the same
// samples and the same verdict.
TEST(FitVerdict, TheReportedDesignMeetsAtTheEvaluationItReports) {
  fit::Problem p = problem_12r("sphere:diameter=15", {"L1,L2"});
  p.task_resolution = 12;
  const fit::Result r = fit::solve(p);
  ASSERT_TRUE(r.best);
  for (const fit::Row& row : r.rows)
    if (row.invalid.empty()) {
      EXPECT_EQ(row.meets, row.report.failing == 0 && row.report.samples > 0) << row.size;
    }
  const fit::Row& best = r.rows[*r.best];
  // Rounded up to a step near the tolerance (2e-3 of about 12: 0.01).
  const double L = best.parameters.at("L1");
  EXPECT_NEAR(L * 100, std::round(L * 100), 1e-9) << L;
  EXPECT_EQ(format_number(L).size(), format_number(std::round(L * 100) / 100).size());
  // The centre: a multiple of fit::centre_step.
  const double step = fit::centre_step(best.size);
  EXPECT_EQ(step, 1e-3);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(best.centre(k) / step, std::round(best.centre(k) / step), 1e-6);
  // Evaluated again from the printed numbers.
  fit::Problem fixed = p;
  fixed.task = task::parse_task("sphere:diameter=15,centre=" + format_number(best.centre.x()) + "," +
                                format_number(best.centre.y()) + "," + format_number(best.centre.z()));
  const auto again = fit::evaluate(fixed, {*parse_number(format_number(L))});
  ASSERT_TRUE(again);
  EXPECT_TRUE(again->meets);
  EXPECT_EQ(again->report.samples, best.report.samples);
  EXPECT_EQ(again->report.failing, 0);
  EXPECT_EQ(again->report.criteria[1].worst, best.report.criteria[1].worst);
}

// The rounded answer stepped up stays a round number as printed.
TEST(FitVerdict, SteppingUpKeepsRoundNumbers) {
  EXPECT_EQ(format_number(fit::step_up(12.2, 0.01)), "12.21");
  EXPECT_EQ(format_number(fit::step_up(0.3, 0.1)), "0.4");
  EXPECT_EQ(format_number(fit::step_up(120, 10)), "130");
  double v = 12.2;  // five steps, as the search takes at most
  for (int i = 0; i < 5; ++i) v = fit::step_up(v, 0.01);
  EXPECT_EQ(format_number(v), "12.25");
}

// The 12R's good region is symmetric: a task fits on both sides of the
// base. Among the places that meet it, the one nearest the home point
// (0, L, L), on the +y side; a centre region on the other side keeps the
// centre in it.
TEST(FitPlacement, NearestTheHomePointAndWithinTheRegionGiven) {
  fit::Problem p = problem_12r("sphere:diameter=12", {"L1,L2"});
  p.variables[0].lo = p.variables[0].hi = 15;
  p.inscribed = {32, 1, 3};
  const auto near_home = fit::evaluate(p, {15.0});
  ASSERT_TRUE(near_home && near_home->meets);
  EXPECT_NEAR((near_home->home - Vector3d(0, 15, 15)).norm(), 0, 1e-12);
  EXPECT_GT(near_home->centre.y(), 0) << near_home->centre.transpose();
  p.inscribed.centres = task::parse_centre_region("box:min=-5,-30,-30,max=5,0,0");
  const auto below = fit::evaluate(p, {15.0});
  ASSERT_TRUE(below && below->meets);
  EXPECT_TRUE(p.inscribed.centres->contains(below->centre)) << below->centre.transpose();
  p.inscribed.centres = task::parse_centre_region("sphere:centre=0,0,20,radius=2");
  const auto ball = fit::evaluate(p, {15.0});
  ASSERT_TRUE(ball);
  EXPECT_LE((ball->centre - Vector3d(0, 0, 20)).norm(), 2 + 1e-9) << ball->centre.transpose();
}

// "What torque is needed" is a fit: the smallest continuous torque whose
// force_iso holds 1 N over a task at a fixed place. Forces scale with the
// torque, so it is 1 N over the worst force at 1 N m, to the answer's
// rounding step; the design at the answer meets the task and one step of
// the tolerance below it does not.
TEST(FitMotors, TheSmallestTorqueIsTheBoundOverTheWorstForcePerNewtonMetre) {
  const auto m = make_mechanism(load_preset("parallel-12r"));
  fit::Problem p = problem_12r("sphere:diameter=6,centre=0,15,15", {});
  p.criteria = {task::parse_criterion("reach"), task::parse_criterion("force_iso>1")};
  p.variables = fit::variables(*m, {"continuous_torque_Nm"}, {}, {"continuous_torque_Nm=0.01:5"});
  p.preset.parameters["peak_torque_Nm"] = 10;  // above every continuous torque tried
  p.tolerance = 1e-3;
  const fit::Result r = fit::solve(p);
  ASSERT_TRUE(r.best);
  const fit::Row& best = r.rows[*r.best];
  const double tau = best.parameters.at("continuous_torque_Nm");
  EXPECT_EQ(best.cost, tau);
  const auto unit = fit::evaluate(p, {1.0});
  ASSERT_TRUE(unit);
  const double needed = 1.0 / unit->report.criteria[1].worst;
  EXPECT_GE(tau, needed * (1 - 1e-9));
  EXPECT_LE(tau, needed * (1 + 2 * p.tolerance) + 1e-3) << "needed " << needed;
  EXPECT_TRUE(best.meets);
  EXPECT_FALSE(fit::evaluate(p, {needed * (1 - p.tolerance)})->meets);
}

// A rating the others contradict (a continuous torque above the peak) is a
// design that cannot be built, not a failed search.
TEST(FitMotors, ContradictoryRatingsAreInvalidDesigns) {
  const auto m = make_mechanism(load_preset("parallel-12r"));
  fit::Problem p = problem_12r("sphere:diameter=6,centre=0,15,15", {});
  p.criteria = {task::parse_criterion("reach"), task::parse_criterion("force_iso>1")};
  p.variables = fit::variables(*m, {"continuous_torque_Nm"}, {}, {"continuous_torque_Nm=0.01:1000"});
  const auto row = fit::evaluate(p, {1000.0});
  ASSERT_TRUE(row);
  EXPECT_NE(row->invalid.find("exceeds its peak_torque_Nm"), std::string::npos) << row->invalid;
}
