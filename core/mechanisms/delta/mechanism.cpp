#include "core/mechanisms/delta/mechanism.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "core/mechanisms/delta/field.h"
#include "core/mechanisms/delta/stops.h"
#include "core/preset.h"

namespace linkscape::delta {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;

// The linkage alone: no actuator ranges, no ball-joint cones (the stability
// sweeps approach singular sets the stops may keep the device from).
Model without_ranges(Model m) {
  for (Interval& r : m.q_limits) r = {-std::numbers::pi, std::numbers::pi};
  m.elbow_cone = m.wrist_cone = std::numbers::pi;
  return m;
}

Vector3d three(const VectorXd& v, const char* what) {
  if (v.size() != 3) throw std::invalid_argument(std::string("delta: ") + what + " needs 3 values");
  return v.head<3>();
}

class DeltaMechanism final : public Mechanism {
 public:
  explicit DeltaMechanism(const Model& model) : model_(model) {
    model_.validate();
    const std::string u = model_.length_unit;
    MechanismInfo& i = info_;
    i.name = std::string(kMechanismName);
    i.title = "Delta parallel haptic device (rotary actuators, parallelogram forearms)";
    i.length_unit = u;
    i.size_description = "La + Lb";
    auto length = [&](const char* n, const char* d, double v) { return Quantity{n, u, d, v, {0.3 * v, 2.0 * v}}; };
    i.parameters = {length("R", "Radius of the motor-axis circle", model_.R),
                    length("r", "Radius of the platform joints' circle", model_.r),
                    length("La", "Upper arm: motor axis to elbow", model_.La),
                    length("Lb", "Forearm (parallelogram): elbow to platform", model_.Lb)};
    const Vector3d q0 = home_pose(model_), p0 = home_position(model_);
    for (int k = 0; k < kLegCount; ++k)
      i.actuators.push_back({"q" + std::to_string(k + 1), "rad",
                             "Motor " + std::to_string(k + 1) + ": 0 = arm horizontal outward, > 0 downward", q0(k),
                             {model_.q_limits[k].lo, model_.q_limits[k].hi}});
    const double s = model_.size();
    i.task = {{"x", u, "Platform centre, base frame", p0.x(), {-0.7 * s, 0.7 * s}},
              {"y", u, "", p0.y(), {-0.7 * s, 0.7 * s}},
              {"z", u, "", p0.z(), {-1.1 * s, 0.4 * s}}};
    i.ik_methods = {{"closed", "closed form", "Tangent half-angle per leg"},
                    {"newton", "newton", "Newton on each leg's closure from a seed"}};
    i.seeded_ik_methods = {"newton"};
    i.fk_methods = {{"closed", "closed form", "Intersection of three spheres"},
                    {"newton", "newton", "Newton on the three closures from a seed"}};
    i.measures = {{"cond", "c(J)", "sigma_max / sigma_min of J = dp/dq"}};
    i.singular_sets = {{"leg-1", "leg 1 (type I)", "Leg 1's forearm normal to its elbow's motion"},
                       {"leg-2", "leg 2 (type I)", "Leg 2's forearm normal to its elbow's motion"},
                       {"leg-3", "leg 3 (type I)", "Leg 3's forearm normal to its elbow's motion"},
                       {"parallel", "parallel (type II)", "The three forearms coplanar: det Jx = 0"}};
    if (model_.has_cones())
      i.extra_fields.push_back({"joint_margin", "joint margin (deg)",
                                "How far the nearest ball joint is from its cone (< 0 beyond it; none where a leg "
                                "does not close)"});
    for (int b = 0; b < kBranchCount; ++b) {
      std::string name = std::to_string(b) + ": elbows ";
      for (int k = 0; k < kLegCount; ++k) name += (b >> k) & 1 ? "i" : "o";
      i.branches.push_back(name);
    }
  }

  const MechanismInfo& info() const override { return info_; }
  std::map<std::string, double> parameters() const override {
    return {{"R", model_.R}, {"r", model_.r}, {"La", model_.La}, {"Lb", model_.Lb}};
  }
  double size() const override { return model_.size(); }
  VectorXd home_task() const override { return home_position(model_); }
  VectorXd home_actuators() const override { return home_pose(model_); }

  // The closed form without a branch gives every branch's assembly, as a
  // described device does (the design's first); Newton the branch it reaches.
  linkscape::IkResult inverse(const VectorXd& x, const linkscape::IkOptions& o) const override {
    const IkMethod method = parse_ik_method(o.method.empty() ? "closed" : o.method);
    if (o.branch && (*o.branch < 0 || *o.branch >= kBranchCount))
      throw std::invalid_argument("delta: branch must be 0..7, got " + std::to_string(*o.branch));
    const Vector3d target = three(x, "x");
    if (o.branch || method != IkMethod::Closed) return solve_branch(target, method, o);
    linkscape::IkResult out;
    for (int b = 0; b < kBranchCount; ++b) {
      linkscape::IkOptions one = o;
      one.branch = b;
      const linkscape::IkResult r = solve_branch(target, method, one);
      if (b == 0 || (r.status == Status::Ok && out.status != Status::Ok)) {
        out.status = r.status;
        out.failing_part = r.failing_part;
        out.status_text = r.status_text;
      }
      out.solutions.insert(out.solutions.end(), r.solutions.begin(), r.solutions.end());
    }
    return out;
  }

  linkscape::FkResult forward(const VectorXd& q, const linkscape::FkOptions& o) const override {
    delta::FkOptions fo;
    if (o.seed) fo.seed = three(*o.seed, "seed");
    fo.tolerance = o.tolerance;
    fo.max_iterations = o.max_iterations;
    delta::FkResult r = delta::forward(model_, three(q, "q"), parse_fk_method(o.method.empty() ? "closed" : o.method), fo);
    // Of the closed form's two assembly modes, the one nearer the seed (the
    // window's last pose: no jump to the mirror image through the elbows).
    if (o.seed && r.method == FkMethod::Closed && (r.p_other_mode - *fo.seed).norm() < (r.p_base_platform - *fo.seed).norm())
      std::swap(r.p_base_platform, r.p_other_mode);
    linkscape::FkResult out;
    out.status = r.status;
    // A pose beyond a ball joint's cone is out of limits, as IK says of it.
    if (r.status == Status::Ok && !joint_stops(model_, three(q, "q"), r.p_base_platform).hold()) out.status = Status::OutOfLimits;
    out.x = r.p_base_platform;
    out.residual = r.residual;
    out.iterations = r.iterations;
    return out;
  }

  Eigen::MatrixXd jacobian(const VectorXd& q, const VectorXd& x) const override {
    return delta::jacobian(model_, three(q, "q"), three(x, "x")).J_task_from_actuated;
  }

  Measures measures(const VectorXd& q, const VectorXd& x) const override {
    const JacobianResult J = delta::jacobian(model_, three(q, "q"), three(x, "x"));
    Measures m;
    m.status = J.status == Status::Ok ? Status::Ok : Status::Singular;
    m.values = {J.cond};
    m.det = J.det_J;
    return m;
  }

  // With cones, at most the size times the nearest cone's margin (as an
  // actuator's range counts), so that its sign agrees with the status.
  double reach_margin(const VectorXd& x, int branch) const override {
    const double margin = delta::reach_margin(model_, three(x, "x"), branch).value;
    if (!model_.has_cones()) return margin;
    delta::IkOptions o;
    o.branch = branch;
    const delta::IkResult r = delta::inverse(model_, three(x, "x"), IkMethod::Closed, o);
    if (r.status == Status::Unreachable || r.status == Status::Singular) return margin;
    return std::min(margin, size() * joint_stops(model_, r.q_actuated, three(x, "x")).margin_deg * std::numbers::pi / 180);
  }

  linkscape::SingularityReport nearest_singularity(const VectorXd& q, const VectorXd& x) const override {
    const auto r = delta::nearest_singularity(model_, three(q, "q"), three(x, "x"));
    return {int(r.nearest), r.distance, {r.distances.begin(), r.distances.end()}};
  }

  // The sets are those of the geometry, so approaches ignore the actuator
  // ranges (they would cut the rays first). Leg k's serial set: along a ray
  // from home out past leg k, the last point a leg reaches (bisection on the
  // IK status); eps is the remaining fraction of the way. No sweep
  // approaches the parallel (type II) set yet: tests/core/mechanisms/delta
  // checks the statuses there.
  std::vector<SingularApproach> singular_approaches() const override {
    std::vector<SingularApproach> out;
    const Model m = without_ranges(model_);
    for (int set = 0; set < kLegCount; ++set) {
      out.push_back({set, [m, set](double eps, int k) -> VectorXd {
                       const Vector3d home = home_position(m);
                       const double tilt = 0.2 * k;
                       Vector3d dir(leg_radial(set).x(), leg_radial(set).y(), -tilt);
                       dir.normalize();
                       double lo = 0, hi = 2 * m.size();
                       for (int it = 0; it < 80; ++it) {
                         const double mid = 0.5 * (lo + hi);
                         (delta::inverse(m, home + mid * dir).status != Status::Unreachable ? lo : hi) = mid;
                       }
                       return home + lo * (1 - eps) * dir;
                     }});
    }
    return out;
  }

  // Sweeps towards the geometry's singular sets, on the linkage without
  // actuator ranges or cones (the default sweeps of core/generic_methods.cpp).
  std::vector<stability::SweepRow> stability_sweeps(const stability::SweepOptions& options) const override {
    return make_mechanism(without_ranges(model_))->Mechanism::stability_sweeps(options);
  }

  // The nearest ball joint to its cone, read out as the described Delta reads it.
  std::vector<std::pair<std::string, std::string>> readouts(const VectorXd& q, const VectorXd& x) const override {
    if (!model_.has_cones()) return {};
    const JointStops st = joint_stops(model_, three(q, "q"), three(x, "x"));
    if (st.leg < 0) return {};
    std::ostringstream margin;
    margin.precision(3);
    margin << st.margin_deg << "° (leg " << st.leg + 1 << " ball joint " << (st.joint == 0 ? "elbow" : "wrist")
           << st.leg + 1 << ")";
    std::vector<std::pair<std::string, std::string>> out{{"joint margin", margin.str()}};
    if (!st.hold()) out.push_back({"stops", stop_reason(st)});
    return out;
  }

  SkeletonModel skeleton_model() const override {
    SkeletonModel sk;
    const auto shapes = body_shapes(model_);
    for (int b = 0; b < kBodyCount; ++b) sk.bodies.push_back({shapes[b].name, shapes[b].polylines, {}, b == 0});
    for (const JointDefinition& d : joint_definitions(model_)) {
      linkscape::Joint j;
      j.name = d.name;
      j.type = d.type == delta::JointType::Revolute ? linkscape::JointType::Revolute : linkscape::JointType::Spherical;
      j.body = d.body_a;
      j.p_body_joint = d.point_in_a;
      j.axis_body_joint = d.axis_in_a;
      j.actuated = d.name.rfind("motor", 0) == 0;
      if (j.actuated) j.label = std::string(1, 'q') + d.name.back();  // "q1" from "motor1"
      sk.joints.push_back(std::move(j));
    }
    sk.scale = model_.La;
    return sk;
  }

  SkeletonPose skeleton_pose(const VectorXd& q, const VectorXd& x, const linkscape::IkResult* failed) const override {
    const Skeleton s = skeleton(model_, three(q, "q"), three(x, "x"));
    SkeletonPose p;
    p.X_world_body.assign(s.X_world_body.begin(), s.X_world_body.end());
    p.states.assign(kBodyCount, BodyState::Normal);
    if (failed && !failed->failing_part.empty()) {
      const int leg = std::stoi(failed->failing_part) - 1;
      if (leg >= 0 && leg < kLegCount) p.states[1 + leg] = p.states[4 + leg] = BodyState::Failing;
    }
    p.p_world_endpoint = s.p_base_platform;
    return p;
  }

  Eigen::AlignedBox3d default_box() const override {
    // The workspace lies within 0.6 size of the z axis and between 1.0
    // size below and 0.35 size above the base (La + Lb bounds every leg).
    const double s = model_.size();
    return {Vector3d(-0.7 * s, -0.7 * s, -1.1 * s), Vector3d(0.7 * s, 0.7 * s, 0.4 * s)};
  }
  // The x-z plane through the pose: it contains leg 1 and the z axis.
  std::pair<Axis, double> default_slice_plane(const VectorXd& x) const override { return {Axis::Y, x(1)}; }

  std::optional<Field> compute_field(const Grid& grid, const VectorXd&, const linkscape::IkOptions& o, int threads,
                                     const FieldProgress& progress) const override {
    FieldRequest request;
    request.grid = grid;
    request.method = parse_ik_method(o.method.empty() ? "closed" : o.method);
    request.ik.branch = o.branch.value_or(0);
    request.ik.tolerance = o.tolerance;
    request.ik.max_iterations = o.max_iterations;
    request.threads = threads;
    std::optional<Field> f = delta::compute_field(model_, request, progress);
    if (f) {
      f->parameters = parameters();
      f->measure_titles = {info_.measures.front().title};
    }
    return f;
  }

 private:
  // One branch (o.branch, else 0) by the closed form, or Newton from its seed.
  linkscape::IkResult solve_branch(const Vector3d& target, IkMethod method, const linkscape::IkOptions& o) const {
    delta::IkOptions io;
    io.branch = o.branch.value_or(0);
    if (o.seed) io.seed = three(*o.seed, "seed");
    io.tolerance = o.tolerance;
    io.max_iterations = o.max_iterations;
    delta::IkResult r = delta::inverse(model_, target, method, io);
    linkscape::IkResult out;
    // A ball joint beyond its cone: out of limits, the leg and joint named.
    int stopped_leg = -1;
    if (r.status == Status::Ok) {
      const JointStops st = joint_stops(model_, r.q_actuated, target);
      if (!st.hold()) {
        r.status = Status::OutOfLimits;
        stopped_leg = st.leg;
        out.status_text = "out-of-limits: " + stop_reason(st);
      }
    }
    // Each leg is regular at a type II singularity, but J is singular there:
    // singular wherever measures() says so.
    if (r.status == Status::Ok && delta::jacobian(model_, r.q_actuated, target).status != Status::Ok)
      r.status = Status::Singular;
    out.status = r.status;
    if (stopped_leg >= 0) out.failing_part = std::to_string(stopped_leg + 1);
    for (int k = 0; k < kLegCount; ++k)
      if (r.leg_status[k] != Status::Ok && out.failing_part.empty()) out.failing_part = std::to_string(k + 1);
    // Newton reports the branch it reached; a requested branch is kept only if met.
    if (r.status == Status::Unreachable) return out;
    if (o.branch && r.branch != *o.branch) {
      out.status = Status::NotConverged;
      return out;
    }
    out.solutions.push_back({r.q_actuated, r.branch, r.status, r.residual, r.iterations, std::string(to_string(r.method)), {}});
    return out;
  }
  Model model_;
  MechanismInfo info_;
};

}  // namespace

std::shared_ptr<const Mechanism> make_mechanism(const Model& model) { return std::make_shared<DeltaMechanism>(model); }

std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset) { return make_mechanism(make_delta_model(preset)); }

Model make_delta_model(const Preset& preset) {
  require_parameters(preset, {"R", "r", "La", "Lb"});
  std::map<std::string, Interval> limits;
  for (const auto& [name, range] : preset.limits_deg) limits[name] = {range.lo, range.hi};
  Model m = Model::from_parameters(preset.parameters, limits, preset.length_unit);
  // "stops": the forearm's ball-joint cones (stops.h), degrees; off, none.
  constexpr double deg = std::numbers::pi / 180;
  for (const auto& [key, v] : stops_numbers(preset, {"elbow_axis_deg", "elbow_cone_deg", "wrist_axis_deg", "wrist_cone_deg"})) {
    const bool cone = key.ends_with("cone_deg");
    if (cone ? !(v > 0 && v < 180) : !std::isfinite(v)) {
      std::ostringstream msg;
      msg << "stops." << key << (cone ? " must be in (0, 180) deg" : " must be a finite angle (deg)") << ", got " << v;
      throw std::invalid_argument(msg.str());
    }
    (key == "elbow_axis_deg" ? m.elbow_axis : key == "elbow_cone_deg" ? m.elbow_cone : key == "wrist_axis_deg" ? m.wrist_axis : m.wrist_cone) = v * deg;
  }
  if (!preset.checks.joint_limits) m.elbow_cone = m.wrist_cone = std::numbers::pi;
  m.validate();
  return m;
}

}  // namespace linkscape::delta
