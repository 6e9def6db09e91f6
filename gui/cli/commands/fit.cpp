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
#include "core/verify/verify.h"
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
  if (!o.centre_region.empty()) {
    if (problem.task.centre)
      throw std::invalid_argument(command + ": --centre-region places a task whose centre is free; --task fixes it "
                                  "(centre=...): give one or the other");
    problem.inscribed.centres = task::parse_centre_region(o.centre_region);
  }
  if (info.plane_z && problem.task.centre && problem.task.centre->z() != *info.plane_z)
    throw std::invalid_argument(command + ": the task's centre has z = " + format_number(problem.task.centre->z()) +
                                ", off " + info.name + "'s plane z = " + format_number(*info.plane_z) +
                                ": a planar device's task lies in its plane (a sphere is a disc there)");
  for (const std::string& c : o.criteria)
    for (task::Criterion& parsed : task::parse_criteria(c)) problem.criteria.push_back(std::move(parsed));
  if (std::none_of(problem.criteria.begin(), problem.criteria.end(), [](const task::Criterion& c) { return c.reach(); }))
    problem.criteria.insert(problem.criteria.begin(), task::parse_criterion("reach"));
  problem.variables = fit::variables(*base, o.free, o.equal, o.bounds, command);
  // A task volume places x, y, z itself: the pose holds only what follows them.
  if (device.pose && info.task.size() <= 3)
    throw std::invalid_argument(command + ": --pose holds the task coordinates after x, y, z, and " + info.name +
                                "'s task has none (the task's centre is --task ...,centre=x,y,z)");
  if (device.pose) problem.pose = *device.pose;
  problem.ik = device.ik;
  problem.torque = device.torque;
  problem.inscribed.resolution = o.resolution;
  problem.inscribed.refinements = o.refinements;
  problem.inscribed.places = o.places;
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

namespace {

// fit --certify: the smallest design bracketed by verify::size; the task's
// centre where it is given, else where fit places it at each design.
int run_certified(const FitOptions& o, const fit::Problem& problem, std::ostream& out) {
  if (!o.output.empty() || !o.chart.empty() || o.size)
    throw std::invalid_argument("fit: --certify prints the certified bracket; --output, --chart and --size belong to "
                                "the sampled search");
  if (problem.variables.size() != 1)
    throw std::invalid_argument("fit: --certify sizes one variable (one --free parameter, or a group held equal such "
                                "as --equal L1,L2), got " + std::to_string(problem.variables.size()));
  if (!(o.bracket > 0) || !std::isfinite(o.bracket))
    throw std::invalid_argument("fit: --bracket must be a positive length, got " + format_number(o.bracket));
  verify::SizingProblem sizing;
  sizing.preset = problem.preset;
  sizing.variable = problem.variables.front();
  sizing.task = problem.task;
  sizing.criteria = problem.criteria;
  sizing.branch = problem.ik.branch.value_or(0);
  sizing.tolerance = o.bracket;
  sizing.options.torque = problem.torque;
  if (!problem.task.centre) sizing.centre_at = verify::placement_by_fit(problem);
  ProgressLine line(o.quiet);
  line.step("fit --certify");
  const verify::SizingResult r = verify::size(sizing, [&](const verify::SizingStep& step) {
    std::ostringstream text;
    text << std::setprecision(6) << "fit --certify: " << sizing.variable.name() << " = " << step.value << " "
         << verify::to_string(step.result.verdict);
    line.describe(text.str());
  });
  line.clear();
  verify::write_report(out, r);
  // The bisection takes a larger design to hold more: true of a task placed
  // at each design, not of one whose centre is fixed.
  if (problem.task.centre)
    out << "note: the task's centre is fixed, so a larger design need not hold more: a design below the bracket (or "
           "below a disproved upper bound) may still be proved; verify it with verify --param\n";
  return verify::exit_status(r);
}

}  // namespace

int run_fit(const FitOptions& o, std::ostream& out) {
  for (const std::string* file : {&o.chart}) {
    const std::string ext = std::filesystem::path(*file).extension().string();
    if (!file->empty() && ext != ".png" && ext != ".svg" && ext != ".pdf")
      throw std::invalid_argument("fit: --chart must end in .png, .svg or .pdf, got '" + *file + "'");
  }
  if (!o.output.empty() && std::filesystem::path(o.output).extension() != ".csv")
    throw std::invalid_argument("fit: --output must end in .csv, got '" + o.output + "'");
  fit::Problem problem = make_problem(o, "fit");
  if (o.certify) return run_certified(o, problem, out);
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
  std::optional<double> smallest, largest_ratio;
  progress.design = [&](const fit::Row& row, std::size_t n) {
    if (row.meets && (!smallest || row.size < *smallest)) smallest = row.size;
    if (row.invalid.empty() && (!largest_ratio || row.ratio > *largest_ratio)) largest_ratio = row.ratio;
    std::ostringstream text;
    text << std::setprecision(4) << "fit: " << n << " designs evaluated";
    if (o.size && largest_ratio) text << ", largest ratio so far " << *largest_ratio;
    else if (smallest) text << ", smallest meeting so far " << info.size_description << " = " << *smallest << " " << info.length_unit;
    line.describe(text.str());
  };
  const fit::Result r = fit::solve(problem, progress);
  line.clear();

  out << fit_report(problem, r, info);
  if (!o.output.empty()) write_fit_csv(o.output, problem, r, info);
  if (!o.chart.empty()) write_fit_chart(o.chart, problem, r, info);
  return 0;
}

void add_problem_options(CLI::App& cmd, FitOptions& o, const DeviceHelp& devices) {
  add_sampling_options(cmd, o.device, devices, " (default: each design's home pose)");
  cmd.add_option("--task", o.task,
                 "sphere:diameter=D (or radius=R) or box:size=X,Y,Z (or size=S), in the device's length unit; "
                 "append ,centre=x,y,z to fix the centre, else the search places it (nearest the home point among "
                 "equal places)")
      ->required();
  cmd.add_option("--centre-region", o.centre_region,
                 "Where the search may place the task's centre: box:min=x,y,z,max=x,y,z or "
                 "sphere:centre=x,y,z,radius=r (default: anywhere in the device's box)");
  cmd.add_option("--criterion", o.criteria,
                 "Quoted for the shell, repeatable or several separated by commas, semicolons or spaces: 'cond<T' "
                 "(the first measure; others by name, e.g. 'cond_jo<T'), 'force_iso>F', 'force_max>F' (N), "
                 "'resolution<R' (mm), 'inertia<M' (kg), and where the device states stops 'joint_margin>D' (deg), "
                 "'clearance>C' (length unit); reach is always implied")
      ->check(criteria_check());
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
             "meets every criterion at every sample evaluated, or with --size the design of that size with the largest "
             "ratio; prints it with the verdict and each criterion's margin, writes every design built as CSV and a "
             "Pareto chart of size against the worst measure (docs/task-volumes.md)");
  add_problem_options(*cmd, *o, devices);
  cmd->add_option("--size", o->size,
                  "Largest ratio at this size instead of the smallest size: among designs of this size (the "
                  "device's size measure, e.g. L1 + L2 for the 12R; length unit) within the bounds, the one whose "
                  "task is furthest inside the criteria (centre free: largest shape / task size; centre fixed: "
                  "smallest bound / worst)");
  cmd->add_option("--tolerance", o->tolerance,
                  "Relative tolerance: on the size (smallest size), on the search's step over the bounds (--size)")
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output,
                  "CSV: the design parameters, cx,cy,cz, size, meets (1: every sample evaluated meets every "
                  "criterion), samples, failing, the largest shape, fraction, ratio, each criterion's worst value, "
                  "margin and failing samples; the smallest design first, then every design built by size (one that "
                  "could not be built is counted in the summary)");
  cmd->add_option("--chart", o->chart, "Pareto chart, size against the worst measure (.png, .svg, .pdf)");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress line on stderr");
  cmd->add_flag("--certify", o->certify,
                "Certified sizing instead of the sampled search: the smallest design bracketed between one proved "
                "to meet the task everywhere (interval arithmetic) and one disproved by a counterexample; one free "
                "variable; the devices verify certifies (docs/task-volumes.md)");
  cmd->add_option("--bracket", o->bracket, "Width of the certified bracket, in the variable's unit (with --certify)")
      ->capture_default_str();
  return {cmd, Runs::Painting,  // the Pareto chart draws with QPainter
          "linkscape fit --task sphere:diameter=15 --criterion 'cond<3' -o fit.csv   the smallest design that serves a task",
          [o](std::istream&, std::ostream& out) { return run_fit(*o, out); }};
}

const RegisterCommand registered{50, add_fit};

}  // namespace

}  // namespace linkscape::gui
