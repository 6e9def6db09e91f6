#include "core/verify/legs.h"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "core/mechanisms/described/chain.h"
#include "core/mechanisms/described/kinematics.h"
#include "core/mechanisms/described/mechanism.h"
#include "core/verify/certifier.h"
#include "core/verify/matrix_bounds.h"
#include "core/verify/verify.h"

namespace linkscape::verify {

using Eigen::MatrixXd;
using Eigen::Vector3d;
using described::BranchRule;
using described::LegPattern;

namespace {

// The device calls a leg singular where the crank's reach line passes
// through its axis (1e-12 of its size), where its actuator's normalised
// entry of Jq falls to 1e-12, where a universal ball locks (the sine of the
// rod's angle to its first axis below 1e-10) and where Jx's condition
// estimate exceeds 1e12; proved boxes keep these margins from those sets.
constexpr double kAxisClearance = 1e-9;       // of the size
constexpr double kActuatorHold = 1e-9;        // |Jq_ii|, the device's unit wrench
constexpr double kLockSine2 = 1e-8;           // sin^2 of the rod's angle to the universal's first axis
constexpr double kJxConditionBound = 1e11;    // n c(Jq) c(M) bounds the device's estimate of c(Jx)
constexpr double kTravelMargin = 1e-12;       // of the size: a slide's travel

enum class Tri { Yes, No, Maybe };

// The enclosure sign and travel tests read. A point's value is its own
// (long double rounded to double: only the reference evaluation uses it,
// which decides nothing a proof rests on).
Interval enclosure(const Interval& v) { return v; }
Interval enclosure(const Dual& v) { return v.v; }
Interval enclosure(double v) { return Interval(v); }
Interval enclosure(long double v) { return Interval(double(v)); }

template <typename T>
using V3 = std::array<T, 3>;

template <typename T>
V3<T> constant(const Vector3d& v) {
  return {T(v.x()), T(v.y()), T(v.z())};
}
template <typename T>
V3<T> operator+(const V3<T>& a, const V3<T>& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
template <typename T>
V3<T> operator-(const V3<T>& a, const V3<T>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <typename T>
V3<T> scaled(const T& k, const V3<T>& a) {
  return {k * a[0], k * a[1], k * a[2]};
}
template <typename T>
T dot(const V3<T>& a, const V3<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <typename T>
V3<T> cross(const V3<T>& a, const V3<T>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <typename T>
T norm2(const V3<T>& a) {
  return sqr(a[0]) + sqr(a[1]) + sqr(a[2]);
}

// A point a branch rule reads, as the leg's closure places it.
struct RulePoint {
  enum class Kind { Constant, Ball, End, Anchor };
  Kind kind = Kind::Constant;
  Vector3d at = Vector3d::Zero();  // Constant
};

struct LegRule {
  BranchRule::Kind kind = BranchRule::Kind::Triple;
  std::array<RulePoint, 3> points{};
  Vector3d axis = Vector3d::UnitZ();  // Triple: the first step's axis; Along: the direction
  int wanted = 1;
};

// One leg's constants, base frame, with the platform at p = 0 (the joint
// centres move with p, the orientation and extras held).
struct LegGeometry {
  LegPattern pattern = LegPattern::CrankRod;
  std::string label, actuator_name;
  int actuator = 0;
  bool prismatic = false, limited = false;
  Range range;
  Vector3d centre, u, v;  // crank: its circle's centre and plane (v = axis x u)
  double rho = 0;         // crank radius
  Vector3d e0, slide;     // slide-rod: the ball at zero travel, the slide's direction
  Vector3d ball;          // extensible: the ball's centre
  double offset = 0;      // extensible: the slide's fixed length
  double rod = 0;         // crank-rod, slide-rod
  Vector3d end_offset, anchor_offset, joint_from_end;
  MatrixXd G;  // 3 x n: the joint centre's velocity per task rate
  // A universal ball's first axis: fixed + cos q along_cos + sin q along_sin.
  bool universal = false;
  Vector3d axis_fixed = Vector3d::Zero(), axis_cos = Vector3d::Zero(), axis_sin = Vector3d::Zero();
  std::vector<LegRule> rules;
};

template <typename T>
struct Kernel {
  enum class Failure { None, Unreachable, Excluded, Undecided };
  Failure failure = Failure::None;
  int leg = -1;
  bool travel = false;  // Excluded: some solution on the branch, outside the travel
  std::vector<T> M;     // n x n, row-major, a row per actuator
  std::vector<T> jq;    // the device's normalised Jq entries
};

// One of a leg's two solutions: the ball's centre, s . dE/dq and the actuator.
template <typename T>
struct Candidate {
  V3<T> ball;
  T rate, q, cos_q, sin_q;
};

}  // namespace

struct LegsCertifier::Model {
  std::string name, measure_title, not_covered;
  double size = 1;
  int n = 0;
  std::vector<int> translation_rows;  // of J, where the measure is cond(Jp)
  std::vector<LegGeometry> legs;
};

namespace {

using Model = LegsCertifier::Model;

template <typename T>
Tri rules_hold(const LegGeometry& g, const Candidate<T>& c, const V3<T>& w, const V3<T>& p) {
  Tri out = Tri::Yes;
  for (const LegRule& r : g.rules) {
    auto point = [&](const RulePoint& rp) -> V3<T> {
      switch (rp.kind) {
        case RulePoint::Kind::Ball: return c.ball;
        case RulePoint::Kind::End: return w;
        case RulePoint::Kind::Anchor: return p + constant<T>(g.anchor_offset);
        case RulePoint::Kind::Constant: break;
      }
      return constant<T>(rp.at);
    };
    T value;
    if (r.kind == BranchRule::Kind::Angle) value = c.sin_q;
    else if (r.kind == BranchRule::Kind::Along) value = dot(point(r.points[1]) - point(r.points[0]), constant<T>(r.axis));
    else {
      const V3<T> a = point(r.points[0]), b = point(r.points[1]);
      value = dot(cross(b - a, point(r.points[2]) - b), constant<T>(r.axis));
    }
    const Interval signed_value = Interval(double(r.wanted)) * enclosure(value);
    if (signed_value.hi < 0) return Tri::No;
    if (!(signed_value.lo > 0)) out = Tri::Maybe;
  }
  return out;
}

template <typename T>
Tri within_travel(const LegGeometry& g, const Candidate<T>& c, double size) {
  if (!g.limited) return Tri::Yes;
  if (g.prismatic) {
    const Interval q = enclosure(c.q), margin(kTravelMargin * size);
    if (q.lo >= (Interval(g.range.lo) + margin).hi && q.hi <= (Interval(g.range.hi) - margin).lo) return Tri::Yes;
    if (q.hi < (Interval(g.range.lo) - margin).lo || q.lo > (Interval(g.range.hi) + margin).hi) return Tri::No;
    return Tri::Maybe;
  }
  const Interval cq = enclosure(c.cos_q), sq = enclosure(c.sin_q);
  if (certainly_within(cq, sq, g.range, true)) return Tri::Yes;
  return certainly_outside(cq, sq, g.range, true) ? Tri::No : Tri::Maybe;
}

// Both solutions of a leg for its joint centre w, as the device's closed
// form orders them; false where the leg certainly does not reach (failure
// set) or might not (undecided).
template <typename T>
bool solutions(const LegGeometry& g, const V3<T>& w, double size, std::array<Candidate<T>, 2>& c,
               typename Kernel<T>::Failure& failure) {
  using std::sqrt;
  using Failure = typename Kernel<T>::Failure;
  const T tiny2(sqr(kAxisClearance * size));
  auto reach = [&](const T& discriminant) {
    const Interval e = enclosure(discriminant);
    if (e.lo > 0) return true;
    failure = e.hi < 0 ? Failure::Unreachable : Failure::Undecided;
    return false;
  };
  if (g.pattern == LegPattern::CrankRod) {
    // |w - E(q)| = rod with E on the crank's circle: du cos q + dv sin q = K.
    const V3<T> d = w - constant<T>(g.centre);
    const T du = dot(constant<T>(g.u), d), dv = dot(constant<T>(g.v), d), D2 = sqr(du) + sqr(dv);
    if (!(enclosure(D2 - tiny2).lo > 0)) {  // on the crank's axis the device solves numerically
      failure = Failure::Undecided;
      return false;
    }
    const T rho(g.rho);
    const T K = (norm2(d) + (sqr(rho) - sqr(T(g.rod)))) / (T(2.0) * rho);
    const T S2 = D2 - sqr(K);
    if (!reach(S2)) return false;
    const T S = sqrt(S2);
    for (int k = 0; k < 2; ++k) {  // q = atan2(dv, du) +- acos(K / D)
      const T sigma(k == 0 ? 1.0 : -1.0);
      const T eu = rho * (K * du - sigma * dv * S) / D2, ev = rho * (K * dv + sigma * du * S) / D2;
      c[std::size_t(k)] = {constant<T>(g.centre) + scaled(eu, constant<T>(g.u)) + scaled(ev, constant<T>(g.v)),
                           -(sigma * rho * S), T(0.0), eu / rho, ev / rho};
    }
    return true;
  }
  if (g.pattern == LegPattern::SlideRod) {
    // |e0 + q slide - w| = rod.
    const V3<T> gap = constant<T>(g.e0) - w;
    const T b = dot(constant<T>(g.slide), gap);
    const T S2 = sqr(T(g.rod)) - (norm2(gap) - sqr(b));
    if (!reach(S2)) return false;
    const T root = sqrt(S2);
    for (int k = 0; k < 2; ++k) {
      const T sigma(k == 0 ? 1.0 : -1.0);
      const T q = sigma * root - b;
      c[std::size_t(k)] = {constant<T>(g.e0) + scaled(q, constant<T>(g.slide)), -(sigma * root), q, T(1.0), T(0.0)};
    }
    return true;
  }
  // Extensible: the slide along +d, or the ball turned over, along -d.
  const V3<T> d = w - constant<T>(g.ball);
  const T n2 = norm2(d);
  if (!(enclosure(n2 - tiny2).lo > 0)) {
    failure = Failure::Undecided;
    return false;
  }
  const T n = sqrt(n2);
  for (int k = 0; k < 2; ++k) {
    const T sigma(k == 0 ? 1.0 : -1.0);
    c[std::size_t(k)] = {constant<T>(g.ball), sigma * n, sigma * n - T(g.offset), T(1.0), T(0.0)};
  }
  return true;
}

template <typename T>
Kernel<T> kernel(const Model& m, const T& x, const T& y, const T& z) {
  using std::sqrt;
  using Failure = typename Kernel<T>::Failure;
  Kernel<T> out;
  const std::size_t n = std::size_t(m.n);
  out.M.assign(n * n, T(0.0));
  out.jq.assign(n, T(0.0));
  const V3<T> p{x, y, z};
  for (std::size_t i = 0; i < m.legs.size(); ++i) {
    const LegGeometry& g = m.legs[i];
    auto fail = [&](Failure f) {
      out.failure = f;
      out.leg = int(i);
      return out;
    };
    const V3<T> w = p + constant<T>(g.end_offset);
    std::array<Candidate<T>, 2> c;
    Failure failure = Failure::None;
    if (!solutions(g, w, m.size, c, failure)) return fail(failure);
    // The device keeps the first solution on the branch within the travel.
    int chosen = -1;
    bool on_branch = false;
    for (int k = 0; k < 2 && chosen < 0; ++k) {
      const Tri rules = rules_hold(g, c[std::size_t(k)], w, p), travel = within_travel(g, c[std::size_t(k)], m.size);
      on_branch = on_branch || rules != Tri::No;
      if (rules == Tri::Yes && travel == Tri::Yes) chosen = k;
      else if (rules != Tri::No && travel != Tri::No) return fail(Failure::Undecided);
    }
    if (chosen < 0) {
      out.travel = on_branch;
      return fail(Failure::Excluded);
    }
    const Candidate<T>& s_k = c[std::size_t(chosen)];
    const V3<T> s = w - s_k.ball;
    if (g.universal) {
      const V3<T> first = constant<T>(g.axis_fixed) + scaled(s_k.cos_q, constant<T>(g.axis_cos)) +
                          scaled(s_k.sin_q, constant<T>(g.axis_sin));
      if (!(enclosure(norm2(cross(first, s)) - T(kLockSine2) * norm2(s)).lo > 0)) return fail(Failure::Undecided);
    }
    // The device's unit wrench along the rod about the chain's end, and its actuator's entry of Jq.
    const T wrench = sqrt(norm2(cross(constant<T>(g.joint_from_end), s)) + sqr(T(m.size)) * norm2(s));
    const T jq = s_k.rate / wrench;
    const Interval hold = enclosure(jq);
    if (!(hold.lo > kActuatorHold || hold.hi < -kActuatorHold)) return fail(Failure::Undecided);
    out.jq[i] = jq;
    for (int col = 0; col < m.n; ++col) {
      T sum(0.0);
      for (int k = 0; k < 3; ++k) sum += s[std::size_t(k)] * T(g.G(k, col));
      out.M[std::size_t(g.actuator) * n + std::size_t(col)] = sum / s_k.rate;
    }
  }
  return out;
}

// The measure of a point M in floating point: c(M), or c of M^-1's translational rows.
template <typename F>
F measure_of(const Model& m, const std::vector<F>& flat) {
  using Matrix = Eigen::Matrix<F, Eigen::Dynamic, Eigen::Dynamic>;
  Matrix M(m.n, m.n);
  for (int i = 0; i < m.n; ++i)
    for (int j = 0; j < m.n; ++j) M(i, j) = flat[std::size_t(i * m.n + j)];
  auto condition = [](const Matrix& A) {
    const auto s = Eigen::JacobiSVD<Matrix>(A).singularValues();
    return s(s.size() - 1) > 0 ? F(s(0) / s(s.size() - 1)) : std::numeric_limits<F>::infinity();
  };
  if (m.translation_rows.empty()) return condition(M);
  const Eigen::FullPivLU<Matrix> lu(M);
  if (!lu.isInvertible()) return std::numeric_limits<F>::infinity();
  const Matrix J = lu.inverse();
  Matrix Jp(Eigen::Index(m.translation_rows.size()), m.n);
  for (std::size_t r = 0; r < m.translation_rows.size(); ++r) Jp.row(Eigen::Index(r)) = J.row(m.translation_rows[r]);
  return condition(Jp);
}

// Bounds on the measure for every M whose entries are within `deviation`
// (magnitudes) of M_c's: [lower, upper] (lower 0, upper +inf where the
// enclosure cannot tell).
struct MeasureBounds {
  double lower = 0, upper = kInf;
  double condition_M = kInf;  // an upper bound on c(M)
};
MeasureBounds measure_bounds(const Model& m, const MatrixXd& M_c, const MatrixXd& deviation) {
  MeasureBounds out;
  const double r = spectral_norm_bound(deviation);
  const SpectrumBounds s = spectrum_bounds(M_c);
  const double smallest = down(s.smallest_lower - r);
  if (smallest > 0) out.condition_M = up(up(s.largest_upper + r) / smallest);
  auto ratio_bounds = [&](const SpectrumBounds& b, double spread) {
    const double low = down(b.smallest_lower - spread), high_lower = down(b.largest_lower - spread);
    if (low > 0) out.upper = up(up(b.largest_upper + spread) / low);
    if (high_lower > 0) out.lower = down(high_lower / up(b.smallest_upper + spread));
  };
  if (m.translation_rows.empty()) {
    ratio_bounds(s, r);
    return out;
  }
  // With X ~ M_c^-1 and rho >= |I - M(p) X| (|I - M_c X| plus |M(p) - M_c| |X|
  // entry by entry): J(p) - X = M(p)^-1 (I - M(p) X) has norm at most
  // rho / sigma_min(M(p)), and its translational rows Jp(p) - Xp =
  // Jp(p) (I - M(p) X) at most sigma_1(Xp) rho / (1 - rho).
  if (!(smallest > 0)) return out;
  const MatrixXd X = M_c.fullPivLu().inverse();
  MatrixXd spread_of_product(m.n, m.n);
  for (int i = 0; i < m.n; ++i)
    for (int j = 0; j < m.n; ++j) {
      Interval sum(0.0);
      for (int k = 0; k < m.n; ++k) sum += Interval(deviation(i, k)) * Interval(std::abs(X(k, j)));
      spread_of_product(i, j) = sum.hi;
    }
  const double rho = up(inverse_residual_bound(M_c, X) + spectral_norm_bound(spread_of_product));
  MatrixXd Xp(Eigen::Index(m.translation_rows.size()), m.n);
  for (std::size_t k = 0; k < m.translation_rows.size(); ++k) Xp.row(Eigen::Index(k)) = X.row(m.translation_rows[k]);
  const SpectrumBounds sp = spectrum_bounds(Xp);
  double spread = up(rho / smallest);
  if (rho < 1) spread = std::min(spread, up(up(sp.largest_upper * rho) / down(1 - rho)));
  ratio_bounds(sp, spread);
  return out;
}

}  // namespace

namespace {

// Where a rule's step is at a closure: a joint centre fixed to the base (at
// or before the leg's first moving centre), the ball, the last joint, the
// anchor; nullopt where the certifier does not follow it.
std::optional<RulePoint> rule_point(const described::ClosedFormLeg& form, const described::internal::Chain& at_zero,
                                    int step) {
  if (step == -2) return RulePoint{RulePoint::Kind::Anchor, Vector3d::Zero()};
  if (step == form.end_step) return RulePoint{RulePoint::Kind::End, Vector3d::Zero()};
  // The actuator's centre and those before it stay (an extensible leg's ball comes first).
  if (step >= 0 && step <= form.actuator_step) return RulePoint{RulePoint::Kind::Constant, at_zero.step_centre[std::size_t(step)]};
  if (step == form.ball_step || (form.ball_joints == 2 && step == form.ball_step + 1))
    return RulePoint{RulePoint::Kind::Ball, Vector3d::Zero()};
  return std::nullopt;
}

// The leg's constants from its closed form at the pose with p = 0.
LegGeometry leg_geometry(const described::Kinematics& kin, int leg, const described::PlatformPose& pose, int branch,
                         const std::string& device) {
  const described::Model& model = kin.model();
  const described::Leg& l = model.legs[std::size_t(leg)];
  const described::ClosedFormLeg& form = *kin.closed_form(leg);
  const described::Actuator& act = model.actuators[std::size_t(l.actuators.front())];
  LegGeometry g;
  g.pattern = form.pattern;
  g.label = l.label();
  g.actuator_name = act.name;
  g.actuator = l.actuators.front();
  g.prismatic = act.prismatic;
  g.limited = act.limited;
  g.range = act.range;
  const Eigen::Isometry3d anchor = kin.anchor(leg, pose);
  g.anchor_offset = anchor.translation();
  g.end_offset = (anchor * form.tail.inverse()).translation();
  g.joint_from_end = g.end_offset - g.anchor_offset;
  g.G = model.size * described::internal::platform_columns(model, pose, g.end_offset).bottomRows(3);
  g.rod = form.rod.translation().norm();
  const Eigen::Matrix3d Rb = form.base.linear();
  const Vector3d a = Rb * form.actuator_axis, o = form.base.translation();
  const described::Step& ball = l.steps[std::size_t(form.ball_step)];
  g.universal = form.ball_joints == 2 && ball.kind == described::Step::Kind::Revolute;
  if (form.pattern == LegPattern::CrankRod) {
    const Vector3d p0 = form.base * form.after_actuator.translation();
    g.centre = o + a * a.dot(p0 - o);
    g.rho = (p0 - g.centre).norm();
    g.u = (p0 - g.centre) / g.rho;
    g.v = a.cross(g.u);
    // The universal's first axis turns with the crank: R(q) f = cos q (f - (x.f) x) + sin q (x ^ f) + (x.f) x.
    const Vector3d x = form.actuator_axis, f = form.after_actuator.linear() * ball.axis;
    g.axis_fixed = Rb * (x.dot(f) * x);
    g.axis_cos = Rb * (f - x.dot(f) * x);
    g.axis_sin = Rb * x.cross(f);
  } else if (form.pattern == LegPattern::SlideRod) {
    g.e0 = form.base * form.after_actuator.translation();
    g.slide = a;
    g.axis_fixed = Rb * form.after_actuator.linear() * ball.axis;
  } else {
    g.ball = o;
    g.offset = form.offset;
    g.axis_fixed = Rb * ball.axis;
  }
  described::LegState zero;
  zero.values = Eigen::VectorXd::Zero(l.variables);
  zero.spheres.assign(std::size_t(l.spheres), Eigen::Matrix3d::Identity());
  const described::internal::Chain at_zero = described::internal::walk(l, zero);
  for (const BranchRule& r : l.rules) {
    LegRule rule;
    rule.kind = r.kind;
    rule.wanted = r.fixed_sign != 0 ? r.fixed_sign : ((branch >> r.free_index) & 1) ? -1 : 1;
    const int count = r.kind == BranchRule::Kind::Triple ? 3 : r.kind == BranchRule::Kind::Along ? 2 : 0;
    bool followed = r.kind != BranchRule::Kind::Angle ||
                    (form.pattern == LegPattern::CrankRod && r.steps[0] == form.actuator_step);
    for (int k = 0; k < count && followed; ++k) {
      const std::optional<RulePoint> point = rule_point(form, at_zero, r.steps[std::size_t(k)]);
      followed = point.has_value();
      if (point) rule.points[std::size_t(k)] = *point;
    }
    if (r.kind == BranchRule::Kind::Along) rule.axis = r.direction;
    if (r.kind == BranchRule::Kind::Triple) {
      // The axis of a step fixed to the base (the actuator or one before it).
      followed = followed && r.steps[0] >= 0 && r.steps[0] <= std::min(form.actuator_step, form.ball_step);
      if (followed) rule.axis = at_zero.step_axis[std::size_t(r.steps[0])];
    }
    if (!followed)
      throw Uncertifiable("verify: '" + device + "' cannot be certified: a branch rule of " + l.label() +
                          " reads a joint whose place the certifier does not follow (it follows the base, the "
                          "actuator, the ball, the last joint and the anchor)");
    g.rules.push_back(rule);
  }
  return g;
}

}  // namespace

Preset without_stops(const Preset& preset) {
  nlohmann::json description = nlohmann::json::parse(preset.description);
  // A passive joint's range_deg, ranges_deg or cone, and a link's radius and name.
  const std::function<void(nlohmann::json&)> strip = [&](nlohmann::json& j) {
    if (j.is_object()) {
      if (j.contains("joint") && !j.value("actuated", false))
        for (const char* key : {"range_deg", "ranges_deg", "cone"}) j.erase(key);
      if (j.contains("translate"))
        for (const char* key : {"radius", "link"}) j.erase(key);
    }
    if (j.is_structured())
      for (nlohmann::json& child : j) strip(child);
  };
  strip(description);
  Preset out = preset;
  out.description = description.dump();
  return out;
}

std::shared_ptr<const LegsCertifier> LegsCertifier::from_preset(const Preset& preset, int branch) {
  const std::string device = preset.source.empty() ? std::string(described::kMechanismName) : preset.source.stem().string();
  const described::Kinematics kin(
      described::build_model(preset.description, preset.parameters, preset.limits_deg, preset.length_unit));
  const described::Model& model = kin.model();
  const std::string refused = "verify: '" + device + "' cannot be certified: ";
  if (model.planar)
    throw Uncertifiable(refused + "it is planar (certified checks cover spatial devices whose legs are crank-rod, "
                                  "slide-rod or extensible)");
  if (model.task.size() < 3 || model.task[0].platform_coordinate != 0 || model.task[1].platform_coordinate != 1 ||
      model.task[2].platform_coordinate != 2)
    throw Uncertifiable(refused + "its task does not begin with x, y, z");
  std::string blocked;
  for (std::size_t i = 0; i < model.legs.size(); ++i) {
    const described::ClosedFormLeg* form = kin.closed_form(int(i));
    const LegPattern p = form ? form->pattern : LegPattern::Numeric;
    std::string why;
    if (p != LegPattern::CrankRod && p != LegPattern::SlideRod && p != LegPattern::Extensible)
      why = described::pattern_name(p);
    else if (form->end_joints == 2)  // its leg also holds the platform's orientation
      why = described::pattern_name(p) + " ending in a universal joint";
    if (!why.empty()) blocked += (blocked.empty() ? "" : ", ") + model.legs[i].label() + " (" + why + ")";
  }
  if (!blocked.empty())
    throw Uncertifiable(refused + "not every leg is of a certified pattern: " + blocked +
                        " (certified: crank-rod, slide-rod and extensible legs)");
  if (int(model.actuators.size()) != model.driven() || model.legs.size() != model.actuators.size())
    throw Uncertifiable(refused + "it does not have one actuator per leg and per driven task coordinate");
  if (branch < 0 || branch >= kin.branches())
    throw std::invalid_argument("verify: " + device + " has branches 0.." + std::to_string(kin.branches() - 1) +
                                ", got " + std::to_string(branch));
  auto m = std::make_unique<Model>();
  m->name = device;
  m->size = model.size;
  m->n = model.driven();
  int rotations = 0, row = 0;
  for (const described::TaskCoordinate& c : model.task) {
    if (c.extra >= 0) continue;
    rotations += c.platform_coordinate >= 3;
    if (c.platform_coordinate < 3) m->translation_rows.push_back(row);
    ++row;
  }
  // As the device measures it (mechanism.cpp): c(J), or with two or more
  // rotations in its task the condition number of J's translational rows.
  m->measure_title = rotations >= 2 ? "cond(Jp)" : "c(J)";
  if (rotations < 2) m->translation_rows.clear();
  if (kin.has_joint_limits()) m->not_covered = "its passive-joint limits";
  if (kin.has_capsules()) m->not_covered += (m->not_covered.empty() ? "" : " and ") + std::string("link interference");
  Eigen::VectorXd x = model.home;
  x.head<3>().setZero();
  const described::PlatformPose pose = kin.pose(x);
  for (int i = 0; i < int(model.legs.size()); ++i) m->legs.push_back(leg_geometry(kin, i, pose, branch, device));
  return std::shared_ptr<const LegsCertifier>(new LegsCertifier(std::move(m)));
}

LegsCertifier::LegsCertifier(std::unique_ptr<const Model> model) : model_(std::move(model)) {}
LegsCertifier::~LegsCertifier() = default;

const std::string& LegsCertifier::measure_title() const { return model_->measure_title; }
const std::string& LegsCertifier::not_covered() const { return model_->not_covered; }

std::optional<double> LegsCertifier::condition_bound(const Vector3d& lo, const Vector3d& hi, double bound) const {
  const Model& m = *model_;
  const Kernel<Dual> box = kernel(m, Dual::variable({lo.x(), hi.x()}, 0), Dual::variable({lo.y(), hi.y()}, 1),
                                  Dual::variable({lo.z(), hi.z()}, 2));
  if (box.failure != Kernel<Dual>::Failure::None) return std::nullopt;
  const Vector3d c = (0.5 * lo + 0.5 * hi).cwiseMax(lo).cwiseMin(hi);
  const Kernel<Interval> at_mid = kernel(m, Interval(c.x()), Interval(c.y()), Interval(c.z()));
  if (at_mid.failure != Kernel<Interval>::Failure::None) return std::nullopt;
  double half_width[3];
  for (int k = 0; k < 3; ++k) half_width[k] = up(std::max(c(k) - lo(k), hi(k) - c(k)));
  // M(p) - M_c over the box, enclosed twice (the box's own enclosure and the
  // mean value form); each holds it, so their intersection does.
  MatrixXd M_c(m.n, m.n), deviation(m.n, m.n);
  for (int i = 0; i < m.n; ++i)
    for (int j = 0; j < m.n; ++j) {
      const std::size_t k = std::size_t(i * m.n + j);
      M_c(i, j) = at_mid.M[k].mid();
      Interval mean_value = at_mid.M[k] - Interval(M_c(i, j));
      for (int a = 0; a < 3; ++a) mean_value += box.M[k].d[a] * Interval(-half_width[a], half_width[a]);
      deviation(i, j) = intersect(box.M[k].v - Interval(M_c(i, j)), mean_value).mag();
    }
  const MeasureBounds b = measure_bounds(m, M_c, deviation);
  if (!(b.upper < bound)) return std::nullopt;
  // Away from where the device's estimate of c(Jx) calls the pose singular.
  double held_most = 0, held_least = kInf;
  for (const Dual& jq : box.jq) {  // each certainly away from 0 (the kernel checked)
    held_most = std::max(held_most, jq.v.mag());
    held_least = std::min({held_least, std::abs(jq.v.lo), std::abs(jq.v.hi)});
  }
  const double jq_condition = up(held_most / held_least);
  if (!(up(up(double(m.n) * jq_condition) * b.condition_M) < kJxConditionBound)) return std::nullopt;
  return b.upper;
}

std::optional<LegsCertifier::Failure> LegsCertifier::certain_failure(const Vector3d& p, double bound) const {
  const Model& m = *model_;
  const Kernel<Interval> at = kernel(m, Interval(p.x()), Interval(p.y()), Interval(p.z()));
  using F = Kernel<Interval>::Failure;
  if (at.failure == F::Undecided) return std::nullopt;
  if (at.failure != F::None) {
    const LegGeometry& g = m.legs[std::size_t(at.leg)];
    if (at.failure == F::Unreachable) return Failure{kInf, "out of reach (" + g.label + " cannot close)"};
    return Failure{kInf, at.travel ? "outside the travel of " + g.actuator_name
                                   : g.label + " closes only on another branch"};
  }
  MatrixXd mid(m.n, m.n), radius(m.n, m.n);
  for (int i = 0; i < m.n; ++i)
    for (int j = 0; j < m.n; ++j) {
      const Interval& e = at.M[std::size_t(i * m.n + j)];
      mid(i, j) = e.mid(), radius(i, j) = e.rad();
    }
  const double lower = measure_bounds(m, mid, radius).lower;
  if (!(lower >= bound)) return std::nullopt;
  std::ostringstream reason;
  reason.precision(6);
  reason << m.measure_title << " >= " << lower;
  return Failure{lower, reason.str()};
}

double LegsCertifier::badness(const Vector3d& p, double bound) const {
  const Kernel<double> at = kernel(*model_, p.x(), p.y(), p.z());
  if (at.failure != Kernel<double>::Failure::None) return kInf;
  return measure_of(*model_, at.M) / bound;
}

long double LegsCertifier::reference_measure(const Vector3d& p) const {
  using LD = long double;
  const Kernel<LD> at = kernel(*model_, LD(p.x()), LD(p.y()), LD(p.z()));
  if (at.failure != Kernel<LD>::Failure::None) return std::numeric_limits<LD>::infinity();
  return measure_of(*model_, at.M);
}

}  // namespace linkscape::verify
