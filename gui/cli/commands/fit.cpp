#include "gui/cli/commands/fit.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "core/fit.h"
#include "core/atomic_file.h"
#include "core/preset.h"
#include "gui/figures/fit_report.h"
#include "gui/cli/terminal.h"
#include "gui/cli/command.h"

namespace linkscape::gui {

fit::Problem make_problem(const FitOptions& o, const std::string& command) {
  if (o.task.empty()) throw std::invalid_argument(command + ": --task is required, e.g. sphere:diameter=15");
  if (o.resolution < 8 || o.refinements < 0 || o.refinements > task::kMaxRefinements || o.places < 1 ||
      o.task_resolution < 2 || o.task_resolution > task::kMaxTaskResolution)
    throw std::invalid_argument(command + ": --resolution must be at least 8, --refinements 0 to " +
                                std::to_string(task::kMaxRefinements) + ", --places at least 1 and --task-resolution 2 to " +
                                std::to_string(task::kMaxTaskResolution) + ", got " + std::to_string(o.resolution) + ", " +
                                std::to_string(o.refinements) + ", " + std::to_string(o.places) + " and " +
                                std::to_string(o.task_resolution));
  const SampledDevice device = check_sampling_options(o.device, command);
  fit::Problem problem;
  problem.preset = device.preset;
  const std::shared_ptr<const Mechanism> base = device.mechanism;
  const MechanismInfo& info = base->info();
  problem.task = task::parse_task(o.task);
  if (info.plane_z && problem.task.centre && problem.task.centre->z() != *info.plane_z)
    throw std::invalid_argument(command + ": the task's centre has z = " + format_number(problem.task.centre->z()) +
                                ", off " + info.name + "'s plane z = " + format_number(*info.plane_z) +
                                ": a planar device's task lies in its plane (a sphere is a disc there)");
  for (const std::string& c : o.criteria) problem.criteria.push_back(task::parse_criterion(c));
  if (std::none_of(problem.criteria.begin(), problem.criteria.end(), [](const task::Criterion& c) { return c.reach(); }))
    problem.criteria.insert(problem.criteria.begin(), task::parse_criterion("reach"));
  problem.variables = fit::variables(*base, o.free, o.equal, o.bounds);
  if (device.pose) problem.pose = *device.pose;
  problem.ik = device.ik;
  problem.torque = device.torque;
  problem.inscribed = {o.resolution, o.refinements, o.places};
  problem.task_resolution = o.task_resolution;
  // The criteria on the base design: an unknown measure is an input error.
  {
    task::Device d;
    d.mechanism = base;
    const bool haptic = std::any_of(problem.criteria.begin(), problem.criteria.end(),
                                    [](const task::Criterion& c) { return c.haptic(); });
    if (haptic) d.data = haptics::device_data(problem.preset, info);
    task::resolve(d, problem.criteria);
  }

  return problem;
}

void run_fit(const FitOptions& o, std::ostream& out) {
  for (const std::string* file : {&o.chart}) {
    const std::string ext = std::filesystem::path(*file).extension().string();
    if (!file->empty() && ext != ".png" && ext != ".svg" && ext != ".pdf")
      throw std::invalid_argument("fit: --chart must end in .png, .svg or .pdf, got '" + *file + "'");
  }
  if (!o.output.empty() && std::filesystem::path(o.output).extension() != ".csv")
    throw std::invalid_argument("fit: --output must end in .csv, got '" + o.output + "'");
  fit::Problem problem = make_problem(o, "fit");
  problem.tolerance = o.tolerance;
  problem.size = o.size;
  for (const std::string* file : {&o.output, &o.chart}) check_output(*file);  // before the search
  const std::shared_ptr<const Mechanism> base = make_mechanism(problem.preset);
  const MechanismInfo& info = base->info();
  fit::Progress progress;
  // The search's length is not known ahead: the line shows the designs so
  // far, the best of them and the time spent.
  ProgressLine line(o.quiet);
  line.step("fit");
  std::optional<double> smallest, largest_margin;
  progress.design = [&](const fit::Row& row, std::size_t n) {
    if (row.meets && (!smallest || row.size < *smallest)) smallest = row.size;
    if (row.invalid.empty() && (!largest_margin || row.margin > *largest_margin)) largest_margin = row.margin;
    std::ostringstream text;
    text << std::setprecision(4) << "fit: " << n << " designs evaluated";
    if (o.size && largest_margin) text << ", largest margin so far " << *largest_margin;
    else if (smallest) text << ", smallest meeting so far " << info.size_description << " = " << *smallest << " " << info.length_unit;
    line.describe(text.str());
  };
  const fit::Result r = fit::solve(problem, progress);
  line.clear();

  out << fit_report(problem, r, info);
  if (!o.output.empty()) write_fit_csv(o.output, problem, r, info);
  if (!o.chart.empty()) write_fit_chart(o.chart, problem, r, info);
}

void add_problem_options(CLI::App& cmd, FitOptions& o, const DeviceHelp& devices) {
  add_sampling_options(cmd, o.device, devices, " (default: each design's home pose)");
  cmd.add_option("--task", o.task,
                 "sphere:diameter=D (or radius=R) or box:size=X,Y,Z (or size=S), in the device's length unit; "
                 "append ,centre=x,y,z to fix the centre, else the search places it")
      ->required();
  cmd.add_option("--criterion", o.criteria,
                 "Repeatable: cond<T (the first measure; others by name, e.g. cond_jo<T), force_iso>F, force_max>F "
                 "(N), resolution<R (mm), inertia<M (kg); reach is always implied");
  cmd.add_option("--free", o.free, "Free design parameters, comma list (default: every parameter of the design panel)")
      ->delimiter(',');
  cmd.add_option("--equal", o.equal, "Parameters held equal, comma list (repeatable), e.g. L1,L2");
  cmd.add_option("--bounds", o.bounds,
                 "NAME=lo:hi (repeatable; a group held equal by any of its names); default the parameter's range in "
                 "the design panel");
  cmd.add_option("--resolution", o.resolution, "Samples along the box for the largest inscribed shape")
      ->capture_default_str();
  cmd.add_option("--refinements", o.refinements,
                 "Zooms onto each place found, 0 to " + std::to_string(task::kMaxRefinements))
      ->capture_default_str();
  cmd.add_option("--places", o.places, "Well-separated places refined")->capture_default_str();
  cmd.add_option("--task-resolution", o.task_resolution,
                 "Samples across the task where it is evaluated, 2 to " + std::to_string(task::kMaxTaskResolution))
      ->capture_default_str();
}

namespace {

Command add_fit(CLI::App& program, const DeviceHelp& devices) {
  auto o = std::make_shared<FitOptions>();
  CLI::App* cmd = program.add_subcommand(
      "fit", "Size a device to a task: the smallest design (within bounds on its free parameters) whose task volume "
             "meets every criterion, or with --size the design of that size with the largest margin; prints it with "
             "each criterion's margin, writes every design as CSV and a Pareto chart of size against the worst "
             "measure (docs/task-volumes.md)");
  add_problem_options(*cmd, *o, devices);
  cmd->add_option("--size", o->size,
                  "Largest margin at this size instead of the smallest size: among designs of this size (the "
                  "device's size measure, e.g. L1 + L2 for the 12R; length unit) within the bounds, the one whose "
                  "task is furthest inside the criteria (centre free: largest shape / task size; centre fixed: "
                  "smallest bound / worst ratio; >= 1 meets)");
  cmd->add_option("--tolerance", o->tolerance,
                  "Relative tolerance: on the size (smallest size), on the search's step over the bounds (--size)")
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output,
                  "CSV: the design parameters, cx,cy,cz, size, meets, the largest shape, the fraction, each "
                  "criterion's worst value and margin; the smallest design first, then every design by size");
  cmd->add_option("--chart", o->chart, "Pareto chart, size against the worst measure (.png, .svg, .pdf)");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress line on stderr");
  return {cmd, Runs::Painting,  // the Pareto chart draws with QPainter
          "linkscape fit --task sphere:diameter=15 --criterion 'cond<3' -o fit.csv   the smallest design that serves a task",
          [o](std::istream&, std::ostream& out) { run_fit(*o, out); }};
}

const RegisterCommand registered{50, add_fit};

}  // namespace

}  // namespace linkscape::gui
