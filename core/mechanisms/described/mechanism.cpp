#include "core/mechanisms/described/mechanism.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/field.h"
#include "core/field_sampling.h"
#include "core/grid_mirror.h"
#include "core/mechanisms/described/approaches.h"
#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/lanes.h"
#include "core/mechanisms/described/skeleton.h"
#include "core/preset.h"
#include "core/simd.h"

namespace linkscape::described {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;

constexpr double kInf = std::numeric_limits<double>::infinity();
// The stops' arrays, as fields and the device's info describe them.
constexpr const char* kJointMarginText =
    "The nearest passive joint's distance to its limit (< 0 beyond it, none where the device does not assemble)";
constexpr const char* kClearanceText =
    "The smallest gap between two legs' links, or a leg's link and the base or platform (< 0 where they overlap, "
    "none where the device does not assemble)";
// A planar device moves in the base frame's xy plane (docs/described-mechanisms.md).
constexpr double kPlaneZ = 0.0;
// The method code and name of the samples a field's SIMD lanes decide (after LegSolver's).
constexpr std::uint8_t kLanesCode = 2;
constexpr const char* kLanesName = "lanes";

class DescribedMechanism final : public Mechanism {
 public:
  DescribedMechanism(const Preset& preset, Model model) : preset_(preset), kin_(std::move(model)) {
    const Model& m = kin_.model();
    MechanismInfo& i = info_;
    // Named by its file, so two described devices (and a described device
    // beside the compiled one it copies) keep apart in reports and charts.
    i.name = preset.source.empty() ? std::string(kMechanismName) : preset.source.stem().string();
    i.title = preset.title;
    i.length_unit = m.length_unit;
    i.size_description = m.size_text;
    for (const auto& [name, value] : m.parameters) {
      Quantity q{name, m.length_unit, "", value, value != 0 ? Range{std::min(0.5 * value, 2 * value), std::max(0.5 * value, 2 * value)} : Range{-1, 1}};
      if (auto it = m.parameter_info.find(name); it != m.parameter_info.end()) {
        if (it->second.range.hi > it->second.range.lo) q.range = it->second.range;
        q.unit = it->second.unit;
        q.description = it->second.description;
        q.in_panel = it->second.in_panel;
      }
      i.parameters.push_back(q);
    }
    home_q_ = kin_.inverse(m.home, 0, 1e-10).q;
    const VectorXd& home = home_q_;
    for (std::size_t a = 0; a < m.actuators.size(); ++a) {
      const Actuator& act = m.actuators[a];
      i.actuators.push_back({act.name, act.prismatic ? m.length_unit : "rad",
                             (act.prismatic ? "Prismatic actuator of leg " : "Revolute actuator of leg ") +
                                 m.legs[std::size_t(act.leg)].name,
                             home(Eigen::Index(a)), act.range});
    }
    // The task, with z inserted for a planar device (not modelled: see the format page).
    for (std::size_t t = 0; t < m.task.size(); ++t) {
      const TaskCoordinate& c = m.task[t];
      const double h = m.home(Eigen::Index(t));
      if (c.extra >= 0) {
        const Extra& e = m.extras[std::size_t(c.extra)];
        i.task.push_back({e.name, e.unit, e.description, h, e.range});
      } else if (c.platform_coordinate < 3) {
        i.task.push_back({c.name, m.length_unit, c.platform_coordinate == 0 ? "Platform frame origin, base frame" : "",
                          h, {h - m.size, h + m.size}});
      } else {
        i.task.push_back({c.name, "rad", "Platform rotation (R = Rz Ry Rx)", h, {h - 0.6, h + 0.6}});
      }
      if (m.planar && t == 1)
        i.task.push_back({"z", m.length_unit, "The plane the device moves in (fixed: a planar device)", kPlaneZ,
                          {kPlaneZ, kPlaneZ}});
    }
    if (m.planar) i.plane_z = kPlaneZ;
    i.ik_methods = {{"closed", "closed", "Closed form per recognised leg (describe), Gauss-Newton for the others"},
                    {"closed-scalar", "closed-scalar",
                     "The closed forms one pose at a time: in fields, the reference of the SIMD lanes"},
                    {"newton", "newton", "Damped Gauss-Newton per leg from seeds, branch by the leg's rules (the reference)"}};
    i.fk_methods = {{"newton", "newton", "Gauss-Newton on every loop closure from a seed pose"}};
    rotations_ = 0;
    for (const TaskCoordinate& c : m.task) rotations_ += c.platform_coordinate >= 3;
    if (rotations_ >= 2)
      i.measures = {{"cond_jp", "cond(Jp)", "Condition number of the translational rows of J"},
                    {"cond_jo", "cond(Jo)", "Condition number of the rotational rows of J"}};
    else
      i.measures = {{"cond", "c(J)", "sigma_max / sigma_min of J = dx/dq"}};
    for (const Leg& l : m.legs)
      i.singular_sets.push_back({"leg-" + l.name + "-serial", l.label() + " (type I)",
                                 "Leg " + l.name + "'s actuator loses its hold: Jq entry zero"});
    i.singular_sets.push_back({"parallel", "parallel (type II)", "Jx singular"});
    for (int b = 0; b < kin_.branches(); ++b) {
      if (m.free_rules == 0) {
        i.branches.push_back("as described");
        break;
      }
      std::string name = std::to_string(b) + ":";
      for (const Leg& l : m.legs)
        for (const BranchRule& r : l.rules)
          if (r.free_index >= 0) name += std::string(" ") + l.name + ((b >> r.free_index) & 1 ? "-" : "+");
      i.branches.push_back(name);
    }
    for (const Extra& e : m.extras) i.fk_inputs.push_back(e.name);
    if (kin_.has_joint_limits()) i.extra_fields.push_back({"joint_margin", "joint margin (deg)", kJointMarginText});
    if (kin_.has_capsules()) i.extra_fields.push_back({"clearance", "clearance (" + m.length_unit + ")", kClearanceText});
    i.eval_columns = {kin_.branches() > 1, "failing_leg", true, true, true, true, true};
    skeleton_ = Skeleton(kin_);
  }

  const MechanismInfo& info() const override { return info_; }
  std::map<std::string, double> parameters() const override { return kin_.model().parameters; }
  double size() const override { return kin_.model().size; }
  VectorXd home_task() const override { return to_interface(kin_.model().home); }
  VectorXd home_actuators() const override { return home_q_; }

  IkResult inverse(const VectorXd& x, const IkOptions& o) const override {
    const LegSolver solver = solver_of(o.method);
    const VectorXd xm = to_model(x, "x");
    if (o.branch && (*o.branch < 0 || *o.branch >= kin_.branches()))
      throw std::invalid_argument("described: branch must be 0.." + std::to_string(kin_.branches() - 1) + ", got " +
                                  std::to_string(*o.branch));
    IkResult out;
    const int first = o.branch.value_or(0), last = o.branch ? *o.branch : kin_.branches() - 1;
    for (int b = first; b <= last; ++b) {
      PoseSolution s = kin_.inverse(xm, b, o.tolerance, solver);
      if (solver != LegSolver::Numeric && assembled(s)) s.residual = kin_.closure_residual(xm, s);
      // Singular at a type I (a leg's) or a type II (the platform's)
      // singularity: wherever measures() reports J singular. It takes the
      // solution nearest q with each leg closed on the fastest path; so
      // here, for the numerical solver, which at a stretched leg stops
      // about sqrt(residual) short of it (an ok row never carries c(J) = inf).
      // A numerical answer within the tolerance of a fold that a leg's
      // closed form cannot close exactly (a hair past a stretched leg's
      // reach) is singular too: measures() finds no exact solution there.
      if (s.status == Status::Ok) {
        const PoseSolution near = solver == LegSolver::Numeric ? kin_.inverse_near(xm, s.q) : PoseSolution{};
        if (near.status != Status::Ok && near.failing_leg >= 0 && kin_.closed_form(near.failing_leg) != nullptr) {
          s.status = Status::Singular;
          s.failing_leg = near.failing_leg;
        } else {
          const JacobianParts parts = kin_.jacobian(xm, near.status == Status::Ok && !near.legs.empty() ? near : s);
          if (parts.status != Status::Ok) {
            s.status = Status::Singular;
            s.failing_leg = parts.singular_leg;
          }
        }
      }
      if (b == first || (s.status == Status::Ok && out.status != Status::Ok)) {
        if (out.status != Status::Ok) {
          out.status = s.status;
          out.failing_part = s.failing_leg >= 0 ? kin_.model().legs[std::size_t(s.failing_leg)].name : "";
          out.status_text = s.stopped ? "out-of-limits: " + kin_.stop_reason(s.stops, leg_states(s)) : "";
        }
      }
      // Every assembly found, with its actuators (a singular one too: its q
      // is the device's there, its c(J) infinite).
      if (s.status == Status::Ok || s.status == Status::OutOfLimits || s.status == Status::Singular)
        out.solutions.push_back({s.q, b, s.status, s.residual, s.iterations, method_name(solver),
                                 s.status == Status::Ok || s.failing_leg < 0
                                     ? std::string()
                                     : kin_.model().legs[std::size_t(s.failing_leg)].name});
    }
    if (out.status == Status::Ok) {
      out.failing_part.clear();
      out.status_text.clear();
    }
    return out;
  }

  FkResult forward(const VectorXd& q, const FkOptions& o) const override {
    check_method(o.method, "FK");
    if (q.size() != Eigen::Index(kin_.model().actuators.size()))
      throw std::invalid_argument("described: q needs " + std::to_string(kin_.model().actuators.size()) + " values");
    if (!q.allFinite()) throw std::invalid_argument("described: the actuator values must be finite numbers");
    const VectorXd seed = o.seed ? *o.seed : home_task();
    const VectorXd sm = to_model(seed, "FK seed");
    const ForwardSolution f = kin_.forward(q, sm, o.tolerance, std::max(o.max_iterations, 1));
    FkResult out;
    out.status = f.status;
    // As the compiled devices: an assembly with an actuator outside its travel.
    if (out.status == Status::Ok && kin_.limits_margin(q) < 0) out.status = Status::OutOfLimits;
    // A passive joint beyond its limit, or two links overlapping. The reason
    // is not the status text: that replaces the status token in eval's CSV.
    if (out.status == Status::Ok && (kin_.has_joint_limits() || kin_.has_capsules()) &&
        !kin_.stops(kin_.pose(f.x), f.legs).hold())
      out.status = Status::OutOfLimits;
    out.x = to_interface(f.x);
    // An assembly where J is singular (type I or II) is singular, as measures() says there.
    if (out.status == Status::Ok) {
      PoseSolution assembly;
      for (const LegState& leg : f.legs) assembly.legs.push_back({leg, Status::Ok, 0.0, 0});
      if (kin_.jacobian(f.x, assembly).status != Status::Ok) out.status = Status::Singular;
    }
    out.residual = f.residual;
    out.iterations = f.iterations;
    return out;
  }

  Eigen::MatrixXd jacobian(const VectorXd& q, const VectorXd& x) const override {
    const VectorXd xm = to_model(x, "x");
    return kin_.jacobian(xm, kin_.inverse_near(xm, q)).J;
  }

  Measures measures(const VectorXd& q, const VectorXd& x) const override {
    const VectorXd xm = to_model(x, "x");
    const PoseSolution s = kin_.inverse_near(xm, q);
    Measures out;
    if (s.status != Status::Ok) {
      out.status = Status::Singular;
      out.values.assign(info_.measures.size(), kInf);
      return out;
    }
    const JacobianParts parts = kin_.jacobian(xm, s);
    out.status = parts.status;
    out.values = measure_values(parts);
    // det J = det Jq / det Jx: 0 where a leg's actuator loses its hold
    // (type I), unbounded where Jx is singular (type II); at a constraint
    // singularity J itself keeps its value.
    const bool type_two = parts.singular_leg < 0 && !(parts.jx_condition <= kSingularCondition);
    out.det = parts.singular_leg >= 0 ? 0.0 : type_two ? kInf : parts.J.determinant();
    return out;
  }

  double reach_margin(const VectorXd& x, int branch) const override {
    return kin_.reach_margin(to_model(x, "x"), branch);
  }

  SingularityReport nearest_singularity(const VectorXd& q, const VectorXd& x) const override {
    const VectorXd xm = to_model(x, "x");
    const PoseSolution s = kin_.inverse_near(xm, q);
    SingularityReport r;
    const int legs = int(kin_.model().legs.size());
    r.distances.assign(std::size_t(legs + 1), kInf);
    if (s.status != Status::Ok) return r;
    const JacobianParts parts = kin_.jacobian(xm, s);
    const PlatformPose pose = kin_.pose(xm);
    for (int l = 0; l < legs; ++l) {
      // Where a leg's reach bounds are exact (a planar dyad, a crank and a
      // rod ending in a ball), its serial set is their boundary: the distance
      // to it, in the length unit, as the compiled Delta gives it; else the
      // leg's margin (size times its actuation wrench's moment).
      // An extensible leg has no serial set: its slide always pushes along its rod.
      const ClosedFormLeg* form = kin_.closed_form(l);
      const bool exact = form && (form->pattern == LegPattern::PlanarDyad ||
                                  (form->pattern == LegPattern::CrankRod && form->end_joints == 1));
      r.distances[std::size_t(l)] = form && form->pattern == LegPattern::Extensible ? kInf
                                    : exact ? std::max(0.0, -kin_.reach_outside(l, kin_.anchor(l, pose)))
                                            : parts.serial_margin[std::size_t(l)];
    }
    r.distances[std::size_t(legs)] = parallel_distance(xm, s);
    r.nearest = int(std::min_element(r.distances.begin(), r.distances.end()) - r.distances.begin());
    r.distance = r.distances[std::size_t(r.nearest)];
    return r;
  }

  // Towards each leg's serial set and the parallel set, from home
  // (approaches.h); a planar device's targets in its plane.
  std::vector<SingularApproach> singular_approaches() const override {
    std::vector<SingularApproach> out;
    const VectorXd home = kin_.model().home;
    const bool planar = kin_.model().planar;
    for (ApproachEnds& a : singular_approach_ends(kin_)) {
      out.push_back({a.set, [points = std::move(a.ends), home, planar](double eps, int k) -> VectorXd {
                       const VectorXd& end = points[std::size_t(k) % points.size()];
                       const VectorXd xm = home + (1 - eps) * (end - home);
                       if (!planar) return xm;
                       VectorXd x(xm.size() + 1);
                       x << xm.head(2), kPlaneZ, xm.tail(xm.size() - 2);
                       return x;
                     }});
    }
    return out;
  }

  // Sweeps towards the geometry's singular sets, on the device without
  // actuator ranges, passive-joint limits or links (they would cut the rays
  // first), as for the compiled Delta.
  std::vector<stability::SweepRow> stability_sweeps(const stability::SweepOptions& options) const override {
    Model free = kin_.model();
    for (Actuator& a : free.actuators) {
      a.limited = false;
      if (!a.prismatic) a.range = {-M_PI, M_PI};
    }
    for (Leg& l : free.legs) {
      l.limits.clear();
      l.capsules.clear();
    }
    return DescribedMechanism(preset_, std::move(free)).Mechanism::stability_sweeps(options);
  }

  std::vector<std::pair<std::string, std::string>> readouts(const VectorXd& q, const VectorXd& x) const override {
    const Mobility& mb = kin_.mobility();
    std::ostringstream s;
    s << mb.freedoms << " (Gruebler-Kutzbach " << mb.gruebler << ", " << mb.fixed << " held, " << mb.idle << " idle";
    if (!kin_.model().extras.empty()) s << ", " << kin_.model().extras.size() << " extra";
    s << ")";
    for (std::size_t i = 0; i < mb.held_by_description_alone.size(); ++i)
      s << (i ? ", " : "; held by the description alone: ") << mb.held_by_description_alone[i];
    std::vector<std::pair<std::string, std::string>> out{{"mobility", s.str()}};
    if (kin_.has_joint_limits() || kin_.has_capsules()) {
      const VectorXd xm = to_model(x, "x");
      const PoseSolution solved = kin_.inverse_near(xm, q);
      if (solved.status == Status::Ok) {
        const std::vector<LegState> legs = leg_states(solved);
        for (const auto& [name, text] : stop_readouts(kin_.stops(kin_.pose(xm), legs), legs)) out.push_back({name, text});
      }
    }
    return out;
  }

  SkeletonModel skeleton_model() const override { return skeleton_.model; }

  SkeletonPose skeleton_pose(const VectorXd& q, const VectorXd& x, const IkResult* ik) const override {
    const VectorXd xm = to_model(x, "x");
    return skeleton_.pose(kin_, assembly(xm, q), kin_.pose(xm), ik ? ik->failing_part : std::string());
  }

  std::optional<interference::LinkCapsules> link_capsules(const VectorXd& q, const VectorXd& x) const override {
    if (!kin_.has_capsules()) return std::nullopt;
    const VectorXd xm = to_model(x, "x");
    const PoseSolution s = assembly(xm, q);
    const PlatformPose pose = kin_.pose(xm);
    const std::vector<LegState> legs = leg_states(s);
    const auto placed = kin_.capsules(pose, legs);
    interference::LinkCapsules out;
    std::vector<int> first;  // per leg: its first link in out.links
    for (std::size_t l = 0; l < placed.size(); ++l) {
      first.push_back(int(out.links.size()));
      const Leg& leg = kin_.model().legs[l];
      for (std::size_t c = 0; c < placed[l].size(); ++c)
        out.links.push_back({placed[l][c], leg.label() + " " + leg.capsules[c].name, int(l),
                             leg.capsules[c].on == LinkCapsule::On::Chain});
    }
    // The pair the device's stops name, so the view agrees with the clearance field.
    const Stops st = kin_.stops(pose, legs);
    if (st.pair[0] >= 0)
      interference::set_closest(out, first[std::size_t(st.pair[0])] + st.pair[1], first[std::size_t(st.pair[2])] + st.pair[3]);
    return out;
  }

  Eigen::AlignedBox3d default_box() const override {
    const Model& m = kin_.model();
    if (m.box) return *m.box;
    const Vector3d c(m.home(0), m.home(1), m.planar ? 0.0 : m.home(2));
    const Vector3d half(m.size, m.size, m.planar ? 0.1 * m.size : m.size);
    return {c - half, c + half};
  }
  std::pair<Axis, double> default_slice_plane(const VectorXd& x) const override {
    return kin_.model().planar ? std::pair{Axis::Z, x(2)} : std::pair{Axis::Y, x(1)};
  }

  std::optional<Field> compute_field(const Grid& grid, const VectorXd& fixed_task, const IkOptions& o, int threads,
                                     const FieldProgress& progress) const override {
    // The numerical reference where asked for, by method or LINKSCAPE_FIELD_KERNEL=scalar.
    const FieldKernel kernel = field_kernel_from_environment();
    const LegSolver solver = kernel == FieldKernel::Scalar ? LegSolver::Numeric : solver_of(o.method);
    const int branch = o.branch.value_or(0);
    if (branch < 0 || branch >= kin_.branches())
      throw std::invalid_argument("described: branch must be 0.." + std::to_string(kin_.branches() - 1));
    const bool second = info_.measures.size() > 1;
    if (kin_.model().planar && grid.dims[2] > 1) return extruded_field(grid, fixed_task, o, threads, progress);
    detail::check_grid(grid, Field::bytes_per_sample() + (second ? sizeof(float) : 0), kFieldMemoryLimitBytes);
    // The fixed task's x, y, z are not used (a planar device's z: its plane).
    VectorXd fixed = fixed_task.size() == Eigen::Index(info_.task.size()) ? fixed_task : home_task();
    if (kin_.model().planar) fixed(2) = kPlaneZ;
    const VectorXd base = to_model(fixed, "fixed task");
    // Point legs in SIMD lanes where the device allows (decided once per field).
    std::optional<LaneDevice> lanes;
    if (solver == LegSolver::Fastest && o.method != "closed-scalar") lanes = lane_device(kin_, base, branch);
    if (lanes) simd::apply_environment();
    // The rows of the upper half in y from the lower half's where the device is its own mirror image.
    const bool mirrored = lanes && kernel == FieldKernel::VectorMirrored && lanes_mirror_holds(*lanes, grid);
    Field f;
    f.grid = grid;
    f.mechanism = info_.name;
    f.length_unit = kin_.model().length_unit;
    f.parameters = parameters();
    for (const Quantity& q : info_.parameters) f.parameter_units[q.name] = q.unit;  // an angle is not a length
    // "closed" where some leg has a closed form; a device with none is solved numerically throughout.
    f.method = lanes ? kLanesName : method_name(kin_.closed_form_count() > 0 ? solver : LegSolver::Numeric);
    for (LegSolver k : {LegSolver::Fastest, LegSolver::Numeric}) f.method_names.emplace_back(method_name(k));  // by LegSolver
    f.method_names.emplace_back(kLanesName);  // kLanesCode
    f.branch = branch;
    for (const NamedItem& n : info_.measures) f.measure_titles.push_back(n.title);
    float* joint_margin = nullptr;
    float* clearance = nullptr;
    if (kin_.has_joint_limits())
      joint_margin = f.add_extra("joint_margin", "joint margin", "deg", kJointMarginText);
    if (kin_.has_capsules())
      clearance = f.add_extra("clearance", "clearance", kin_.model().length_unit, kClearanceText);
    const double tolerance = o.tolerance;
    // The sample at a row's point t; x the model's task, its x, y, z the point's.
    const auto set_point = [&](VectorXd& x, const detail::GridRow& r, int t) {
      const Vector3d p = r.point(grid, t);
      x(0) = p.x();
      x(1) = p.y();
      if (!kin_.model().planar) x(2) = p.z();
    };
    // The scalar closed path at a lane it hands off (rare: built only then).
    const auto scalar_at = [&](const detail::GridRow& r, int t, double& margin, double& gap) {
      VectorXd x = base;
      set_point(x, r, t);
      Stops stops;
      const FieldSample s = sample(x, branch, tolerance, solver, stops);
      margin = stops.joint_margin_deg;
      gap = stops.clearance;
      return s;
    };
    const bool complete = detail::fill_field_rows(
        f, second, threads, progress,
        [&](const detail::GridRow& row, const detail::FieldRowOut& out) {
          if (lanes) {
            const auto stops_of = [&](const detail::GridRow& r) {
              return LaneStopsOut{joint_margin ? joint_margin + r.index : nullptr, clearance ? clearance + r.index : nullptr};
            };
            // Two pointers: held in the std::function itself, no allocation per row.
            const auto fallback_of = [&](const detail::GridRow& r) -> LaneFallback {
              return [at = &scalar_at, r = &r](int t, double& margin, double& gap) { return (*at)(*r, t, margin, gap); };
            };
            detail::RowImage image;  // the mirror's fallback points to its row: declared first
            std::optional<LaneMirror> mirror;
            if (mirrored) {
              image = detail::image_in_y(grid, row);
              if (!image.sampled) return;
              if (image.image)
                mirror = LaneMirror{out.shifted(image.by), stops_of(*image.image), fallback_of(*image.image)};
            }
            sample_row_lanes(*lanes, grid, row, out, stops_of(row), kLanesCode, fallback_of(row), nullptr,
                             mirror ? &*mirror : nullptr);
            return;
          }
          VectorXd x = base;
          for (int t = 0; t < row.count; ++t) {
            Stops stops;
            set_point(x, row, t);
            out.store(t, sample(x, branch, tolerance, solver, stops));
            if (joint_margin) joint_margin[row.index + std::size_t(t)] = float(stops.joint_margin_deg);
            if (clearance) clearance[row.index + std::size_t(t)] = float(stops.clearance);
          }
        },
        lanes ? detail::kVectorChunkSamples : detail::kChunkSamples);
    if (!complete) return std::nullopt;
    return f;
  }

 private:
  // A planar device ignores z: one layer sampled, copied to every z layer.
  std::optional<Field> extruded_field(const Grid& grid, const VectorXd& fixed_task, const IkOptions& o, int threads,
                                      const FieldProgress& progress) const {
    detail::check_grid(grid, Field::bytes_per_sample() + (info_.measures.size() > 1 ? sizeof(float) : 0),
                       kFieldMemoryLimitBytes);
    Grid layer = grid;
    layer.dims[2] = 1;
    std::optional<Field> f = compute_field(layer, fixed_task, o, threads, progress);
    if (!f) return f;
    const std::size_t n = layer.size(), layers = std::size_t(grid.dims[2]);
    auto extrude = [&](auto& a) {
      if (a.empty()) return;
      a.resize(n * layers);
      for (std::size_t k = 1; k < layers; ++k) std::copy(a.begin(), a.begin() + std::ptrdiff_t(n), a.begin() + std::ptrdiff_t(k * n));
    };
    extrude(f->cond);
    extrude(f->reach_margin);
    extrude(f->residual);
    extrude(f->reachable);
    extrude(f->status);
    extrude(f->iterations);
    extrude(f->method_used);
    extrude(f->cond_orientation);
    for (Field::NamedArray& a : f->extras) extrude(a.values);
    f->grid = grid;
    return f;
  }

  // `stops` gets the pose's stops, NaN where it does not assemble.
  FieldSample sample(const VectorXd& xm, int branch, double tolerance, LegSolver solver, Stops& stops) const {
    FieldSample s;
    const float inf = std::numeric_limits<float>::infinity();
    s.cond = s.cond_orientation = inf;
    // The thread's scratch: a field's samples reuse its storage.
    thread_local PlatformPose pose;
    thread_local PoseSolution ik;
    thread_local JacobianParts jacobian;
    kin_.pose_into(xm, pose);
    kin_.inverse_into(pose, branch, tolerance, solver, ik, false);  // the states serve only where it assembles
    s.iterations = std::uint16_t(std::min(ik.iterations, 65535));
    const bool closes = assembled(ik);
    Status status = ik.status;
    s.residual = closes ? float(ik.residual) : inf;
    const JacobianParts* parts = nullptr;
    if (closes) {
      kin_.jacobian_into(pose, ik, solver, jacobian);
      parts = &jacobian;
    }
    const double margin = kin_.reach_margin(ik, parts);
    if (parts) {
      if (status == Status::Ok && parts->status != Status::Ok) status = Status::Singular;
      if (status == Status::Ok) {
        const std::array<double, 2> v = measure_pair(*parts);
        s.cond = float(v[0]);
        if (info_.measures.size() > 1) s.cond_orientation = float(v[1]);
        s.method_used = std::uint8_t(solver);  // the code method_names names
      }
    }
    s.reach_margin = float(margin);
    stops = ik.stops;
    if (!closes) stops.joint_margin_deg = stops.clearance = std::numeric_limits<double>::quiet_NaN();
    s.status = std::uint8_t(status);
    s.reachable = status == Status::Ok;
    return s;
  }

  // The assembly at xm (model order) nearest the actuators q, for drawing;
  // throws std::invalid_argument naming the leg where it does not assemble.
  PoseSolution assembly(const VectorXd& xm, const VectorXd& q) const {
    PoseSolution s = kin_.inverse_near(xm, q);
    if (s.status != Status::Ok)
      throw std::invalid_argument("described: the pose does not assemble (leg " +
                                  kin_.model().legs[std::size_t(std::max(0, s.failing_leg))].name + ")");
    return s;
  }

  static std::vector<LegState> leg_states(const PoseSolution& s) {
    std::vector<LegState> out;
    for (const LegSolution& l : s.legs) out.push_back(l.state);
    return out;
  }

  // The window's readouts of a pose's stops: each margin and where it is least.
  std::vector<std::pair<std::string, std::string>> stop_readouts(const Stops& st, const std::vector<LegState>& legs) const {
    std::vector<std::pair<std::string, std::string>> out;
    const Model& m = kin_.model();
    auto number = [](double v, const std::string& unit) {
      std::ostringstream s;
      s.precision(3);
      s << v << (unit == "°" ? "" : " ") << unit;
      return s.str();
    };
    if (kin_.has_joint_limits() && st.joint_leg >= 0) {
      const Leg& leg = m.legs[std::size_t(st.joint_leg)];
      out.push_back({"joint margin", number(st.joint_margin_deg, "°") + " (" + leg.label() + " " +
                                         leg.limits[std::size_t(st.joint_limit)].label + ")"});
    }
    if (kin_.has_capsules() && st.pair[0] >= 0) {
      auto link = [&](int leg, int c) {
        const Leg& l = m.legs[std::size_t(leg)];
        return l.label() + " " + l.capsules[std::size_t(c)].name;
      };
      out.push_back({"clearance", number(st.clearance, m.length_unit) + " (" + link(st.pair[0], st.pair[1]) + " to " +
                                      link(st.pair[2], st.pair[3]) + ")"});
    }
    if (!st.hold()) out.push_back({"stops", kin_.stop_reason(st, legs)});
    return out;
  }

  std::vector<double> measure_values(const JacobianParts& parts) const {
    const std::array<double, 2> v = measure_pair(parts);
    return {v.begin(), v.begin() + std::ptrdiff_t(info_.measures.size())};
  }
  // The measures (the second only where there are two), +inf where J is singular.
  std::array<double, 2> measure_pair(const JacobianParts& parts) const {
    if (parts.status != Status::Ok) return {kInf, kInf};
    const auto cond = internal::condition_number;
    if (info_.measures.size() == 1) return {cond(parts.J), kInf};
    // Rows of J in task order: translations first (x, y, z), then rotations.
    const Model& m = kin_.model();
    thread_local Eigen::MatrixXd Jp, Jo;
    Jp.resize(3, parts.J.cols());
    Jo.resize(rotations_, parts.J.cols());
    int row = 0, p = 0, o = 0;
    for (const TaskCoordinate& c : m.task) {
      if (c.extra >= 0) continue;
      if (c.platform_coordinate < 3) Jp.row(p++) = parts.J.row(row);
      else Jo.row(o++) = parts.J.row(row);
      ++row;
    }
    return {cond(Jp.topRows(p)), cond(Jo)};
  }

  // First-order distance to the type II set: |Jx|'s smallest singular value
  // over its gradient in the task (central differences).
  double parallel_distance(const VectorXd& xm, const PoseSolution& s) const {
    auto smallest = [&](const VectorXd& x) {
      const PoseSolution near = kin_.inverse_near(x, s.q);
      if (near.status != Status::Ok) return kInf;
      const JacobianParts parts = kin_.jacobian(x, near);
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(parts.Jx);
      return svd.singularValues()(svd.singularValues().size() - 1);
    };
    const double f0 = smallest(xm);
    const double h = 1e-6 * kin_.model().size;
    double g2 = 0;
    for (int k = 0; k < (kin_.model().planar ? 2 : 3); ++k) {
      VectorXd a = xm, b = xm;
      a(k) += h;
      b(k) -= h;
      const double g = (smallest(a) - smallest(b)) / (2 * h);
      if (!std::isfinite(g)) return kInf;
      g2 += g * g;
    }
    return g2 > 0 ? f0 / std::sqrt(g2) : kInf;
  }

  void check_method(const std::string& method, const char* what) const {
    if (!method.empty() && method != "newton")
      throw std::invalid_argument(std::string("described: unknown ") + what + " method '" + method + "' (known: newton)");
  }
  static LegSolver solver_of(const std::string& method) {
    if (method.empty() || method == "closed" || method == "closed-scalar") return LegSolver::Fastest;
    if (method == "newton") return LegSolver::Numeric;
    throw std::invalid_argument("described: unknown IK method '" + method + "' (known: closed, closed-scalar, newton)");
  }
  static const char* method_name(LegSolver s) { return s == LegSolver::Numeric ? "newton" : "closed"; }

  // Interface task (x, y, z, ... with z inserted for planar devices) <-> model task.
  // A planar device refuses a z off its plane (within rounding of the size).
  VectorXd to_model(const VectorXd& x, const char* what) const {
    const Eigen::Index n = Eigen::Index(info_.task.size());
    if (x.size() != n) throw std::invalid_argument(std::string("described: ") + what + " needs " + std::to_string(n) + " values");
    if (!x.allFinite()) throw std::invalid_argument(std::string("described: ") + what + " must be finite numbers");
    if (kin_.model().planar && !(std::abs(x(2) - kPlaneZ) <= 1e-12 * kin_.model().size)) {
      std::ostringstream msg;
      msg << "described: " << what << " has z = " << x(2) << " " << kin_.model().length_unit << ", but "
          << info_.name << " is planar: it moves in the plane z = " << kPlaneZ << " of its base frame";
      throw std::invalid_argument(msg.str());
    }
    // Far beyond any device its squared distances would overflow (a slide's
    // leg has no reach bound to stop there first).
    const double far = 1e9 * kin_.model().size;
    if (!(x.head(3).lpNorm<Eigen::Infinity>() <= far)) {
      std::ostringstream msg;
      msg << "described: " << what << " (" << x(0) << ", " << x(1) << ", " << x(2) << ") " << kin_.model().length_unit
          << " is beyond 1e9 times the device's size (" << far << " " << kin_.model().length_unit << ")";
      throw std::invalid_argument(msg.str());
    }
    if (!kin_.model().planar) return x;
    VectorXd out(n - 1);
    out << x.head(2), x.tail(n - 3);
    return out;
  }
  VectorXd to_interface(const VectorXd& xm) const {
    if (!kin_.model().planar) return xm;
    VectorXd out(xm.size() + 1);
    out << xm.head(2), kPlaneZ, xm.tail(xm.size() - 2);
    return out;
  }

  Preset preset_;
  Kinematics kin_;
  MechanismInfo info_;
  VectorXd home_q_;  // the actuators at the home task, branch 0 (solved once)
  int rotations_ = 0;
  // The drawing: which link body follows which leg step, where the platform bodies start.
  Skeleton skeleton_;
};

}  // namespace

std::shared_ptr<const Mechanism> make_mechanism(const Preset& preset) {
  if (preset.description.empty())
    throw std::invalid_argument("a described mechanism needs a \"description\" (docs/described-mechanisms.md)");
  Model model = build_model(preset.description, preset.parameters, preset.limits_deg, preset.length_unit);
  switch_off_stops(model, preset.checks);
  return std::make_shared<DescribedMechanism>(preset, std::move(model));
}

}  // namespace linkscape::described
