// Times the certified checks of docs/task-volumes.md ("Certified verdicts")
// for the 12R with L1 = L2 = L:
//   verify_bench verify L TASK CRITERION [threads]
//   verify_bench preset NAME TASK CRITERION [threads]   (any preset, as it is)
//   verify_bench size LO HI TOLERANCE TASK CRITERION REFERENCE_L [threads]
//   verify_bench size-fit LO HI TOLERANCE TASK CRITERION [threads]
// (size: the task's centre is where it is at L = REFERENCE_L, and moves with
// L; size-fit: the task has no centre, fit places it at each design.)
#include <cstdlib>
#include <iostream>
#include <string>

#include "core/verify/verify.h"

using namespace linkscape;

static int run_sizing(const verify::SizingProblem& sizing) {
  const verify::SizingResult r = verify::size(sizing, [](const verify::SizingStep& s) {
    std::cerr << s.value << ": " << verify::to_string(s.result.verdict) << " (" << s.result.task << ") in "
              << s.result.seconds << " s\n";
  });
  verify::write_report(std::cout, r);
  return verify::exit_status(r);
}

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  verify::Options options;
  options.time_limit_seconds = 600;
  if (mode == "verify" && argc >= 5) {
    options.threads = argc > 5 ? std::atoi(argv[5]) : 2;
    Preset preset = load_preset("parallel-12r");
    preset.parameters["L1"] = preset.parameters["L2"] = std::atof(argv[2]);
    const verify::Result r =
        verify::verify(preset, task::parse_task(argv[3]), {task::parse_criterion(argv[4])}, options);
    verify::write_report(std::cout, r);
    return verify::exit_status(r.verdict);
  }
  if (mode == "preset" && argc >= 5) {
    options.threads = argc > 5 ? std::atoi(argv[5]) : 2;
    const verify::Result r =
        verify::verify(load_preset(argv[2]), task::parse_task(argv[3]), {task::parse_criterion(argv[4])}, options);
    verify::write_report(std::cout, r);
    return verify::exit_status(r.verdict);
  }
  // The 12R with L1 = L2 between argv[2] and argv[3], to argv[4], the task argv[5] meeting argv[6].
  auto twelve_r_sizing = [&] {
    verify::SizingProblem sizing;
    sizing.preset = load_preset("parallel-12r");
    sizing.variable = {{"L1", "L2"}, std::atof(argv[2]), std::atof(argv[3])};
    sizing.tolerance = std::atof(argv[4]);
    sizing.task = task::parse_task(argv[5]);
    sizing.criteria = {task::parse_criterion(argv[6])};
    sizing.options = options;
    return sizing;
  };
  if (mode == "size" && argc >= 8) {
    options.threads = argc > 8 ? std::atoi(argv[8]) : 2;
    verify::SizingProblem sizing = twelve_r_sizing();
    sizing.centre_scales_from = std::atof(argv[7]);
    return run_sizing(sizing);
  }
  if (mode == "size-fit" && argc >= 7) {
    options.threads = argc > 7 ? std::atoi(argv[7]) : 2;
    verify::SizingProblem sizing = twelve_r_sizing();
    fit::Problem placement;
    placement.preset = sizing.preset;
    placement.variables = {sizing.variable};
    placement.task = sizing.task;
    placement.criteria = sizing.criteria;
    placement.threads = options.threads;
    sizing.centre_at = verify::placement_by_fit(placement);
    return run_sizing(sizing);
  }

  std::cerr << "usage: verify_bench verify L TASK CRITERION [threads]\n"
               "       verify_bench preset NAME TASK CRITERION [threads]\n"
               "       verify_bench size LO HI TOLERANCE TASK CRITERION REFERENCE_L [threads]\n"
               "       verify_bench size-fit LO HI TOLERANCE TASK CRITERION [threads]\n";
  return 2;
}
