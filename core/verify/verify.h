// Certified task checks (`linkscape verify`) and certified sizing
// (`fit --certify`): proofs by interval arithmetic that every point of a
// task volume meets every criterion, or a counterexample confirmed by
// independent evaluations. docs/task-volumes.md ("Certified verdicts")
// describes the method, its soundness and its limits.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/fit.h"
#include "core/mechanism.h"
#include "core/preset.h"
#include "core/task.h"

namespace linkscape::verify {

// A device, criterion or task the certifier has no enclosure for (a device
// without closed-form kinematics here, a haptic criterion, a planar or
// centre-less task). The command line treats it as bad input (exit 2).
struct Uncertifiable : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

enum class Verdict {
  Proved,     // every point of the task meets every criterion
  Disproved,  // a point of the task fails a criterion (the counterexample)
  Undecided,  // neither within the depth and time limits
};
std::string_view to_string(Verdict verdict);

// Exit statuses of `verify` (bad input stays 2, a failed write 1).
inline constexpr int kExitProved = 0;
inline constexpr int kExitDisproved = 3;
inline constexpr int kExitUndecided = 4;
int exit_status(Verdict verdict);

struct Options {
  // Bisections of the task's bounding box a box may take (3 halve it in
  // every direction); boxes still open there are undecided.
  int max_depth = 48;
  double time_limit_seconds = 120;  // then the open boxes are undecided; <= 0: no limit
  int threads = 0;                  // 0: all (OpenMP)
  bool keep_boxes = false;          // keep the proved and undecided boxes (drawing, tests)
  // Samples of the task searched for a counterexample before subdividing.
  int search_samples = 6000;
  // Boxes one generation may hold (2^24: about 1 GB with their children);
  // beyond, the open boxes are undecided.
  std::int64_t max_open_boxes = std::int64_t(1) << 24;
  // The torque the force criteria use.
  haptics::TorqueRating torque = haptics::TorqueRating::Continuous;
  // Set and true: stop as at the time limit (the open boxes undecided).
  const std::atomic<bool>* cancel = nullptr;
};

// An axis-aligned box of positions, in the device's length unit.
struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  double volume() const { return (hi - lo).prod(); }
};

struct Counterexample {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // inside the task (certified)
  std::string criterion;  // the criterion it fails, as given
  std::string reason;     // "c(J) >= 3.0004", "force_iso <= 0.93 N", "out of reach", "outside the range of beta"
  // The failing measure there: a certified bound (interval arithmetic; at
  // least it for c(J) and resolution, at most it for force_iso), an
  // independent evaluation in long double (the paper's angles and J for the
  // 12R, the tangent half-angle leg solution for the Delta; for a described
  // device its legs' closed forms in long double), and the device's own
  // evaluation through the mechanism interface (a described device without
  // its stops: what the verdict is about). Out of reach
  // or singular: bound +inf, and the values are the measure's failing
  // extreme (c(J) +inf) or the device's reach margin.
  double bound = 0;
  double long_double_value = 0;
  double device_value = 0;
};

struct Result {
  Verdict verdict = Verdict::Undecided;
  std::string mechanism;
  std::map<std::string, double> parameters;
  std::string task;                     // as core/task.h writes it
  std::vector<std::string> criteria;    // as given
  std::optional<Counterexample> counterexample;
  // Where proved with a cond criterion: the largest of the boxes' certified
  // upper bounds on c(J). Below the threshold, and above the task's largest
  // c(J) by however much the boxes were left wide (boxes are split only
  // until they prove): not the task's worst value.
  std::optional<double> largest_box_bound;
  double task_volume = 0;
  double proved_volume = 0;     // of the boxes proved (clipped to the task's bounding boxes)
  double undecided_volume = 0;  // of the boxes left open (an upper bound on the task's part)
  double undecided_fraction() const { return task_volume > 0 ? std::min(1.0, undecided_volume / task_volume) : 0.0; }
  std::int64_t boxes = 0;       // evaluated
  int deepest = 0;              // bisections of the deepest box evaluated
  bool timed_out = false;       // open boxes left at the time limit
  bool box_limit = false;       // open boxes left when a generation outgrew Options::max_open_boxes
  double seconds = 0;
  std::vector<Box> proved_boxes, undecided_boxes;  // with Options::keep_boxes
  // What the device states that the verdict does not cover (a described
  // device's passive-joint limits, link interference): the verdict is about
  // the device without them. Empty: it covers everything the device checks.
  std::string not_covered;
  // Where not_covered is set: the device's own evaluation (with them) at the
  // counterexample search's samples of the task, not certified: how many
  // assemble but are stopped by them, and the first such sample's words.
  int stop_samples = 0, stop_failures = 0;
  std::string stop_example;
};

// Proves or disproves that every point of `task` (with its centre) meets
// every criterion on the preset's device in the IK branch `branch`.
// Certifiable: the devices parallel-12r and delta, with the criteria reach,
// cond<T (the device's first measure), force_iso>F and resolution<R (with
// the preset's actuator data); described devices whose legs are all
// crank-rod, slide-rod or extensible (legs.h), with reach and cond<T, their
// passive-joint limits and link interference not covered (Result::not_covered). Throws Uncertifiable for others,
// std::invalid_argument for bad input (a task without a centre, an unknown
// or malformed criterion, a branch the device does not have, a depth
// outside 1..200, threads < 0).
Result verify(const Preset& preset, const task::TaskVolume& task, const std::vector<task::Criterion>& criteria,
              const Options& options = {}, int branch = 0);

// The report: the verdict in words, the counterexample with its three
// evaluations, the undecided fraction, boxes and time.
void write_report(std::ostream& out, const Result& result);
// The same as one JSON object.
void write_json(std::ostream& out, const Result& result);

// ---- Certified sizing ----------------------------------------------------------------

struct SizingProblem {
  Preset preset;              // the design the variable starts from; the rest is held
  fit::Variable variable;     // one parameter or several held equal (L1=L2), with bounds lo..hi
  task::TaskVolume task;      // with its centre
  std::vector<task::Criterion> criteria;
  int branch = 0;
  double tolerance = 0.05;    // width of the bracket, in the variable's unit
  Options options;            // for each design
  // Set: the task's centre is where it is at this value of the variable and
  // moves in proportion to it, for a device whose geometry scales with the
  // variable (the 12R with L1 = L2 = L: c(J) at p depends on p / L only), so
  // each design is checked with the task where a placement at its own size
  // puts it. Unset: the centre stays.
  std::optional<double> centre_scales_from;
  // Set: the task's centre for the design with the variable at `value`
  // (e.g. placement_by_fit), overriding the two above; the task's own
  // centre may then be unset. Each design's result names its centre.
  std::function<Eigen::Vector3d(double value)> centre_at;
};

// The centre `fit` places a free-centre task at for each design of a
// one-variable problem (fit::evaluate: the largest inscribed sphere or box;
// where none is found, the device's default box's centre). Throws
// std::invalid_argument unless the problem has one variable and no centre.
std::function<Eigen::Vector3d(double value)> placement_by_fit(const fit::Problem& problem);

struct SizingStep {
  double value = 0;  // of the variable
  Result result;     // its boxes dropped
};

struct SizingResult {
  std::string variable;
  double tolerance = 0;
  // The smallest design proved and the largest disproved below it: the
  // answer lies in (disproved_at, proved_at]. Unset where no design in the
  // bounds was proved (or disproved).
  std::optional<double> proved_at, disproved_at;
  std::optional<Result> proved, disproved;  // their verdicts (the disproved one's counterexample)
  bool proved_at_lower_bound = false;       // the lower bound itself is proved: the answer is at or below it
  std::vector<SizingStep> steps;            // every design verified, in order
  double seconds = 0;
  bool bracketed() const {
    return proved_at && (proved_at_lower_bound || (disproved_at && *proved_at - *disproved_at <= tolerance));
  }
};

// Bisects the variable between its bounds: the upper bound must be proved
// and the lower disproved (else the result says which end is not), then
// each midpoint's verdict moves one end, until the bracket is at most the
// tolerance. A midpoint left undecided ends the search with the bracket so
// far. Assumes a larger design covers more (true of the link lengths of
// both devices). `progress` is called after each design. Throws as verify
// does, and std::invalid_argument for bounds with lo >= hi or a tolerance
// that is not positive.
SizingResult size(const SizingProblem& problem, const std::function<void(const SizingStep&)>& progress = {});

// 0 when the bracket meets the tolerance; kExitDisproved when even the
// upper bound is disproved; kExitUndecided otherwise.
int exit_status(const SizingResult& result);
void write_report(std::ostream& out, const SizingResult& result);
void write_json(std::ostream& out, const SizingResult& result);

}  // namespace linkscape::verify
