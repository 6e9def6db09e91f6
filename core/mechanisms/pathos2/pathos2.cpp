#include "core/mechanisms/pathos2/pathos2.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string_view>
#include <stdexcept>

#include "core/conditioning.h"
#include "core/mechanisms/pathos2/checks.h"

namespace linkscape::pathos2 {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
using checks::require_finite;
using checks::require_pose;
using checks::require_positive;

Matrix3d rot_x(double a) { return Eigen::AngleAxisd(a, Vector3d::UnitX()).toRotationMatrix(); }
Matrix3d rot_y(double a) { return Eigen::AngleAxisd(a, Vector3d::UnitY()).toRotationMatrix(); }
Matrix3d rot_z(double a) { return Eigen::AngleAxisd(a, Vector3d::UnitZ()).toRotationMatrix(); }

void require_length(double v, std::string_view what) {
  if (!(v >= kMinLength && v <= kMaxLength)) {
    std::ostringstream msg;
    msg << "pathos2: " << what << " must be a length in [" << kMinLength << ", " << kMaxLength << "] cm, got " << v;
    throw std::invalid_argument(msg.str());
  }
}

void require_offset(double v, std::string_view what) {
  if (!(std::abs(v) <= kMaxLength)) {
    std::ostringstream msg;
    msg << "pathos2: " << what << " must be in [" << -kMaxLength << ", " << kMaxLength << "] cm, got " << v;
    throw std::invalid_argument(msg.str());
  }
}

void require_limit(double v, std::string_view what) {
  require_finite(v, what);
  if (v <= 0.0 || v > kPi + 1e-12) {
    std::ostringstream msg;
    msg << "pathos2: " << what << " must be in (0, 180] deg, got " << v / kDeg << " deg";
    throw std::invalid_argument(msg.str());
  }
}

}  // namespace

// ---- Model ------------------------------------------------------------------

void Model::validate() const {
  require_length(l0, "l0");
  require_length(lb, "lb");
  require_length(l1, "l1");
  require_length(l2, "l2");
  require_length(l3, "l3");
  require_offset(lp, "lp");
  if (lp < 0.0) throw std::invalid_argument("pathos2: lp must be >= 0, got " + std::to_string(lp));
  require_length(h0, "h0");
  require_finite(theta_t, "theta_t");
  require_finite(theta_g, "theta_g");
  require_offset(db, "db");
  require_offset(lx, "lx");
  require_finite(base_phase, "base_phase");
  require_finite(plate_phase, "plate_phase");
  if (tilt_sign != 1.0 && tilt_sign != -1.0)
    throw std::invalid_argument("pathos2: tilt_sign must be +1 or -1, got " + std::to_string(tilt_sign));
  for (int i = 0; i < kLegCount; ++i)
    if (branch[i] != 1 && branch[i] != -1)
      throw std::invalid_argument("pathos2: branch_" + std::to_string(i + 1) +
                                  " must be +1 or -1, got " + std::to_string(branch[i]));
  require_limit(cone_limit, "cone_limit");
  require_limit(t2_limit, "t2_limit");
  require_limit(t3_limit, "t3_limit");
  for (const auto& [radius, name] : {std::pair{link_radius, "link_radius"}, std::pair{grip_radius, "grip_radius"}})
    if (!(radius >= 0.0 && radius <= kMaxLength))
      throw std::invalid_argument("pathos2: " + std::string(name) + " must be in [0, " + std::to_string(kMaxLength) +
                                  "] cm, got " + std::to_string(radius));
}

std::vector<std::string> Model::parameter_names() {
  return {"l0",         "lb",          "l1",         "l2",       "l3",       "lp",
          "h0",         "theta_t",     "theta_g",    "db",       "lx",       "tilt_sign",
          "base_phase", "plate_phase", "cone_limit", "t2_limit", "t3_limit", "branch_1",
          "branch_2",   "branch_3",    "branch_4",   "branch_5", "branch_6"};
}

Model Model::from_parameters(const std::map<std::string, double>& parameters) {
  Model m;
  bool has_db = false, has_lx = false;
  for (const auto& [name, value] : parameters) {
    if (name == "l0") m.l0 = value;
    else if (name == "lb") m.lb = value;
    else if (name == "l1") m.l1 = value;
    else if (name == "l2") m.l2 = value;
    else if (name == "l3") m.l3 = value;
    else if (name == "lp") m.lp = value;
    else if (name == "h0") m.h0 = value;
    else if (name == "theta_t") m.theta_t = value * kDeg;
    else if (name == "theta_g") m.theta_g = value * kDeg;
    else if (name == "db") m.db = value, has_db = true;
    else if (name == "lx") m.lx = value, has_lx = true;
    else if (name == "tilt_sign") m.tilt_sign = value;
    else if (name == "base_phase") m.base_phase = value * kDeg;
    else if (name == "plate_phase") m.plate_phase = value * kDeg;
    else if (name == "cone_limit") m.cone_limit = value * kDeg;
    else if (name == "t2_limit") m.t2_limit = value * kDeg;
    else if (name == "t3_limit") m.t3_limit = value * kDeg;
    else if (name.size() == 8 && name.starts_with("branch_") && name[7] >= '1' && name[7] <= '6') {
      require_finite(value, name);
      if (value != 1.0 && value != -1.0)
        throw std::invalid_argument("pathos2: " + name + " must be +1 or -1, got " + std::to_string(value));
      m.branch[name[7] - '1'] = static_cast<int>(value);
    } else {
      std::string known;
      for (const auto& n : parameter_names()) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("pathos2: unknown parameter '" + name + "' (known: " + known + ")");
    }
  }
  // Derived offsets follow the given lb and theta_t unless set explicitly.
  if (!has_db) m.db = m.lb * std::tan(m.theta_t);
  if (!has_lx) m.lx = m.lb / std::cos(m.theta_t);
  m.validate();
  return m;
}

std::map<std::string, double> Model::to_parameters() const {
  std::map<std::string, double> p{
      {"l0", l0},           {"lb", lb},
      {"l1", l1},           {"l2", l2},
      {"l3", l3},           {"lp", lp},
      {"h0", h0},           {"theta_t", theta_t / kDeg},
      {"theta_g", theta_g / kDeg}, {"db", db},
      {"lx", lx},           {"tilt_sign", tilt_sign},
      {"base_phase", base_phase / kDeg}, {"plate_phase", plate_phase / kDeg},
      {"cone_limit", cone_limit / kDeg}, {"t2_limit", t2_limit / kDeg},
      {"t3_limit", t3_limit / kDeg}};
  for (int i = 0; i < kLegCount; ++i) p["branch_" + std::to_string(i + 1)] = branch[i];
  return p;
}

Pose Pose::from_xyz_rpy(double x, double y, double z, double rx, double ry, double rz, double h0) {
  Pose pose;
  pose.p_world_E = Vector3d(x, y, z);
  pose.R_world_E = rot_z(rz) * rot_y(ry) * rot_x(rx);
  pose.h0 = h0;
  return pose;
}

Vector3d Pose::rpy() const {
  const Matrix3d& R = R_world_E;
  const double ry = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  const double rx = std::atan2(R(2, 1), R(2, 2));
  const double rz = std::atan2(R(1, 0), R(0, 0));
  return {rx, ry, rz};
}

Pose home_pose(const Model& model) {
  return Pose::from_xyz_rpy(0.0, 0.0, model.l0 / 2.0, 0.0, 0.0, 30.0 * kDeg, model.h0);
}

Geometry make_geometry(const Model& model) {
  model.validate();
  Geometry g;
  g.model = model;
  for (int i = 0; i < kLegCount; ++i) {
    const bool upper = i >= 3;
    const int k = i % 3;
    const Matrix3d flip = upper ? rot_x(kPi) : Matrix3d::Identity();
    const Vector3d lift(0.0, 0.0, upper ? model.l0 : 0.0);
    const Matrix3d R_around = flip * rot_z(model.base_phase + 2.0 * kPi / 3.0 * k);
    const Matrix3d R_tilt = rot_y(model.tilt_sign * model.theta_t);
    g.R_world_B[i] = R_around * R_tilt;
    g.p_world_B[i] = lift + R_around * (Vector3d(0.0, 0.0, model.db) + R_tilt * Vector3d(model.lx, 0.0, 0.0));
    const Matrix3d R_plate = flip * rot_z(model.plate_phase + 2.0 * kPi / 3.0 * k);
    g.p_E_attach_plate[i] = R_plate * Vector3d(model.lp, 0.0, 0.0);
    g.grip_side[i] = upper ? 1.0 : -1.0;  // Rx(theta_b1) Tz(-h0)
    g.R_E_A[i] = R_plate * rot_y(model.theta_g);
  }
  return g;
}

// ---- Leg ----------------------------------------------------------------------

Vector3d leg_forward(double l1, double l2, double l3, double t1, double t2, double t3) {
  // Eq. 3: Rz(t1)[Tz(l1) + Ry(t2){Tz(l2) + Rx(t3) Tz(l3)}].
  const Vector3d c2(0.0, -l3 * std::sin(t3), l2 + l3 * std::cos(t3));
  const Vector3d c1 = Vector3d(0.0, 0.0, l1) + rot_y(t2) * c2;
  return rot_z(t1) * c1;
}

namespace {

// Closed-form leg IK without angle output beyond what the caller needs; the
// gradient dt1/da (first row of the inverse leg Jacobian) comes for free.
struct LegCore {
  Status status = Status::Unreachable;
  double c1x = 0, c1y = 0, c2z = 0;  // Eq. 14 coefficients
  double cos1 = 1, sin1 = 0;         // of t1, without trigonometric calls
};

inline LegCore leg_core(double l1, double l2, double l3, const Vector3d& a, int branch) {
  LegCore r;
  const double dz = a.z() - l1;
  const double rxy2 = a.x() * a.x() + a.y() * a.y();
  const double rho2 = rxy2 + dz * dz;  // |a - l1 z|^2
  const double scale2 = (l2 + l3) * (l2 + l3);
  // Eq. 14 (corrected): c2z = w = l2 + l3 c3; c1y = +-sqrt(l3^2 - (c2z - l2)^2);
  // c1x = +sqrt(a_x^2 + a_y^2 - c1y^2) (the printed a_z^2 under the root is a misprint).
  r.c2z = (l2 * l2 - l3 * l3 + rho2) / (2.0 * l2);
  const double e = r.c2z - l2;
  double y2 = l3 * l3 - e * e;
  if (y2 < -kRootSlack * scale2) return r;  // |a - l1 z| outside [|l2 - l3|, l2 + l3]
  y2 = std::max(y2, 0.0);
  r.c1y = (branch >= 0 ? 1.0 : -1.0) * std::sqrt(y2);
  double x2 = rxy2 - y2;
  if (x2 < -kRootSlack * scale2) return r;  // |a_z - l1| > |w|: the R2 circle misses a
  x2 = std::max(x2, 0.0);
  r.c1x = std::sqrt(x2);
  if (rxy2 > 0.0) {
    // Eq. 9: Rz(t1) (c1x, c1y) = (a_x, a_y).
    r.cos1 = (r.c1x * a.x() + r.c1y * a.y()) / rxy2;
    r.sin1 = (r.c1x * a.y() - r.c1y * a.x()) / rxy2;
  }
  r.status = std::abs(r.c1x * r.c1y) <= kLegSingularTolerance * scale2 ? Status::Singular : Status::Ok;
  return r;
}

}  // namespace

LegSolution leg_inverse(double l1, double l2, double l3, const Vector3d& a, int branch) {
  if (!a.allFinite()) throw std::invalid_argument("pathos2: leg target must be finite");
  if (!(l1 > 0.0 && l2 > 0.0 && l3 > 0.0))
    throw std::invalid_argument("pathos2: leg lengths l1, l2, l3 must be > 0");
  LegSolution s;
  s.p_B_globular = a;
  const LegCore c = leg_core(l1, l2, l3, a, branch);
  s.status = c.status;
  if (c.status == Status::Unreachable) return s;
  s.t1 = std::atan2(c.sin1, c.cos1);
  // Eq. 11 with c2x = 0; atan2 keeps the quadrant when w = c2z < 0 (l3 > l2).
  s.t2 = std::atan2(c.c2z * c.c1x, c.c2z * (a.z() - l1));
  s.t3 = std::atan2(-c.c1y, c.c2z - l2);  // Eq. 13
  s.det = -l2 * c.c1x * c.c1y;            // = l2 l3 w sin t2 sin t3
  return s;
}

// ---- Pose IK -----------------------------------------------------------------

GlobularOffsets globular_offsets(const Geometry& g, const Pose& pose) {
  GlobularOffsets offsets;
  for (int i = 0; i < kLegCount; ++i) {
    Vector3d r_E = g.p_E_attach_plate[i];
    r_E.z() += g.grip_side[i] * pose.h0;
    offsets[i] = pose.R_world_E * r_E;
  }
  return offsets;
}

namespace {

int severity(Status s) {
  switch (s) {
    case Status::Unreachable: return 3;
    case Status::Singular: return 2;
    case Status::OutOfLimits: return 1;
    default: return 0;
  }
}

PoseIkResult inverse_with(const Geometry& g, const Pose& pose, IkDetail detail, const GlobularOffsets& offsets) {
  const Model& m = g.model;
  PoseIkResult out;
  out.status = Status::Ok;
  const Matrix3d& R = pose.R_world_E;
  // Limits compare cosines: |t| <= lim  <=>  cos t >= cos lim for t in [-pi, pi].
  // The default limits (pi: none) take their cosine from one call.
  static const double cos_pi = std::cos(kPi);
  const auto cos_limit = [](double limit) { return limit == kPi ? cos_pi : std::cos(limit); };
  const double cos_cone = cos_limit(m.cone_limit), cos_t2 = cos_limit(m.t2_limit), cos_t3 = cos_limit(m.t3_limit);
  // A cone limit of pi (the default) excludes nothing: t5 is in [0, pi].
  const bool check_cone = m.cone_limit < kPi;
  for (int i = 0; i < kLegCount; ++i) {
    LegSolution& leg = out.legs[i];
    const Vector3d p_glob = pose.p_world_E + offsets[i];
    out.p_world_globular[i] = p_glob;
    // Written in place: a copy from a temporary stalled on store forwarding.
    leg.p_B_globular.noalias() = g.R_world_B[i].transpose() * (p_glob - g.p_world_B[i]);
    const Vector3d& a = leg.p_B_globular;
    const LegCore c = leg_core(m.l1, m.l2, m.l3, a, m.branch[i]);
    leg.status = c.status;
    leg.c1y = c.c1y;
    if (c.status != Status::Unreachable) {
      // Sines and cosines straight from Eq. 14's coefficients (w = c2z != 0
      // whenever the leg is reachable and not singular).
      const double w = c.c2z;
      const double s2 = w != 0.0 ? c.c1x / w : 1.0, c2 = w != 0.0 ? (a.z() - m.l1) / w : 0.0;
      const double s3 = -c.c1y / m.l3, c3 = (w - m.l2) / m.l3;
      leg.cos_t1 = c.cos1, leg.sin_t1 = c.sin1, leg.cos_t2 = c2, leg.sin_t2 = s2, leg.cos_t3 = c3, leg.sin_t3 = s3;
      if (detail != IkDetail::Field) leg.t1 = std::atan2(c.sin1, c.cos1);  // Eq. 9
      leg.det = -m.l2 * c.c1x * c.c1y;
      const double c1 = c.cos1, s1 = c.sin1;
      // cos t5 = z of the end of l3 (Rz(t1) Ry(t2) Rx(t3) e_z, from the
      // cosines) against z of A_i; only the z columns are needed.
      double cos_t5 = 1.0;
      if (detail == IkDetail::ActiveOnly) {
        if (check_cone) {
          const Vector3d z_B_end(c1 * s2 * c3 + s1 * s3, s1 * s2 * c3 - c1 * s3, c2 * c3);
          cos_t5 = (g.R_world_B[i] * z_B_end).dot(R * g.R_E_A[i].col(2));
        }
      } else {
        // Field: the globular joint only for a cone limit, t2 and t3 only for theirs.
        const bool full = detail == IkDetail::Full;
        if (full || check_cone) {
          // End of l3: Rz(t1) Ry(t2) Rx(t3), built from the cosines.
          Matrix3d R_B_end;
          R_B_end << c1 * c2, c1 * s2 * s3 - s1 * c3, c1 * s2 * c3 + s1 * s3,
                     s1 * c2, s1 * s2 * s3 + c1 * c3, s1 * s2 * c3 - c1 * s3,
                     -s2,     c2 * s3,                c2 * c3;
          const Matrix3d R_world_end = g.R_world_B[i] * R_B_end;
          const Matrix3d R_world_A = R * g.R_E_A[i];
          cos_t5 = R_world_end.col(2).dot(R_world_A.col(2));
          // Globular joint (Eqs. 15-18): Rz(t4) Ry(t5) Rz(t6) = B, the rotation
          // left between the end of l3 and the attachment frame A_i.
          const Matrix3d B = R_world_end.transpose() * R_world_A;
          const double rho = std::sqrt(B(0, 2) * B(0, 2) + B(1, 2) * B(1, 2));
          leg.t5 = std::atan2(rho, B(2, 2));  // Eq. 17
          if (full) {
            const double c4 = rho > 0.0 ? B(0, 2) / rho : 1.0, s4 = rho > 0.0 ? B(1, 2) / rho : 0.0;
            leg.t4 = std::atan2(s4, c4);                                                      // Eq. 16
            leg.t6 = std::atan2(-B(0, 0) * s4 + B(1, 0) * c4, -B(0, 1) * s4 + B(1, 1) * c4);  // Eq. 18
          }
        }
        // Eq. 11 with c2x = 0; atan2 keeps the quadrant when w < 0 (l3 > l2).
        if (full || m.t2_limit < kPi) leg.t2 = std::atan2(w * c.c1x, w * (a.z() - m.l1));
        if (full || m.t3_limit < kPi) leg.t3 = std::atan2(-c.c1y, w - m.l2);  // Eq. 13
      }
      if (leg.status == Status::Ok && ((check_cone && cos_t5 < cos_cone) || c2 < cos_t2 || c3 < cos_t3))
        leg.status = Status::OutOfLimits;
    }
    out.q_active[i] = leg.t1;
    // The pose's status is its most severe leg's (the first such leg named):
    // a pose that some leg cannot close is unreachable, never out of limits.
    if (severity(leg.status) > severity(out.status)) {
      out.failing_leg = i;
      out.status = leg.status;
    }
  }
  return out;
}

}  // namespace

PoseIkResult inverse(const Geometry& g, const Pose& pose, IkDetail detail) {
  // Field: the caller checked the rotation and grip once (compute_field).
  if (detail != IkDetail::Field) require_pose(pose);
  else if (!pose.p_world_E.allFinite()) throw std::invalid_argument("pathos2: pose must be finite");
  return inverse_with(g, pose, detail, globular_offsets(g, pose));
}

PoseIkResult inverse_field_sample(const Geometry& g, const Pose& pose, const GlobularOffsets& offsets) {
  if (!pose.p_world_E.allFinite()) throw std::invalid_argument("pathos2: pose must be finite");
  return inverse_with(g, pose, IkDetail::Field, offsets);
}

PoseIkResult inverse(const Model& model, const Pose& pose) {
  return inverse(make_geometry(model), pose);
}

// ---- Mobility --------------------------------------------------------------------

MechanismGraph mechanism_graph(bool lock_grip) {
  MechanismGraph graph;
  graph.links.push_back({"ground (both base plates)"});
  const int lower_plate = 1;
  graph.links.push_back({lock_grip ? "top plates (grip locked)" : "lower top plate"});
  int upper_plate = lower_plate;
  if (!lock_grip) {
    graph.links.push_back({"upper top plate"});
    upper_plate = 2;
    graph.joints.push_back({"grip (prismatic)", lower_plate, upper_plate, 1});
  }
  for (int i = 0; i < kLegCount; ++i) {
    const std::string leg = "leg " + std::to_string(i + 1);
    const int first = static_cast<int>(graph.links.size());
    for (int l = 1; l <= 3; ++l) graph.links.push_back({leg + " link " + std::to_string(l)});
    graph.joints.push_back({leg + " R1 (active)", 0, first, 1});
    graph.joints.push_back({leg + " R2", first, first + 1, 1});
    graph.joints.push_back({leg + " R3", first + 1, first + 2, 1});
    graph.joints.push_back({leg + " globular", first + 2, i < 3 ? lower_plate : upper_plate, 3});
  }
  return graph;
}

int mobility(const MechanismGraph& graph) {
  const int links = static_cast<int>(graph.links.size());
  int freedoms = 0;
  for (const GraphJoint& j : graph.joints) {
    if (j.link_a < 0 || j.link_a >= links || j.link_b < 0 || j.link_b >= links || j.link_a == j.link_b)
      throw std::invalid_argument("pathos2: joint '" + j.name + "' connects links " +
                                  std::to_string(j.link_a) + " and " + std::to_string(j.link_b) +
                                  " of " + std::to_string(links));
    if (j.dof < 1 || j.dof > 5)
      throw std::invalid_argument("pathos2: joint '" + j.name + "' has " + std::to_string(j.dof) +
                                  " DOF (expected 1..5)");
    freedoms += j.dof;
  }
  return 6 * (links - static_cast<int>(graph.joints.size()) - 1) + freedoms;
}

// ---- Skeleton ---------------------------------------------------------------------

Skeleton skeleton(const Geometry& g, const Pose& pose, const PoseIkResult& ik) {
  if (ik.status != Status::Ok && ik.status != Status::OutOfLimits)
    throw std::invalid_argument("pathos2: skeleton needs a solved pose (leg " +
                                std::to_string(ik.failing_leg + 1) + " is " +
                                std::string(to_string(ik.status)) + ")");
  const Model& m = g.model;
  Skeleton s;
  s.p_world_E = pose.p_world_E;
  for (int i = 0; i < kLegCount; ++i) {
    const LegSolution& leg = ik.legs[i];
    const Matrix3d& RB = g.R_world_B[i];
    const Matrix3d R1 = RB * rot_z(leg.t1);
    const Matrix3d R2 = R1 * rot_y(leg.t2);
    LegSkeleton& ls = s.legs[i];
    ls.r1 = g.p_world_B[i];
    ls.r1_axis = RB.col(2);
    ls.r2 = ls.r1 + m.l1 * R1.col(2);
    ls.r2_axis = R1.col(1);
    ls.r3 = ls.r2 + m.l2 * R2.col(2);
    ls.r3_axis = R2.col(0);
    ls.globular = ls.r3 + m.l3 * (R2 * rot_x(leg.t3)).col(2);
    s.base_plates[i / 3].push_back(ls.r1);
    s.top_plates[i / 3][i % 3] = ik.p_world_globular[i];
  }
  return s;
}

Skeleton skeleton(const Model& model, const Pose& pose) {
  const Geometry g = make_geometry(model);
  return skeleton(g, pose, inverse(g, pose));
}

}  // namespace linkscape::pathos2
