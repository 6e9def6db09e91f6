#include "core/mechanisms/pathos2/design.h"

#include "core/mechanisms/pathos2/stops.h"
#include <omp.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace linkscape::pathos2 {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

Pose moved(const Pose& start, int axis, double s) {
  Pose p = start;
  if (axis < 3) {
    p.p_world_E[axis] += s;
  } else {
    p.R_world_E = Eigen::AngleAxisd(s, Eigen::Vector3d::Unit(axis - 3)).toRotationMatrix() * start.R_world_E;
  }
  return p;
}

// Largest s in [0, max] such that every pose on [0, s] tested with the step
// is inside; the first failure is bisected down to tol.
double march(const Geometry& g, const Pose& start, int axis, double sign, double step, double tol,
             double max, double cond_limit, int& evaluations) {
  double good = 0.0;
  while (good < max) {
    const double s = std::min(good + step, max);
    ++evaluations;
    if (!pose_inside(g, moved(start, axis, sign * s), cond_limit)) {
      double bad = s;
      while (bad - good > tol) {
        const double mid = 0.5 * (good + bad);
        ++evaluations;
        if (pose_inside(g, moved(start, axis, sign * mid), cond_limit)) good = mid;
        else bad = mid;
      }
      return good;
    }
    good = s;
  }
  return good;
}

}  // namespace

bool pose_inside(const Geometry& g, const Pose& pose, double cond_limit) {
  // The links' clearance needs the leg angles' cosines only: ActiveOnly has them.
  const PoseIkResult ik = inverse(g, pose, IkDetail::ActiveOnly);
  if (ik.status != Status::Ok) return false;
  if (has_capsules(g.model) && stops(g, pose, ik).clearance < 0) return false;
  if (!(cond_limit > 0.0) || std::isinf(cond_limit)) return true;
  const JacobianResult jr = jacobian(g, pose, ik);
  return jr.status == Status::Ok && jr.cond_p <= cond_limit && jr.cond_o <= cond_limit;
}

MovableRanges movable_ranges(const Geometry& g, const Pose& start, const RangeOptions& o) {
  return movable_ranges(g, start, o, false);
}

MovableRanges movable_ranges(const Geometry& g, const Pose& start, const RangeOptions& o,
                             bool only_translation) {
  if (!(o.step_cm > 0) || !(o.step_rad > 0) || !(o.tolerance_cm > 0) || !(o.tolerance_rad > 0) ||
      !(o.max_cm > 0) || !(o.max_rad > 0) || !std::isfinite(o.step_cm) || !std::isfinite(o.step_rad))
    throw std::invalid_argument("pathos2: range options need positive finite steps, tolerances and maxima");
  MovableRanges r;
  const PoseIkResult ik = inverse(g, start);
  r.start_status = ik.status;
  if (ik.status != Status::Ok) return r;
  if (!pose_inside(g, start, o.cond_limit)) {
    r.start_status = Status::Singular;  // inside the reach but above the cond limit
    return r;
  }
  for (int axis = 0; axis < (only_translation ? 3 : 6); ++axis) {
    const bool lin = axis < 3;
    const double step = lin ? o.step_cm : o.step_rad, tol = lin ? o.tolerance_cm : o.tolerance_rad;
    const double max = lin ? o.max_cm : o.max_rad;
    r.minus[axis] = march(g, start, axis, -1.0, step, tol, max, o.cond_limit, r.evaluations[axis]);
    r.plus[axis] = march(g, start, axis, +1.0, step, tol, max, o.cond_limit, r.evaluations[axis]);
  }
  return r;
}

double cost_g(const MovableRanges& ranges, double l2, double l3, double lp) {
  const double size = (l2 + l3 + lp) / 3.0;
  if (!(size > 0.0)) return 0.0;
  return (ranges.delta(0) + ranges.delta(1) + ranges.delta(2)) / size;
}

// ---- Grid search ----------------------------------------------------------

int GridAxis::count() const {
  if (!(step > 0.0) || !std::isfinite(lo) || !std::isfinite(hi) || hi < lo)
    throw std::invalid_argument("pathos2: grid axis needs lo <= hi and step > 0");
  return static_cast<int>(std::floor((hi - lo) / step + 1e-9)) + 1;
}

std::size_t DesignGrid::size() const {
  return static_cast<std::size_t>(l2.count()) * l3.count() * lp.count() * rz.count();
}

Model table1_model() {
  return Model::from_parameters({{"l0", 50.0}, {"lb", 10.0}, {"l1", 7.0}, {"h0", 7.0},
                                 {"theta_t", 30.0}, {"theta_g", 0.0}});
}

Pose table1_pose(const Model& model, double rz_rad) {
  // Mid-way between the base plates: z = 25 for Table 1's l0 = 50.
  return Pose::from_xyz_rpy(0.0, 0.0, model.l0 / 2.0, 0.0, 0.0, rz_rad, model.h0);
}

DesignSearchResult design_search(const Model& base, const DesignGrid& grid, const RangeOptions& options,
                                 const std::function<void(std::size_t, std::size_t)>& progress,
                                 const std::atomic<bool>* cancel) {
  base.validate();
  const int n2 = grid.l2.count(), n3 = grid.l3.count(), np = grid.lp.count(), nr = grid.rz.count();
  const std::size_t total = grid.size();
  DesignSearchResult result;
  result.rows.resize(total);
  std::atomic<std::size_t> done{0};
  std::atomic<bool> stopped{false};
  // One (l2, l3, lp) triple per task: its Rz values share one Geometry.
  const long long triples = static_cast<long long>(n2) * n3 * np;
#pragma omp parallel for schedule(dynamic)
  for (long long t = 0; t < triples; ++t) {
    const int i2 = static_cast<int>(t / (n3 * np)), i3 = static_cast<int>((t / np) % n3),
              ip = static_cast<int>(t % np);
    const double l2 = grid.l2.value(i2), l3 = grid.l3.value(i3), lp = grid.lp.value(ip);
    const bool skip = stopped.load(std::memory_order_relaxed) ||
                      (cancel && cancel->load(std::memory_order_relaxed));
    if (skip) stopped.store(true, std::memory_order_relaxed);
    const bool degenerate = !(l2 > 0.0) || !(l3 > 0.0);
    Geometry g;
    if (!skip && !degenerate) {
      Model m = base;
      m.l2 = l2, m.l3 = l3, m.lp = lp;
      g = make_geometry(m);
    }
    for (int ir = 0; ir < nr; ++ir) {
      DesignRow& row = result.rows[static_cast<std::size_t>(t) * nr + ir];
      row.l2 = l2, row.l3 = l3, row.lp = lp, row.rz_deg = grid.rz.value(ir);
      if (skip) {
        row.outcome = DesignOutcome::Cancelled;
        continue;
      }
      if (degenerate) {
        row.outcome = DesignOutcome::Degenerate;
        continue;
      }
      const MovableRanges r = movable_ranges(g, table1_pose(g.model, row.rz_deg * kDeg), options, true);
      if (r.start_status != Status::Ok) {
        row.outcome = DesignOutcome::StartInfeasible;
        continue;
      }
      row.outcome = DesignOutcome::Evaluated;
      row.dLx = r.delta(0), row.dLy = r.delta(1), row.dLz = r.delta(2);
      row.G = cost_g(r, l2, l3, lp);
    }
    const std::size_t now = done.fetch_add(static_cast<std::size_t>(nr)) + nr;
    if (progress && omp_get_thread_num() == 0 && (now / nr) % 64 == 0) progress(now, total);
  }
  result.cancelled = stopped.load();
  for (std::size_t i = 0; i < result.rows.size(); ++i) {
    const DesignRow& row = result.rows[i];
    if (row.outcome != DesignOutcome::Evaluated) continue;
    ++result.evaluated;
    if (result.best < 0 || row.G > result.rows[result.best].G) result.best = static_cast<int>(i);
  }
  if (progress) progress(done.load(), total);
  return result;
}

// ---- l0 sweep -------------------------------------------------------------------

std::vector<L0Row> l0_sweep(const Model& model, double l0_lo, double l0_hi, double step,
                            const RangeOptions& options) {
  const GridAxis axis{l0_lo, l0_hi, step};
  std::vector<L0Row> rows(static_cast<std::size_t>(axis.count()));
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < static_cast<int>(rows.size()); ++i) {
    Model m = model;
    m.l0 = axis.value(i);
    const Geometry g = make_geometry(m);
    rows[i].l0 = m.l0;
    rows[i].ranges = movable_ranges(g, home_pose(m), options);
  }
  return rows;
}

// ---- Workspace statistics ----------------------------------------------------------

WorkspaceStats workspace_stats(const Geometry& g, const Pose& centre, double half_extent_cm, double step_cm,
                               double cond_threshold) {
  if (!(half_extent_cm > 0) || !(step_cm > 0) || !std::isfinite(half_extent_cm) || !std::isfinite(step_cm))
    throw std::invalid_argument("pathos2: workspace grid needs positive finite extent and step");
  const int n = static_cast<int>(std::floor(half_extent_cm / step_cm + 1e-9));
  const int side = 2 * n + 1;
  WorkspaceStats total;
  total.min_cm = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  total.max_cm = -total.min_cm;
#pragma omp parallel
  {
    WorkspaceStats local;
    local.min_cm = total.min_cm;
    local.max_cm = total.max_cm;
#pragma omp for schedule(dynamic)
    for (int iz = 0; iz < side; ++iz) {
      for (int iy = 0; iy < side; ++iy) {
        for (int ix = 0; ix < side; ++ix) {
          Pose p = centre;
          const Eigen::Vector3d d((ix - n) * step_cm, (iy - n) * step_cm, (iz - n) * step_cm);
          p.p_world_E += d;
          ++local.samples;
          const PoseIkResult ik = inverse(g, p, IkDetail::ActiveOnly);
          if (ik.status != Status::Ok) continue;
          ++local.reachable;
          local.min_cm = local.min_cm.cwiseMin(d);
          local.max_cm = local.max_cm.cwiseMax(d);
          const JacobianResult jr = jacobian(g, p, ik);
          const bool bp = jr.cond_p <= cond_threshold, bo = jr.cond_o <= cond_threshold;
          local.cond_p_below += bp;
          local.cond_o_below += bo;
          local.both_below += bp && bo;
        }
      }
    }
#pragma omp critical
    {
      total.samples += local.samples;
      total.reachable += local.reachable;
      total.cond_p_below += local.cond_p_below;
      total.cond_o_below += local.cond_o_below;
      total.both_below += local.both_below;
      total.min_cm = total.min_cm.cwiseMin(local.min_cm);
      total.max_cm = total.max_cm.cwiseMax(local.max_cm);
    }
  }
  if (total.reachable == 0) total.min_cm = total.max_cm = Eigen::Vector3d::Zero();
  total.volume_cm3 = static_cast<double>(total.reachable) * step_cm * step_cm * step_cm;
  total.equivalent_diameter_cm = 2.0 * std::cbrt(3.0 * total.volume_cm3 / (4.0 * kPi));
  return total;
}

}  // namespace linkscape::pathos2
