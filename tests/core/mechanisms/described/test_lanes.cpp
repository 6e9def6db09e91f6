// The SIMD lanes of described devices' fields against the scalar closed path
// (IK method closed-scalar): on every shipped description and on
// random designs (parameters drawn within their ranges), each branch, a box
// reaching past the workspace and a slice, on the best instruction set and
// on the portable baseline: statuses identical sample for sample, c(J),
// cond(Jo), reach margin, residual and joint margin within 1e-9 relative in
// double, so as stored (float) equal or one float step apart. And which
// devices the lanes serve, and that they do serve.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <string>

#include "core/field.h"
#include "core/mechanism.h"
#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/lanes.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/preset.h"
#include "core/simd.h"
#include "tests/core/mechanisms/described/designs.h"

namespace linkscape {
namespace {

constexpr std::uint8_t kLanesCode = 2;  // method_names: closed, newton, lanes

// Equal, within 1e-9 relative, or one float step apart (each side rounds its
// double to float once); NaN matches NaN.
bool agree(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (a == b) return true;
  if (std::isinf(a) || std::isinf(b)) return false;
  return std::abs(double(a) - double(b)) <= 1e-9 * std::max(std::abs(double(a)), std::abs(double(b))) ||
         std::nextafter(a, b) == b;
}

Field field(const Mechanism& m, const Grid& g, const Eigen::VectorXd& fixed, const std::string& method, int branch) {
  IkOptions o;
  o.method = method;
  o.branch = branch;
  std::optional<Field> f = m.compute_field(g, fixed, o, 2, {});
  if (!f) throw std::runtime_error("field cancelled");
  return *f;
}

struct Tally {
  std::size_t ok = 0, lanes = 0;  // samples ok, and of them decided in lanes (the others carry no method)
  std::size_t stopped = 0;        // beyond a passive joint's stop or with links overlapping
};

// Lanes against the scalar closed path, sample for sample; returns how many samples the lanes served.
void compare(const Field& lanes, const Field& scalar, const std::string& what, Tally& tally,
             const char* reference = "closed") {
  ASSERT_EQ(lanes.method, "lanes") << what;
  ASSERT_EQ(scalar.method, reference) << what;
  const std::size_t n = lanes.grid.size();
  int reported = 0;
  auto report = [&](std::size_t i, const char* name, double a, double b) {
    if (reported++ < 5)
      ADD_FAILURE() << what << " sample " << i << " at " << lanes.grid.point(int(i % std::size_t(lanes.grid.dims[0])),
                                                                               int(i / std::size_t(lanes.grid.dims[0]) % std::size_t(lanes.grid.dims[1])),
                                                                               int(i / std::size_t(lanes.grid.dims[0] * lanes.grid.dims[1])))
                                                                   .transpose()
                    << ": " << name << " lanes " << a << ", scalar " << b;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (lanes.status[i] != scalar.status[i]) report(i, "status", lanes.status[i], scalar.status[i]);
    if (!agree(lanes.cond[i], scalar.cond[i])) report(i, "cond", lanes.cond[i], scalar.cond[i]);
    if (!agree(lanes.reach_margin[i], scalar.reach_margin[i])) report(i, "reach margin", lanes.reach_margin[i], scalar.reach_margin[i]);
    if (!agree(lanes.residual[i], scalar.residual[i])) report(i, "residual", lanes.residual[i], scalar.residual[i]);
    if (!lanes.cond_orientation.empty() && !agree(lanes.cond_orientation[i], scalar.cond_orientation[i]))
      report(i, "cond(Jo)", lanes.cond_orientation[i], scalar.cond_orientation[i]);
    for (std::size_t e = 0; e < lanes.extras.size(); ++e)
      if (!agree(lanes.extras[e].values[i], scalar.extras[e].values[i]))
        report(i, lanes.extras[e].name.c_str(), lanes.extras[e].values[i], scalar.extras[e].values[i]);
    if (lanes.reachable[i] != scalar.reachable[i]) report(i, "reachable", lanes.reachable[i], scalar.reachable[i]);
    tally.ok += lanes.status[i] == std::uint8_t(Status::Ok);
    tally.lanes += lanes.method_used[i] == kLanesCode;
    bool stopped = false;
    for (const Field::NamedArray& e : lanes.extras) stopped = stopped || e.values[i] < 0;
    tally.stopped += stopped;
  }
}

// The default box, a box about home (mostly inside the workspace) and a
// slice through home, every branch.
void check_device(const Mechanism& m, const std::string& what, Tally& tally, bool turned = false) {
  Eigen::VectorXd fixed = m.home_task();
  // Turned, and any extras (a grip) away from home: fixed in the field like the rotation.
  if (turned && fixed.size() >= 6) fixed.segment(3, 3) << 0.08, -0.05, 0.12;
  if (turned) fixed.tail(fixed.size() - std::min<Eigen::Index>(fixed.size(), 6)) *= 0.8;
  const Eigen::AlignedBox3d box = m.default_box();
  const Eigen::Vector3d home = m.home_task().head(3), near = Eigen::Vector3d::Constant(0.3 * m.size());
  const Grid whole = Grid::box(box.min(), box.max(), {14, 13, 12});
  const Grid inside = Grid::box(home - near, home + near, {12, 11, 10});
  const auto [normal, position] = m.default_slice_plane(m.home_task());
  const std::array<Axis, 2> axes = Grid::slice_axes(normal);
  const int u = int(axes[0]), v = int(axes[1]);
  const Grid slice = Grid::slice(normal, position, box.min()(u), box.max()(u), box.min()(v), box.max()(v), 48, 48);
  const int branches = int(m.info().branches.size());
  for (int b = 0; b < branches; ++b)
    for (const Grid* g : {&whole, &inside, &slice}) {
      const Field scalar = field(m, *g, fixed, "closed-scalar", b);
      for (const char* target : {"", "baseline"}) {
        simd::limit_targets(target);
        const Field lanes = field(m, *g, fixed, "closed", b);
        compare(lanes, scalar, what + " branch " + std::to_string(b) + (g == &whole ? " box" : g == &inside ? " inside" : " slice") +
                                   " on " + simd::current_target(), tally);
      }
      simd::limit_targets("");
    }
}

// Haply and Falcon with passive revolutes' stops and link capsules: a planar
// dyad's elbows; a crank-parallelogram's knee, upper and grip joints. The
// described PATHOS-II: three-revolute legs with angle rules, and an extra.
const char* const kLaneDevices[] = {"delta-described", "hexapod-rus", "stewart", "linear-delta", "five-bar",
                                    "three-rrr",       "haply-2diy",  "falcon",  "pathos2-described",
                                    "omnid-delta",     "three-rpr"};
bool has_stops(const std::string& name) { return name == "haply-2diy" || name == "falcon"; }
bool turns(const std::string& name) { return name == "stewart" || name == "pathos2-described"; }

// A shipped preset with `edit` applied to its description (each
// replacement must match).
Preset preset_with(const char* name, const std::vector<std::pair<std::string, std::string>>& edit) {
  Preset p = load_preset(name);
  for (const auto& [from, to] : edit) {
    std::size_t at = p.description.find(from);
    if (at == std::string::npos) throw std::runtime_error("no " + from + " in the description");
    for (; at != std::string::npos; at = p.description.find(from, at + to.size())) p.description.replace(at, from.size(), to);
  }
  return p;
}
Preset pathos2_with(const std::vector<std::pair<std::string, std::string>>& edit) {
  return preset_with("pathos2-described", edit);
}
// (The description as the preset holds it: compact JSON, keys sorted.)
const std::pair<std::string, std::string> kActuatorTravel = {R"("name":"q#")", R"("name":"q#","range_deg":[140,220])"};
const std::pair<std::string, std::string> kThirdJointStop = {R"("name":"t3_#")", R"("name":"t3_#","range_deg":[-170,170])"};

TEST(DescribedLanes, ShippedDevicesAgreeWithTheScalarClosedPath) {
  for (const char* name : kLaneDevices) {
    Tally tally;
    const auto m = make_mechanism(load_preset(name));
    check_device(*m, name, tally);
    if (turns(name)) check_device(*m, std::string(name) + " turned", tally, true);
    // The lanes decide most samples; the scalar path only a band near thresholds.
    EXPECT_GT(double(tally.lanes), 0.95 * double(tally.ok)) << name;
    if (has_stops(name)) {
      EXPECT_GT(tally.stopped, 100u) << name;
    }
    std::printf("%s: %zu samples ok, %zu of them in lanes; %zu stopped\n", name, tally.ok, tally.lanes, tally.stopped);
  }
}

// The Falcon's crank-parallelograms each hold the platform's orientation
// by a couple square to their knee's and upper bar's axes; where the three
// couples lie in one plane the platform gains a turn the legs held (a
// constraint singularity). Found from the legs' joint axes alone (the
// couples' determinant, bisected) and sampled there: the lanes call it
// singular as the scalar path does, and a millimetre off it ok.
TEST(DescribedLanes, AConstraintSingularityIsSingularInLanes) {
  using namespace described;
  // Without its travel and stops: the singular surface lies where the
  // shipped device's knees are beyond theirs.
  Preset preset = load_preset("falcon");
  preset.limits_deg.clear();
  for (std::size_t at; (at = preset.description.find(R"(,"range_deg":)")) != std::string::npos;)
    preset.description.erase(at, preset.description.find(']', at) + 1 - at);
  const Kinematics kin(build_model(preset.description, preset.parameters, preset.limits_deg, preset.length_unit));
  const auto determinant = [&](const Eigen::Vector3d& x) {
    const PoseSolution s = kin.inverse(x, 0, 1e-12);
    if (s.status != Status::Ok) return std::numeric_limits<double>::quiet_NaN();
    Eigen::Matrix3d couples;
    internal::Chain c;
    for (int leg = 0; leg < 3; ++leg) {
      internal::walk_into(kin.model().legs[std::size_t(leg)], s.legs[std::size_t(leg)].state, c);
      couples.col(leg) = c.axis[1].cross(c.axis[2]).normalized();  // knee x upper
    }
    return couples.determinant();
  };
  // A sign change between two poses 5 mm apart in z, both assembled, bisected.
  Eigen::Vector3d lo, hi;
  bool found = false;
  for (double x = -100; x <= 100 && !found; x += 10)
    for (double z = -150; z <= 200 && !found; z += 5) {
      lo = {x, 10, z}, hi = {x, 10, z + 5};
      found = determinant(lo) * determinant(hi) < 0;
    }
  ASSERT_TRUE(found) << "no sign change of the couples' determinant";
  for (int i = 0; i < 80; ++i) {
    const Eigen::Vector3d mid = 0.5 * (lo + hi);
    (determinant(lo) * determinant(mid) <= 0 ? hi : lo) = mid;
  }
  // Three samples on one thread, 1 mm apart in z, the root last (a thread's
  // scratch carries nothing from one sample to the next).
  const Eigen::Vector3d root = 0.5 * (lo + hi);
  const Grid g = Grid::box(root - Eigen::Vector3d(1, 1, 2.5), root + Eigen::Vector3d(1, 1, 0.5), {1, 1, 3});
  ASSERT_LT((g.point(0, 0, 2) - root).norm(), 1e-12);
  ASSERT_LT(std::abs(determinant(g.point(0, 0, 2))), 1e-12) << root.transpose();
  const auto m = linkscape::make_mechanism(preset);
  for (const char* method : {"closed-scalar", "closed"}) {
    IkOptions o;
    o.method = method;
    const std::optional<Field> f = m->compute_field(g, m->home_task(), o, 1, {});
    ASSERT_TRUE(f);
    if (std::string(method) == "closed") EXPECT_EQ(f->method, "lanes");
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(Status(f->status[std::size_t(k)]), k == 2 ? Status::Singular : Status::Ok)
          << method << " at " << g.point(0, 0, k).transpose();
  }
}

// A cylinder as designers write it (universal joint, the body's length,
// the stroke, the rod's end): the slide starts along the leg from the ball.
TEST(DescribedLanes, ACylindersBodyBeforeItsSlideAgreesWithTheScalarClosedPath) {
  const Preset p = testing_support::stewart_with_cylinder_bodies();
  EXPECT_NE(described::describe(p).find("field: lanes"), std::string::npos);
  Tally tally;
  const auto m = make_mechanism(p);
  check_device(*m, "stewart with cylinder bodies", tally);
  check_device(*m, "stewart with cylinder bodies, turned", tally, true);
  EXPECT_GT(tally.ok, 500u);
  EXPECT_GT(double(tally.lanes), 0.95 * double(tally.ok));
}

// In the plane, slides between revolutes (3-RPR) and slides carrying rods
// (3-PRR) as the crank and rod of a planar dyad: each leg one force along
// its line.
TEST(DescribedLanes, PlanarSlideLegsAgreeWithTheScalarClosedPath) {
  for (const bool carried : {false, true}) {
    const Preset p = testing_support::planar_slide_legs(carried);
    EXPECT_NE(described::describe(p).find("field: lanes"), std::string::npos) << p.title;
    Tally tally;
    check_device(*make_mechanism(p), p.title, tally);
    EXPECT_GT(tally.ok, 500u) << p.title;
    EXPECT_GT(double(tally.lanes), 0.95 * double(tally.ok)) << p.title;
    std::printf("%s: %zu samples ok, %zu of them in lanes\n", p.title.c_str(), tally.ok, tally.lanes);
  }
}

// The lanes' doubles (before the Field's floats) against the scalar closed
// path's own, computed here from Kinematics: inverse, jacobian, reach margin
// and the condition numbers by SVD, on the default box and a box about
// home, every branch. Returns the worst relative differences.
struct Worst {
  double cond = 0, margin = 0;
  double joint_margin = 0, clearance = 0;  // relative to max(|value|, 1e-6 deg or size)
  std::size_t stopped = 0, overlapping = 0;  // samples beyond a passive joint's stop, with links overlapping
  double cond_clustered = 0;  // where two singular values lie within 1e-3 relative of each other
  double at_cond = 0;         // c(J) where the worst c(J) difference is
  std::size_t compared = 0;  // samples the lanes decided
  std::size_t samples = 0;   // of all samples (unreachable ones too)
};
Worst compare_doubles(const Preset& preset) {
  using namespace described;
  const Kinematics kin(build_model(preset.description, preset.parameters, preset.limits_deg, preset.length_unit));
  const Model& model = kin.model();
  const auto mechanism = linkscape::make_mechanism(preset);
  const Eigen::AlignedBox3d box = mechanism->default_box();
  const Eigen::Vector3d home = mechanism->home_task().head(3), about = Eigen::Vector3d::Constant(0.3 * model.size);
  const int rows_of_task = model.planar ? 2 : 3;
  Worst worst;
  for (int branch = 0; branch < kin.branches(); ++branch) {
    const std::optional<LaneDevice> device = lane_device(kin, model.home, branch);
    if (!device) throw std::runtime_error("not in lanes");
    for (const Grid& g : {Grid::box(box.min(), box.max(), model.planar ? std::array<int, 3>{41, 37, 1} : std::array<int, 3>{17, 15, 13}),
                          Grid::box(home - about, home + about, model.planar ? std::array<int, 3>{38, 35, 1} : std::array<int, 3>{16, 14, 12})}) {
      const std::size_t n = std::size_t(g.dims[0]);
      std::vector<float> cond(n), margin(n), residual(n), orientation(n);
      std::vector<std::uint8_t> reachable(n), status(n), method(n);
      std::vector<std::uint16_t> iterations(n);
      const detail::FieldRowOut out{cond.data(), margin.data(), residual.data(), reachable.data(),
                                    status.data(), iterations.data(), method.data(), orientation.data()};
      for (int k = 0; k < g.dims[2]; ++k)
        for (int j = 0; j < g.dims[1]; ++j) {
          const detail::GridRow row{0, {0, j, k}, g.dims[0], g.index(0, j, k)};
          LaneValues values;
          sample_row_lanes(*device, g, row, out, {}, kLanesCode,
                           [](int, double& jm, double& gap) { return jm = gap = 0, FieldSample{}; }, &values);
          for (int t = 0; t < row.count; ++t) {
            ++worst.samples;
            if (std::isnan(values.reach_margin[std::size_t(t)])) continue;  // the scalar path's sample
            Eigen::VectorXd x = model.home;
            x.head(rows_of_task) = row.point(g, t).head(rows_of_task);
            const PoseSolution solved = kin.inverse(x, branch, 1e-10);
            std::optional<JacobianParts> parts;
            if (assembled(solved)) parts = kin.jacobian(x, solved);
            const double margin_ref = kin.reach_margin(solved, parts ? &*parts : nullptr);
            const double lane_margin = values.reach_margin[std::size_t(t)];
            worst.margin = std::max(worst.margin, std::abs(lane_margin - margin_ref) / std::max(std::abs(margin_ref), 1e-6 * model.size));
            ++worst.compared;
            const double lane_stops[2] = {values.joint_margin[std::size_t(t)], values.clearance[std::size_t(t)]};
            const bool closes = assembled(solved);
            const double ref_stops[2] = {closes && kin.has_joint_limits() ? solved.stops.joint_margin_deg : NAN,
                                         closes && kin.has_capsules() ? solved.stops.clearance : NAN};
            const double floor[2] = {1e-6, 1e-6 * model.size};
            double* worst_stops[2] = {&worst.joint_margin, &worst.clearance};
            for (int k = 0; k < 2; ++k) {
              EXPECT_EQ(std::isnan(lane_stops[k]), std::isnan(ref_stops[k])) << k;
              if (!std::isnan(ref_stops[k]))
                *worst_stops[k] = std::max(*worst_stops[k], std::abs(lane_stops[k] - ref_stops[k]) / std::max(std::abs(ref_stops[k]), floor[k]));
            }
            worst.stopped += closes && solved.stops.joint_margin_deg < 0;
            worst.overlapping += closes && solved.stops.clearance < 0;
            if (status[std::size_t(t)] != std::uint8_t(Status::Ok)) continue;
            EXPECT_EQ(parts ? parts->status : Status::Unreachable, Status::Ok);
            std::vector<Eigen::MatrixXd> blocks;
            if (parts->J.rows() == 6) {
              Eigen::MatrixXd Jp(3, 6), Jo(3, 6);
              int p = 0, o = 0, r = 0;
              for (const TaskCoordinate& c : model.task)
                if (c.platform_coordinate >= 0) (c.platform_coordinate < 3 ? Jp.row(p++) : Jo.row(o++)) = parts->J.row(r++);
              blocks = {Jp, Jo};
            } else {
              blocks = {parts->J};
            }
            const double lane[2] = {values.cond[std::size_t(t)], values.cond_orientation[std::size_t(t)]};
            for (std::size_t e = 0; e < blocks.size(); ++e) {
              const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(blocks[e]).singularValues();
              const double ref = sv(0) / sv(sv.size() - 1);
              double gap = 1;
              for (Eigen::Index i = 0; i + 1 < sv.size(); ++i) gap = std::min(gap, (sv(i) - sv(i + 1)) / sv(i));
              const double d = std::abs(lane[e] - ref) / ref;
              if (gap < 1e-3) worst.cond_clustered = std::max(worst.cond_clustered, d);
              else if (d > worst.cond) worst.cond = d, worst.at_cond = ref;
            }
          }
        }
    }
  }
  return worst;
}

// Where two singular values coincide (symmetric poses: the Stewart
// platform's and the Delta's axis) c(J) in closed form would keep only about
// the square root of the rounding; the lanes hand those samples to the
// scalar path, and the test checks them apart.
TEST(DescribedLanes, DoublesAgreeWithTheScalarClosedPath) {
  for (const char* name : kLaneDevices) {
    const Worst w = compare_doubles(load_preset(name));
    std::printf("%s: %zu samples, worst c(J) %.2e (at c(J) %.3g), %.2e where two singular values coincide, worst reach "
                "margin %.2e, joint margin %.2e, clearance %.2e (relative); %zu beyond a stop, %zu overlapping\n",
                name, w.compared, w.cond, w.at_cond, w.cond_clustered, w.margin, w.joint_margin, w.clearance, w.stopped,
                w.overlapping);
    EXPECT_GT(w.compared, 1000u) << name;
    // Unreachable samples too: the scalar path only near thresholds.
    EXPECT_GT(double(w.compared), 0.95 * double(w.samples)) << name << ": " << w.compared << " of " << w.samples;
    EXPECT_LE(w.joint_margin, 1e-9) << name;
    EXPECT_LE(w.clearance, 1e-9) << name;
    if (has_stops(name)) {  // decided in lanes (overlaps: the random designs)
      EXPECT_GT(w.stopped, 20u) << name;
    }
    EXPECT_LE(w.cond, 1e-9) << name;
    EXPECT_LE(w.cond_clustered, 1e-9) << name;
    EXPECT_LE(w.margin, 1e-9) << name;
  }
}

// `p` with its parameters drawn within their ranges, and its mechanism
// (null for a design whose home does not assemble: it is refused).
std::shared_ptr<const Mechanism> random_design(const Mechanism& base, std::mt19937_64& rng, Preset& p) {
  for (const Quantity& q : base.info().parameters)
    p.parameters[q.name] = std::uniform_real_distribution<double>(q.range.lo, q.range.hi)(rng);
  try {
    return make_mechanism(p);
  } catch (const std::invalid_argument&) {
    return nullptr;
  }
}

TEST(DescribedLanes, RandomDesignsAgreeWithTheScalarClosedPath) {
  std::mt19937_64 rng(2811);
  for (const char* name : kLaneDevices) {
    const Preset shipped = load_preset(name);
    const auto base = make_mechanism(shipped);
    Tally tally;
    int designs = 0;
    std::size_t stopped = 0, overlapping = 0;
    for (int attempt = 0; attempt < 40 && designs < 4; ++attempt) {
      Preset p = shipped;
      const std::shared_ptr<const Mechanism> m = random_design(*base, rng, p);
      if (!m) continue;
      ++designs;
      check_device(*m, std::string(name) + " design " + std::to_string(designs), tally, true);
      const Worst w = compare_doubles(p);
      std::printf("%s design %d: worst c(J) %.2e (at c(J) %.3g), %.2e where two singular values coincide, worst reach "
                  "margin %.2e, joint margin %.2e, clearance %.2e; %zu beyond a stop, %zu overlapping\n", name, designs, w.cond,
                  w.at_cond, w.cond_clustered, w.margin, w.joint_margin, w.clearance, w.stopped, w.overlapping);
      stopped += w.stopped;
      overlapping += w.overlapping;
      EXPECT_LE(w.joint_margin, 1e-9) << name << " design " << designs;
      EXPECT_LE(w.clearance, 1e-9) << name << " design " << designs;
      EXPECT_LE(w.cond, 1e-9) << name << " design " << designs;
      EXPECT_LE(w.cond_clustered, 1e-9) << name << " design " << designs;
      EXPECT_LE(w.margin, 1e-9) << name << " design " << designs;
    }
    EXPECT_GE(designs, 2) << name;
    if (has_stops(name)) {  // decided in lanes
      EXPECT_GT(stopped, 20u) << name;
      EXPECT_GT(overlapping, 20u) << name;
    }
    EXPECT_GT(double(tally.lanes), 0.9 * double(tally.ok)) << name;
    std::printf("%s: %d random designs, %zu samples ok, %zu of them in lanes\n", name, designs, tally.ok, tally.lanes);
  }
}

// The described PATHOS-II with its actuators' travel limited (part of the
// grid beyond it) and on its other branch (each leg's third joint's sign
// turned over), as the shipped devices are checked.
TEST(DescribedLanes, PathosVariantsAgreeWithTheScalarClosedPath) {
  Preset flipped = load_preset("pathos2-described");
  for (int k = 1; k <= 6; ++k) flipped.parameters["branch_" + std::to_string(k)] *= -1;
  const std::pair<const char*, Preset> variants[] = {{"pathos2 travel", pathos2_with({kActuatorTravel})},
                                                     {"pathos2 other branch", flipped}};
  for (const auto& [name, preset] : variants) {
    Tally tally;
    const auto m = make_mechanism(preset);
    check_device(*m, name, tally);
    check_device(*m, std::string(name) + " turned", tally, true);
    EXPECT_GT(double(tally.lanes), 0.95 * double(tally.ok)) << name;
    const Worst w = compare_doubles(preset);
    std::printf("%s: %zu samples ok, %zu in lanes; doubles: %zu samples, worst c(J) %.2e, %.2e clustered, reach margin %.2e\n",
                name, tally.ok, tally.lanes, w.compared, w.cond, w.cond_clustered, w.margin);
    EXPECT_GT(w.compared, 1000u) << name;
    EXPECT_LE(w.cond, 1e-9) << name;
    EXPECT_LE(w.cond_clustered, 1e-9) << name;
    EXPECT_LE(w.margin, 1e-9) << name;
  }
  // The travel decides: a slice through home has samples beyond it.
  const auto m = make_mechanism(variants[0].second);
  const auto [normal, position] = m->default_slice_plane(m->home_task());
  const Eigen::AlignedBox3d box = m->default_box();
  const std::array<Axis, 2> axes = Grid::slice_axes(normal);
  const Field f = field(*m, Grid::slice(normal, position, box.min()(int(axes[0])), box.max()(int(axes[0])),
                                        box.min()(int(axes[1])), box.max()(int(axes[1])), 48, 48),
                        m->home_task(), "closed", 0);
  EXPECT_GT(std::count(f.status.begin(), f.status.end(), std::uint8_t(Status::OutOfLimits)), 20);
}

TEST(DescribedLanes, WhichDevicesTheLanesServe) {
  for (const char* name : kLaneDevices) {
    const Preset p = load_preset(name);
    EXPECT_NE(described::describe(p).find("field: lanes"), std::string::npos) << name;
  }
  // A stop on a three-revolute leg's joint: the scalar closed path for the
  // whole field, and describe says why.
  {
    const Preset p = pathos2_with({kThirdJointStop});
    const std::string name = "pathos2 with a stop";
    EXPECT_NE(described::describe(p).find("field: closed, one pose at a time (not in lanes: leg 1: a joint limit on a "
                                          "three-revolute leg)"),
              std::string::npos)
        << described::describe(p);
    const auto m = make_mechanism(p);
    const auto [normal, position] = m->default_slice_plane(m->home_task());
    const Eigen::AlignedBox3d box = m->default_box();
    const std::array<Axis, 2> axes = Grid::slice_axes(normal);
    const int u = int(axes[0]), v = int(axes[1]);
    const Field f = field(*m, Grid::slice(normal, position, box.min()(u), box.max()(u), box.min()(v), box.max()(v), 8, 8),
                          m->home_task(), "closed", 0);
    EXPECT_EQ(f.method, "closed") << name;
    for (std::uint8_t code : f.method_used) EXPECT_NE(code, kLanesCode) << name;
  }
}

// The described Delta's leg 0 with its platform joint on the crank's axis at
// the rod's length from the crank circle: every crank angle closes (the
// closed form cannot decide, the scalar path solves it numerically). The
// lanes hand such a sample to the scalar path; its neighbours stay in lanes.
TEST(DescribedLanes, ADegeneratePoseGoesToTheScalarPath) {
  const auto m = make_mechanism(load_preset("delta-described"));
  const auto p = m->parameters();
  const double x = p.at("R") - p.at("r");
  const double y = std::sqrt(p.at("Lb") * p.at("Lb") - p.at("La") * p.at("La"));  // |w - crank circle| = Lb
  const Grid g = Grid::slice(Axis::Z, 0, x - 0.3, x + 0.3, y - 0.3, y + 0.3, 3, 3);  // the middle sample on the axis
  ASSERT_LT((g.point(1, 1, 0) - Eigen::Vector3d(x, y, 0)).norm(), 1e-14);
  const Field lanes = field(*m, g, m->home_task(), "closed", 0);
  const Field scalar = field(*m, g, m->home_task(), "closed-scalar", 0);
  EXPECT_EQ(lanes.method, "lanes");
  const std::size_t middle = g.index(1, 1, 0);
  EXPECT_NE(lanes.method_used[middle], kLanesCode);
  for (std::size_t i = 0; i < g.size(); ++i) {
    EXPECT_EQ(lanes.status[i], scalar.status[i]) << i;
    EXPECT_EQ(lanes.method_used[i], scalar.method_used[i] == 0 && i != middle ? kLanesCode : scalar.method_used[i]) << i;
  }
}

// A leg whose shortest reach from its base is tiny (the rod a hair longer
// than the crank: 5e-9 of the size) and boxes round its anchor's place at its
// base, where the bound's cut near the base decides: the lanes' squared
// distance must round there as the scalar path's distance does.
TEST(DescribedLanes, NearALegsBaseTheBoundDecidesAsTheScalarPath) {
  Preset p = load_preset("delta-described");
  p.parameters["Lb"] = p.parameters.at("La") * (1 + 1e-8);
  const auto m = make_mechanism(p);
  const double x = p.parameters.at("R") - p.parameters.at("r");  // leg 1's anchor at its base
  Tally tally;
  std::size_t unreachable = 0, samples = 0;
  for (double half : {2e-7, 1e-7, 6e-8}) {
    const Grid g = Grid::box({x - half, -half, -half}, {x + half, half, half}, {24, 23, 22});
    const Field scalar = field(*m, g, m->home_task(), "closed-scalar", 0);
    const Field lanes = field(*m, g, m->home_task(), "closed", 0);
    compare(lanes, scalar, "half width " + std::to_string(half), tally);
    for (std::uint8_t s : lanes.status) unreachable += s == std::uint8_t(Status::Unreachable);
    samples += g.size();
  }
  // The boxes straddle the cut: anchors nearer the base than its reach and farther.
  EXPECT_GT(unreachable, samples / 10);
  EXPECT_LT(unreachable, samples - samples / 10);
}

TEST(DescribedLanes, TheKernelVariableStillSelectsTheNumericalReference) {
  const auto m = make_mechanism(load_preset("delta-described"));
  const Grid g = Grid::slice(Axis::Y, 0, -10, 10, -25, -5, 6, 6);
  ::setenv("LINKSCAPE_FIELD_KERNEL", "scalar", 1);
  const Field reference = field(*m, g, m->home_task(), "closed", 0);
  ::unsetenv("LINKSCAPE_FIELD_KERNEL");
  EXPECT_EQ(reference.method, "newton");
  const Field lanes = field(*m, g, m->home_task(), "closed", 0);
  EXPECT_EQ(lanes.method, "lanes");
  for (std::size_t i = 0; i < g.size(); ++i) EXPECT_EQ(lanes.status[i], reference.status[i]) << i;
}

// ---- The mirror in y ------------------------------------------------------------

bool mirrored(const Preset& p, int branch) {
  const described::Kinematics kin(described::build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
  const std::optional<described::LaneDevice> device = described::lane_device(kin, kin.model().home, branch);
  if (!device) throw std::runtime_error("not in lanes");
  return device->mirror_y;
}

// A field computed with LINKSCAPE_FIELD_KERNEL set to `kernel`.
Field field_with_kernel(const char* kernel, const Mechanism& m, const Grid& g, const std::string& method, int branch) {
  ::setenv("LINKSCAPE_FIELD_KERNEL", kernel, 1);
  Field f = field(m, g, m.home_task(), method, branch);
  ::unsetenv("LINKSCAPE_FIELD_KERNEL");
  return f;
}

// The device's fields on grids symmetric in y about 0 (a box and a slice
// z = home's, y exact negatives: dyadic spacings), every branch: mirrored
// (the default) against the unmirrored lanes and the scalar closed path.
// Returns how many of its fields the mirror served.
int check_mirror(const Mechanism& m, const Preset& p, const std::string& what) {
  const Eigen::AlignedBox3d box = m.default_box();
  const Eigen::Vector3d home = m.home_task().head(3);
  const double s = std::exp2(std::round(std::log2(m.size()))) / 32;  // the spacing in y
  const double z = std::round(home.z() / s) * s;
  const Grid grids[] = {Grid::box({box.min().x(), -8 * s, z - 8 * s}, {box.max().x(), 8 * s, z + 8 * s}, {13, 16, 9}),
                        Grid::box({box.min().x(), -7.5 * s, z - 8 * s}, {box.max().x(), 7.5 * s, z + 8 * s}, {14, 15, 10}),
                        Grid::slice(Axis::Z, z, box.min().x(), box.max().x(), -8 * s, 8 * s, 40, 16)};
  int served = 0;
  Tally all;
  for (int b = 0; b < int(m.info().branches.size()); ++b) {
    const bool mirror = mirrored(p, b);
    for (const Grid& g : grids) {
      const std::string at = what + " branch " + std::to_string(b) + " " + std::to_string(g.dims[1]) + " rows in y";
      const described::Kinematics kin(described::build_model(p.description, p.parameters, p.limits_deg, p.length_unit));
      EXPECT_EQ(described::lanes_mirror_holds(*described::lane_device(kin, kin.model().home, b), g), mirror) << at;
      const Field scalar = field(m, g, m.home_task(), "closed-scalar", b);
      const Field unmirrored = field_with_kernel("vector", m, g, "closed", b);
      for (const char* target : {"", "baseline"}) {
        simd::limit_targets(target);
        for (const char* kernel : {"vector-mirrored", ""}) {
          const Field lanes = field_with_kernel(kernel, m, g, "closed", b);
          Tally again;
          const std::string on = " on " + simd::current_target();
          compare(lanes, unmirrored, at + on + " against the unmirrored lanes", again, "lanes");
          compare(lanes, scalar, at + on + " against the scalar path", all);
        }
      }
      simd::limit_targets("");
      served += mirror;
    }
  }
  // The grids reach the workspace, and the lanes decide most of it.
  EXPECT_GT(all.ok, 200u) << what;
  EXPECT_GT(double(all.lanes), 0.9 * double(all.ok)) << what;
  return served;
}

// Which shipped devices are their own mirror image in y: the described
// Delta, the 6-RUS hexapod, the Stewart platform, the linear Delta and the
// Omnid's Delta; not the planar ones (symmetric in x, if at all), the Falcon
// (parallelograms) or the described PATHOS-II (three-revolute legs). Their
// fields agree with the unmirrored lanes and the scalar path.
TEST(DescribedLanes, MirroredFieldsAgreeWithTheUnmirroredAndTheScalarPath) {
  const std::map<std::string, bool> expected = {{"delta-described", true}, {"hexapod-rus", true}, {"stewart", true},
                                                {"linear-delta", true},    {"five-bar", false},   {"three-rrr", false},
                                                {"haply-2diy", false},     {"falcon", false},     {"pathos2-described", false},
                                                {"omnid-delta", true},     {"three-rpr", false}};
  for (const char* name : kLaneDevices) {
    const Preset p = load_preset(name);
    EXPECT_EQ(mirrored(p, 0), expected.at(name)) << name;
    if (!expected.at(name)) continue;
    const auto m = make_mechanism(p);
    EXPECT_GT(check_mirror(*m, p, name), 0) << name;
  }
}

TEST(DescribedLanes, RandomDesignsMirroredAgreeWithTheUnmirroredAndTheScalarPath) {
  std::mt19937_64 rng(2812);
  for (const char* name : {"delta-described", "hexapod-rus", "linear-delta"}) {
    const Preset shipped = load_preset(name);
    const auto base = make_mechanism(shipped);
    int designs = 0;
    for (int attempt = 0; attempt < 20 && designs < 2; ++attempt) {
      Preset p = shipped;
      const std::shared_ptr<const Mechanism> m = random_design(*base, rng, p);
      if (!m) continue;
      ++designs;
      check_mirror(*m, p, std::string(name) + " design " + std::to_string(designs));
    }
    EXPECT_GE(designs, 1) << name;
  }
}

// A device that is not its own mirror image is not mirrored: one leg's rod
// longer by 1e-9 (beyond the 1e-12 of the size the comparison allows; 1e-14
// is within it, as cos 120 degrees' rounding), a branch with one leg's rule
// turned over (legs 1 and 2 are partners), a platform turned about x. And
// the unmirrored kernel by the variable.
TEST(DescribedLanes, AnAsymmetricDeviceIsNotMirrored) {
  const auto longer = [](const char* by) {
    return preset_with("delta-described", {{R"("translate":["Lb",0,0])", std::string(R"("translate":["Lb + k * (k - 2) * )") + by + R"(",0,0])"}});
  };
  EXPECT_FALSE(mirrored(longer("1e-9"), 0));
  EXPECT_TRUE(mirrored(longer("1e-14"), 0));
  EXPECT_TRUE(mirrored(longer("0"), 0));
  const Preset delta = load_preset("delta-described");
  EXPECT_FALSE(mirrored(delta, 2));  // leg 1's rule turned over, not leg 2's
  EXPECT_FALSE(mirrored(delta, 4));
  EXPECT_TRUE(mirrored(delta, 6));
  EXPECT_TRUE(mirrored(delta, 1));
  // Not mirrored, the field still agrees with the scalar path.
  const auto m = make_mechanism(longer("1e-9"));
  EXPECT_EQ(check_mirror(*m, longer("1e-9"), "delta with a longer rod"), 0);
  // The Stewart platform turned about x or z is not mirrored; about y it is.
  const Preset stewart = load_preset("stewart");
  const described::Kinematics kin(described::build_model(stewart.description, stewart.parameters, stewart.limits_deg,
                                                         stewart.length_unit));
  for (int axis = 3; axis < 6; ++axis) {
    Eigen::VectorXd turned = kin.model().home;
    turned(axis) = 0.05;
    EXPECT_EQ(described::lane_device(kin, turned, 0)->mirror_y, axis == 4) << axis;
  }
}

// A method the device does not have is refused naming the three it has.
TEST(DescribedLanes, AnUnknownMethodNamesTheThreeMethods) {
  const auto m = make_mechanism(load_preset("delta-described"));
  const Grid g = Grid::slice(Axis::Y, 0, -10, 10, -25, -5, 4, 4);
  try {
    field(*m, g, m->home_task(), "magic", 0);
    FAIL() << "an unknown method was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("(known: closed, closed-scalar, newton)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace linkscape
