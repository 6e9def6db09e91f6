// c(J) at a point in long double by a route independent of kernels.h: the
// actuator angles first (trigonometry), then the Jacobian from them and an
// SVD. Counterexamples are confirmed with it and the tests check the
// enclosures against it.
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "core/verify/certifier.h"
#include "core/verify/legs.h"

namespace linkscape::verify {
namespace {

using LD = long double;
using Vector3L = Eigen::Matrix<LD, 3, 1>;
using Matrix3L = Eigen::Matrix<LD, 3, 3>;
constexpr LD kPiL = std::numbers::pi_v<long double>;
constexpr LD kInfL = std::numeric_limits<LD>::infinity();


bool inside(LD q, const Range& range, bool wraps) {
  if (cuts_nothing(range)) return true;
  if (!wraps) return q >= range.lo && q <= range.hi;
  const LD centre = 0.5L * (LD(range.lo) + LD(range.hi));
  const LD q_near = centre + std::remainder(q - centre, 2 * kPiL);
  return q_near >= range.lo && q_near <= range.hi;
}

// The paper's Eqs. 11-13 differentiated (parallel12r.cpp's link_direction),
// at angles from the planar two-link solution.
std::optional<Matrix3L> jacobian_12r(const Certifier& c, const Vector3L& p) {
  const LD L1 = c.L1, L2 = c.L2, x = p.x(), y = p.y(), z = p.z();
  const LD rho = std::hypot(x, y), R = p.norm();
  if (y == 0 || R >= L1 + L2 || R <= std::abs(L1 - L2)) return std::nullopt;
  const LD sign_y = y > 0 ? 1 : -1, r = sign_y * rho;
  const LD a = (R * R + L1 * L1 - L2 * L2) / (2 * R);
  const LD h = std::sqrt((L1 + L2 - R) * (L2 - L1 + R) * (R + L1 - L2) * (R + L1 + L2)) / (2 * R);
  const LD s = c.branch == 0 ? 1 : -1, ur = r / R, uz = z / R;
  const LD l1r = a * ur - s * h * uz, l1z = a * uz + s * h * ur;
  const LD alpha = std::atan2(-x * sign_y, std::abs(y));
  const LD ca = std::cos(alpha), sa = std::sin(alpha);
  const LD q[3] = {alpha, std::atan2(l1z, ca * l1r), std::atan2(z - l1z, ca * (r - l1r))};
  if (c.check_ranges)
    for (int k = 0; k < 3; ++k)
      if (!inside(q[k], c.ranges[k], false)) return std::nullopt;
  Matrix3L J;
  J.col(0).setZero();
  for (int link = 0; link < 2; ++link) {
    const LD L = link == 0 ? L1 : L2, t = q[1 + link];
    const LD st = std::sin(t), ct = std::cos(t), d2 = ca * ca + sa * sa * ct * ct, d3 = d2 * std::sqrt(d2);
    J.col(0) += L * Vector3L(-ca * ct, -sa * ct * ct * ct, -sa * st * ct * ct) / d3;
    J.col(1 + link) = L * ca * Vector3L(sa * ca * st, -ca * ca * st, ct) / d3;
  }
  return J;
}

// Each leg by the tangent half-angle of A cos q + B sin q = C (delta.cpp's
// solve_leg), then J = -Jx^-1 Jq from the elbows.
std::optional<Matrix3L> jacobian_delta(const Certifier& c, const Vector3L& p) {
  const DeltaGeometry& g = c.delta;
  const LD La = g.La, Lb = g.Lb;
  Matrix3L Jx;
  Vector3L Jq;
  for (int i = 0; i < 3; ++i) {
    const LD phi = i * (2 * kPiL / 3);
    const Vector3L e(std::cos(phi), std::sin(phi), 0), z(0, 0, 1);
    const Vector3L d = p - (LD(g.R) - LD(g.r)) * e;
    const LD u = d.dot(e), w = d.z();
    const LD A = 2 * La * u, B = -2 * La * w, C = d.squaredNorm() + La * La - Lb * Lb;
    const LD disc = A * A + B * B - C * C;
    if (!(disc > 0)) return std::nullopt;
    const LD sigma = (g.branch >> i) & 1 ? 1 : -1;
    const LD n1 = B + sigma * std::sqrt(disc), d1 = C + A, n2 = C - A, d2 = B - sigma * std::sqrt(disc);
    const LD half = std::hypot(n1, d1) >= std::hypot(n2, d2) ? std::atan2(n1, d1) : std::atan2(n2, d2);
    const LD q = 2 * half;
    if (c.check_ranges && !inside(q, c.ranges[i], true)) return std::nullopt;
    const Vector3L s = p + LD(g.r) * e - (LD(g.R) * e + La * (std::cos(q) * e - std::sin(q) * z));
    Jx.row(i) = s.transpose();
    Jq(i) = La * s.dot(std::sin(q) * e + std::cos(q) * z);
  }
  if (Jx.determinant() == 0) return std::nullopt;
  return Matrix3L(-Jx.inverse() * Jq.asDiagonal());
}

}  // namespace

std::optional<Matrix3L> reference_jacobian(const Certifier& certifier, const Eigen::Vector3d& p) {
  if (certifier.legs) return std::nullopt;  // a described device: reference_condition alone
  const Vector3L pl = p.cast<LD>();
  return certifier.device == Device::Parallel12r ? jacobian_12r(certifier, pl) : jacobian_delta(certifier, pl);
}

long double reference_condition(const Certifier& certifier, const Eigen::Vector3d& p) {
  if (certifier.legs) return certifier.legs->reference_measure(p);
  const std::optional<Matrix3L> J = reference_jacobian(certifier, p);
  if (!J) return kInfL;
  const Vector3L s = Eigen::JacobiSVD<Matrix3L>(*J).singularValues();
  return s(2) > 0 ? s(0) / s(2) : kInfL;
}

long double reference_value(const Certifier& certifier, const Certifier::ColumnCriterion& criterion,
                            const Eigen::Vector3d& p) {
  const std::optional<Matrix3L> J = reference_jacobian(certifier, p);
  if (!J) return criterion.force ? 0 : kInfL;
  LD value = criterion.force ? kInfL : 0;
  for (int i = 0; i < 3; ++i) {
    const LD scale = 0.5L * (LD(criterion.scale[i].lo) + LD(criterion.scale[i].hi)), length = J->col(i).norm();
    value = criterion.force ? std::min(value, scale / length) : std::max(value, scale * length);
  }
  return value;
}

}  // namespace linkscape::verify
