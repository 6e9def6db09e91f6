#include "core/mechanisms/parallel12r/field.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "core/conditioning.h"
#include "core/field_sampling.h"
#include "core/mechanisms/parallel12r/planar_kernel.h"
#include "core/simd.h"

namespace linkscape {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using parallel12r::Model;
namespace planar = parallel12r::planar;

namespace {

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

}  // namespace

namespace parallel12r::planar {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Sample unsolved(double margin, Status status) { return {kInfinity, margin, kInfinity, status}; }

}  // namespace

bool full_ranges(const Model& m) {
  constexpr double pi = std::numbers::pi;
  return m.alpha_limits.lo <= -pi / 2 && m.alpha_limits.hi >= pi / 2 && m.beta_limits.lo <= -pi &&
         m.beta_limits.hi >= pi && m.gamma_limits.lo <= -pi && m.gamma_limits.hi >= pi;
}

UnitModel unit_model(const Model& m) {
  const int exponent = std::ilogb(m.reach());
  UnitModel u{m, std::ldexp(1.0, -exponent), std::ldexp(1.0, exponent)};
  u.unit.L1 = m.L1 * u.to_unit;
  u.unit.L2 = m.L2 * u.to_unit;
  return u;
}

namespace {

// The planar closed form without trigonometry, in unit lengths. The target
// fixes alpha (cos a, sin a from x, y) and the plane of the links, in which
// the two-link IK gives each link's components l_i = (l_ir, l_iz); the
// paper's angles follow, (cos t_i, sin t_i) proportional to (cos a l_ir, l_iz),
// with d_i = sqrt(1 - sin^2 a sin^2 t_i) = cos a |l_i| / n_i where
// n_i^2 = cos^2 a l_ir^2 + l_iz^2. Written in the l_i (|l_i| = L_i), the
// paper's Jacobian needs no square root, with k_i = 1 / (cos a L_i^2):
//   dD/dalpha = sum_i k_i (-n_i^2 l_ir, -sin a cos a l_ir^3, -sin a l_iz l_ir^2),
//   dD/dbeta  = k_1 n_1^2 (sin a l_1z, -cos a l_1z, l_1r), dD/dgamma likewise,
// and forward(q) = sum_i L_i / |l_i| (-sin a l_ir, cos a l_ir, l_iz).
// tests/core/mechanisms/parallel12r/test_field.cpp checks c(J) against
// parallel12r::jacobian. Same equations as parallel12r::inverse(Planar).
Sample sample_unit(const Model& m, const Vector3d& p, int branch, bool check_limits) {
  const double x = p.x(), y = p.y(), z = p.z();
  const double rho2 = x * x + y * y, R2 = rho2 + z * z, R = std::sqrt(R2), rho = std::sqrt(rho2);
  const double margin = geometric_margin(m, R);
  const double tol = kSingularTolerance * m.reach();
  if (margin < -tol) return unsolved(margin, Status::Unreachable);
  if (margin <= tol || std::abs(y) <= tol || rho <= tol) return unsolved(margin, Status::Singular);

  const double L1 = m.L1, L2 = m.L2;
  const double sign_y = y > 0 ? 1.0 : -1.0, abs_y = std::abs(y);
  // 1/rho, 1/R and 1/|y| from one division.
  const double inv = 1.0 / (rho * R * abs_y), inv_rho = R * abs_y * inv, inv_R = rho * abs_y * inv;
  const double ca = abs_y * inv_rho, sa = -x * sign_y * inv_rho, r = sign_y * rho, inv_ca = rho * (rho * R * inv);
  const double half_inv_R = 0.5 * inv_R;
  const double a = (R2 + L1 * L1 - L2 * L2) * half_inv_R;
  const double h = std::sqrt(std::max(0.0, (L1 + L2 - R) * (L2 - L1 + R) * (R + L1 - L2) * (R + L1 + L2))) * half_inv_R;
  const double ur = r * inv_R, uz = z * inv_R, s = branch == 0 ? 1.0 : -1.0;
  const double l1r = a * ur - s * h * uz, l1z = a * uz + s * h * ur;
  const double l2r = r - l1r, l2z = z - l1z;

  const double n1 = ca * ca * l1r * l1r + l1z * l1z, n2 = ca * ca * l2r * l2r + l2z * l2z;  // n_i^2
  const double k1 = inv_ca * (1.0 / (L1 * L1)), k2 = inv_ca * (1.0 / (L2 * L2));
  Matrix3d J;
  J.col(0) = k1 * Vector3d(-n1 * l1r, -sa * ca * l1r * l1r * l1r, -sa * l1z * l1r * l1r) +
             k2 * Vector3d(-n2 * l2r, -sa * ca * l2r * l2r * l2r, -sa * l2z * l2r * l2r);
  J.col(1) = k1 * n1 * Vector3d(sa * l1z, -ca * l1z, l1r);
  J.col(2) = k2 * n2 * Vector3d(sa * l2z, -ca * l2z, l2r);
  // forward(q) - p, with L_i / |l_i| = 1 + d_i to first order in the links'
  // length errors (d_i ~ 1e-16 here, so the second order is below rounding).
  const Vector3d w1(-sa * l1r, ca * l1r, l1z), w2(-sa * l2r, ca * l2r, l2z);
  const double d1 = (L1 * L1 - (l1r * l1r + l1z * l1z)) * (0.5 / (L1 * L1));
  const double d2 = (L2 * L2 - (l2r * l2r + l2z * l2z)) * (0.5 / (L2 * L2));
  const Vector3d error = (w1 + w2 - p) + d1 * w1 + d2 * w2;

  Sample out;
  out.residual = error.norm();
  out.reach_margin = margin;
  double limit_margin = kInfinity;
  if (check_limits) {
    limit_margin = limits_margin(m, Vector3d(std::atan2(sa, ca), std::atan2(l1z, ca * l1r), std::atan2(l2z, ca * l2r)));
    out.reach_margin = std::min(margin, limit_margin);
  }
  out.status = limit_margin < 0 ? Status::OutOfLimits : Status::Ok;
  out.cond = kInfinity;
  if (out.status == Status::Ok) {
    // Beyond what double resolves (kMaxTrustedCondition): singular, as the IK
    // reports targets within its singular band, never a wrong finite c(J).
    const double cond = condition_number_fast(J);
    if (cond <= kMaxTrustedCondition) out.cond = cond;
    else out.status = Status::Singular;
  }
  return out;
}

}  // namespace

// In the model's units: solved in unit lengths, margin and residual scaled back.
Sample sample(const UnitModel& u, const Vector3d& p, int branch, bool check_limits) {
  Sample s = sample_unit(u.unit, p * u.to_unit, branch, check_limits);
  s.reach_margin *= u.from_unit;
  s.residual *= u.from_unit;
  return s;
}

}  // namespace parallel12r::planar

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// A solved sample whose c(J) is beyond what double resolves
// (parallel12r::kMaxTrustedCondition): singular, never a wrong finite c(J).
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

PlanarKernel kernel_of(const FieldRequest& req) { return req.kernel ? *req.kernel : field_kernel_from_environment(); }

// The planar kernel is odd in x with alpha -> -alpha (sa changes sign, every
// other quantity keeps its value or changes sign exactly), so the sample at
// (-x, y, z) equals the one at (x, y, z) bit for bit where the alpha range is
// symmetric (or unchecked). A row can then be computed for one half and
// mirrored, if the grid's x coordinates are themselves exact mirrors.
bool mirror_is_exact(const Model& m, bool check_limits, const Grid& g) {
  if (check_limits && m.alpha_limits.lo != -m.alpha_limits.hi) return false;
  const int n = g.dims[0];
  for (int i = 0; i < n; ++i)
    if (g.point(i, 0, 0).x() != -g.point(n - 1 - i, 0, 0).x()) return false;
  return true;
}

}  // namespace

FieldSample sample_point(const Model& m, const Vector3d& p, const FieldRequest& req) {
  const bool check_limits = !planar::full_ranges(m);
  return req.method == parallel12r::IkMethod::Planar
             ? planar::to_field_sample(planar::sample(planar::unit_model(m), p, req.branch, check_limits))
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
  using parallel12r::IkMethod;
  for (IkMethod k : {IkMethod::Paper, IkMethod::Planar, IkMethod::Newton, IkMethod::DampedLeastSquares, IkMethod::Fallback})
    f.method_names.emplace_back(parallel12r::to_string(k));  // method_used holds the IkMethod's value
  f.branch = req.branch;

  const Grid& g = req.grid;
  const bool check_limits = !planar::full_ranges(m);
  const bool planar_method = req.method == parallel12r::IkMethod::Planar;
  const PlanarKernel kernel = planar_method ? kernel_of(req) : PlanarKernel::Scalar;
  if (kernel != PlanarKernel::Scalar) simd::apply_environment();
  const bool mirrored = kernel == PlanarKernel::VectorMirrored && mirror_is_exact(m, check_limits, g);
  const planar::UnitModel unit = planar::unit_model(m);
  const bool complete =
      detail::fill_field_rows(f, false, req.threads, progress, [&](const detail::GridRow& row, const detail::FieldRowOut& out) {
        const int n = row.count;
        if (!planar_method) {
          for (int t = 0; t < n; ++t) out.store(t, sample_general(m, row.point(g, t), req, check_limits));
        } else if (kernel == PlanarKernel::Scalar) {
          for (int t = 0; t < n; ++t)
            out.store(t, planar::to_field_sample(planar::sample(unit, row.point(g, t), req.branch, check_limits)));
        } else if (mirrored && row.axis == 0) {
          planar::sample_row_vector(unit, req.branch, check_limits, g, row, n / 2, n - n / 2, true, out);
        } else {
          planar::sample_row_vector(unit, req.branch, check_limits, g, row, 0, n, false, out);
        }
      }, kernel != PlanarKernel::Scalar ? detail::kVectorChunkSamples : detail::kChunkSamples);
  if (!complete) return std::nullopt;
  return f;
}

}  // namespace linkscape
