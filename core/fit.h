// Sizing a device to a task (`linkscape fit`): the smallest design (or, with
// motor ratings free, the smallest ratings), within
// bounds on its free parameters, whose task volume meets every criterion
// (every sample evaluated meets every one: task::TaskReport::meets), or the
// design with the largest ratio at a given size. The size is
// Mechanism::size() of the design (12R: L1 + L2; Delta: La + Lb;
// PATHOS-II: l2 + l3). docs/task-volumes.md describes both searches.
#pragma once

#include <Eigen/Core>
#include <atomic>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/preset.h"
#include "core/task.h"

namespace linkscape::fit {

// A free variable: one parameter, or several held equal (--equal), with bounds.
struct Variable {
  std::vector<std::string> parameters;
  double lo = 0, hi = 0;
  std::string name() const;  // "L1" or "L1=L2"
};

struct Problem {
  Preset preset;                     // the design the free variables start from; the rest is held
  std::vector<Variable> variables;
  task::TaskVolume task;
  std::vector<task::Criterion> criteria;  // parsed; resolved on each design
  // The task coordinates beyond x, y, z (orientation, grip), in the
  // device's order with x, y, z ignored; empty: each design's home.
  Eigen::VectorXd pose;
  IkOptions ik;
  haptics::TorqueRating torque = haptics::TorqueRating::Continuous;
  // Where the centre is free: the search for the largest shape, within
  // inscribed.centres where set, preferring among equal places the one
  // nearest the design's home point.
  task::InscribedOptions inscribed;
  int task_resolution = task::kTaskResolution;  // task::evaluate at the placed or given centre
  double tolerance = 1e-3;           // relative: on the size along each ray; on the step of the margin search
  int threads = 0;
  // Set: the largest ratio among designs of this size (Mechanism::size(),
  // the device's length unit); unset: the smallest design meeting the task.
  std::optional<double> size;
};

// One design evaluated.
struct Row {
  std::vector<double> values;                // per variable
  std::map<std::string, double> parameters;  // the whole design
  double size = 0;                           // Mechanism::size()
  // What the smallest-design search minimises: the size, or with motor
  // ratings free (fit --free continuous_torque_Nm), the sum of their values.
  double cost = 0;
  std::string invalid;                       // why the design cannot be built (then nothing else is set)
  bool meets = false;                        // report.meets(): every sample evaluated meets every criterion
  // Centre free: the largest shape's size over the task's (sphere:
  // diameter ratio; box: scale) found by the placement search. Centre
  // fixed: the fraction of the task's volume meeting every criterion.
  double fit = 0;
  // How far inside the criteria the task is, as a ratio (the criteria's
  // margins are differences, in each measure's unit: CriterionReport).
  // Centre free: `fit`. Centre fixed: the smallest over the criteria on a
  // measure of bound / worst (bounds from above, e.g. cond) or worst / bound
  // (from below, e.g. force_iso); with reach alone, the fraction covered.
  double ratio = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // placed (rounded to centre_step) or given
  Eigen::Vector3d home = Eigen::Vector3d::Zero();    // the design's home point
  task::TaskReport report;                            // the task at the centre: the verdict
};

// The step a placed centre is rounded to, about 1e-4 of the device's size
// (a power of ten), so that the centre a report prints is the one evaluated.
double centre_step(double device_size);

// `v`, a multiple of `step` (a power of ten), one step larger, itself a round
// number: step_up(12.2, 0.01) is the double 12.21, not 12.2 + 0.01.
double step_up(double v, double step);

struct Result {
  std::vector<Row> rows;             // every design, in the order evaluated
  // The smallest design meeting the task, its free variables rounded up to
  // round numbers near the tolerance where the rounded design meets it too
  // (rounded: it was evaluated); at a given size, the one with the largest
  // ratio (when it meets the task).
  std::optional<std::size_t> best;
  std::optional<std::size_t> closest;  // where none does: the valid design closest to meeting it
  bool at_lower_bounds = false;      // the best design sits on the lower bounds (lower them to go smaller)
  double seconds = 0;
};

struct Progress {
  std::function<void(const Row& row, std::size_t evaluated)> design;  // after each design
  const std::atomic<bool>* cancel = nullptr;
};

// The largest magnitude of a bound: beyond it the samples and the
// searches lose their resolution (a bisection over bounds 1e15 wide stops
// a thousand cm from the answer; a design of 1e18 cm has a default box
// whose corners round together).
inline constexpr double kLargestBound = 1e6;

// Throws std::invalid_argument (messages starting with `command`) for no
// variable, or bounds beyond +-kLargestBound or with lo > hi.
void check_bounds(const std::vector<Variable>& variables, const std::string& command);

// Throws std::invalid_argument for a problem no search can run: no free
// variable, lo > hi or bounds beyond +-kLargestBound, criteria the device does not know,
// bounds where no design can be built (naming the device's reason); with a
// size, one that is not positive, that no design within the bounds has, or
// that no free variable changes.
// Otherwise a task no design meets is a result (best empty, closest set).
Result solve(const Problem& problem, const Progress& progress = {});

// The problem's preset with each variable's parameters set to `values`
// (one per variable).
Preset design_preset(const Problem& problem, const std::vector<double>& values);

// One design: the problem's preset with each variable's parameters set to
// `values` (one per variable), evaluated as solve evaluates each design. A
// design that cannot be built is a row with `invalid` set. nullopt if
// cancelled. Throws std::invalid_argument where the problem's pose does not
// fit the device.
std::optional<Row> evaluate(const Problem& problem, const std::vector<double>& values,
                            const std::atomic<bool>* cancel = nullptr);

// The columns every table of designs scores them by (fit's CSV, sweep's
// table), comma-joined: cx,cy,cz,size,meets,samples,failing, the largest
// shape (centre free: inscribed_diameter or inscribed_scale), fraction,
// ratio, and per criterion worst_M,margin_M,failing_M.
std::string score_header(const Problem& problem);
// A row's cells under score_header (meets is 1 exactly when failing is 0).
std::string score_cells(const Problem& problem, const Row& row);

// The parameters Mechanism::size() sums, as its size_description names them
// ("L1 + L2": L1, L2).
std::vector<std::string> size_terms(const MechanismInfo& info);

// Variables from command-line lists: `free` parameters (empty: every
// parameter the device shows in its design panel), groups from `equal`
// ("L1,L2", each a comma list held equal; its parameters are free),
// bounds "NAME=lo:hi" (default: the parameter's range in the device's
// description; a group takes the intersection). Throws
// std::invalid_argument naming an unknown parameter, a malformed bound or
// a variable bounded twice, each message headed by `command` (fit, sweep).
std::vector<Variable> variables(const Mechanism& mechanism, const std::vector<std::string>& free,
                                const std::vector<std::string>& equal, const std::vector<std::string>& bounds,
                                const std::string& command = "fit");

}  // namespace linkscape::fit
