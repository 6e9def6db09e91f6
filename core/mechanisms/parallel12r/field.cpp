#include "core/mechanisms/parallel12r/field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/conditioning.h"
#include "core/field_sampling.h"

namespace linkscape {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using parallel12r::Model;
constexpr float kInf = std::numeric_limits<float>::infinity();

bool full_ranges(const Model& m) {
  constexpr double pi = std::numbers::pi;
  return m.alpha_limits.lo <= -pi / 2 && m.alpha_limits.hi >= pi / 2 && m.beta_limits.lo <= -pi &&
         m.beta_limits.hi >= pi && m.gamma_limits.lo <= -pi && m.gamma_limits.hi >= pi;
}

// Signed distance to the spheres |D| = L1 + L2 and |D| = |L1 - L2|, > 0 inside.
double geometric_margin(const Model& m, double radius) {
  return std::min(m.reach() - radius, radius - m.inner_reach());
}

// Actuator-range margin of a configuration, in length: angle margin times the
// reach (the largest lever arm), so it is zero exactly on a range limit.
double limits_margin(const Model& m, const Vector3d& q) {
  const parallel12r::Interval r[] = {m.alpha_limits, m.beta_limits, m.gamma_limits};
  double margin = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) margin = std::min({margin, q(k) - r[k].lo, r[k].hi - q(k)});
  return margin * m.reach();
}

// A solved sample whose c(J) is beyond what double resolves
// (parallel12r::kMaxTrustedCondition): singular, as the IK reports targets
// within its singular band, never a wrong finite c(J).
void mark_singular(FieldSample& s) {
  s.status = std::uint8_t(Status::Singular);
  s.reachable = 0;
  s.cond = kInf;
  s.method_used = Field::kNoMethod;
}

FieldSample unreachable_sample(double margin, Status status) {
  FieldSample s;
  s.cond = kInf;
  s.residual = kInf;
  s.reach_margin = float(margin);
  s.status = std::uint8_t(status);
  return s;
}

// The model with lengths divided by a power of two near its reach (exact):
// angles and c(J) do not depend on scale, and in these units no product in
// the planar closed form (up to length^4) can overflow or underflow.
struct UnitModel {
  Model unit;
  double to_unit = 1.0, from_unit = 1.0;  // 2^-e and 2^e: lengths of the model = unit lengths * 2^e
};
UnitModel unit_model(const Model& m) {
  const int exponent = std::ilogb(m.reach());
  UnitModel u{m, std::ldexp(1.0, -exponent), std::ldexp(1.0, exponent)};
  u.unit.L1 = m.L1 * u.to_unit;
  u.unit.L2 = m.L2 * u.to_unit;
  return u;
}

FieldSample sample_planar_unit(const Model& m, const Vector3d& p, int branch, bool check_limits);

// The planar sample in the model's units: solved in unit lengths, margin and
// residual scaled back.
FieldSample sample_planar(const UnitModel& u, const Vector3d& p, int branch, bool check_limits) {
  FieldSample s = sample_planar_unit(u.unit, p * u.to_unit, branch, check_limits);
  s.reach_margin = float(double(s.reach_margin) * u.from_unit);
  s.residual = float(double(s.residual) * u.from_unit);
  return s;
}

// The planar closed form written without trigonometry: cos/sin of alpha,
// beta, gamma come from the target by algebra, the Jacobian from them, and
// c(J) from the closed form. Same equations as parallel12r::inverse(Planar).
FieldSample sample_planar_unit(const Model& m, const Vector3d& p, int branch, bool check_limits) {
  const double x = p.x(), y = p.y(), z = p.z();
  const double rho2 = x * x + y * y, R2 = rho2 + z * z, R = std::sqrt(R2), rho = std::sqrt(rho2);
  const double margin = geometric_margin(m, R);
  const double tol = parallel12r::kSingularTolerance * m.reach();
  if (margin < -tol) return unreachable_sample(margin, Status::Unreachable);
  if (margin <= tol || std::abs(y) <= tol || rho <= tol) return unreachable_sample(margin, Status::Singular);

  const double L1 = m.L1, L2 = m.L2;
  const double sign_y = y > 0 ? 1.0 : -1.0;
  const double ca = std::abs(y) / rho, sa = -x * sign_y / rho, r = sign_y * rho;
  const double a = (R2 + L1 * L1 - L2 * L2) / (2.0 * R);
  const double h = std::sqrt(std::max(0.0, (L1 + L2 - R) * (L2 - L1 + R) * (R + L1 - L2) * (R + L1 + L2)) / (4.0 * R2));
  const double ur = r / R, uz = z / R, s = branch == 0 ? 1.0 : -1.0;
  const double l1r = a * ur - s * h * uz, l1z = a * uz + s * h * ur;
  const double l2r = r - l1r, l2z = z - l1z;
  // (cos t, sin t) is proportional to (cos a * cos phi, sin phi) for each link.
  const double nb = std::sqrt(ca * ca * l1r * l1r + l1z * l1z), ng = std::sqrt(ca * ca * l2r * l2r + l2z * l2z);
  const double cb = ca * l1r / nb, sb = l1z / nb, cg = ca * l2r / ng, sg = l2z / ng;
  const double db2 = 1.0 - sa * sa * sb * sb, dg2 = 1.0 - sa * sa * sg * sg;
  const double db = std::sqrt(db2), dg = std::sqrt(dg2), db3 = db2 * db, dg3 = dg2 * dg;

  Matrix3d J;
  J.col(0) = L1 / db3 * Vector3d(-ca * cb, -sa * cb * cb * cb, -sa * sb * cb * cb) +
             L2 / dg3 * Vector3d(-ca * cg, -sa * cg * cg * cg, -sa * sg * cg * cg);
  J.col(1) = L1 * ca / db3 * Vector3d(sa * ca * sb, -ca * ca * sb, cb);
  J.col(2) = L2 * ca / dg3 * Vector3d(sa * ca * sg, -ca * ca * sg, cg);
  const Vector3d back = L1 / db * Vector3d(-sa * cb, ca * cb, ca * sb) + L2 / dg * Vector3d(-sa * cg, ca * cg, ca * sg);

  FieldSample out;
  out.residual = float((back - p).norm());
  out.reach_margin = float(margin);
  double limit_margin = std::numeric_limits<double>::infinity();
  if (check_limits) {
    const Vector3d q(std::atan2(sa, ca), std::atan2(sb, cb), std::atan2(sg, cg));
    limit_margin = limits_margin(m, q);
    out.reach_margin = float(std::min(margin, limit_margin));
  }
  out.status = std::uint8_t(limit_margin < 0 ? Status::OutOfLimits : Status::Ok);
  out.reachable = limit_margin >= 0;
  out.method_used = std::uint8_t(parallel12r::IkMethod::Planar);
  out.cond = kInf;
  if (out.reachable) {
    const double cond = condition_number_fast(J);
    if (cond <= parallel12r::kMaxTrustedCondition) out.cond = float(cond);
    else mark_singular(out);
  }
  return out;
}

FieldSample sample_general(const Model& m, const Vector3d& p, const FieldRequest& req, bool check_limits) {
  const double margin = geometric_margin(m, p.norm());
  const parallel12r::IkResult r = parallel12r::inverse(m, p, req.method, req.ik);
  const parallel12r::IkSolution* s = nullptr;
  for (const auto& candidate : r.solutions)
    if (candidate.branch == req.branch) s = &candidate;
  if (!s) {
    FieldSample out = unreachable_sample(margin, r.status == Status::Ok ? Status::NotConverged : r.status);
    return out;
  }
  FieldSample out;
  out.status = std::uint8_t(s->status);
  out.residual = float(s->residual);
  out.iterations = std::uint16_t(std::min(s->iterations, 65535));
  if (s->status == Status::Ok || s->status == Status::OutOfLimits) out.method_used = std::uint8_t(s->method);
  out.reach_margin = float(check_limits ? std::min(margin, limits_margin(m, s->q_actuated)) : margin);
  out.reachable = s->status == Status::Ok;
  out.cond = kInf;
  if (out.reachable) {
    const parallel12r::Conditioning c = parallel12r::conditioning(m, s->q_actuated);
    if (c.status == Status::Ok) out.cond = float(c.cond);
    else mark_singular(out);
  }
  return out;
}

void check_request(const FieldRequest& req) {
  if (req.branch != 0 && req.branch != 1)
    throw std::invalid_argument("field: branch must be 0 or 1, got " + std::to_string(req.branch));
  detail::check_grid(req.grid, Field::bytes_per_sample(), req.memory_limit_bytes);
}

}  // namespace

FieldSample sample_point(const Model& m, const Vector3d& p, const FieldRequest& req) {
  const bool check_limits = !full_ranges(m);
  return req.method == parallel12r::IkMethod::Planar ? sample_planar(unit_model(m), p, req.branch, check_limits)
                                                     : sample_general(m, p, req, check_limits);
}

std::optional<Field> compute_field(const Model& m, const FieldRequest& req, const FieldProgress& progress) {
  m.validate();
  check_request(req);
  Field f;
  f.grid = req.grid;
  f.mechanism = std::string(parallel12r::kMechanismName);
  f.length_unit = m.length_unit;
  f.parameters = {{"L1", m.L1}, {"L2", m.L2}};
  f.measure_titles = {"c(J)"};
  f.method = std::string(parallel12r::to_string(req.method));
  f.branch = req.branch;

  const bool check_limits = !full_ranges(m);
  const bool planar = req.method == parallel12r::IkMethod::Planar;
  const UnitModel unit = unit_model(m);
  const bool complete = detail::fill_field(f, false, req.threads, progress, [&](const Vector3d& p) {
    return planar ? sample_planar(unit, p, req.branch, check_limits) : sample_general(m, p, req, check_limits);
  });
  if (!complete) return std::nullopt;
  return f;
}

}  // namespace linkscape
