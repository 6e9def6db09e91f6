#include "core/mechanisms/parallel12r/mechanism.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/mechanisms/parallel12r/field.h"
#include "core/mechanisms/parallel12r/methods.h"
#include "core/mechanisms/parallel12r/stability.h"
#include "core/preset.h"

namespace linkscape::parallel12r {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;
constexpr double kPi = std::numbers::pi;

Vector3d three(const VectorXd& v, const char* what) {
  if (v.size() != 3) throw std::invalid_argument(std::string("parallel-12r: ") + what + " needs 3 values");
  return v.head<3>();
}

// Singular sets in the order of SingularSet, and the sweep that approaches each.
constexpr stability::SweepPath kApproach[] = {stability::SweepPath::CosAlpha, stability::SweepPath::BetaGamma,
                                              stability::SweepPath::BetaGammaPi, stability::SweepPath::ZAxis};

class Parallel12rMechanism final : public Mechanism {
 public:
  explicit Parallel12rMechanism(const Model& model) : model_(model) {
    model_.validate();
    const std::string u = model_.length_unit;
    const double R = model_.reach();
    MechanismInfo& i = info_;
    i.name = std::string(kMechanismName);
    i.title = "10-link 12R parallel hand controller";
    i.length_unit = u;
    i.size_description = "L1 + L2";
    i.parameters = {{"L1", u, "Link along u(alpha, beta) (Eqs. 11-13)", model_.L1, {0.1 * model_.L1, 3 * model_.L1}},
                    {"L2", u, "Link along u(alpha, gamma)", model_.L2, {0.1 * model_.L2, 3 * model_.L2}}};
    const Vector3d home = home_pose(0);
    i.actuators = {{"alpha", "rad", "Actuator A about the z axis", home.x(), {model_.alpha_limits.lo, model_.alpha_limits.hi}},
                   {"beta", "rad", "Actuator B about the x axis", home.y(), {model_.beta_limits.lo, model_.beta_limits.hi}},
                   {"gamma", "rad", "Actuator C about the x axis", home.z(), {model_.gamma_limits.lo, model_.gamma_limits.hi}}};
    const Vector3d d = parallel12r::forward(model_, home);
    i.task = {{"x", u, "Endpoint D, base frame", d.x(), {-R, R}},
              {"y", u, "", d.y(), {-R, R}},
              {"z", u, "", d.z(), {-R, R}}};
    i.ik_methods = {{"planar", "planar", "Planar two-link reduction in the plane normal to n(alpha)"},
                    {"paper", "paper", "The paper's Eqs. 14-16, corrected"},
                    {"newton", "newton", "Newton-Raphson with backtracking from a seed"},
                    {"dls", "dls", "Damped least squares (Levenberg-Marquardt) from a seed"},
                    {"fallback", "fallback", "Planar; where it misses the tolerance, Newton from its candidate"}};
    i.seeded_ik_methods = {"newton", "dls"};
    i.fk_methods = {{"closed", "closed form", "Eqs. 11-13"}};
    i.measures = {{"cond", "c(J)", "sigma_max / sigma_min of the 3x3 Jacobian"}};
    i.singular_sets = {{"actuator-plane", "actuator plane", "cos(alpha) = 0: endpoint in the x-z plane"},
                       {"stretched", "stretched", "beta = gamma: outer reach sphere |D| = L1 + L2"},
                       {"folded", "folded", "beta = gamma +- pi: inner sphere |D| = |L1 - L2|"},
                       {"z-axis", "z axis", "x = y = 0"}};
    i.branches = {"0: sin(beta - gamma) > 0", "1: sin(beta - gamma) < 0"};
    i.eval_columns.fk_diagnostics = false;  // a closed form: no iterations
  }

  const MechanismInfo& info() const override { return info_; }
  std::map<std::string, double> parameters() const override { return {{"L1", model_.L1}, {"L2", model_.L2}}; }
  double size() const override { return model_.reach(); }
  VectorXd home_task() const override { return parallel12r::forward(model_, home_pose(0)); }
  VectorXd home_actuators() const override { return home_pose(0); }

  linkscape::IkResult inverse(const VectorXd& x, const linkscape::IkOptions& o) const override {
    const Vector3d target = three(x, "x");
    parallel12r::IkOptions ik;
    if (o.seed) ik.seed = three(*o.seed, "seed");
    ik.tolerance = o.tolerance;
    ik.max_iterations = o.max_iterations;
    const IkMethod method = parse_ik_method(o.method.empty() ? "planar" : o.method);
    const parallel12r::IkResult r = parallel12r::inverse(model_, target, method, ik);
    linkscape::IkResult out;
    out.status = r.status;
    bool any_ok = false, demoted = false;
    for (const auto& s : r.solutions) {
      if (o.branch && s.branch != *o.branch) continue;
      // Singular wherever measures() reports J singular.
      const Status status = s.status == Status::Ok && singular_at(s.q_actuated) ? Status::Singular : s.status;
      any_ok = any_ok || status == Status::Ok;
      demoted = demoted || status != s.status;
      out.solutions.push_back(linkscape::IkSolution{s.q_actuated, s.branch, status, s.residual, s.iterations, std::string(to_string(s.method)), {}});
    }
    if (out.status == Status::Ok && !any_ok && demoted) out.status = Status::Singular;
    return out;
  }

  linkscape::FkResult forward(const VectorXd& q, const linkscape::FkOptions& o) const override {
    if (!o.method.empty() && o.method != "closed")
      throw std::invalid_argument("parallel-12r: unknown FK method '" + o.method + "' (known: closed)");
    linkscape::FkResult r;
    r.x = parallel12r::forward(model_, three(q, "q"));
    // As the Delta's: beyond an actuator's travel out of limits (no pose
    // given), else singular where measures() says so.
    const Vector3d a = three(q, "q");
    r.status = !model_.within_limits(a) ? Status::OutOfLimits : singular_at(a) ? Status::Singular : Status::Ok;
    return r;
  }

  Eigen::MatrixXd jacobian(const VectorXd& q, const VectorXd&) const override {
    return parallel12r::jacobian(model_, three(q, "q"));
  }

  Measures measures(const VectorXd& q, const VectorXd&) const override {
    const Conditioning c = conditioning(model_, three(q, "q"));
    Measures m;
    m.values = {c.cond};
    m.det = c.det;
    m.status = std::isfinite(c.cond) ? Status::Ok : Status::Singular;
    return m;
  }
  // Where measures() reports J singular (c(J) beyond what double resolves).
  bool singular_at(const Vector3d& q) const { return !std::isfinite(conditioning(model_, q).cond); }

  double reach_margin(const VectorXd& x, int branch) const override {
    linkscape::FieldRequest request;
    request.branch = branch;
    return sample_point(model_, three(x, "x"), request).reach_margin;
  }

  linkscape::SingularityReport nearest_singularity(const VectorXd& q, const VectorXd&) const override {
    const auto r = parallel12r::nearest_singularity(model_, three(q, "q"));
    return {int(r.nearest), r.distance, {r.distances.begin(), r.distances.end()}};
  }

  std::vector<SingularApproach> singular_approaches() const override {
    std::vector<SingularApproach> out;
    for (int set = 0; set < 4; ++set) {
      const Model m = model_;
      const stability::SweepPath path = kApproach[set];
      out.push_back({set, [m, path](double eps, int k) -> VectorXd {
                       return stability::sweep_point(m, path, eps, k, 7).target;
                     }});
    }
    return out;
  }

  SkeletonModel skeleton_model() const override {
    SkeletonModel sk;
    const auto shapes = link_shapes(model_);
    for (int k = 0; k < kLinkCount; ++k) {
      Body b;
      b.name = "link " + std::to_string(k + 1);
      b.polylines = shapes[k].polylines;
      b.ground = k == 0;
      sk.bodies.push_back(std::move(b));
    }
    for (const JointDefinition& d : joint_definitions(model_)) {
      linkscape::Joint j;
      j.name = d.name;
      j.type = JointType::Revolute;
      j.body = d.link_a - 1;
      j.p_body_joint = d.point_in_a;
      j.axis_body_joint = d.axis_in_a;
      j.actuated = d.name == "A" || d.name == "B" || d.name == "C";
      if (j.actuated) j.label = d.name;
      sk.joints.push_back(std::move(j));
    }
    sk.scale = std::min(model_.L1, model_.L2);
    return sk;
  }

  SkeletonPose skeleton_pose(const VectorXd& q, const VectorXd&, const linkscape::IkResult*) const override {
    const Skeleton s = parallel12r::skeleton(model_, three(q, "q"));
    SkeletonPose p;
    p.X_world_body.assign(s.link_frames.begin(), s.link_frames.end());
    p.states.assign(kLinkCount, BodyState::Normal);
    p.p_world_endpoint = s.endpoint;
    return p;
  }

  Eigen::AlignedBox3d default_box() const override {
    const double r = model_.reach();
    return {Vector3d::Constant(-r), Vector3d::Constant(r)};
  }

  // x = 0.25 for L1 = L2 = 1, as in the paper's Fig. 5.
  std::pair<Axis, double> default_slice_plane(const VectorXd&) const override {
    return {Axis::X, 0.125 * model_.reach()};
  }

  std::optional<Field> compute_field(const Grid& grid, const VectorXd&, const linkscape::IkOptions& o, int threads,
                                     const FieldProgress& progress) const override {
    linkscape::FieldRequest request;
    request.grid = grid;
    request.method = parse_ik_method(o.method.empty() ? "planar" : o.method);
    request.branch = o.branch.value_or(0);
    request.ik.tolerance = o.tolerance;
    request.ik.max_iterations = o.max_iterations;
    request.threads = threads;
    return linkscape::compute_field(model_, request, progress);
  }

  // The shell between the spheres |L1 - L2| and L1 + L2, when the actuator
  // ranges do not cut it.
  std::optional<double> analytic_reach_volume() const override {
    const Model full;
    const Model& m = model_;
    const bool full_ranges = m.alpha_limits.lo <= full.alpha_limits.lo && m.alpha_limits.hi >= full.alpha_limits.hi &&
                             m.beta_limits.lo <= full.beta_limits.lo && m.beta_limits.hi >= full.beta_limits.hi &&
                             m.gamma_limits.lo <= full.gamma_limits.lo && m.gamma_limits.hi >= full.gamma_limits.hi;
    if (!full_ranges) return std::nullopt;
    const double R = m.reach(), r = m.inner_reach();
    return 4.0 / 3.0 * kPi * (R * R * R - r * r * r);
  }

  std::vector<methods::MethodRow> measure_methods(const methods::HarnessOptions& options) const override {
    return methods::run_method_harness(model_, options);
  }
  std::vector<stability::SweepRow> stability_sweeps(const stability::SweepOptions& options) const override {
    return stability::run_stability_sweeps(model_, options);
  }

  const Model& model() const { return model_; }

 private:
  Model model_;
  MechanismInfo info_;
};

}  // namespace

std::shared_ptr<const Mechanism> make_mechanism(const Model& model) {
  return std::make_shared<Parallel12rMechanism>(model);
}

std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset) { return make_mechanism(make_parallel12r(preset)); }

}  // namespace linkscape::parallel12r

namespace linkscape {

parallel12r::Model make_parallel12r(const Preset& preset) {
  if (preset.mechanism != parallel12r::kMechanismName)
    throw std::invalid_argument("expected a parallel-12r preset, got '" + preset.mechanism + "'");
  require_parameters(preset, {"L1", "L2"});
  std::map<std::string, parallel12r::Interval> limits_deg;
  for (const auto& [name, range] : preset.limits_deg) limits_deg[name] = {range.lo, range.hi};
  return parallel12r::Model::from_parameters(preset.parameters, limits_deg, preset.length_unit);
}

}  // namespace linkscape
