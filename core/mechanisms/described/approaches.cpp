#include "core/mechanisms/described/approaches.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace linkscape::described {

using Eigen::VectorXd;

namespace {

constexpr double kPi = 3.141592653589793;
constexpr double kTolerance = 1e-10;
constexpr int kBisections = 60;

// The last t in [lo, hi] where `inside` holds, `inside(lo)` true and
// `inside(hi)` false.
double bisect(double lo, double hi, const std::function<bool(double)>& inside) {
  for (int it = 0; it < kBisections; ++it) {
    const double mid = 0.5 * (lo + hi);
    (inside(mid) ? lo : hi) = mid;
  }
  return lo;
}

// Each leg's serial set: along the base axes from home, the last pose that
// is ok (beyond an actuator's range the sweep would test the range, not the
// set), given to the leg with the smallest serial margin there.
void serial_ends(const Kinematics& kin, std::vector<ApproachEnds>& out) {
  const Model& m = kin.model();
  std::vector<std::vector<VectorXd>> ends(m.legs.size());
  for (int dir = 0; dir < 6; ++dir) {
    if (m.planar && dir / 2 == 2) continue;
    VectorXd d = VectorXd::Zero(m.home.size());
    d(dir / 2) = dir % 2 ? -1.0 : 1.0;
    const auto ok = [&](double t) { return kin.inverse(m.home + t * d, 0, kTolerance).status == Status::Ok; };
    const double hi = 2 * m.size;
    if (ok(hi)) continue;
    const VectorXd end = m.home + bisect(0, hi, ok) * d;
    const PoseSolution s = kin.inverse(end, 0, kTolerance);
    if (s.status != Status::Ok) continue;
    const JacobianParts parts = kin.jacobian(end, s);
    const auto nearest = std::min_element(parts.serial_margin.begin(), parts.serial_margin.end());
    ends[std::size_t(nearest - parts.serial_margin.begin())].push_back(end);
  }
  for (std::size_t leg = 0; leg < ends.size(); ++leg)
    if (!ends[leg].empty()) out.push_back({int(leg), std::move(ends[leg])});
}

// The parallel set: along each platform coordinate of the task, the first
// sign change of det Jx with every leg closed, marched in 64 steps (to twice
// the size, or half a turn) and bisected. A ray that leaves the poses that
// assemble before the sign changes has no end here.
void parallel_ends(const Kinematics& kin, std::vector<ApproachEnds>& out) {
  const Model& m = kin.model();
  const auto det_at = [&](const VectorXd& x) {
    const PoseSolution s = kin.inverse(x, 0, kTolerance);
    // Out of limits, the legs still close: the set is the geometry's.
    const bool closed = s.status == Status::Ok || s.status == Status::OutOfLimits;
    return closed ? kin.jacobian(x, s).Jx.determinant() : double(NAN);
  };
  const double home_det = det_at(m.home);
  if (!std::isfinite(home_det) || home_det == 0) return;
  ApproachEnds parallel{int(m.legs.size()), {}};
  constexpr int kSteps = 64;
  for (std::size_t k = 0; k < m.task.size(); ++k) {
    const int c = m.task[k].platform_coordinate;
    if (c < 0) continue;  // an extra: read by a sensor, not driven
    for (const double sign : {1.0, -1.0}) {
      VectorXd d = VectorXd::Zero(m.home.size());
      d(Eigen::Index(k)) = sign * (c < 3 ? 2 * m.size : kPi) / kSteps;
      const auto same_side = [&](double t) { return det_at(m.home + t * d) * home_det > 0; };
      for (int step = 1; step <= kSteps; ++step) {
        const double det = det_at(m.home + step * d);
        if (!std::isfinite(det)) break;
        if (det * home_det > 0) continue;
        // A sign change, not a gap in the poses that assemble: det Jx near 0 there.
        const VectorXd end = m.home + bisect(step - 1, step, same_side) * d;
        if (std::abs(det_at(end)) <= 1e-6 * std::abs(home_det)) parallel.ends.push_back(end);
        break;
      }
    }
  }
  if (!parallel.ends.empty()) out.push_back(std::move(parallel));
}

}  // namespace

std::vector<ApproachEnds> singular_approach_ends(const Kinematics& kin) {
  std::vector<ApproachEnds> out;
  serial_ends(kin, out);
  parallel_ends(kin, out);
  return out;
}

}  // namespace linkscape::described
