#include "core/mechanisms/described/closed_form.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace linkscape::described {
namespace {

using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Kind = Step::Kind;

// A leg's steps grouped: runs of fixed steps merged, a universal's halves as one joint.
struct Token {
  enum class Type { Fixed, Revolute, Universal, Spherical, Prismatic };
  Type type = Type::Fixed;
  int step = 0;  // the first step
  bool actuated = false;
  Isometry3d fixed = Isometry3d::Identity();
};
using Type = Token::Type;

}  // namespace

bool meets_as_universal(const Leg& leg, std::size_t step) {
  if (step + 1 >= leg.steps.size()) return false;
  const Step &a = leg.steps[step], &b = leg.steps[step + 1];
  return a.kind == Kind::Revolute && b.kind == Kind::Revolute && a.actuator < 0 && b.actuator < 0 &&
         a.joint != b.joint && a.axis.cross(b.axis).norm() > 1e-6;
}

namespace {

std::vector<Token> tokens_of(const Leg& leg) {
  std::vector<Token> out;
  for (std::size_t i = 0; i < leg.steps.size(); ++i) {
    const Step& s = leg.steps[i];
    if (s.kind == Kind::Fixed) {
      if (out.empty() || out.back().type != Type::Fixed) out.push_back({Type::Fixed, int(i), false, Isometry3d::Identity()});
      out.back().fixed = out.back().fixed * s.transform;
      continue;
    }
    if (s.kind == Kind::Revolute && !out.empty() && out.back().type == Type::Revolute &&
        (leg.steps[std::size_t(out.back().step)].joint == s.joint || meets_as_universal(leg, i - 1))) {
      out.back().type = Type::Universal;
      continue;
    }
    const Type t = s.kind == Kind::Revolute ? Type::Revolute : s.kind == Kind::Prismatic ? Type::Prismatic : Type::Spherical;
    out.push_back({t, int(i), s.actuator >= 0, Isometry3d::Identity()});
  }
  return out;
}

// Matches tokens against a pattern of joint types, each joint optionally
// preceded by fixed steps; fills the fixed transform before each joint and
// after the last (identity where absent).
bool match(const std::vector<Token>& tokens, const std::vector<Type>& joints, std::vector<const Token*>& found,
           std::vector<Isometry3d>& between) {
  found.clear();
  between.assign(joints.size() + 1, Isometry3d::Identity());
  std::size_t t = 0;
  for (std::size_t j = 0; j <= joints.size(); ++j) {
    if (t < tokens.size() && tokens[t].type == Type::Fixed) between[j] = tokens[t++].fixed;
    if (j == joints.size()) break;
    if (t >= tokens.size() || tokens[t].type != joints[j]) return false;
    found.push_back(&tokens[t++]);
  }
  return t == tokens.size();
}

bool pure_translation(const Isometry3d& T) { return T.linear().isApprox(Matrix3d::Identity(), 1e-14); }

// The angle that turns p about unit a onto q (their parts across a).
double turn(const Vector3d& a, const Vector3d& p, const Vector3d& q) {
  const Vector3d pp = p - a * a.dot(p), qq = q - a * a.dot(q);
  return std::atan2(a.dot(pp.cross(qq)), pp.dot(qq));
}

// Paden-Kahan subproblem 2: the angles (t1, t2) with exp(a1 t1) exp(a2 t2) p
// = q, |p| = |q|, axes through one point; up to two solutions.
int two_axes(const Vector3d& a1, const Vector3d& a2, const Vector3d& p, const Vector3d& q,
             std::array<std::array<double, 2>, 2>& out) {
  const double c = a1.dot(a2), s2 = 1 - c * c;
  if (s2 < 1e-12) return 0;
  const double alpha = (c * a2.dot(p) - a1.dot(q)) / (c * c - 1);
  const double beta = (c * a1.dot(q) - a2.dot(p)) / (c * c - 1);
  double g2 = (p.squaredNorm() - alpha * alpha - beta * beta - 2 * alpha * beta * c) / s2;
  if (g2 < 0) {
    if (g2 < -1e-12 * p.squaredNorm()) return 0;
    g2 = 0;
  }
  const Vector3d n = a1.cross(a2);
  const int count = g2 > 0 ? 2 : 1;
  for (int k = 0; k < count; ++k) {
    const Vector3d z = alpha * a1 + beta * a2 + (k == 0 ? 1 : -1) * std::sqrt(g2) * n;
    out[std::size_t(k)] = {turn(a1, z, q), turn(a2, p, z)};
  }
  return count;
}

// Solutions of B cos t + C sin t = K.
int harmonic(double B, double C, double K, std::array<double, 2>& t) {
  const double R = std::hypot(B, C);
  if (R == 0) return 0;
  const double phi = std::atan2(C, B), ratio = std::clamp(K / R, -1.0, 1.0);
  const double half = std::acos(ratio);
  t = {phi + half, phi - half};
  return half > 0 ? 2 : 1;
}

struct Builder {
  const ClosedFormLeg& form;
  const Model& model;
  const Leg& leg;
  const Isometry3d& anchor;
  LegCandidates& out;
  bool leave_ends_open = false;
  int branch = -1;  // >= 0: leave out the solutions its angle rules reject

  // Whether `value` of the joint at `step` keeps the branch's angle rules on it.
  bool angle_kept(int step, double value) {
    if (branch < 0) return true;
    for (const BranchRule& r : leg.rules) {
      if (r.kind != BranchRule::Kind::Angle || r.steps[0] != step) continue;
      if (sine_sign(value) * wanted_sign(r, branch) < 0) {
        out.dropped = true;
        return false;
      }
    }
    return true;
  }

  int var(int step) const { return leg.steps[std::size_t(step)].variable; }
  int sphere_index(int step) const {
    int k = 0;
    for (int i = 0; i < step; ++i) k += leg.steps[std::size_t(i)].kind == Kind::Spherical;
    return k;
  }
  LegState& fresh(const LegState& from) {
    out.open[std::size_t(out.count)] = false;
    LegState& s = out.states[std::size_t(out.count++)];
    s.values = from.values;
    s.spheres = from.spheres;
    return s;
  }
  // Closes the last joint of the candidate just made (dropping it where a
  // universal end cannot take the anchor's orientation), or leaves it open.
  void end_at(LegState& s, const Isometry3d& at) {
    if (!leave_ends_open) {
      if (!close_end(s, at)) --out.count;
      return;
    }
    const std::size_t i = std::size_t(out.count - 1);
    out.end_frames[i] = at;
    out.open[i] = true;
  }
  // Sets the last joint so that the chain's end frame is the anchor frame;
  // `at` is the frame at the last joint before it turns. False where a
  // universal end cannot turn by the rotation asked of it.
  bool close_end(LegState& s, const Isometry3d& at) const {
    const Matrix3d M = at.linear().transpose() * anchor.linear() * form.tail.linear().transpose();
    if (form.end_joints == 2) return close_universal_end(s, M);
    if (leg.steps[std::size_t(form.end_step)].kind == Kind::Spherical) s.spheres[std::size_t(sphere_index(form.end_step))] = M;
    else s.values(var(form.end_step)) = std::atan2(M(1, 0), M(0, 0));  // a planar revolute about z
    return true;
  }
  // exp(b1 t1) exp(b2 t2) = M for the universal's square axes b1, b2: M b2 =
  // exp(b1 t1) b2 gives t1 (b2's part along b1 must be kept), the rest is a
  // turn about b2; within 1e-10 (the solver's tolerance) or none.
  bool close_universal_end(LegState& s, const Matrix3d& M) const {
    const Vector3d b1 = leg.steps[std::size_t(form.end_step)].axis, b2 = leg.steps[std::size_t(form.end_step + 1)].axis;
    const double t1 = turn(b1, b2, M * b2);
    const Matrix3d rest = Eigen::AngleAxisd(-t1, b1).toRotationMatrix() * M;
    const double t2 = turn(b2, b1, rest * b1);
    if (!((rest - Eigen::AngleAxisd(t2, b2).toRotationMatrix()).norm() <= 1e-10)) return false;
    s.values(var(form.end_step)) = t1;
    s.values(var(form.end_step + 1)) = t2;
    return true;
  }
  // The ball at frame `at` (its centre) turned so that `link` (ball frame)
  // points along `direction` (base frame), then the last joint closed, `after`
  // leading from the ball to it: one candidate per way the ball can do it.
  void point_ball(const LegState& partial, const Isometry3d& at, const Vector3d& link, const Vector3d& direction,
                  const Isometry3d& after) {
    const Vector3d wanted = at.linear().transpose() * direction;
    const Step& first = leg.steps[std::size_t(form.ball_step)];
    if (first.kind == Kind::Spherical) {
      LegState& s = fresh(partial);
      const Matrix3d Rb = Eigen::Quaterniond::FromTwoVectors(link, wanted).toRotationMatrix();
      s.spheres[std::size_t(sphere_index(form.ball_step))] = Rb;
      end_at(s, at * Isometry3d(Rb) * after);
      return;
    }
    if (form.ball_joints == 1) {  // planar revolute about z
      LegState& s = fresh(partial);
      const double angle = std::atan2(link.x() * wanted.y() - link.y() * wanted.x(), link.dot(wanted));
      s.values(var(form.ball_step)) = angle;
      end_at(s, at * Eigen::AngleAxisd(angle, first.axis) * after);
      return;
    }
    const Step& second = leg.steps[std::size_t(form.ball_step + 1)];
    std::array<std::array<double, 2>, 2> angles{};
    // The universal's second way to point the link differs only in its own
    // angles: needed only where a branch rule reads them.
    // A universal end needs both where its axes cannot undo the half turn
    // about the rod by which the two differ.
    const int n = std::min(two_axes(first.axis, second.axis, link.normalized(), wanted.normalized(), angles),
                           form.ball_read || form.end_joints == 2 ? 2 : 1);
    for (int k = 0; k < n; ++k) {
      LegState& s = fresh(partial);
      s.values(var(form.ball_step)) = angles[std::size_t(k)][0];
      s.values(var(form.ball_step + 1)) = angles[std::size_t(k)][1];
      const Matrix3d Rb = (Eigen::AngleAxisd(angles[std::size_t(k)][0], first.axis) *
                           Eigen::AngleAxisd(angles[std::size_t(k)][1], second.axis))
                              .toRotationMatrix();
      end_at(s, at * Isometry3d(Rb) * after);
    }
  }
  // The rod from the ball at `at` to the last joint's centre w.
  void point_rod(const LegState& partial, const Isometry3d& at, const Vector3d& w) {
    point_ball(partial, at, form.rod.translation(), w - at.translation(), form.rod);
  }

  // The last joint's centre the anchor asks for.
  // (The translation of anchor * tail^-1, without its rotation.)
  Vector3d end_centre() const { return anchor.linear() * form.tail.inverse().translation() + anchor.translation(); }

  void crank_rod(LegState& partial) {
    const Vector3d a = form.base.linear() * form.actuator_axis, o = form.base.translation();
    const Vector3d p0 = form.base * form.after_actuator.translation();
    const Vector3d centre = o + a * a.dot(p0 - o), r0 = p0 - centre;
    const double rho = r0.norm(), L = form.rod.translation().norm();
    const Vector3d u = r0 / rho, v = a.cross(u), w = end_centre(), d = w - centre;
    const double du = u.dot(d), dv = v.dot(d), R = std::hypot(du, dv), dd = d.squaredNorm() + rho * rho;
    const double nearest = std::sqrt(std::max(0.0, dd - 2 * rho * R)), farthest = std::sqrt(dd + 2 * rho * R);
    if (L < nearest || L > farthest) {
      out.miss = std::max(nearest - L, L - farthest);
      return;
    }
    if (R <= 1e-12 * model.size) {  // the rod's end on the crank's axis: every angle or none
      out.undecided = true;
      return;
    }
    std::array<double, 2> t{};
    const int n = harmonic(du, dv, (dd - L * L) / (2 * rho), t);
    for (int k = 0; k < n; ++k) {
      partial.values(var(form.actuator_step)) = t[std::size_t(k)];
      const Isometry3d at = form.base * Eigen::AngleAxisd(t[std::size_t(k)], form.actuator_axis) * form.after_actuator;
      point_rod(partial, at, w);
    }
  }

  void slide_rod(LegState& partial) {
    const Vector3d s = form.base.linear() * form.actuator_axis;
    const Vector3d e0 = form.base * form.after_actuator.translation(), w = end_centre(), g = e0 - w;
    const double L = form.rod.translation().norm(), b = s.dot(g), h2 = g.squaredNorm() - b * b;
    if (h2 > L * L) {
      out.miss = std::sqrt(h2) - L;
      return;
    }
    const double root = std::sqrt(std::max(0.0, L * L - h2));
    for (double q : {-b + root, -b - root}) {
      partial.values(var(form.actuator_step)) = q;
      Isometry3d at = form.base;
      at.translation() += s * q;
      point_rod(partial, at * form.after_actuator, w);
      if (root == 0) break;
    }
  }

  void extensible(LegState& partial) {
    const Vector3d axis = leg.steps[std::size_t(form.actuator_step)].axis;
    const Vector3d d = end_centre() - form.base.translation();
    const double n = d.norm();
    if (n <= 1e-12 * model.size) {
      out.undecided = true;
      return;
    }
    // The slide along +d or, the ball turned over, along -d.
    for (double sign : {1.0, -1.0}) {
      const double q = sign * n - form.offset;
      partial.values(var(form.actuator_step)) = q;
      point_ball(partial, form.base, axis, sign * d, form.after_actuator * Eigen::Translation3d(axis * q) * form.rod);
    }
  }

  void three_revolute(LegState& partial) {
    const Vector3d a3 = leg.steps[std::size_t(form.third_step)].axis;
    const Vector3d t2 = form.second_link, t3 = form.third_link;
    const Vector3d c2 = form.base * form.after_actuator.translation(), w = end_centre();
    const Vector3d g = form.base.linear().transpose() * (w - c2);
    // |t2 + R3(t) t3| = |g| fixes the third angle.
    const double A = t2.dot(a3) * a3.dot(t3), B = t2.dot(t3) - A, C = t2.dot(a3.cross(t3));
    const double K = 0.5 * (g.squaredNorm() - t2.squaredNorm() - t3.squaredNorm()) - A, R = std::hypot(B, C);
    const double nearest = std::sqrt(std::max(0.0, t2.squaredNorm() + t3.squaredNorm() + 2 * (A - R)));
    const double farthest = std::sqrt(t2.squaredNorm() + t3.squaredNorm() + 2 * (A + R)), n = g.norm();
    if (n < nearest || n > farthest) {
      out.miss = std::max(nearest - n, n - farthest);
      return;
    }
    std::array<double, 2> t{};
    const int m = harmonic(B, C, K, t);
    if (m == 0) {
      out.undecided = true;
      return;
    }
    const Vector3d a1 = form.actuator_axis, a2 = leg.steps[std::size_t(form.second_step)].axis;
    for (int k = 0; k < m; ++k) {
      if (!angle_kept(form.third_step, t[std::size_t(k)])) continue;
      const Eigen::AngleAxisd R3(t[std::size_t(k)], a3);
      const Vector3d v = t2 + R3 * t3;
      std::array<std::array<double, 2>, 2> angles{};
      const int p = two_axes(a1, a2, v, g * (v.norm() / n), angles);
      for (int j = 0; j < p; ++j) {
        if (!angle_kept(form.actuator_step, angles[std::size_t(j)][0]) ||
            !angle_kept(form.second_step, angles[std::size_t(j)][1]))
          continue;
        LegState& s = fresh(partial);
        s.values(var(form.actuator_step)) = angles[std::size_t(j)][0];
        s.values(var(form.second_step)) = angles[std::size_t(j)][1];
        s.values(var(form.third_step)) = t[std::size_t(k)];
        // Left open, the frame at the spherical joint follows from the three
        // angles when the candidate is kept.
        if (leave_ends_open) out.open[std::size_t(out.count - 1)] = true;
        else if (!close_end(s, three_revolute_end(s))) --out.count;
      }
    }
  }
  // The frame at a three-revolute leg's spherical joint, from its angles.
  Isometry3d three_revolute_end(const LegState& s) const {
    const Vector3d a1 = form.actuator_axis, a2 = leg.steps[std::size_t(form.second_step)].axis;
    const Vector3d a3 = leg.steps[std::size_t(form.third_step)].axis;
    return form.base * Eigen::AngleAxisd(s.values(var(form.actuator_step)), a1) * form.after_actuator *
           Eigen::AngleAxisd(s.values(var(form.second_step)), a2) * Eigen::Translation3d(form.second_link) *
           Eigen::AngleAxisd(s.values(var(form.third_step)), a3) * Eigen::Translation3d(form.third_link);
  }

  void crank_parallelogram(LegState& partial) {
    const ClosedFormLeg::Parallelogram& g = form.parallelogram;
    const Vector3d A = form.actuator_axis;
    // The grip's frame in the actuator's: the chain turns it only about A.
    const Isometry3d N = form.base.inverse() * anchor * form.tail.inverse();
    if (!((N.linear() * A - A).norm() <= 1e-12)) {  // an end turned off A: the leg cannot close (or only by luck)
      out.undecided = true;
      return;
    }
    const double level = turn(A, g.across, N.linear() * g.across);
    const Vector3d w = N.translation(), across = w - A * A.dot(w);
    const double h = A.dot(w) - g.height, rho = across.norm(), r1 = g.thigh.norm();
    // The end's distance from the reachable set, exactly: the thigh's circle
    // swept by the circle (bar +- side sin, side cos) about A's direction, in
    // the plane of (distance from A's line, height).
    const double lo = std::abs(rho - r1), hi = rho + r1;
    double miss = std::numeric_limits<double>::infinity();
    for (double centre : {g.bar, -g.bar}) {
      const double nearest = std::hypot(std::clamp(centre, lo, hi) - centre, h);
      const double farthest = std::max(std::hypot(lo - centre, h), std::hypot(hi - centre, h));
      miss = std::min(miss, std::max({0.0, nearest - g.side, g.side - farthest}));
    }
    if (miss > 0) {
      out.miss = miss;
      return;
    }
    if (rho <= 1e-12 * model.size) {  // the end on the crank's axis: every crank angle or none
      out.undecided = true;
      return;
    }
    const double c = std::clamp(h / g.side, -1.0, 1.0), s = std::sqrt(1 - c * c);
    for (double upper_sign : {1.0, -1.0}) {
      const double x = g.bar - g.side * upper_sign * s;  // the parallelogram's reach along n
      if (std::abs(x) <= 1e-12 * model.size) {  // the 2R's second link vanishes
        if (std::abs(rho - r1) > 1e-9 * model.size) continue;  // the end off the thigh's circle: no knee
        out.undecided = true;  // on it: every knee angle
        return;
      }
      const double cos_elbow = (rho * rho - r1 * r1 - x * x) / (2 * r1 * x);
      if (std::abs(cos_elbow) > 1 + 1e-9) continue;
      const double elbow = std::acos(std::clamp(cos_elbow, -1.0, 1.0));
      const double upper = std::atan2(upper_sign * s, c) + g.phase;
      for (double e : {elbow, -elbow}) {
        const double knee = e - g.thigh_phase;  // about A
        const double q = turn(A, g.thigh + x * (Eigen::AngleAxisd(knee, A) * g.across), across);
        LegState& st = fresh(partial);
        st.values(var(form.actuator_step)) = q;
        st.values(var(g.knee_step)) = g.knee_sign * knee;
        st.values(var(g.upper_step)) = upper;
        st.values(var(g.lower_step)) = -g.lower_sign * upper;
        st.values(var(form.end_step)) = g.grip_sign * (level - q - knee);
        if (elbow == 0) break;
      }
      if (s == 0) break;
    }
    if (out.count == 0) out.undecided = true;  // reached by the distance, missed by rounding: let the solver decide
  }
};

// An actuated revolute, a thigh, a knee parallel to it, a parallelogram
// (two parallel revolutes square to the knee, a side between them) and a grip
// parallel to the knee: the Falcon's leg, its links any vectors whose sum
// after the knee (knee bar, side, lower bar) has no part along the
// parallelogram's axis, so that the leg's reach is the closed form's.
std::optional<ClosedFormLeg> crank_parallelogram(const Leg& leg, const std::vector<Token>& tokens, double tiny) {
  std::vector<const Token*> j;
  std::vector<Isometry3d> f;
  const std::vector<Type> five(5, Type::Revolute);
  if (!match(tokens, five, j, f) || !j[0]->actuated) return std::nullopt;
  for (int i = 1; i <= 4; ++i)
    if (!pure_translation(f[std::size_t(i)])) return std::nullopt;
  auto axis = [&](int i) { return leg.steps[std::size_t(j[std::size_t(i)]->step)].axis; };
  // +-1 where the axes are parallel, 0 where they are not.
  auto parallel = [](const Vector3d& a, const Vector3d& b) {
    const double c = a.dot(b);
    return std::abs(c) >= 1 - 1e-12 ? (c > 0 ? 1.0 : -1.0) : 0.0;
  };
  const Vector3d A = axis(0), B = axis(2), n = A.cross(B);
  const Vector3d t1 = f[1].translation(), t2 = f[2].translation(), t3 = f[3].translation(), t4 = f[4].translation();
  ClosedFormLeg c;
  ClosedFormLeg::Parallelogram& g = c.parallelogram;
  g.knee_sign = parallel(A, axis(1));
  g.lower_sign = parallel(B, axis(3));
  g.grip_sign = parallel(A, axis(4));
  g.thigh = t1 - A * A.dot(t1);
  g.side = std::hypot(t3.dot(A), t3.dot(n));
  if (!g.knee_sign || !g.lower_sign || !g.grip_sign || std::abs(A.dot(B)) > 1e-12 || g.thigh.norm() <= tiny ||
      g.side <= tiny || std::abs((t2 + t3 + t4).dot(B)) > tiny)
    return std::nullopt;
  c.pattern = LegPattern::CrankParallelogram;
  c.base = leg.base * f[0];
  c.actuator_step = j[0]->step;
  c.actuator_axis = A;
  c.end_step = j[4]->step;
  c.tail = f[5];
  g.knee_step = j[1]->step;
  g.upper_step = j[2]->step;
  g.lower_step = j[3]->step;
  g.across = n;
  g.thigh_phase = turn(A, g.thigh, n);
  g.height = A.dot(t1 + t2 + t4);
  g.phase = std::atan2(t3.dot(n), t3.dot(A));
  g.bar = (t2 + t4).dot(n);
  return c;
}

}  // namespace

std::string pattern_name(LegPattern p) {
  switch (p) {
    case LegPattern::CrankRod: return "crank-rod";
    case LegPattern::SlideRod: return "slide-rod";
    case LegPattern::Extensible: return "extensible";
    case LegPattern::PlanarDyad: return "planar-dyad";
    case LegPattern::ThreeRevolute: return "three-revolute";
    case LegPattern::CrankParallelogram: return "crank-parallelogram";
    case LegPattern::Numeric: break;
  }
  return "numeric";
}

std::string joint_sequence(const Leg& leg) {
  std::string out;
  for (const Token& t : tokens_of(leg)) {
    if (t.type == Type::Fixed) continue;
    if (!out.empty()) out += ", ";
    out += t.type == Type::Revolute    ? "revolute"
           : t.type == Type::Universal ? "universal"
           : t.type == Type::Spherical ? "spherical"
                                       : "prismatic";
    if (t.actuated) out += "*";
  }
  return out;
}

LegPattern pattern_of_name(const std::string& name) {
  for (LegPattern p : {LegPattern::Numeric, LegPattern::CrankRod, LegPattern::SlideRod, LegPattern::Extensible,
                       LegPattern::PlanarDyad, LegPattern::ThreeRevolute, LegPattern::CrankParallelogram})
    if (pattern_name(p) == name) return p;
  throw std::invalid_argument("unknown pattern \"" + name +
                              "\" (known: crank-rod, slide-rod, extensible, planar-dyad, three-revolute, crank-parallelogram, numeric)");
}

namespace {
std::optional<ClosedFormLeg> recognise_pattern(const Model& model, const Leg& leg) {
  if (leg.actuators.size() != 1) return std::nullopt;
  const std::vector<Token> tokens = tokens_of(leg);
  std::vector<const Token*> j;
  std::vector<Isometry3d> f;
  ClosedFormLeg c;
  const double tiny = 1e-9 * model.size;
  auto start = [&](const Token& actuator, LegPattern p) {
    c.pattern = p;
    c.base = leg.base * f[0];
    c.actuator_step = actuator.step;
    c.actuator_axis = leg.steps[std::size_t(actuator.step)].axis;
    c.end_step = j.back()->step;
    c.end_joints = j.back()->type == Type::Universal ? 2 : 1;
    c.tail = f.back();
  };
  auto ball = [&](const Token& b) {
    c.ball_step = b.step;
    c.ball_joints = b.type == Type::Universal ? 2 : 1;
    for (const BranchRule& r : leg.rules)
      for (int i = 0; i < 3; ++i) c.ball_read = c.ball_read || r.steps[std::size_t(i)] == b.step || r.steps[std::size_t(i)] == b.step + 1;
  };
  // A universal points a link anywhere when its axes are square and the link
  // square to the second one (the link sweeps a great circle through the first axis).
  auto points_anywhere = [&](const Token& b, const Vector3d& link) {
    if (b.type != Type::Universal) return true;
    const Vector3d a1 = leg.steps[std::size_t(b.step)].axis, a2 = leg.steps[std::size_t(b.step + 1)].axis;
    return std::abs(a1.dot(a2)) < 1e-12 && std::abs(a2.dot(link.normalized())) < 1e-12;
  };
  // A universal end only after a universal ball (RUU, PUU, UPU: the leg
  // holds the platform's orientation too), its axes square as a ball's.
  const auto end_ok = [&](Type b, Type e) {
    if (e != Type::Universal) return true;
    const int step = j.back()->step;
    return b == Type::Universal &&
           std::abs(leg.steps[std::size_t(step)].axis.dot(leg.steps[std::size_t(step + 1)].axis)) < 1e-12;
  };
  // An actuated revolute (crank) or slide (carriage), a ball, a rod to the end joint.
  const auto rod_leg = [&](Type actuator, Type b, Type e, LegPattern pattern) {
    if (!match(tokens, {actuator, b, e}, j, f) || !j[0]->actuated || f[2].translation().norm() <= tiny ||
        !points_anywhere(*j[1], f[2].translation()) || !end_ok(b, e))
      return false;
    start(*j[0], pattern);
    c.after_actuator = f[1];
    c.rod = f[2];
    ball(*j[1]);
    // A crank's elbow off the actuator's axis.
    const Vector3d p = f[1].translation();
    return actuator != Type::Revolute || (p - c.actuator_axis * c.actuator_axis.dot(p)).norm() > tiny;
  };
  // A ball, an actuated slide (fixed lengths along it before and after: a
  // cylinder's body, its rod's end), the end joint.
  const auto extensible_leg = [&](Type b, Type e) {
    if (!match(tokens, {b, Type::Prismatic, e}, j, f) || !j[1]->actuated || !pure_translation(f[1]) ||
        !pure_translation(f[2]) || !end_ok(b, e))
      return false;
    const Vector3d s = leg.steps[std::size_t(j[1]->step)].axis, t1 = f[1].translation(), t2 = f[2].translation();
    const auto along = [&](const Vector3d& t) { return (t - s * s.dot(t)).norm() <= tiny; };
    if (!along(t1) || !along(t2) || !points_anywhere(*j[0], s)) return false;
    start(*j[1], LegPattern::Extensible);
    ball(*j[0]);
    c.after_actuator = f[1];  // here the ball's link to the slide
    c.rod = f[2];
    c.offset = s.dot(t1 + t2);
    return true;
  };
  // In the plane a revolute stands for each ball: a crank carrying a rod (a
  // dyad: five-bar, 3-RRR), a slide carrying one (3-PRR), a slide between two
  // revolutes (3-RPR).
  if (model.planar) {
    const Type R = Type::Revolute;
    if (rod_leg(R, R, R, LegPattern::PlanarDyad) || rod_leg(Type::Prismatic, R, R, LegPattern::SlideRod) ||
        extensible_leg(R, R))
      return c;
    return std::nullopt;
  }
  for (Type b : {Type::Spherical, Type::Universal})
    for (Type e : {Type::Spherical, Type::Universal})
      if (rod_leg(Type::Revolute, b, e, LegPattern::CrankRod) || rod_leg(Type::Prismatic, b, e, LegPattern::SlideRod) ||
          extensible_leg(b, e))
        return c;
  if (match(tokens, {Type::Revolute, Type::Revolute, Type::Revolute, Type::Spherical}, j, f) && j[0]->actuated &&
      pure_translation(f[1]) && pure_translation(f[2]) && pure_translation(f[3])) {
    const Vector3d a1 = leg.steps[std::size_t(j[0]->step)].axis, t1 = f[1].translation();
    if ((t1 - a1 * a1.dot(t1)).norm() > tiny) return std::nullopt;  // the second joint off the first axis
    start(*j[0], LegPattern::ThreeRevolute);
    c.after_actuator = f[1];
    c.second_step = j[1]->step;
    c.third_step = j[2]->step;
    c.second_link = f[2].translation();
    c.third_link = f[3].translation();
    return c;
  }
  if (std::optional<ClosedFormLeg> p = crank_parallelogram(leg, tokens, tiny)) return p;
  return std::nullopt;
}
}  // namespace

std::optional<ClosedFormLeg> recognise(const Model& model, const Leg& leg) {
  std::optional<ClosedFormLeg> c = recognise_pattern(model, leg);
  // An angle rule reads its joint's value; the others read joint centres and
  // axes, which a joint's own value does not move.
  if (c)
    for (const BranchRule& r : leg.rules)
      for (int step : r.steps)
        c->end_read = c->end_read || step > c->end_step || (step == c->end_step && r.kind == BranchRule::Kind::Angle);
  return c;
}

void solve_closed(const ClosedFormLeg& form, const Model& model, const Leg& leg, const Isometry3d& anchor,
                  LegCandidates& out, bool leave_ends_open, int branch) {
  out.count = 0;
  out.miss = 0;
  out.undecided = false;
  out.dropped = false;
  thread_local LegState partial;
  partial.values.setZero(leg.variables);
  partial.spheres.assign(std::size_t(leg.spheres), Matrix3d::Identity());
  Builder b{form, model, leg, anchor, out, leave_ends_open && !form.end_read && form.end_joints == 1, branch};
  switch (form.pattern) {
    case LegPattern::CrankRod:
    case LegPattern::PlanarDyad: b.crank_rod(partial); break;
    case LegPattern::SlideRod: b.slide_rod(partial); break;
    case LegPattern::Extensible: b.extensible(partial); break;
    case LegPattern::ThreeRevolute: b.three_revolute(partial); break;
    case LegPattern::CrankParallelogram: b.crank_parallelogram(partial); break;
    case LegPattern::Numeric: out.undecided = true; break;
  }
  // Within the rod's reach but no candidate's universal end taking the
  // anchor's orientation: a design that holds it only in part, or rounding
  // at a lock; the numerical solver decides.
  if (form.end_joints == 2 && out.count == 0 && out.miss == 0) out.undecided = true;
}

void close_open_end(const ClosedFormLeg& form, const Model& model, const Leg& leg, const Isometry3d& anchor,
                    LegState& s, const Isometry3d& frame) {
  thread_local LegCandidates unused;
  const Builder b{form, model, leg, anchor, unused};
  // Only a spherical end is left open (solve_closed), so this one closes.
  b.close_end(s, form.pattern == LegPattern::ThreeRevolute ? b.three_revolute_end(s) : frame);
}

}  // namespace linkscape::described
