#include "gui/window/device_state.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace linkscape::gui {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

std::string status_text(Status s, const std::string& text = {}) { return text.empty() ? std::string(to_string(s)) : text; }

// As QString::number(v, 'g', precision) writes it.
std::string number(double v, int precision) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", precision, v);
  return text;
}

// A failing part as the status says it: "leg 3" from the column
// "failing_leg" and the part "3"; a part named "leg 3" in its file already
// says what it is.
std::string part_label(const MechanismInfo& info, const std::string& part) {
  std::string column = info.eval_columns.ik_failing_part;
  const std::string prefix = "failing_";
  if (column.rfind(prefix, 0) == 0) column = column.substr(prefix.size());
  const std::string kind = column.empty() ? "part" : column;
  return part.rfind(kind + " ", 0) == 0 ? part : kind + " " + part;
}

}  // namespace

double angle_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double d = 0;
  for (Eigen::Index k = 0; k < a.size(); ++k) d = std::max(d, std::abs(std::remainder(a(k) - b(k), 2 * kPi)));
  return d;
}

int branch_of(const Mechanism& m, const Eigen::VectorXd& q, const Eigen::VectorXd& x, int fallback) {
  if (m.info().branches.size() <= 1) return 0;
  IkOptions o;
  o.seed = q;
  IkResult r;
  try {
    r = m.inverse(x, o);
  } catch (const std::invalid_argument&) {
    return fallback;
  }
  int best = fallback;
  double nearest = INFINITY;
  for (const IkSolution& s : r.solutions)
    if (s.status == Status::Ok && angle_distance(s.q, q) < nearest) {
      nearest = angle_distance(s.q, q);
      best = s.branch;
    }
  return best;
}

DeviceState::DeviceState(const Preset& preset) : preset_(preset), mechanism_(make_mechanism(preset)) {
  q_ = mechanism_->home_actuators();
  x_ = mechanism_->home_task();
  branch_ = branch_of(*mechanism_, q_, x_, 0);
}

bool DeviceState::refuse(std::string why, const IkResult* failed) {
  refusal_ = std::move(why);
  failed_.reset();
  if (failed) failed_ = *failed;
  return false;
}

void DeviceState::take(const Eigen::VectorXd& q, const Eigen::VectorXd& x, int branch) {
  q_ = q;
  x_ = x;
  branch_ = branch;
  refusal_.clear();
  failed_.reset();
}

bool DeviceState::set_task(const Eigen::VectorXd& x, bool tracking) {
  const MechanismInfo& info = mechanism_->info();
  if (x.size() != Eigen::Index(info.task.size()) || !x.allFinite())
    return refuse("The target is not " + std::to_string(info.task.size()) + " finite task coordinates.");
  IkOptions o;
  o.seed = q_;
  if (info.branches.size() > 1) o.branch = branch_;
  IkResult r;
  try {
    r = mechanism_->inverse(x, o);
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  const IkSolution* s = nullptr;
  for (const IkSolution& c : r.solutions)
    if (c.branch == branch_) s = &c;
  if (!s || s->status != Status::Ok) {
    std::string why = status_text(s ? s->status : r.status, s ? std::string() : r.status_text);
    if (!r.failing_part.empty()) why = part_label(info, r.failing_part) + ": " + why;
    if ((s ? s->status : r.status) == Status::Singular && s) {
      const SingularityReport near = mechanism_->nearest_singularity(s->q, x);
      why += " (on the " + info.singular_sets.at(near.nearest).title + ")";
    }
    if (info.branches.size() > 1) why += " in branch " + std::to_string(branch_);
    return refuse(why + "; the device stays at the last valid pose", &r);
  }
  if (tracking && angle_distance(s->q, q_) > kMaxTrackingStep)
    return refuse("jump: reaching this target would make the device jump (it lies across a singular set); "
                  "move through the workspace instead");
  take(s->q, x, branch_);
  return true;
}

bool DeviceState::move_endpoint_to(const Eigen::Vector3d& target, int branch) {
  Eigen::VectorXd x = x_;
  x.head<3>() = target;
  if (branch < 0) return set_task(x, true);
  if (branch >= int(mechanism_->info().branches.size())) return refuse("There is no branch " + std::to_string(branch) + ".");
  const int kept = branch_;
  branch_ = branch;
  if (set_task(x, false)) return true;
  branch_ = kept;
  return false;
}

bool DeviceState::set_actuators(const Eigen::VectorXd& q, const std::optional<Eigen::VectorXd>& task_inputs) {
  const MechanismInfo& info = mechanism_->info();
  if (q.size() != Eigen::Index(info.actuators.size()) || !q.allFinite())
    return refuse("The actuators need " + std::to_string(info.actuators.size()) + " finite values.");
  FkOptions o;
  Eigen::VectorXd seed = x_;
  if (task_inputs)
    for (const std::string& name : info.fk_inputs)
      for (std::size_t k = 0; k < info.task.size(); ++k)
        if (info.task[k].name == name) seed(Eigen::Index(k)) = (*task_inputs)(Eigen::Index(k));
  o.seed = seed;
  FkResult r;
  try {
    r = mechanism_->forward(q, o);
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  if (r.status != Status::Ok)
    return refuse("FK " + status_text(r.status, r.status_text) + " after " + std::to_string(r.iterations) +
                  " iterations (residual " + number(r.residual, 2) + "); the device stays at the last valid pose");
  // The pose FK found must assemble: its IK names a failing part if not.
  IkOptions check;
  check.seed = q;
  IkResult ik;
  try {
    ik = mechanism_->inverse(r.x, check);
  } catch (const std::invalid_argument& e) {
    return refuse(e.what());
  }
  if (ik.status != Status::Ok && !ik.failing_part.empty())
    return refuse(part_label(info, ik.failing_part) + ": " + status_text(ik.status, ik.status_text) +
                      " at the FK pose; the device stays at the last valid pose",
                  &ik);
  take(q, r.x, branch_of(*mechanism_, q, r.x, branch_));
  return true;
}

DesignPlan DeviceState::with_parameters(const std::map<std::string, double>& parameters) const {
  DesignPlan plan;
  plan.preset = design_with(parameters, {});
  try {
    plan.mechanism = make_mechanism(plan.preset);
    plan.mechanism->skeleton_model();  // a design the view cannot draw is refused too
  } catch (const std::invalid_argument& e) {
    plan.refusal = e.what();
    return plan;
  }
  const Mechanism& m = *plan.mechanism;
  IkOptions o;
  o.seed = q_;
  if (m.info().branches.size() > 1) o.branch = branch_;
  const IkResult ik = m.inverse(x_, o);
  if (ik.status == Status::Ok && !ik.solutions.empty() && ik.solutions.front().status == Status::Ok) {
    plan.q = ik.solutions.front().q;
    plan.x = x_;
    plan.branch = branch_;
    plan.kept = DesignPlan::Kept::Task;
    return plan;
  }
  FkOptions fo;
  fo.seed = x_;
  const FkResult fk = m.forward(q_, fo);
  IkOptions check;
  check.seed = q_;
  if (fk.status == Status::Ok && m.inverse(fk.x, check).status == Status::Ok) {
    plan.q = q_;
    plan.x = fk.x;
    plan.branch = branch_of(m, plan.q, plan.x, branch_);
    plan.kept = DesignPlan::Kept::Actuators;
    return plan;
  }
  plan.q = m.home_actuators();
  plan.x = m.home_task();
  plan.kept = DesignPlan::Kept::Home;
  if (m.inverse(plan.x, check).status != Status::Ok) {
    plan.refusal = "This design cannot reach its home pose; design unchanged.";
    return plan;
  }
  plan.branch = branch_of(m, plan.q, plan.x, 0);
  return plan;
}

DesignPlan DeviceState::with_saved_pose(const Preset& next, const Eigen::VectorXd& pose,
                                        const Eigen::VectorXd& task) const {
  DesignPlan plan;
  plan.preset = next;
  plan.mechanism = make_mechanism(next);  // throws: nothing changed
  const Mechanism& m = *plan.mechanism;
  const MechanismInfo& info = m.info();
  if (pose.size() > 0 && pose.size() != Eigen::Index(info.actuators.size()))
    throw std::invalid_argument("session: the pose has " + std::to_string(pose.size()) + " actuator values, the device " +
                                std::to_string(info.actuators.size()));
  if (task.size() > 0 && task.size() != Eigen::Index(info.task.size()))
    throw std::invalid_argument("session: the task has " + std::to_string(task.size()) + " coordinates, the device " +
                                std::to_string(info.task.size()));
  std::optional<Eigen::VectorXd> q, x;
  if (task.size() > 0) {
    IkOptions o;
    if (pose.size() > 0) o.seed = pose;
    const IkResult r = m.inverse(task, o);
    double nearest = INFINITY;
    for (const IkSolution& sol : r.solutions) {
      const double d = pose.size() > 0 ? angle_distance(sol.q, pose) : sol.branch == branch_ ? 0.0 : 1.0;
      if (sol.status == Status::Ok && d < nearest) {
        nearest = d;
        q = sol.q;
        x = task;
      }
    }
    // The saved actuators themselves where they are that solution (no rounding).
    if (q && pose.size() > 0 && angle_distance(*q, pose) < 1e-9) q = pose;
    plan.kept = DesignPlan::Kept::Task;
  } else {
    FkOptions o;
    const FkResult r = m.forward(pose, o);
    if (r.status == Status::Ok) {
      q = pose;
      x = r.x;
    }
    plan.kept = DesignPlan::Kept::Actuators;
  }
  if (q && x) {
    plan.q = *q;
    plan.x = *x;
    plan.branch = branch_of(m, plan.q, plan.x, branch_);
  } else {
    plan.q = m.home_actuators();
    plan.x = m.home_task();
    plan.branch = branch_of(m, plan.q, plan.x, 0);
    plan.kept = DesignPlan::Kept::Home;
  }
  return plan;
}

Preset DeviceState::design_with(const std::map<std::string, double>& parameters,
                               const std::map<std::string, std::array<double, 2>>& limits_deg) const {
  Preset next = preset_;
  for (const auto& [name, value] : parameters) next.parameters[name] = value;
  for (const auto& [name, range] : limits_deg) next.limits_deg[name] = {range[0], range[1]};
  return next;
}

std::map<std::string, std::array<double, 2>> DeviceState::limits_deg() const {
  std::map<std::string, std::array<double, 2>> limits;
  for (const Quantity& a : mechanism_->info().actuators) limits[a.name] = {a.range.lo / kDeg, a.range.hi / kDeg};
  return limits;
}

void DeviceState::adopt(const DesignPlan& plan) {
  if (!plan.ok()) throw std::invalid_argument("a refused design cannot be adopted: " + plan.refusal);
  preset_ = plan.preset;
  mechanism_ = plan.mechanism;
  take(plan.q, plan.x, plan.branch);
}

bool DeviceState::set_actuator_limits(const std::map<std::string, std::array<double, 2>>& limits_deg,
                                      std::string& why) {
  const Preset next = design_with({}, limits_deg);
  try {
    mechanism_ = make_mechanism(next);
  } catch (const std::invalid_argument& e) {
    why = e.what();
    return false;
  }
  preset_ = next;
  // The pose is clamped into the new travel; where FK fails there, it stays.
  Eigen::VectorXd q = q_;
  const auto& actuators = mechanism_->info().actuators;
  for (std::size_t k = 0; k < actuators.size(); ++k)
    q(Eigen::Index(k)) = std::clamp(q(Eigen::Index(k)), actuators[k].range.lo, actuators[k].range.hi);
  if (!set_actuators(q)) take(q_, x_, branch_);
  return true;
}

bool DeviceState::takes_limits() const {
  Preset p = preset_;
  for (const Quantity& a : mechanism_->info().actuators)
    if (!p.limits_deg.count(a.name)) p.limits_deg[a.name] = {a.range.lo / kDeg, a.range.hi / kDeg};
  try {
    make_mechanism(p);
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

}  // namespace linkscape::gui
