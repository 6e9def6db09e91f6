// PATHOS-II workspace and design search (paper Sections 3-4): movable ranges
// along the axes, the cost G of Eq. 21, the Table 2 grid search, the l0 sweep
// of Fig. 6 and fixed-orientation workspace statistics. Units: cm, rad.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <functional>
#include <vector>

#include "core/mechanisms/pathos2/pathos2.h"

namespace linkscape::pathos2 {

// A pose counts as inside when every leg is Ok (reachable, not singular,
// within the model's joint limits), no two links' capsules overlap where the
// model gives them a radius (stops.h) and, if cond_limit is finite, both
// cond(Jp) and cond(Jo) are at most cond_limit.
struct RangeOptions {
  double step_cm = 0.25;       // march step along a translation axis
  double step_rad = 0.02;      // march step about a rotation axis
  double tolerance_cm = 1e-3;  // bisection stops below this
  double tolerance_rad = 1e-4;
  double max_cm = 60.0;        // give up marching beyond (reported as reaching it)
  double max_rad = 3.141592653589793;
  double cond_limit = 0.0;     // 0 or inf: no conditioning test (the paper's ranges)
};

bool pose_inside(const Geometry& geometry, const Pose& pose, double cond_limit = 0.0);

// Movable range from `start` along +-x, +-y, +-z (world, cm) and about the
// world x, y, z axes through the E origin (rad), in the paper's sense: the
// IK exists continuously from the start (march with the step, then bisect
// the first failure). Index 0..5 = x, y, z, rx, ry, rz.
struct MovableRanges {
  Status start_status = Status::Unreachable;  // of the start pose; ranges 0 unless Ok
  std::array<double, 6> minus{};              // distance reached in the - direction
  std::array<double, 6> plus{};               // in the + direction
  std::array<int, 6> evaluations{};           // IK calls per axis
  double delta(int axis) const { return minus[axis] + plus[axis]; }  // dLx, ..., dRz
};
MovableRanges movable_ranges(const Geometry& geometry, const Pose& start, const RangeOptions& options = {});
// With only_translation, the rotation axes are skipped (left 0).
MovableRanges movable_ranges(const Geometry& geometry, const Pose& start, const RangeOptions& options,
                             bool only_translation);

// Eq. 21: G = (dLx + dLy + dLz) / ((l2 + l3 + lp) / 3).
double cost_g(const MovableRanges& ranges, double l2, double l3, double lp);

// ---- Table 2 grid search -------------------------------------------------

struct GridAxis {
  double lo = 0.0, hi = 0.0, step = 1.0;
  int count() const;  // values lo, lo + step, ..., <= hi (+ rounding slack)
  double value(int i) const { return lo + step * i; }
};

struct DesignGrid {
  GridAxis l2{0.0, 20.0, 1.0};   // cm (Table 2)
  GridAxis l3{0.0, 20.0, 1.0};   // cm
  GridAxis lp{0.0, 20.0, 1.0};   // cm
  GridAxis rz{0.0, 120.0, 15.0};  // deg, initial orientation about z
  std::size_t size() const;       // 21 * 21 * 21 * 9 = 83,349 for Table 2
};

// Table 1: l0 = 50, lb = 10, l1 = 7, h0 = 7, theta_t = 30 deg, theta_g = 0;
// the other parameters keep the Model defaults.
Model table1_model();
// Table 1 pose: (0, 0, l0 / 2) (= 25 for Table 1), Rx = Ry = 0, Rz = rz_rad.
Pose table1_pose(const Model& model, double rz_rad);

enum class DesignOutcome : unsigned char {
  Evaluated,       // G computed
  Degenerate,      // l2 = 0 or l3 = 0: the leg has no elbow (G = 0)
  StartInfeasible, // the Table 1 pose itself is not inside (G = 0)
  Cancelled,       // skipped after the cancel flag was raised
};

struct DesignRow {
  double l2 = 0, l3 = 0, lp = 0, rz_deg = 0;
  DesignOutcome outcome = DesignOutcome::Cancelled;
  double dLx = 0, dLy = 0, dLz = 0;  // cm
  double G = 0;
};

struct DesignSearchResult {
  std::vector<DesignRow> rows;  // grid order: l2 slowest, then l3, lp, rz
  std::size_t evaluated = 0;    // rows with outcome Evaluated
  bool cancelled = false;
  int best = -1;                // index of the largest G (first one on ties)
};

// progress(done, total) is called from one thread, at most every few hundred
// designs and once at the end; cancel may be null. Parallel with OpenMP.
DesignSearchResult design_search(const Model& base, const DesignGrid& grid = {},
                                 const RangeOptions& options = {},
                                 const std::function<void(std::size_t, std::size_t)>& progress = {},
                                 const std::atomic<bool>* cancel = nullptr);

// ---- Fig. 6: l0 sweep ---------------------------------------------------------

struct L0Row {
  double l0 = 0;
  MovableRanges ranges;  // from the Table 3 pose (0, 0, l0 / 2, Rz = 30 deg)
};
// l0 from l0_lo to l0_hi (cm) in steps, for the given model (l0 replaced).
std::vector<L0Row> l0_sweep(const Model& model, double l0_lo = 40.0, double l0_hi = 55.0,
                            double step = 1.0, const RangeOptions& options = {});

// ---- Fixed-orientation workspace ------------------------------------------------

struct WorkspaceStats {
  std::size_t samples = 0;    // grid points tested
  std::size_t reachable = 0;  // inside (all legs Ok)
  std::size_t cond_p_below = 0, cond_o_below = 0, both_below = 0;  // of reachable
  double volume_cm3 = 0;                 // reachable * step^3
  double equivalent_diameter_cm = 0;     // of a sphere with that volume
  Eigen::Vector3d min_cm = Eigen::Vector3d::Zero(), max_cm = Eigen::Vector3d::Zero();  // bounding box
};
// Samples a cube of +-half_extent_cm around `centre` (orientation and grip
// from it) with the given step; counts reachable points and those with
// cond(Jp), cond(Jo) <= cond_threshold. Parallel with OpenMP.
WorkspaceStats workspace_stats(const Geometry& geometry, const Pose& centre, double half_extent_cm,
                               double step_cm, double cond_threshold = 5.0);

}  // namespace linkscape::pathos2
