#include "core/mechanisms/pathos2/mechanism.h"

#include <Eigen/SVD>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "core/mechanisms/pathos2/field.h"
#include "core/mechanisms/pathos2/methods.h"
#include "core/mechanisms/pathos2/stability.h"
#include "core/mechanisms/pathos2/stops.h"
#include "core/preset.h"

namespace linkscape::pathos2 {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Eigen::VectorXd;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
// The stops' arrays, as fields and the device's info describe them (stops.h).
constexpr const char* kJointMarginText =
    "How far the nearest limited joint (globular cone, R2, R3) is from its limit (< 0 beyond it, none where a leg "
    "does not close)";
constexpr const char* kClearanceText =
    "The smallest gap between the capsules of two legs' links or of a link and the grip (< 0 where they overlap, "
    "none where a leg does not close)";

Pose pose_of(const VectorXd& x) {
  if (x.size() != 7) throw std::invalid_argument("pathos2: the task needs x, y, z, rx, ry, rz, h0");
  return Pose::from_xyz_rpy(x(0), x(1), x(2), x(3), x(4), x(5), x(6));
}

VectorXd task_of(const Pose& p) {
  VectorXd x(7);
  const Vector3d rpy = p.rpy();
  x << p.p_world_E, rpy, p.h0;
  return x;
}

Vector6d actuators_of(const VectorXd& q) {
  if (q.size() != 6) throw std::invalid_argument("pathos2: the actuators are q1..q6");
  return q.head<6>();
}

// Bodies: the two base plates (ground), per leg its three links, the two top plates.
int link_body(int leg, int link) { return 1 + 3 * leg + link; }
constexpr int kLowerPlate = 1 + 3 * kLegCount, kUpperPlate = kLowerPlate + 1;

class Pathos2Mechanism final : public Mechanism {
 public:
  explicit Pathos2Mechanism(const Model& model) : geometry_(make_geometry(model)) {
    const Model& m = geometry_.model;
    MechanismInfo& i = info_;
    i.name = std::string(kMechanismName);
    i.title = "PATHOS-II 7-DOF parallel haptic device";
    i.length_unit = "cm";
    i.size_description = "l2 + l3";
    auto length = [](const char* n, const char* d, double v) { return Quantity{n, "cm", d, v, {0.5 * v, 1.5 * v}}; };
    i.parameters = {length("l0", "Distance between the base plates", m.l0),
                    length("l2", "Second link, R2 to R3", m.l2),
                    length("l3", "Third link, R3 to the globular centre", m.l3),
                    {"lp", "cm", "Radius of the globular centres on the top plates", m.lp, {0.0, 6.0}},
                    {"theta_t", "deg", "Tilt of the R1 axes from the plate normal", m.theta_t / kDeg, {0.0, 60.0}},
                    {"db", "cm", "Height of R1 above its plate", m.db, {0.0, 2 * m.db + 1}}};
    // The rest of the model's parameters: preset and --param only.
    for (const auto& [name, value] : m.to_parameters()) {
      bool listed = false;
      for (const Quantity& q : i.parameters) listed = listed || q.name == name;
      if (!listed) i.parameters.push_back({name, "", "", value, {value, value}, false});
    }
    const Pose home = home_pose(m);
    const PoseIkResult ik = pathos2::inverse(geometry_, home);
    for (int k = 0; k < kLegCount; ++k)
      i.actuators.push_back({"q" + std::to_string(k + 1), "rad", "Active joint R1 of leg " + std::to_string(k + 1),
                             ik.q_active(k), {-kPi, kPi}});
    const Vector3d c = home.p_world_E, rpy = home.rpy();
    const double reach = m.l2 + m.l3;
    i.task = {{"x", "cm", "Platform centre E, world frame", c.x(), {c.x() - reach, c.x() + reach}},
              {"y", "cm", "", c.y(), {c.y() - reach, c.y() + reach}},
              {"z", "cm", "", c.z(), {c.z() - reach, c.z() + reach}},
              {"rx", "rad", "Rotation about x (R = Rz Ry Rx)", rpy.x(), {-0.6, 0.6}},
              {"ry", "rad", "Rotation about y", rpy.y(), {-0.6, 0.6}},
              {"rz", "rad", "Rotation about z", rpy.z(), {rpy.z() - 0.8, rpy.z() + 0.8}},
              {"h0", "cm", "Grip: half the distance between the top plates", home.h0, {0.3 * home.h0, 1.5 * home.h0}}};
    i.ik_methods = {{"closed", "closed form", "Closed-form leg IK (Eqs. 8-14, corrected)"}};
    i.fk_methods = {{"newton", "numerical", "Damped Newton on the pose from a seed"}};
    i.measures = {{"cond_jp", "cond(Jp)", "Condition number of the translational 3x6 block"},
                  {"cond_jo", "cond(Jo)", "Condition number of the rotational 3x6 block"}};
    i.singular_sets = {{"leg-line", "leg in line", "sin t3 = 0: links 2 and 3 stretched or folded"},
                       {"leg-elbow", "leg elbow", "sin t2 = 0"},
                       {"actuation", "actuation", "the 6x6 Jacobian is singular"}};
    i.branches = {"preset (branch_1..branch_6)"};
    i.fk_inputs = {"h0"};
    i.eval_columns = {false, "failing_leg", false, false, true, false, true};
    if (has_joint_limits(m)) i.extra_fields.push_back({"joint_margin", "joint margin (deg)", kJointMarginText});
    if (has_capsules(m)) i.extra_fields.push_back({"clearance", "clearance (cm)", kClearanceText});
  }

  const MechanismInfo& info() const override { return info_; }
  std::map<std::string, double> parameters() const override { return geometry_.model.to_parameters(); }
  double size() const override { return geometry_.model.l2 + geometry_.model.l3; }
  VectorXd home_task() const override { return task_of(home_pose(geometry_.model)); }
  VectorXd home_actuators() const override { return pathos2::inverse(geometry_, home_pose(geometry_.model)).q_active; }

  linkscape::IkResult inverse(const VectorXd& x, const linkscape::IkOptions& o) const override {
    if (!o.method.empty() && o.method != "closed")
      throw std::invalid_argument("pathos2: unknown IK method '" + o.method + "' (known: closed)");
    if (o.branch && *o.branch != 0) throw std::invalid_argument("pathos2 has one branch (its legs' are in the preset)");
    if (x.size() != 7) throw std::invalid_argument("pathos2: the task needs x, y, z, rx, ry, rz, h0");
    if (!x.allFinite()) throw std::invalid_argument("pathos2: the pose must be finite numbers");
    linkscape::IkResult out;
    if (!(x(6) > 0)) {
      out.status = Status::Unreachable;
      out.status_text = "invalid-grip";
      return out;
    }
    const Pose pose = pose_of(x);
    PoseIkResult ik = pathos2::inverse(geometry_, pose);
    if (const std::optional<Stops> st = stopped(pose, ik)) {
      ik.status = Status::OutOfLimits;
      ik.failing_leg = st->leg_at_fault();
      out.status_text = "out-of-limits: " + stop_reason(*st);
    }
    // Where the 6x6 J is singular (its condition past kMaxJacobianCondition),
    // as measures() says: the legs close, the device does not hold the pose.
    if (ik.status == Status::Ok && pathos2::jacobian(geometry_, pose, ik).status == Status::Singular)
      ik.status = Status::Singular;
    out.status = ik.status;
    if (ik.failing_leg >= 0) out.failing_part = std::to_string(ik.failing_leg + 1);
    if (ik.status == Status::Ok || ik.status == Status::Singular)
      out.solutions.push_back(linkscape::IkSolution{ik.q_active, 0, ik.status, 0.0, 0, "closed", {}});
    return out;
  }

  linkscape::FkResult forward(const VectorXd& q, const linkscape::FkOptions& o) const override {
    if (!o.method.empty() && o.method != "newton")
      throw std::invalid_argument("pathos2: unknown FK method '" + o.method + "' (known: newton)");
    const Vector6d qa = actuators_of(q);
    const VectorXd seed_x = o.seed ? *o.seed : home_task();
    linkscape::FkResult r;
    if (seed_x.size() != 7) throw std::invalid_argument("pathos2: the FK seed needs x, y, z, rx, ry, rz, h0");
    if (!qa.allFinite()) throw std::invalid_argument("pathos2: the actuator values must be finite numbers");
    const double h0 = seed_x(6);
    if (!(h0 > 0)) {
      r.status = Status::Unreachable;
      r.status_text = "invalid-input";
      return r;
    }
    pathos2::FkOptions fo;
    fo.max_iterations = std::max(o.max_iterations, 1);
    fo.tolerance = o.tolerance;
    const pathos2::FkResult fk = forward_numeric(geometry_, qa, h0, pose_of(seed_x), fo);
    r.status = fk.status;
    // A pose beyond a stop is out of limits, as IK says of it.
    if (fk.status == Status::Ok && stopped(fk.pose, pathos2::inverse(geometry_, fk.pose))) r.status = Status::OutOfLimits;
    r.x = task_of(fk.pose);
    r.residual = fk.residual;
    r.iterations = fk.iterations;
    return r;
  }

  Eigen::MatrixXd jacobian(const VectorXd&, const VectorXd& x) const override {
    const Pose pose = pose_of(x);
    return pathos2::jacobian(geometry_, pose, pathos2::inverse(geometry_, pose)).J_twist_from_qdot;
  }

  Measures measures(const VectorXd&, const VectorXd& x) const override {
    const Pose pose = pose_of(x);
    const PoseIkResult ik = pathos2::inverse(geometry_, pose);
    const JacobianResult J = pathos2::jacobian(geometry_, pose, ik);
    Measures m;
    m.status = J.status;
    m.values = {J.cond_p, J.cond_o};
    // Of the 6x6 twist-from-rates map (cm^3 rad^3 per rad^6); 0 where singular.
    m.det = J.status == Status::Ok ? J.J_twist_from_qdot.determinant() : 0.0;
    return m;
  }

  // At most the clearance, so that its sign agrees with the status.
  double reach_margin(const VectorXd& x, int) const override {
    const Pose pose = pose_of(x);
    const PoseIkResult ik = pathos2::inverse(geometry_, pose);
    const double margin = pathos2::reach_margin(geometry_, ik);
    return assembles(ik) && has_capsules(geometry_.model) ? std::min(margin, stops(geometry_, pose, ik).clearance) : margin;
  }

  // Distance-like measures (cm): per leg l3 |sin t3| and l2 |sin t2| (the
  // lever arms that vanish there), the smallest over the legs; the actuation
  // singularity as size / cond of the 6x6 J (0 when singular).
  linkscape::SingularityReport nearest_singularity(const VectorXd&, const VectorXd& x) const override {
    const Model& m = geometry_.model;
    const Pose pose = pose_of(x);
    const PoseIkResult ik = pathos2::inverse(geometry_, pose);
    linkscape::SingularityReport r;
    r.distances = {INFINITY, INFINITY, 0.0};
    for (const LegSolution& leg : ik.legs) {
      r.distances[0] = std::min(r.distances[0], m.l3 * std::abs(std::sin(leg.t3)));
      r.distances[1] = std::min(r.distances[1], m.l2 * std::abs(leg.sin_t2));
    }
    if (ik.status == Status::Ok) {
      const JacobianResult J = pathos2::jacobian(geometry_, pose, ik);
      const Eigen::JacobiSVD<Matrix6d> svd(J.J_qdot_from_twist);
      const auto s = svd.singularValues();
      r.distances[2] = s(0) > 0 ? size() * s(5) / s(0) : 0.0;
    }
    for (int k = 1; k < 3; ++k)
      if (r.distances[k] < r.distances[r.nearest]) r.nearest = k;
    r.distance = r.distances[r.nearest];
    return r;
  }

  std::vector<SingularApproach> singular_approaches() const override {
    // From the home pose along a seeded direction of (x, y, z, rx, ry, rz)
    // towards the first pose no leg can reach, as the sweeps do.
    const Pose home = home_pose(geometry_.model);
    const Geometry g = geometry_;
    return {{0, [g, home](double eps, int k) -> VectorXd {
               Vector6d dir;
               for (int j = 0; j < 6; ++j) dir(j) = std::sin(12.9898 * (j + 1) + 78.233 * (k + 1));
               dir.normalize();
               const Vector6d step = dir.cwiseProduct((Vector6d() << 1, 1, 1, 0.1, 0.1, 0.1).finished());
               double lo = 0, hi = 1;
               while (pathos2::inverse(g, step_pose(home, hi * step), IkDetail::ActiveOnly).status == Status::Ok && hi < 1e3)
                 hi *= 2;
               for (int it = 0; it < 60; ++it) {
                 const double mid = 0.5 * (lo + hi);
                 (pathos2::inverse(g, step_pose(home, mid * step), IkDetail::ActiveOnly).status == Status::Ok ? lo : hi) = mid;
               }
               return task_of(step_pose(home, lo * (1 - eps) * step));
             }}};
  }

  std::vector<std::pair<std::string, std::string>> readouts(const VectorXd&, const VectorXd& x) const override {
    const Pose pose = pose_of(x);
    const PoseIkResult ik = pathos2::inverse(geometry_, pose);
    if (ik.status != Status::Ok) return {};
    const pathos2::FkResult nine = forward_nine_sensors(geometry_, sensors_of(ik));
    std::ostringstream text;
    text.precision(3);
    if (nine.status == Status::Ok)
      text << "agrees to " << std::scientific << (nine.pose.p_world_E - pose.p_world_E).norm() << " cm";
    else
      text << to_string(nine.status);
    std::vector<std::pair<std::string, std::string>> out{{"Nine-sensor FK", text.str()}};
    const Stops st = stops(geometry_, pose, ik);
    std::ostringstream margin;
    margin.precision(3);
    if (st.joint_leg >= 0)
      margin << st.joint_margin_deg << "° (leg " << st.joint_leg + 1 << (st.joint == 0 ? " globular joint)" : st.joint == 1 ? " R2)" : " R3)");
    if (st.joint_leg >= 0) out.push_back({"joint margin", margin.str()});
    std::ostringstream gap;
    gap.precision(3);
    if (st.pair[0] >= 0) gap << st.clearance << " cm (" << capsule_name(st.pair[0]) << " to " << capsule_name(st.pair[1]) << ")";
    if (st.pair[0] >= 0) out.push_back({"clearance", gap.str()});
    return out;
  }

  SkeletonModel skeleton_model() const override {
    const Model& m = geometry_.model;
    SkeletonModel sk;
    Body bases{"base plates", {}, {}, true};
    for (int plate = 0; plate < 2; ++plate) {
      std::vector<Vector3d> ring;
      for (int k = 0; k < 3; ++k) ring.push_back(geometry_.p_world_B[3 * plate + k]);
      bases.faces.push_back(ring);
      ring.push_back(ring.front());
      bases.polylines.push_back(ring);
    }
    sk.bodies.push_back(bases);
    const double lengths[] = {m.l1, m.l2, m.l3};
    for (int leg = 0; leg < kLegCount; ++leg)
      for (int link = 0; link < 3; ++link)
        sk.bodies.push_back({"leg " + std::to_string(leg + 1) + " link " + std::to_string(link + 1),
                             {{Vector3d::Zero(), Vector3d(0, 0, lengths[link])}}, {}, false});
    for (int plate = 0; plate < 2; ++plate) {
      std::vector<Vector3d> tri;
      for (int k = 0; k < 3; ++k) tri.push_back(geometry_.p_E_attach_plate[3 * plate + k]);
      Body b{plate == 0 ? "lower top plate" : "upper top plate", {}, {tri}, false};
      tri.push_back(tri.front());
      b.polylines.push_back(tri);
      sk.bodies.push_back(b);
    }
    // Joints in their link's frame: R1 (actuated) about z, R2 about y, R3
    // about x, the globular joint at the end of link 3.
    for (int leg = 0; leg < kLegCount; ++leg) {
      const std::string n = std::to_string(leg + 1);
      sk.joints.push_back({"R1 of leg " + n, JointType::Revolute, link_body(leg, 0), Vector3d::Zero(), Vector3d::UnitZ(), true, n});
      sk.joints.push_back({"R2 of leg " + n, JointType::Revolute, link_body(leg, 1), Vector3d::Zero(), Vector3d::UnitY(), false, ""});
      sk.joints.push_back({"R3 of leg " + n, JointType::Revolute, link_body(leg, 2), Vector3d::Zero(), Vector3d::UnitX(), false, ""});
      sk.joints.push_back({"globular of leg " + n, JointType::Spherical, link_body(leg, 2), Vector3d(0, 0, m.l3),
                           Vector3d::UnitZ(), false, ""});
    }
    sk.scale = 0.35 * (m.l2 + m.l3);
    return sk;
  }

  SkeletonPose skeleton_pose(const VectorXd&, const VectorXd& x, const linkscape::IkResult* failed) const override {
    const Pose pose = pose_of(x);
    const PoseIkResult ik = pathos2::inverse(geometry_, pose);
    if (ik.status != Status::Ok && ik.status != Status::OutOfLimits)
      throw std::invalid_argument("pathos2: cannot draw a pose leg " + std::to_string(ik.failing_leg + 1) +
                                  " cannot reach (" + std::string(to_string(ik.status)) + ")");
    const Model& m = geometry_.model;
    SkeletonPose p;
    p.X_world_body.assign(kUpperPlate + 1, Eigen::Isometry3d::Identity());
    p.states.assign(kUpperPlate + 1, BodyState::Normal);
    for (int leg = 0; leg < kLegCount; ++leg) {
      const LegSolution& s = ik.legs[leg];
      const Matrix3d R1 = geometry_.R_world_B[leg] * Eigen::AngleAxisd(s.t1, Vector3d::UnitZ()).toRotationMatrix();
      const Matrix3d R2 = R1 * Eigen::AngleAxisd(s.t2, Vector3d::UnitY()).toRotationMatrix();
      const Matrix3d R3 = R2 * Eigen::AngleAxisd(s.t3, Vector3d::UnitX()).toRotationMatrix();
      const Vector3d r1 = geometry_.p_world_B[leg], r2 = r1 + m.l1 * R1.col(2), r3 = r2 + m.l2 * R2.col(2);
      const Matrix3d Rs[] = {R1, R2, R3};
      const Vector3d ps[] = {r1, r2, r3};
      for (int link = 0; link < 3; ++link) {
        Eigen::Isometry3d& f = p.X_world_body[link_body(leg, link)];
        f.linear() = Rs[link];
        f.translation() = ps[link];
      }
    }
    for (int plate = 0; plate < 2; ++plate) {
      Eigen::Isometry3d& f = p.X_world_body[plate == 0 ? kLowerPlate : kUpperPlate];
      f.linear() = pose.R_world_E;
      f.translation() = pose.p_world_E + pose.R_world_E * Vector3d(0, 0, (plate == 0 ? -1.0 : 1.0) * pose.h0);
    }
    if (failed && !failed->failing_part.empty()) {
      const int leg = std::stoi(failed->failing_part) - 1;
      if (leg >= 0 && leg < kLegCount)
        for (int link = 0; link < 3; ++link) p.states[link_body(leg, link)] = BodyState::Failing;
    }
    p.p_world_endpoint = pose.p_world_E;
    return p;
  }

  std::optional<interference::LinkCapsules> link_capsules(const VectorXd&, const VectorXd& x) const override {
    if (!has_capsules(geometry_.model)) return std::nullopt;
    const Pose pose = pose_of(x);
    const PoseIkResult ik = pathos2::inverse(geometry_, pose);
    if (!assembles(ik))
      throw std::invalid_argument("pathos2: the pose does not assemble (leg " + std::to_string(ik.failing_leg + 1) + ")");
    interference::LinkCapsules out;
    const std::vector<interference::Capsule> placed = capsules(geometry_, pose, ik);
    for (int c = 0; c < int(placed.size()); ++c)
      out.links.push_back({placed[std::size_t(c)], capsule_name(c), c < kGripCapsule ? c / 3 : -1, c < kGripCapsule});
    const Stops st = stops(geometry_, pose, ik);
    if (st.pair[0] >= 0) interference::set_closest(out, st.pair[0], st.pair[1]);
    return out;
  }

  Eigen::AlignedBox3d default_box() const override {
    // The workspace spans about half the leg reach each way; 0.6 (l2 + l3)
    // leaves room, and mesh reports a surface cut by the box.
    const Model& m = geometry_.model;
    const double half = 0.6 * (m.l2 + m.l3);
    const Vector3d centre(0, 0, m.l0 / 2);
    return {centre - Vector3d::Constant(half), centre + Vector3d::Constant(half)};
  }

  // The x-y plane through the pose.
  std::pair<Axis, double> default_slice_plane(const VectorXd& x) const override { return {Axis::Z, x(2)}; }

  std::optional<Field> compute_field(const Grid& grid, const VectorXd& fixed_task, const linkscape::IkOptions& o, int threads,
                                     const FieldProgress& progress) const override {
    if (!o.method.empty() && o.method != "closed")
      throw std::invalid_argument("pathos2: unknown IK method '" + o.method + "' (known: closed)");
    if (fixed_task.size() != 7) throw std::invalid_argument("pathos2: the task needs x, y, z, rx, ry, rz, h0");
    if (o.branch && *o.branch != 0) throw std::invalid_argument("pathos2 has one branch (its legs' are in the preset)");
    if (o.tolerance != linkscape::IkOptions{}.tolerance)
      throw std::invalid_argument("pathos2: a tolerance does not apply (its IK is closed-form)");
    if (!(fixed_task(6) > 0)) throw std::invalid_argument("pathos2: the grip h0 must be > 0");
    pathos2::FieldRequest request;
    request.grid = grid;
    request.rpy = fixed_task.segment<3>(3);
    request.h0 = fixed_task(6);
    request.threads = threads;
    return pathos2::compute_field(geometry_.model, request, progress);
  }

  std::vector<methods::MethodRow> measure_methods(const methods::HarnessOptions& options) const override {
    pathos2_methods::HarnessOptions o;
    o.samples = options.samples;
    o.seed = options.seed;
    o.repeats = options.repeats;
    o.progress = options.progress;
    o.cancel = options.cancel;
    return pathos2_methods::run_pathos2_harness(geometry_.model, o);
  }
  std::vector<stability::SweepRow> stability_sweeps(const stability::SweepOptions& options) const override {
    return stability::run_pathos2_sweeps(geometry_.model, options);
  }

 private:
  // Every leg closes (the stops are defined).
  static bool assembles(const PoseIkResult& ik) {
    return std::none_of(ik.legs.begin(), ik.legs.end(), [](const LegSolution& l) { return l.status == Status::Unreachable; });
  }
  // The stops of a pose whose legs all close but that a stop bounds (the
  // IK's own joint limits or two links overlapping); nullopt otherwise.
  std::optional<Stops> stopped(const Pose& pose, const PoseIkResult& ik) const {
    const Model& m = geometry_.model;
    if ((!has_joint_limits(m) && !has_capsules(m)) || !assembles(ik)) return std::nullopt;
    if (ik.status != Status::Ok && ik.status != Status::OutOfLimits) return std::nullopt;
    const Stops st = stops(geometry_, pose, ik);
    if (st.hold()) return std::nullopt;
    return st;
  }

  Geometry geometry_;
  MechanismInfo info_;
};

}  // namespace

std::shared_ptr<const Mechanism> make_mechanism(const Model& model) {
  return std::make_shared<Pathos2Mechanism>(model);
}

std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset) { return make_mechanism(make_pathos2(preset)); }

}  // namespace linkscape::pathos2

namespace linkscape {
namespace {

// "stops": {"source": text, "globular_cone_deg": a, "link_radius": r, "grip_radius": g}
// (docs/mechanisms/pathos2.md, "Stops"); a cone_limit parameter replaces the cone.
void read_pathos2_stops(const Preset& preset, pathos2::Model& m) {
  for (const auto& [key, v] : stops_numbers(preset, {"globular_cone_deg", "link_radius", "grip_radius"})) {
    std::ostringstream given;
    given << v;
    if (key == "globular_cone_deg") {
      if (!(v > 0 && v < 180)) throw std::invalid_argument("stops." + key + " must be in (0, 180) deg, got " + given.str());
      if (!preset.parameters.contains("cone_limit")) m.cone_limit = v * std::numbers::pi / 180.0;
    } else {
      if (!(v > 0 && v <= pathos2::kMaxLength))
        throw std::invalid_argument("stops." + key + " must be a positive length (cm), got " + given.str());
      (key == "link_radius" ? m.link_radius : m.grip_radius) = v;
    }
  }
  if (m.grip_radius > 0 && !(m.link_radius > 0))
    throw std::invalid_argument("stops.grip_radius needs stops.link_radius (the grip is checked against the links)");
}

}  // namespace

pathos2::Model make_pathos2(const Preset& preset) {
  if (preset.mechanism != pathos2::kMechanismName)
    throw std::invalid_argument("expected a pathos2 preset, got '" + preset.mechanism + "'");
  // db and lx follow from lb and theta_t, the limits from the stops, where not given.
  require_parameters(preset, {"l0", "lb", "l1", "l2", "l3", "lp", "h0", "theta_t"});
  // Its joint limits are the parameters t2_limit, t3_limit and cone_limit.
  if (!preset.limits_deg.empty())
    throw std::invalid_argument("pathos2 takes no actuator_limits_deg; its joint limits are the parameters "
                                "t2_limit, t3_limit and cone_limit (degrees)");
  pathos2::Model m = pathos2::Model::from_parameters(preset.parameters);
  read_pathos2_stops(preset, m);
  // A stop switched off: the device as if it stated none of that kind.
  if (!preset.checks.joint_limits) m.cone_limit = m.t2_limit = m.t3_limit = std::numbers::pi;
  if (!preset.checks.interference) m.link_radius = m.grip_radius = 0.0;
  m.validate();
  return m;
}

}  // namespace linkscape
