// linkscape verify: a proof that every point of a task volume meets every
// criterion, or a counterexample (core/verify/verify.h, docs/task-volumes.md).
#include <iostream>
#include <optional>
#include <stdexcept>

#include "core/csv.h"
#include "core/verify/verify.h"
#include "gui/cli/command.h"
#include "gui/cli/sampling.h"

namespace linkscape::gui {
namespace {

struct VerifyOptions {
  PresetChoice mechanism;
  int branch = 0;
  std::string task;                   // with its centre
  std::vector<std::string> criteria;  // "cond<3", ...
  std::string torque = "continuous";
  verify::Options limits;
  bool json = false;
};

int run_verify(const VerifyOptions& o, std::ostream& out) {
  // verify::verify refuses a task without its centre and an empty list of criteria.
  const task::TaskVolume task = task::parse_task(o.task);
  std::vector<task::Criterion> criteria;
  for (const std::string& c : o.criteria)
    for (task::Criterion& parsed : task::parse_criteria(c)) criteria.push_back(std::move(parsed));
  verify::Options limits = o.limits;
  limits.torque = haptics::parse_torque_rating(o.torque);
  const verify::Result r = verify::verify(chosen_preset(o.mechanism), task, criteria, limits, o.branch);
  if (o.json) verify::write_json(out, r);
  else verify::write_report(out, r);
  return verify::exit_status(r.verdict);
}

Command add_verify(CLI::App& program, const DeviceHelp&) {
  auto o = std::make_shared<VerifyOptions>();
  CLI::App* cmd = program.add_subcommand(
      "verify",
      "Prove that every point of a task volume meets every criterion (interval arithmetic through the device's "
      "closed forms), or disprove it with a counterexample; exit 0 proved, 3 disproved, 4 undecided, 2 bad input. "
      "The 12R, the Delta, and spatial described devices whose legs are crank-rod, slide-rod or extensible, each "
      "ending in a spherical joint (not in a universal one), with one actuator per leg (their passive-joint limits "
      "and links not covered; planar devices are not) (docs/task-volumes.md, \"Certified verdicts\")");
  add_mechanism_options(*cmd, o->mechanism);
  cmd->add_option("--task", o->task, "sphere:diameter=D,centre=x,y,z or box:size=X,Y,Z,centre=x,y,z (length unit)")
      ->required();
  cmd->add_option("--criterion", o->criteria,
                  "Quoted for the shell, repeatable or several separated by commas, semicolons or spaces: reach, "
                  "'cond<T', 'force_iso>F' (N), 'resolution<R' (mm)")
      ->check(criteria_check());
  cmd->add_option("--branch", o->branch, "The IK branch the device holds over the task")->capture_default_str();
  cmd->add_option("--torque", o->torque, "Torque the force criteria use: continuous or peak")->capture_default_str();
  cmd->add_option("--depth", o->limits.max_depth,
                  "Bisections a box may take, 1 to 200; boxes still open there are undecided")
      ->capture_default_str();
  cmd->add_option("--time-limit", o->limits.time_limit_seconds,
                  "Seconds before the open boxes are reported undecided (0: no limit)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            const std::optional<double> v = parse_number(text);
            return v && *v >= 0 && *v <= 1e9 ? "" : "must be a number of seconds from 0 to 1e9, got '" + text + "'";
          },
          "SECONDS"))
      ->capture_default_str();
  cmd->add_option("--threads", o->limits.threads, "Threads, 0 to 256 (0: all cores)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the result as one JSON object instead of the report");
  return {cmd, Runs::Headless,
          "linkscape verify --task sphere:diameter=15,centre=0.7,-13,-8.4 --criterion 'cond<3' --param L1=12.4 "
          "--param L2=12.4    prove a task, or find where it fails",
          [o](std::istream&, std::ostream& out) { return run_verify(*o, out); }};
}

const RegisterCommand registered{55, add_verify};

}  // namespace
}  // namespace linkscape::gui
