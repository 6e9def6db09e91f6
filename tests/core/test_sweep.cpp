// Design sweeps (core/sweep.h): the designs of a grid and of a seeded random
// sample, each row against fit's own evaluation of the design, the Pareto
// front against its definition, a design that cannot be built, and the
// checkpoint (a partial last line dropped, another plan refused, the table
// from a resumed journal identical to one run straight through).
#include <gtest/gtest.h>

#include "expect_error.h"

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "core/csv.h"
#include "core/pareto.h"
#include "core/sweep.h"

using namespace linkscape;
namespace fs = std::filesystem;

namespace {

// Coarse settings: these tests check the sweep, not the sampling's accuracy.
sweep::Plan plan_12r(const std::string& l1_bounds = "L1=10:20") {
  sweep::Plan plan;
  fit::Problem& p = plan.problem;
  p.preset = load_preset("parallel-12r");
  p.variables = fit::variables(*make_mechanism(p.preset), {}, {}, {l1_bounds, "L2=10:20"});
  p.task = task::parse_task("sphere:diameter=15");
  p.criteria = {task::parse_criterion("reach"), task::parse_criterion("cond<3")};
  p.inscribed = {16, 1, 1};
  p.task_resolution = 6;
  plan.levels = 3;
  plan.columns = {"L1", "L2"};
  return plan;
}

std::vector<std::string> cells(const std::string& line) { return csv_cells(line); }

std::map<std::size_t, std::string> every_row(const sweep::Plan& plan) {
  const auto designs = sweep::designs(plan);
  std::map<std::size_t, std::string> rows;
  for (std::size_t i = 0; i < designs.size(); ++i) rows[i] = sweep::evaluate_row(plan, i, designs[i]);
  return rows;
}

fs::path temp(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_sweep_tests";
  fs::create_directories(dir);
  return dir / name;
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(SweepDesigns, GridHasEveryCombinationWithTheLastVariableFastest) {
  sweep::Plan plan = plan_12r();
  const auto d = sweep::designs(plan);
  ASSERT_EQ(d.size(), 9u);
  EXPECT_EQ(d[0], (std::vector<double>{10, 10}));
  EXPECT_EQ(d[1], (std::vector<double>{10, 15}));
  EXPECT_EQ(d[3], (std::vector<double>{15, 10}));
  EXPECT_EQ(d[8], (std::vector<double>{20, 20}));  // the upper bounds exactly
  plan.levels = 1;
  expect_error([&] { sweep::designs(plan); }, "at least 2 values");
  plan.levels = 40000;
  expect_error([&] { sweep::designs(plan); }, "more than 10^9");
}

TEST(SweepDesigns, RandomDesignsDependOnTheSeedAloneAndStayInBounds) {
  sweep::Plan plan = plan_12r();
  plan.sampling = sweep::Sampling::Random;
  plan.count = 200;
  plan.seed = 7;
  const auto a = sweep::designs(plan), b = sweep::designs(plan);
  EXPECT_EQ(a, b);
  plan.seed = 8;
  EXPECT_NE(sweep::designs(plan), a);
  double mean = 0;
  for (const auto& v : a) {
    for (double x : v) {
      EXPECT_GE(x, 10);
      EXPECT_LT(x, 20);
    }
    mean += v[0] / double(a.size());
  }
  EXPECT_NEAR(mean, 15, 0.6);  // uniform: the mean's standard error is 10/sqrt(12*200) = 0.2
}

TEST(SweepRows, EachRowIsFitsEvaluationOfItsDesign) {
  const sweep::Plan plan = plan_12r();
  const auto designs = sweep::designs(plan);
  const std::vector<std::string> head = cells(sweep::header(plan));
  EXPECT_EQ(sweep::header(plan),
            "design,L1,L2,cx,cy,cz,size,meets,samples,failing,inscribed_diameter,fraction,ratio,worst_reach,margin_reach,"
            "failing_reach,worst_cond,margin_cond,failing_cond,pareto,error");
  for (std::size_t i : {0u, 4u, 8u}) {
    const auto row = cells(sweep::evaluate_row(plan, i, designs[i]));
    ASSERT_EQ(row.size(), head.size());
    const auto fit_row = fit::evaluate(plan.problem, designs[i]);
    ASSERT_TRUE(fit_row);
    auto at = [&](const std::string& column) {
      return *parse_number(row[std::size_t(std::find(head.begin(), head.end(), column) - head.begin())]);
    };
    EXPECT_EQ(at("design"), double(i));
    EXPECT_EQ(at("L1"), designs[i][0]);
    EXPECT_EQ(at("size"), fit_row->size);
    EXPECT_EQ(at("meets"), fit_row->meets ? 1 : 0);
    EXPECT_EQ(at("inscribed_diameter"), fit_row->fit * 15);
    EXPECT_EQ(at("ratio"), fit_row->ratio);
    EXPECT_EQ(at("failing"), fit_row->report.failing);
    EXPECT_EQ(at("meets"), at("failing") == 0 ? 1 : 0) << "one verdict: every sample meets";
    EXPECT_EQ(at("worst_cond"), fit_row->report.criteria[1].worst);
    EXPECT_EQ(row.back(), "");
  }
}

TEST(SweepRows, ADesignThatCannotBeBuiltIsARowWithItsReason) {
  const sweep::Plan plan = plan_12r("L1=-5:20");
  const auto rows = every_row(plan);
  const auto first = cells(rows.at(0));
  EXPECT_EQ(first[1], "-5");
  // The reason word for word, its commas quoted (RFC 4180), not replaced.
  std::string reason;
  try {
    make_mechanism(fit::design_preset(plan.problem, sweep::designs(plan)[0]));
  } catch (const std::invalid_argument& e) {
    reason = e.what();
  }
  ASSERT_NE(reason.find(','), std::string::npos) << reason;
  EXPECT_EQ(first.back(), "invalid design: " + reason);
  EXPECT_EQ(first[cells(sweep::header(plan)).size() - 2], "0");  // never on the front
  EXPECT_EQ(cells(rows.at(8)).back(), "");  // the others are scored
  const std::string table = sweep::table(plan, rows);
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 10);
}

TEST(SweepRows, FieldMeasuresMatchTheFieldSampledDirectly) {
  sweep::Plan plan = plan_12r();
  plan.field_resolution = 12;
  const auto designs = sweep::designs(plan);
  const std::vector<std::string> head = cells(sweep::header(plan));
  const auto row = cells(sweep::evaluate_row(plan, 4, designs[4]));
  ASSERT_EQ(row.size(), head.size());
  auto at = [&](const std::string& column) {
    return *parse_number(row[std::size_t(std::find(head.begin(), head.end(), column) - head.begin())]);
  };
  // The same field, reduced here independently: every reachable sample's 1/c.
  Preset preset = plan.problem.preset;
  preset.parameters["L1"] = designs[4][0];
  preset.parameters["L2"] = designs[4][1];
  const auto m = make_mechanism(preset);
  const auto box = m->default_box();
  std::array<int, 3> dims{};
  for (int k = 0; k < 3; ++k) dims[std::size_t(k)] = std::max(2, int(std::lround(12 * box.sizes()(k) / box.sizes().maxCoeff())));
  const Grid grid = Grid::box(box.min(), box.max(), dims);
  const auto field = m->compute_field(grid, m->home_task(), {}, 1, {});
  ASSERT_TRUE(field);
  double sum = 0;
  int reachable = 0;
  for (std::size_t s = 0; s < grid.size(); ++s)
    if (field->reachable[s]) ++reachable, sum += std::isfinite(field->cond[s]) ? 1.0 / field->cond[s] : 0.0;
  ASSERT_GT(reachable, 0);
  EXPECT_NEAR(at("gci"), sum / reachable, 1e-12);
  EXPECT_GT(at("gci"), 0);
  EXPECT_LE(at("gci"), 1);  // c >= 1
  EXPECT_NEAR(at("reach_volume"), reachable * grid.spacing.prod(), 1e-9 * at("reach_volume"));
  EXPECT_GE(at("task_worst_cond"), at("task_mean_cond"));
  EXPECT_GE(at("task_mean_cond"), 1);
}

TEST(SweepPareto, TheFrontIsThePointsNoOtherBeatsOnBoth) {
  std::mt19937 random(3);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> x, y;
    for (int i = 0; i < 40; ++i) {
      x.push_back(double(random() % 10));  // ties on purpose
      y.push_back(double(random() % 10));
    }
    for (bool larger : {false, true}) {
      const std::vector<bool> front = non_dominated(x, y, larger);
      for (std::size_t a = 0; a < x.size(); ++a) {
        bool dominated = false;
        for (std::size_t b = 0; b < x.size(); ++b)
          dominated = dominated ||
                      (x[b] <= x[a] && (larger ? y[b] >= y[a] : y[b] <= y[a]) && (x[b] < x[a] || y[b] != y[a]));
        EXPECT_EQ(front[a], !dominated) << "trial " << trial << " point " << a;
      }
    }
  }
}

TEST(SweepCheckpoint, AResumedJournalGivesTheSameTableAsOneRunStraightThrough) {
  const sweep::Plan plan = plan_12r();
  const auto designs = sweep::designs(plan);
  const std::string straight = sweep::table(plan, every_row(plan));
  const fs::path path = temp("resume.checkpoint");
  fs::remove(path);
  {
    sweep::Checkpoint journal(path, plan, designs.size(), false);
    for (std::size_t i : {5u, 0u, 2u}) journal.add(i, sweep::evaluate_row(plan, i, designs[i]));
    journal.flush();
  }
  // A run killed while writing design 7's row.
  std::ofstream(path, std::ios::app) << sweep::evaluate_row(plan, 7, designs[7]).substr(0, 12);
  sweep::Checkpoint resumed(path, plan, designs.size(), true);
  ASSERT_EQ(resumed.rows().size(), 3u);
  EXPECT_TRUE(resumed.rows().count(5) && resumed.rows().count(0) && resumed.rows().count(2));
  for (std::size_t i = 0; i < designs.size(); ++i)
    if (!resumed.rows().count(i)) resumed.add(i, sweep::evaluate_row(plan, i, designs[i]));
  resumed.flush();
  EXPECT_EQ(sweep::table(plan, resumed.rows()), straight);
  // The journal read again holds every row once, the partial line gone.
  sweep::Checkpoint again(path, plan, designs.size(), true);
  EXPECT_EQ(again.rows().size(), designs.size());
  const std::string journal = read(path);
  EXPECT_EQ(std::count(journal.begin(), journal.end(), '\n'), 1 + long(designs.size()));
  again.remove();
  EXPECT_FALSE(fs::exists(path));
}

TEST(SweepCheckpoint, AnotherPlanOrAMalformedJournalIsRefused) {
  const sweep::Plan plan = plan_12r();
  const fs::path path = temp("other.checkpoint");
  fs::remove(path);
  expect_error([&] { sweep::Checkpoint(path, plan, 9, true); }, "finds no checkpoint");
  { sweep::Checkpoint(path, plan, 9, false); }
  expect_error([&] { sweep::Checkpoint(path, plan, 9, false); }, "add --resume to finish it, or remove it");
  sweep::Plan other = plan_12r();
  other.levels = 4;
  expect_error([&] { sweep::Checkpoint(path, other, 16, true); }, "is of another sweep");
  std::ofstream(path, std::ios::app) << "12,1,2\n";
  expect_error([&] { sweep::Checkpoint(path, plan, 9, true); }, "other.checkpoint:2: a checkpoint row starts with a design index below 9");
  fs::remove(path);
  { sweep::Checkpoint(path, plan, 9, false); }
  std::ofstream(path, std::ios::app) << "3,1,2\n";
  expect_error([&] { sweep::Checkpoint(path, plan, 9, true); }, "other.checkpoint:2: 3 cells, expected 21");
}

// A journal named through a symbolic link to a file not yet there: the
// journal is written at the link's target, and once the table is written it
// goes and the link stays, as every output's link does.
TEST(SweepCheckpoint, ALinkToAMissingJournalStaysAndItsTargetIsWritten) {
  const sweep::Plan plan = plan_12r();
  const fs::path link = temp("link.checkpoint"), target = temp("target.checkpoint");
  fs::remove(link);
  fs::remove(target);
  fs::create_symlink(target.filename(), link);
  sweep::Checkpoint journal(link, plan, 9, false);
  journal.add(0, sweep::evaluate_row(plan, 0, sweep::designs(plan)[0]));
  journal.flush();
  EXPECT_TRUE(fs::is_regular_file(target));
  const std::string written = read(link);
  EXPECT_EQ(std::count(written.begin(), written.end(), '\n'), 2);  // the plan's line and the row
  journal.remove();
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_FALSE(fs::exists(target));
  fs::remove(link);
}

// Cells as RFC 4180 writes them: quoted where they hold a comma, a quote or
// a line break, each quote doubled; read back to the same text.
TEST(SweepCsv, CellsRoundTripThroughQuoting) {
  EXPECT_EQ(csv_text("plain text"), "plain text");
  EXPECT_EQ(csv_text("a, b"), "\"a, b\"");
  EXPECT_EQ(csv_text("say \"hi\""), "\"say \"\"hi\"\"\"");
  const std::vector<std::string> texts = {"", "1.5", "a,b", "\"", "x\"y,z", ",,", "end,", "two\nlines"};
  std::string line;
  for (std::size_t k = 0; k < texts.size(); ++k) {
    if (k) line += ',';
    line += csv_text(texts[k]);
  }
  EXPECT_EQ(csv_cells(line), texts) << line;
  EXPECT_EQ(csv_cells("a,,b,"), (std::vector<std::string>{"a", "", "b", ""}));
  expect_error([] { csv_cells("1,\"open"); }, "not closed");
  expect_error([] { csv_cells("\"a\"b,c"); }, "followed by 'b'");
}

// A sweep whose table would not fit in the memory available now is refused
// before its designs take any; the estimate grows with designs and columns.
TEST(SweepDesigns, ATableLargerThanTheMemoryIsRefused) {
  sweep::Plan plan = plan_12r();
  plan.sampling = sweep::Sampling::Random;
  plan.count = 1000;
  const double thousand = sweep::table_bytes(plan);
  EXPECT_GT(thousand, 1000 * 1024.0);
  plan.count = 2000;
  EXPECT_DOUBLE_EQ(sweep::table_bytes(plan), 2 * thousand);
  plan.field_resolution = 8;  // five more columns
  EXPECT_GT(sweep::table_bytes(plan), 2 * thousand);
  plan.count = 1'000'000'000;  // about 3 TB
  expect_error([&] { sweep::designs(plan); }, "GiB of memory available now");
}
