// Task volumes and criteria (core/task.h): parsing and its errors, the
// distance transform and box erosion against brute force, the sampled
// field's verdicts against point-wise evaluation, and the inscribed sphere
// against the task evaluated where it was placed.
#include <gtest/gtest.h>

#include "expect_error.h"

#include <random>

#include "core/preset.h"
#include "core/task.h"

using namespace linkscape;
using namespace linkscape::task;
using Eigen::Vector3d;

namespace {

Device device_of(const std::string& name, const std::vector<std::string>& params = {}) {
  Preset preset = load_preset(name);
  apply_overrides(preset, params);
  Device s;
  s.mechanism = make_mechanism(preset);
  s.fixed_task = s.mechanism->home_task();
  s.data = haptics::device_data(preset, s.mechanism->info());
  s.threads = 2;
  return s;
}

}  // namespace

TEST(TaskVolume, ParsesSpheresAndBoxesWithOrWithoutCentre) {
  const TaskVolume a = parse_task("sphere:diameter=15");
  EXPECT_EQ(a.shape, Shape::Sphere);
  EXPECT_EQ(a.diameter(), 15);
  EXPECT_FALSE(a.centre);
  const TaskVolume b = parse_task("sphere:radius=2,centre=1,-2,3.5");
  EXPECT_EQ(b.diameter(), 4);
  ASSERT_TRUE(b.centre);
  EXPECT_EQ(*b.centre, Vector3d(1, -2, 3.5));
  const TaskVolume c = parse_task("box:size=10,8,6,centre=0,20,0");
  EXPECT_EQ(c.shape, Shape::Box);
  EXPECT_EQ(c.size, Vector3d(10, 8, 6));
  EXPECT_NEAR(c.volume(), 480, 1e-12);
  EXPECT_TRUE(c.contains(Vector3d(4.9, 23.9, -2.9), *c.centre));
  EXPECT_FALSE(c.contains(Vector3d(4.9, 24.1, 0), *c.centre));
  EXPECT_EQ(parse_task("box:size=5").size, Vector3d::Constant(5));

  expect_error([] { parse_task("sphere:diameter=0"); }, "is empty");
  expect_error([] { parse_task("box:size=1,-1,1"); }, "is empty");
  expect_error([] { parse_task("sphere:diameter=2,radius=1"); }, "give the diameter or the radius");
  expect_error([] { parse_task("cylinder:diameter=2"); }, "unknown shape 'cylinder'");
  expect_error([] { parse_task("sphere:diameter=2,center=1,2,3"); }, "unknown key 'center'");
  expect_error([] { parse_task("sphere:diameter=2,centre=1,2"); }, "centre expects 3 values");
  expect_error([] { parse_task("box:size=1,2"); }, "size=S or size=X,Y,Z");
  expect_error([] { parse_task("sphere:diameter=nan"); }, "finite numbers");
  expect_error([] { parse_task("sphere"); }, "expected sphere:diameter=D");
}

TEST(TaskVolume, TextReadsBackToTheSameVolume) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> size(0.01, 50), at(-40, 40);
  for (int i = 0; i < 1000; ++i) {
    task::TaskVolume t;
    t.shape = i % 2 ? task::Shape::Sphere : task::Shape::Box;
    t.size = t.shape == task::Shape::Sphere ? Eigen::Vector3d::Constant(size(rng))
                                            : Eigen::Vector3d(size(rng), size(rng), size(rng));
    if (i % 3) t.centre = Eigen::Vector3d(at(rng), at(rng), at(rng));
    const task::TaskVolume back = task::parse_task(task::to_text(t));
    EXPECT_EQ(back.shape, t.shape);
    EXPECT_EQ(back.size, t.size) << task::to_text(t);  // bit for bit: shortest round-trip numbers
    ASSERT_EQ(back.centre.has_value(), t.centre.has_value());
    if (t.centre) {
      EXPECT_EQ(*back.centre, *t.centre);
    }
  }
}

TEST(TaskCriteria, ParseBoundsOnTheGoodSideAndRefuseImpossibleOnes) {
  const Criterion c = parse_criterion("cond<3");
  EXPECT_EQ(c.measure, "cond");
  EXPECT_FALSE(c.above);
  EXPECT_EQ(c.threshold, 3);
  const Criterion f = parse_criterion("force_iso>=2.5");
  EXPECT_TRUE(f.above);
  EXPECT_EQ(f.threshold, 2.5);
  EXPECT_TRUE(parse_criterion("reach").reach());
  expect_error([] { parse_criterion("cond<1"); }, "no pose meets it");
  expect_error([] { parse_criterion("cond>3"); }, "bounded from above");
  expect_error([] { parse_criterion("force_iso<3"); }, "bounded from below");
  expect_error([] { parse_criterion("force_iso>0"); }, "no pose meets it");
  expect_error([] { parse_criterion("resolution<x"); }, "finite number");
  expect_error([] { parse_criterion("comfort"); }, "expected reach or NAME<VALUE");
  expect_error([] { parse_criterion("reach<3"); }, "reach takes no threshold");  // not a threshold ignored
  const std::vector<Criterion> spaced = parse_criteria("cond < 3, force_iso >= 2 reach");
  ASSERT_EQ(spaced.size(), 3u);
  EXPECT_EQ(spaced[0].text, "cond<3");
  EXPECT_EQ(spaced[1].text, "force_iso>=2");
  EXPECT_TRUE(spaced[2].reach());

  const auto m = make_mechanism(load_preset("pathos2"));
  EXPECT_EQ(resolve(parse_criterion("cond_jo<5"), m->info(), nullptr).measure_index, 1);
  EXPECT_EQ(resolve(parse_criterion("cond_jp<5"), m->info(), nullptr).measure_index, 0);
  expect_error([&] { resolve(parse_criterion("stiffness<5"), m->info(), nullptr); }, "known: reach, cond, cond_jp, cond_jo");
  expect_error([&] { resolve(parse_criterion("force_iso>1"), m->info(), nullptr); }, "actuator data");
}

namespace {

// By brute force on a mask, the best over good samples of the distance to
// the nearest failing sample (or the ring just outside the grid), and of
// the smallest weighted Chebyshev distance max_k |d_k| / (shape_k / 2) to
// one: the inscribed sphere's radius and box's scale.
struct BruteForce {
  double radius = -1, scale = -1;
};
BruteForce brute_force(const Grid& g, const std::vector<std::uint8_t>& good, const Vector3d& shape) {
  BruteForce out;
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        if (!good[g.index(i, j, k)]) continue;
        double d = INFINITY, scale = INFINITY;
        for (int c = -1; c <= g.dims[2]; ++c)
          for (int b = -1; b <= g.dims[1]; ++b)
            for (int a = -1; a <= g.dims[0]; ++a) {
              const bool outside = a < 0 || b < 0 || c < 0 || a >= g.dims[0] || b >= g.dims[1] || c >= g.dims[2];
              if (!outside && good[g.index(a, b, c)]) continue;
              const Vector3d off = g.point(a, b, c) - g.point(i, j, k);
              d = std::min(d, off.norm());
              scale = std::min(scale, off.cwiseAbs().cwiseQuotient(shape / 2).maxCoeff());
            }
        out.radius = std::max(out.radius, d);
        out.scale = std::max(out.scale, scale);
      }
  return out;
}

}  // namespace

// The exact distance transform and the box scales against brute force on
// random masks.
TEST(InscribedShapes, AgreeWithBruteForceOnRandomMasks) {
  std::mt19937_64 rng(7);
  const Vector3d shape(1.0, 0.5, 0.7);
  for (int trial = 0; trial < 20; ++trial) {
    const Grid g = Grid::box({0, 0, 0}, {1.0, 1.3, 0.8}, {10, 13, 8});
    std::vector<std::uint8_t> good(g.size());
    for (auto& v : good) v = std::bernoulli_distribution(0.93)(rng);
    const BruteForce expected = brute_force(g, good, shape);
    const Inscribed s = inscribed_sphere(g, good);
    ASSERT_TRUE(s.found);
    EXPECT_NEAR(s.size, 2 * expected.radius, 1e-12) << "trial " << trial;
    const Inscribed b = inscribed_box(g, good, shape);
    ASSERT_TRUE(b.found);
    EXPECT_NEAR(b.size, expected.scale, 1e-8 * expected.scale) << "trial " << trial;
  }
  // A mask with no good sample has no shape.
  const Grid g = Grid::box({0, 0, 0}, {1, 1, 1}, {4, 4, 4});
  EXPECT_FALSE(inscribed_sphere(g, std::vector<std::uint8_t>(g.size(), 0)).found);
  EXPECT_FALSE(inscribed_box(g, std::vector<std::uint8_t>(g.size(), 0), Vector3d::Ones()).found);
}

// Boxes of any aspect ratio, needles and sheets up to 1e-12 thin relative
// to their length, against brute force: the box's scale is bounded by the
// grid along its longest axis relative to the grid, so no window overflows.
TEST(InscribedShapes, BoxesOfAnyAspectRatioAgreeWithBruteForce) {
  std::mt19937_64 rng(11);
  for (const Vector3d& shape : {Vector3d(1e8, 1, 1), Vector3d(1, 1, 1e-9), Vector3d(1e-12, 1e3, 1), Vector3d(1e12, 1e-12, 1)}) {
    const Grid g = Grid::box({0, 0, 0}, {1.0, 1.3, 0.8}, {10, 13, 8});
    std::vector<std::uint8_t> good(g.size());
    for (auto& v : good) v = std::bernoulli_distribution(0.95)(rng);
    const double expected = brute_force(g, good, shape).scale;
    const Inscribed b = inscribed_box(g, good, shape);
    ASSERT_TRUE(b.found) << shape.transpose();
    EXPECT_NEAR(b.size, expected, 1e-8 * expected) << shape.transpose();
  }
}

// A ball-shaped good region: the inscribed sphere is the ball, to the
// sampling's resolution; the cube is the ball's inscribed cube.
TEST(InscribedShapes, BallRegionGivesTheBallAndItsCube) {
  const Grid g = Grid::box({-1, -1, -1}, {1, 1, 1}, {64, 64, 64});
  const Vector3d c(0.1, -0.2, 0.05);
  const double R = 0.6;
  std::vector<std::uint8_t> good(g.size());
  for (int k = 0; k < 64; ++k)
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 64; ++i) good[g.index(i, j, k)] = (g.point(i, j, k) - c).norm() < R;
  const Inscribed s = inscribed_sphere(g, good);
  EXPECT_NEAR(s.size, 2 * R, 2 * s.spacing);
  EXPECT_LT((s.centre - c).norm(), 2 * s.spacing);
  const Inscribed cube = inscribed_box(g, good, Vector3d::Ones());
  EXPECT_NEAR(cube.size, 2 * R / std::sqrt(3.0), 2 * cube.spacing);
}

// The device's sampled verdicts and the point-wise ones agree at the same
// points (both go through the interface; the field uses the device's kernel).
TEST(TaskEvaluation, FieldVerdictsAgreeWithPointwiseEvaluation) {
  for (const std::string name : {"parallel-12r", "pathos2", "delta"}) {
    Device s = device_of(name);
    const std::vector<Criterion> criteria =
        resolve(s, {parse_criterion("cond<3"), parse_criterion("force_iso>0.3"), parse_criterion("resolution<0.5")});
    const Eigen::AlignedBox3d box = s.mechanism->default_box();
    const Grid grid = Grid::box(box.min(), box.max(), {14, 14, 14});
    const auto field = sample(s, criteria, grid);
    ASSERT_TRUE(field);
    const auto good = good_mask(*field, criteria);
    int agree = 0, good_count = 0;
    for (int k = 0; k < 14; ++k)
      for (int j = 0; j < 14; ++j)
        for (int i = 0; i < 14; ++i) {
          const PointValues v = evaluate_point(s, criteria, grid.point(i, j, k));
          agree += v.meets == bool(good[grid.index(i, j, k)]);
          good_count += v.meets;
        }
    EXPECT_EQ(agree, 14 * 14 * 14) << name;
    EXPECT_GT(good_count, 5) << name;
  }
}

// 12R, L1 = L2 = 1: the isotropic point (0, 1, 1) has c(J) = 1; a small
// sphere there meets c < 3 everywhere; one across the actuator plane y = 0
// fails there, and says so.
TEST(TaskEvaluation, ReportsFractionWorstValuesAndWhereItFails) {
  Device s = device_of("parallel-12r", {"L1=1", "L2=1"});
  const std::vector<Criterion> criteria = resolve(s, {parse_criterion("cond<3"), parse_criterion("reach")});
  const TaskVolume small = parse_task("sphere:diameter=0.2");
  const TaskReport good = evaluate(s, criteria, small, Vector3d(0, 1, 1), 12);
  EXPECT_TRUE(good.meets());
  EXPECT_EQ(good.fraction, 1.0);
  EXPECT_GT(good.criteria[0].worst, 1.0);
  EXPECT_LT(good.criteria[0].worst, 3.0);
  EXPECT_NEAR(good.criteria[0].margin(), 3.0 - good.criteria[0].worst, 1e-15);
  EXPECT_LT((good.criteria[0].worst_point - Vector3d(0, 1, 1)).norm(), 0.1 + 1e-9);  // on the surface
  EXPECT_GT(good.criteria[1].worst, 0.0);  // reach margin

  // y from -0.6 to 0.6: c(J) < 3 holds only for |y| beyond about 0.35.
  const TaskReport across = evaluate(s, criteria, parse_task("box:size=0.2,1.2,0.2"), Vector3d(0.2, 0.0, 1.0), 24);
  EXPECT_FALSE(across.meets());
  EXPECT_GT(across.fraction, 0.2);
  EXPECT_LT(across.fraction, 0.7);
  EXPECT_NEAR(across.failing_centroid.y(), 0.0, 0.01);  // the failing slab straddles y = 0
  EXPECT_GT(across.failing_bounds.sizes().y(), 0.4);
  EXPECT_LT(across.failing_bounds.sizes().y(), 1.0);
  EXPECT_GT(across.criteria[0].worst, 100.0);  // towards the singular plane y = 0
  EXPECT_NEAR(across.criteria[0].worst_point.y(), 0.0, 0.05);
}

// The largest sphere in c(J) < 3 (12R, L1 = L2 = 1; about 1.22 across,
// docs/task-volumes.md) fits where it was placed, evaluated point-wise,
// when shrunk by 2 %, and fails when grown by 5 %.
TEST(TaskEvaluation, InscribedSphereFitsWhereItIsPlaced) {
  Device s = device_of("parallel-12r", {"L1=1", "L2=1"});
  const std::vector<Criterion> criteria = resolve(s, {parse_criterion("cond<3")});
  TaskVolume probe = parse_task("sphere:diameter=1");
  const auto found = largest_inscribed(s, criteria, probe, s.mechanism->default_box());
  ASSERT_TRUE(found && found->found);
  EXPECT_NEAR(found->size, 1.22, 0.02);
  probe.size = Vector3d::Constant(0.98 * found->size);
  EXPECT_TRUE(evaluate(s, criteria, probe, found->centre, 16).meets());
  probe.size = Vector3d::Constant(1.05 * found->size);
  EXPECT_FALSE(evaluate(s, criteria, probe, found->centre, 16).meets());
}

// On a planar device a sphere task is a disc in the plane: the largest one
// is not bounded by the thin z extent of the device's default box (0.2 of
// its size), it fits where it is placed (every sample in the plane), and a
// disc a little larger does not.
TEST(TaskPlanar, TheLargestSphereOfAPlanarDeviceIsADiscInItsPlane) {
  const Device s = device_of("five-bar");
  const std::vector<Criterion> criteria = resolve(s, {parse_criterion("reach")});
  TaskVolume probe = parse_task("sphere:diameter=1");
  const Eigen::AlignedBox3d box = s.mechanism->default_box();
  const auto found = largest_inscribed(s, criteria, probe, box);
  ASSERT_TRUE(found && found->found);
  EXPECT_GT(found->size, 1.5 * box.sizes().z());
  ASSERT_TRUE(s.mechanism->info().plane_z);
  EXPECT_EQ(found->centre.z(), *s.mechanism->info().plane_z);
  probe.size = Vector3d::Constant(0.98 * found->size);
  EXPECT_TRUE(evaluate(s, criteria, probe, found->centre, 24).meets());
  probe.size = Vector3d::Constant(1.1 * found->size);
  const TaskReport larger = evaluate(s, criteria, probe, found->centre, 24);
  ASSERT_FALSE(larger.meets());
  EXPECT_EQ(larger.failing_bounds.min().z(), found->centre.z());  // it fails in the plane only
  EXPECT_EQ(larger.failing_bounds.max().z(), found->centre.z());
  EXPECT_EQ(larger.criteria[0].worst_point.z(), found->centre.z());
}

// A box on a planar device is the rectangle of its x and y edges: its z
// edge changes nothing, and the largest scaled box is not bounded by the
// default box's thin z extent either.
TEST(TaskPlanar, ABoxOnAPlanarDeviceIsTheRectangleOfItsXAndYEdges) {
  const Device s = device_of("five-bar");
  const std::vector<Criterion> criteria = resolve(s, {parse_criterion("reach")});
  const Vector3d centre(0, 17, 0);
  const TaskReport thin = evaluate(s, criteria, parse_task("box:size=12,8,0.1"), centre, 16);
  const TaskReport tall = evaluate(s, criteria, parse_task("box:size=12,8,1000"), centre, 16);
  EXPECT_EQ(thin.samples, tall.samples);
  EXPECT_EQ(thin.fraction, tall.fraction);
  EXPECT_EQ(thin.criteria[0].worst, tall.criteria[0].worst);
  const auto found = largest_inscribed(s, criteria, parse_task("box:size=1"), s.mechanism->default_box());
  ASSERT_TRUE(found && found->found);
  EXPECT_GT(found->size, 1.5 * s.mechanism->default_box().sizes().z()) << "the square's side";
}

TEST(TaskVerdict, ASampleShareIsNeverRoundedToAllOrNone) {
  EXPECT_EQ(samples_text(7783, 7784), "7783 of 7784 samples (99.99 %)");
  EXPECT_EQ(samples_text(99999, 100000), "99999 of 100000 samples (99.99 %)");
  EXPECT_EQ(samples_text(1, 100000), "1 of 100000 samples (0.01 %)");
  EXPECT_EQ(samples_text(7784, 7784), "7784 of 7784 samples (100 %)");
  EXPECT_EQ(samples_text(0, 10), "0 of 10 samples (0 %)");
  EXPECT_EQ(samples_text(1, 3), "1 of 3 samples (33.33 %)");
  TaskReport r;
  r.samples = 7784;
  r.failing = 1;
  r.resolution = 24;
  EXPECT_FALSE(r.meets());
  EXPECT_EQ(verdict_text(r), "fails: only 7783 of 7784 samples (99.99 %) meet every criterion (evaluated at resolution 24)");
  r.failing = 0;
  EXPECT_TRUE(r.meets());
  EXPECT_EQ(verdict_text(r), "meets every criterion at all 7784 samples (evaluated at resolution 24)");
  EXPECT_FALSE(TaskReport{}.meets()) << "nothing evaluated meets nothing";
}

// Each criterion counts the samples failing it; a sample failing any of them
// fails the task.
TEST(TaskVerdict, CriteriaCountTheirFailingSamples) {
  const Device d = device_of("parallel-12r");
  const auto c = resolve(d, {parse_criterion("reach"), parse_criterion("cond<3"), parse_criterion("cond<2")});
  const TaskReport r = evaluate(d, c, parse_task("sphere:diameter=20"), Vector3d(0, 15, 15), 10);
  ASSERT_EQ(r.criteria.size(), 3u);
  int most = 0, sum = 0;
  for (const CriterionReport& cr : r.criteria) most = std::max(most, cr.failing), sum += cr.failing;
  EXPECT_GT(r.criteria[2].failing, r.criteria[1].failing) << "a tighter bound fails more samples";
  EXPECT_GE(r.failing, most);
  EXPECT_LE(r.failing, sum);
  EXPECT_EQ(r.resolution, 10);
}

TEST(CentreRegion, ParsesBoxesAndBallsAndRefusesTheRest) {
  const CentreRegion box = parse_centre_region("box:min=-1,2,-3,max=1,4,3");
  EXPECT_EQ(box.shape, Shape::Box);
  EXPECT_TRUE(box.contains(Vector3d(0, 3, 0)));
  EXPECT_FALSE(box.contains(Vector3d(0, 5, 0)));
  EXPECT_EQ(to_text(box), "box:min=-1,2,-3,max=1,4,3");
  const CentreRegion ball = parse_centre_region("sphere:centre=0,15,15,radius=2.5");
  EXPECT_TRUE(ball.contains(Vector3d(0, 15, 17.4)));
  EXPECT_FALSE(ball.contains(Vector3d(0, 15, 17.6)));
  EXPECT_EQ(parse_centre_region(to_text(ball)).bounds().min(), Vector3d(-2.5, 12.5, 12.5));
  expect_error([] { parse_centre_region("box:min=1,1,1"); }, "give min and max");
  expect_error([] { parse_centre_region("box:min=1,1,1,max=0,2,2"); }, "min must not exceed max");
  expect_error([] { parse_centre_region("sphere:centre=0,0,0,radius=0"); }, "radius must be positive");
  expect_error([] { parse_centre_region("sphere:centre=0,0,radius=1"); }, "centre expects 3 values");
  expect_error([] { parse_centre_region("cone:min=0,0,0"); }, "unknown shape 'cone'");
  expect_error([] { parse_centre_region("box:min=0,0,0,max=1,1,1,size=2"); }, "unknown key 'size'");
  expect_error([] { parse_centre_region("box"); }, "expected box:min=x,y,z,max=x,y,z");
}

// A centre region: the shape's centre stays in it, even where a larger
// shape fits elsewhere.
TEST(CentreRegion, TheLargestShapeIsCentredInTheRegion) {
  const Device d = device_of("parallel-12r");
  const auto c = resolve(d, {parse_criterion("reach"), parse_criterion("cond<3")});
  InscribedOptions options{32, 1, 2};
  const auto anywhere = largest_inscribed(d, c, parse_task("sphere:diameter=5"), d.mechanism->default_box(), options);
  ASSERT_TRUE(anywhere && anywhere->found);
  options.centres = parse_centre_region("box:min=-2,10,10,max=2,14,14");
  const auto within = largest_inscribed(d, c, parse_task("sphere:diameter=5"), d.mechanism->default_box(), options);
  ASSERT_TRUE(within && within->found);
  EXPECT_TRUE(options.centres->contains(within->centre)) << within->centre.transpose();
  EXPECT_LT(within->size, anywhere->size);
}

// One syntax everywhere: commas, semicolons or spaces; a bare name (what a
// shell leaves of an unquoted cond>3) says to quote it.
TEST(TaskCriteria, ListsTakeCommasSemicolonsOrSpaces) {
  const std::vector<std::string> expected = {"cond<3", "force_iso>1", "reach"};
  for (const std::string text : {"cond<3, force_iso>1, reach", "cond<3;force_iso>1; reach", "cond<3 force_iso>1  reach",
                                 " cond<3,;force_iso>1 ;reach;"})
    EXPECT_EQ(split_criteria(text), expected) << text;
  EXPECT_TRUE(split_criteria(" ,; ").empty());
  EXPECT_EQ(parse_criteria("cond<3, force_iso>1").size(), 2u);
  expect_error([] { parse_criteria("cond<3, cond"); }, "quote the criterion: 'cond<3'");
  expect_error([] { parse_criteria("force_max"); }, "quote the criterion: 'force_max>1'");
  // A margin to a stop is bounded from below too: its example is one the parser takes.
  for (const std::string margin : {"joint_margin", "clearance"}) {
    const std::string hint = quoting_hint(margin);
    const std::size_t from = hint.find('\'') + 1;
    const std::string example = hint.substr(from, hint.find('\'', from) - from);
    EXPECT_EQ(example.rfind(margin + ">", 0), 0u) << hint;
    EXPECT_TRUE(parse_criterion(example).above) << example;
  }
  EXPECT_EQ(quoting_hint("cond<3"), "");
  EXPECT_EQ(quoting_hint("reach"), "");
}

// evaluate_if_meets gives evaluate's report where the task meets, nothing
// where it fails: the same samples, the same verdict.
TEST(TaskVerdict, EvaluateIfMeetsAgreesWithEvaluate) {
  const Device d = device_of("parallel-12r");
  const auto c = resolve(d, {parse_criterion("reach"), parse_criterion("cond<3")});
  for (const double diameter : {4.0, 10.0, 30.0}) {
    const TaskVolume t = parse_task("sphere:diameter=" + std::to_string(diameter));
    const TaskReport full = evaluate(d, c, t, Vector3d(0, 15, 12), 12);
    const std::optional<TaskReport> quick = evaluate_if_meets(d, c, t, Vector3d(0, 15, 12), 12);
    EXPECT_EQ(quick.has_value(), full.meets()) << diameter;
    if (quick) {
      EXPECT_EQ(quick->samples, full.samples);
      EXPECT_EQ(quick->criteria[1].worst, full.criteria[1].worst);
      EXPECT_EQ(quick->fraction, full.fraction);
    }
  }
}
