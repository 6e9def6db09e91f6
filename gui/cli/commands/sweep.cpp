#include "gui/cli/commands/sweep.h"

#include <omp.h>
#include <unistd.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStringArray.h>

#include <charconv>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/sweep.h"
#include "gui/figures/fit_report.h"
#include "gui/cli/command.h"
#include "gui/cli/sweep_ranks.h"
#include "gui/cli/terminal.h"
#include "render/field_vtk.h"

namespace linkscape::gui {
namespace {

// Threads per process: each samples its design's fields at once, so
// thousands would exhaust the memory or the threads the system gives long
// before they could help.
constexpr int kMostThreads = 256;

// What rank 0 prints when the job is stopped by a signal (mpirun sends
// SIGTERM to the surviving ranks when one dies): the rows finished are in
// the checkpoint. Set before the handler is installed; written with write(2),
// the only output a signal handler may do.
char stopped_message[1024];

extern "C" void report_stop(int signal_number) {
  const ssize_t ignored = ::write(STDERR_FILENO, stopped_message, std::strlen(stopped_message));
  (void)ignored;
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

bool has_error(const std::string& row) { return row.back() != ','; }

// A grid sweep of one to three variables as VTK image data: a point per
// design at its variables' values (the first variable along x), a double
// array per numeric column of the table (NaN where a design has an error),
// and the variables' names as field data ("axis_x", ...), for ParaView.
void write_sweep_vti(const sweep::Plan& plan, const std::string& table, const std::string& path) {
  const auto& vars = plan.problem.variables;
  const int n = plan.levels;
  vtkNew<vtkImageData> image;
  int dims[3] = {1, 1, 1};
  double origin[3] = {0, 0, 0}, spacing[3] = {1, 1, 1};
  for (std::size_t a = 0; a < vars.size(); ++a) {
    dims[a] = n;
    origin[a] = vars[a].lo;
    spacing[a] = vars[a].hi > vars[a].lo ? (vars[a].hi - vars[a].lo) / (n - 1) : 1;
  }
  image->SetDimensions(dims);
  image->SetOrigin(origin);
  image->SetSpacing(spacing);
  std::istringstream lines(table);
  std::string line;
  std::getline(lines, line);
  const std::vector<std::string> head = csv_cells(line);
  const std::size_t first = std::size_t(std::find(head.begin(), head.end(), "cx") - head.begin());
  std::vector<vtkSmartPointer<vtkDoubleArray>> arrays;
  for (std::size_t c = first; c + 1 < head.size(); ++c) {  // every score, the error column aside
    arrays.push_back(vtkSmartPointer<vtkDoubleArray>::New());
    arrays.back()->SetName(head[c].c_str());
    arrays.back()->SetNumberOfTuples(vtkIdType(image->GetNumberOfPoints()));
    image->GetPointData()->AddArray(arrays.back());
  }
  for (std::size_t design = 0; std::getline(lines, line); ++design) {
    const std::vector<std::string> row = csv_cells(line);
    // The design's grid indices (the last variable fastest in the table).
    int at[3] = {0, 0, 0};
    std::size_t rest = design;
    for (std::size_t a = vars.size(); a-- > 0;) at[a] = int(rest % std::size_t(n)), rest /= std::size_t(n);
    const vtkIdType point = at[0] + vtkIdType(dims[0]) * (at[1] + vtkIdType(dims[1]) * at[2]);
    for (std::size_t k = 0; k < arrays.size(); ++k)
      arrays[k]->SetValue(point, parse_number(row[first + k]).value_or(std::nan("")));
  }
  for (std::size_t a = 0; a < vars.size(); ++a) {
    vtkNew<vtkStringArray> name;
    name->SetName((std::string("axis_") + "xyz"[a]).c_str());
    name->InsertNextValue(vars[a].name());
    image->GetFieldData()->AddArray(name);
  }
  render::write_image_data(image, path);
}

}  // namespace

void run_sweep(const SweepOptions& o, std::ostream& out) {
  const auto t0 = std::chrono::steady_clock::now();
  if (o.grid.has_value() == (o.random > 0))
    throw std::invalid_argument("sweep: give either --grid N (values per parameter) or --random N (designs)");
  if (o.output.empty() || std::filesystem::path(o.output).extension() != ".csv")
    throw std::invalid_argument("sweep: --output must end in .csv, got '" + o.output + "'");
  const std::string chart_ext = std::filesystem::path(o.chart).extension().string();
  if (!o.chart.empty() && chart_ext != ".png" && chart_ext != ".svg" && chart_ext != ".pdf")
    throw std::invalid_argument("sweep: --chart must end in .png, .svg or .pdf, got '" + o.chart + "'");
  if (!o.vti.empty() && std::filesystem::path(o.vti).extension() != ".vti")
    throw std::invalid_argument("sweep: --vti must end in .vti, got '" + o.vti + "'");
  if (o.field_resolution < 0 || (o.field_resolution > 0 && o.field_resolution < 4))
    throw std::invalid_argument("sweep: --field-resolution must be 0 (none) or at least 4");
  if (o.threads < 0 || o.threads > kMostThreads)
    throw std::invalid_argument("sweep: --threads must be 0 (OpenMP's default) to " + std::to_string(kMostThreads) +
                                ", got " + std::to_string(o.threads));
  if (o.chunk < 1) throw std::invalid_argument("sweep: --chunk must be at least 1");
  const int ranks = sweep_ranks::launched_ranks();
  if (ranks > 1 && !sweep_ranks::mpi_built())
    throw std::invalid_argument("sweep: started by an MPI launcher with " + std::to_string(ranks) +
                                " ranks, but this linkscape was built without MPI (LINKSCAPE_MPI=OFF)");

  sweep::Plan plan;
  plan.problem = make_problem(o.problem, "sweep");
  plan.problem.threads = 1;  // designs run in parallel, each on one thread (gui/cli/sweep_ranks.h)
  fit::check_bounds(plan.problem.variables, "sweep");  // lo <= hi, within reason
  // A variable held at one value would repeat every design along it.
  for (const fit::Variable& v : plan.problem.variables)
    if (!(v.lo < v.hi))
      throw std::invalid_argument("sweep: --bounds " + v.name() + "=" + format_number(v.lo) + ":" + format_number(v.hi) +
                                  " holds it at one value (each design would repeat); give --param " +
                                  v.parameters.front() + "=VALUE instead");
  plan.sampling = o.grid ? sweep::Sampling::Grid : sweep::Sampling::Random;
  plan.levels = o.grid.value_or(0);
  plan.count = o.random;
  plan.seed = o.seed;
  plan.field_resolution = o.field_resolution;
  const std::shared_ptr<const Mechanism> base = make_mechanism(plan.problem.preset);
  plan.columns = design_columns(base->info(), plan.problem.variables);
  const std::vector<std::vector<double>> designs = sweep::designs(plan);
  if (!o.vti.empty() && (plan.sampling != sweep::Sampling::Grid || plan.problem.variables.size() > 3))
    throw std::invalid_argument("sweep: --vti needs --grid over at most 3 free variables, got " +
                                std::to_string(plan.problem.variables.size()) +
                                (plan.sampling == sweep::Sampling::Grid ? "" : " and --random"));

  const std::filesystem::path checkpoint_path = o.checkpoint.empty() ? o.output + ".checkpoint" : o.checkpoint;
  for (const std::filesystem::path& file : {std::filesystem::path(o.output), checkpoint_path,
                                           std::filesystem::path(o.chart), std::filesystem::path(o.vti)})
    check_output(file);  // before any design is evaluated

  sweep_ranks::Job job;
  job.evaluate = [&](std::size_t i) { return sweep::evaluate_row(plan, i, designs[i]); };
  job.max_chunk = o.chunk;
  job.threads = o.threads > 0 ? o.threads : omp_get_max_threads();
  // Under a launcher the ranks share the work even when there is one (so
  // that mpirun -np 1 runs the MPI path); otherwise MPI is never touched.
  const bool distributed = ranks >= 1 && sweep_ranks::mpi_built();
  if (distributed && sweep_ranks::launched_rank() != 0) {  // a worker: evaluates what rank 0 hands it, writes nothing
    sweep_ranks::run_over_ranks(job);
    return;
  }

  sweep::Checkpoint checkpoint(checkpoint_path, plan, designs.size(), o.resume);
  const std::size_t already = checkpoint.rows().size();
  std::size_t failed = 0;
  for (const auto& [index, row] : checkpoint.rows()) failed += has_error(row);
  for (std::size_t i = 0; i < designs.size(); ++i)
    if (!checkpoint.rows().count(i)) job.todo.push_back(i);
  if (o.resume && !o.quiet)
    std::cerr << "sweep: resuming " << checkpoint_path.string() << ": " << already << " of " << designs.size()
              << " designs done\n";

  std::snprintf(stopped_message, sizeof stopped_message,
                "\nsweep: stopped by a signal (under mpirun: a rank died or the job was cancelled); the finished "
                "designs are in %s: run the same command with --resume to finish\n",
                checkpoint_path.c_str());
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) std::signal(sig, report_stop);

  // Designs done out of the total, the failed ones and the time left.
  ProgressLine progress(o.quiet);
  progress.step("sweep");
  job.finished = [&](const sweep_ranks::Rows& rows) {
    for (const auto& [index, row] : rows) {
      checkpoint.add(index, row);
      failed += has_error(row);
    }
    checkpoint.flush();
    const std::size_t done = checkpoint.rows().size();
    progress.describe("sweep: " + std::to_string(done) + "/" + std::to_string(designs.size()) + " designs" +
                      (failed ? " (" + std::to_string(failed) + " with an error)" : std::string()));
    progress.report(double(done) / double(std::max<std::size_t>(designs.size(), 1)));
  };
  const int threads = job.threads;
  sweep_ranks::Place place;
  if (distributed) place = sweep_ranks::run_over_ranks(job);
  else sweep_ranks::run_here(job);
  progress.clear();
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) std::signal(sig, SIG_DFL);

  const std::string table = sweep::table(plan, checkpoint.rows());
  write_text_atomically(o.output, table);
  const fit::Result result = sweep::as_fit_result(plan, checkpoint.rows());
  const MechanismInfo& info = base->info();
  if (!o.chart.empty()) write_fit_chart(o.chart, plan.problem, result, info);
  if (!o.vti.empty()) write_sweep_vti(plan, table, o.vti);
  checkpoint.remove();

  std::size_t on_front = 0;
  {
    std::istringstream lines(table);
    std::string line;
    std::getline(lines, line);
    const std::vector<std::string> head = csv_cells(line);
    const std::size_t pareto = std::size_t(std::find(head.begin(), head.end(), "pareto") - head.begin());
    while (std::getline(lines, line)) on_front += csv_cells(line).at(pareto) == "1";
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out << "sweep " << info.name << ": " << designs.size() << " designs (" << failed << " with an error";
  if (already) out << ", " << already << " from the checkpoint";
  out << ") on " << place.ranks << (place.ranks == 1 ? " process" : " ranks") << " x " << threads
      << (threads == 1 ? " thread" : " threads") << " in " << duration_text(seconds) << "; " << on_front
      << " on the Pareto front";
  if (result.best)
    out << "; smallest meeting the task: size " << format_number(result.rows[*result.best].size) << " "
        << info.length_unit;
  out << "; table " << o.output << "\n";
}

namespace {

Command add_sweep(CLI::App& program, const DeviceHelp& devices) {
  auto o = std::make_shared<SweepOptions>();
  CLI::App* cmd = program.add_subcommand(
      "sweep", "Score a grid or random sample of a device's designs against a task (as fit scores each design) and "
               "field measures, as one CSV table with the Pareto front marked; runs alike on one process or under "
               "mpirun (docs/sweeps.md)");
  add_problem_options(*cmd, o->problem, devices);
  cmd->add_option("--grid", o->grid, "Values per free parameter, its bounds included (a full grid), at least 2");
  cmd->add_option("--random", o->random, "Or this many designs drawn uniformly within the bounds");
  cmd->add_option("--seed", o->seed, "Seed of the random designs, 0 to 2^64 - 1 (the same seed, the same designs)")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            std::uint64_t seed = 0;
            const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), seed);
            if (error == std::errc() && end == text.data() + text.size()) return "";
            return "--seed expects a whole number from 0 to 18446744073709551615, got '" + text + "'";
          },
          "SEED"))
      ->capture_default_str();
  cmd->add_option("--field-resolution", o->field_resolution,
                  "Also sample each design's field over its default box, N samples along the longest side (0: "
                  "none): reach_volume, gci (mean of 1/c over the reachable samples), and inside the task at its "
                  "centre task_reach, task_worst_cond, task_mean_cond")
      ->capture_default_str();
  cmd->add_option("--threads", o->threads,
                  "OpenMP threads per process, each evaluating whole designs, 0 to " + std::to_string(kMostThreads) +
                      " (0: OMP_NUM_THREADS or every core)")
      ->capture_default_str();
  cmd->add_option("--chunk", o->chunk,
                  "Most designs handed to a rank at a time under mpirun (never fewer than its threads)")
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output,
                  "The table (.csv): design, every design parameter, cx,cy,cz, size, meets (1: every sample "
                  "evaluated meets every criterion), samples, failing, the largest shape (centre free), fraction, "
                  "ratio, each criterion's worst value, margin and failing samples, the field measures, pareto, error; one "
                  "row per design in design order")
      ->required();
  cmd->add_option("--checkpoint", o->checkpoint,
                  "Journal of the finished designs, removed once the table is written (default: OUTPUT.checkpoint)");
  cmd->add_flag("--resume", o->resume, "Continue a stopped sweep from its checkpoint (the same command otherwise)");
  cmd->add_option("--chart", o->chart, "Pareto chart, size against the worst measure (.png, .svg, .pdf)");
  cmd->add_option("--vti", o->vti,
                  "A --grid sweep of 1 to 3 variables as VTK image data (.vti): a point per design at its values, "
                  "an array per score (NaN where a design has an error), for ParaView");
  cmd->add_flag("-q,--quiet", o->quiet, "No progress on stderr");
  cmd->footer(
      "Examples:\n"
      "  linkscape sweep --mechanism parallel-12r --task sphere:diameter=15 --criterion 'cond<3' \\\n"
      "      --bounds L1=10:20 --bounds L2=10:20 --grid 5 --field-resolution 32 -o sweep.csv --chart sweep.png\n"
      "  mpirun -np 4 linkscape sweep ...same options...         the same table, four processes\n"
      "  linkscape sweep ...same options... --resume              finish a stopped sweep from its checkpoint\n"
      "A design that cannot be built or whose evaluation fails is a row with its reason in 'error'.");
  return {cmd, Runs::Painting,  // the Pareto chart draws with QPainter
          "linkscape sweep --task sphere:diameter=15 --grid 5 -o sweep.csv   score a grid of designs (also under mpirun)",
          [o](std::istream&, std::ostream& out) {
            run_sweep(*o, out);
            return 0;
          }};
}

const RegisterCommand registered{60, add_sweep};

}  // namespace

}  // namespace linkscape::gui
