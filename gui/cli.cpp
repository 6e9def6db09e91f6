#include "gui/cli.h"

#include <QCoreApplication>
#include <QGuiApplication>
#include <CLI/CLI.hpp>
#include <vtkObject.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "core/csv.h"
#include "core/preset.h"
#include "gui/mechanisms/commands.h"
#include "gui/headless.h"
#include "gui/mechanism_window.h"

namespace linkscape::gui {
namespace {

constexpr const char* kDescription =
    "Linkscape: kinematic design of parallel haptic-device mechanisms.\n"
    "Without a command it opens the window; with one it runs headless.";

constexpr const char* kHeadlessHint =
    "Headless commands (no display needed):\n"
    "  linkscape eval --mechanism parallel-12r --ik points.csv   inverse kinematics (x,y,z)\n"
    "  linkscape eval --mechanism parallel-12r --fk angles.csv   forward kinematics (alpha,beta,gamma)\n"
    "  linkscape slice --plane x=0.25 --output slice.png          condition-number slice image\n"
    "  linkscape field --resolution 128 --output volume.vti       sampled volume for ParaView\n"
    "  linkscape mesh --surface cond<3 --output ws.stl            workspace isosurface mesh\n"
    "  linkscape eval --mechanism pathos2 --ik poses.csv         PATHOS-II pose IK (x,y,z,rx,ry,rz,h0)\n"
    "  linkscape slice --mechanism pathos2 --field cond_jo -o s.png   PATHOS-II cond(Jo) through the home pose\n"
    "  linkscape design --table t2.csv --sweep l0.csv --chart d.png   PATHOS-II Table 2 search and l0 sweep\n"
    "  linkscape bench --chart m.png --sweeps s.png --csv b.csv   speed and accuracy of every method\n"
    "Run 'linkscape --help' or 'linkscape eval --help' for every option.\n";

}  // namespace

void add_mechanism_options(CLI::App& app, MechanismChoice& choice) {
  std::string presets;
  for (const auto& n : available_presets()) presets += (presets.empty() ? "" : ", ") + n;
  app.add_option("-m,--mechanism", choice.mechanism,
                 "Preset name (" + presets + ") or path to a preset .json file")
      ->capture_default_str();
  app.add_option("-p,--param", choice.params,
                 "Override a model parameter, key=value in the preset's unit (repeatable), e.g. L1=1");
}

namespace {

void add_sampling_options(CLI::App& app, SamplingOptions& s) {
  add_mechanism_options(app, s.mechanism);
  app.add_option("--method", s.method,
                 "IK method per sample, one of the device's (default: its first). parallel-12r: planar, paper, newton, "
                 "dls, fallback (planar, then Newton from its candidate where planar misses the tolerance; the "
                 "choice is recorded per sample); pathos2: closed")
      ->capture_default_str();
  app.add_option("--branch", s.branch, "Assembly branch evaluated: 0 or 1")->capture_default_str();
  app.add_option("--tolerance", s.tolerance,
                 "Accept a sample's IK solution when its residual <= tolerance * (L1 + L2); a tighter value shows "
                 "where each method gives up")
      ->capture_default_str();
  app.add_option("--pose", s.pose,
                 "pathos2: x,y,z (cm), rx,ry,rz (rad, R = Rz Ry Rx), h0 (cm); orientation and grip are held fixed "
                 "over the grid, the default slice passes through the position (default: Table 3 home pose "
                 "0,0,l0/2,0,0,pi/6,h0)");
  app.add_flag("-q,--quiet", s.quiet, "No progress line on stderr");
}

Eigen::VectorXd parse_seed(const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string part;
  while (std::getline(ss, part, ',')) v.push_back(parse_number_or_throw(part, "--seed"));
  if (v.empty()) throw std::invalid_argument("--seed expects the actuator values, comma separated, got '" + text + "'");
  return Eigen::Map<const Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
}

// Options of the window given before a command would be ignored by it (a
// silent wrong answer: `linkscape --param L1=12 eval` ran with L1 = 15).
void reject_window_options(const CLI::App& app, const CLI::App& command) {
  for (const CLI::Option* option : app.get_options()) {
    if (option->count() == 0 || option->get_name() == "--help" || option->get_name() == "--version") continue;
    throw std::invalid_argument("option " + option->get_name() + " belongs after the command: linkscape " +
                                command.get_name() + " " + option->get_name() + " ...");
  }
}

// A runtime directory for Qt where the session has none (root in a
// container): the one Qt would pick anyway, without its warning.
void ensure_runtime_dir() {
  if (const char* dir = std::getenv("XDG_RUNTIME_DIR"); dir && *dir) return;
  const std::filesystem::path runtime = std::filesystem::temp_directory_path() / ("runtime-" + std::to_string(getuid()));
  std::error_code ec;
  std::filesystem::create_directories(runtime, ec);
  std::filesystem::permissions(runtime, std::filesystem::perms::owner_all, ec);
  if (!ec) setenv("XDG_RUNTIME_DIR", runtime.c_str(), 1);
}

// Headless commands that draw text need a QGuiApplication on the offscreen
// platform: no display.
void prepare_offscreen_painting() {
  if (!std::getenv("QT_QPA_PLATFORM")) setenv("QT_QPA_PLATFORM", "offscreen", 1);
  ensure_runtime_dir();
}

bool has_display() {
  const char* platform = std::getenv("QT_QPA_PLATFORM");
  if (platform && *platform) return true;  // the user chose a platform explicitly
  for (const char* var : {"DISPLAY", "WAYLAND_DISPLAY"})
    if (const char* v = std::getenv(var); v && *v) return true;
  return false;
}

}  // namespace

int run(int argc, char** argv) {
  CLI::App app(kDescription, "linkscape");
  app.set_version_flag("--version", std::string("linkscape ") + LINKSCAPE_VERSION);
  app.footer(kHeadlessHint);

  WindowOptions window;
  add_mechanism_options(app, window.mechanism);
  app.add_option("--session", window.session, "Open a saved session (.json) at start, with its mechanism");
  app.add_option("--screenshot", window.screenshot,
                 "Open the window, wait until the fields are computed, save it as PNG to this file and exit");
  app.add_option("--size", window.size, "Window size for --screenshot and --latency, WIDTHxHEIGHT")->capture_default_str();
  app.add_flag("--latency", window.latency,
               "Open the window, measure slider-to-frame, link-length-to-slice and isosurface latencies, print them and exit");

  EvalOptions eval;
  std::string seed_text;
  CLI::App* eval_cmd = app.add_subcommand(
      "eval", "Evaluate kinematics for each CSV row; writes CSV (stdout by default)");
  add_mechanism_options(*eval_cmd, eval.mechanism);
  auto* ik = eval_cmd->add_option("--ik", eval.ik_file,
                                  "Inverse kinematics of targets in a CSV with header x,y,z ('-' = stdin). "
                                  "Writes x,y,z,branch,status,alpha,beta,gamma,cond,det,residual,iterations, "
                                  "one row per branch found. pathos2: header x,y,z,rx,ry,rz,h0 (cm, rad); writes "
                                  "the pose, status, failing_leg, q1..q6 (rad), cond_jp, cond_jo");
  auto* fk = eval_cmd->add_option("--fk", eval.fk_file,
                                  "Forward kinematics of a CSV with header alpha,beta,gamma (rad). "
                                  "Writes alpha,beta,gamma,x,y,z,cond,det. pathos2: header q1..q6,h0; numerical "
                                  "FK from the home pose, or from the row's seed_x,seed_y,seed_z,seed_rx,seed_ry,seed_rz when given, so each "
                                  "row's answer depends on that row alone; writes the pose, status, iterations");
  ik->excludes(fk);
  eval_cmd->add_option("--method", eval.method,
                       "IK method, one of the device's (default: its first). parallel-12r: paper (Eqs. 14-16, corrected), planar (planar reduction), "
                       "newton (Newton-Raphson from a seed), dls (damped least squares from a seed), "
                       "fallback (planar, then Newton from its candidate)")
      ->capture_default_str();
  eval_cmd->add_option("--branch", eval.branch, "Only this assembly branch: 0 (sin(beta-gamma) > 0) or 1");
  eval_cmd->add_option("--seed", seed_text,
                       "Start for iterative IK methods (closed forms do not use it): the actuator values in rad, e.g. alpha,beta,gamma (default: each branch's home pose)");
  eval_cmd->add_option("--tolerance", eval.tolerance, "Accept a solution when residual <= tolerance * (L1 + L2)")
      ->capture_default_str();
  eval_cmd->add_option("--max-iterations", eval.max_iterations, "Iteration limit for newton/dls")
      ->capture_default_str();
  eval_cmd->add_option("-o,--output", eval.output, "Output CSV file (written atomically); '-' = stdout")
      ->capture_default_str();

  SliceOptions slice;
  CLI::App* slice_cmd = app.add_subcommand(
      "slice", "Sample a field on a plane and write a colour-mapped image or CSV (no display needed)");
  add_sampling_options(*slice_cmd, slice.sampling);
  slice_cmd->add_option("--plane", slice.plane,
                        "Plane as axis=position in the length unit, e.g. x=0.25 (default: x = (L1+L2)/8 for "
                        "parallel-12r, z through the pose for pathos2)");
  slice_cmd->add_option("--extent", slice.extent,
                        "u_min,u_max,v_min,v_max of the plane's axes (x: y,z; y: x,z; z: x,y); default the "
                        "mechanism's box (+-(L1+L2); pathos2: +-0.6(l2+l3) around the mid-plane)")
      ->delimiter(',')
      ->expected(4);
  slice_cmd->add_option("--size", slice.size, "Samples along u and v, WIDTHxHEIGHT")->capture_default_str();
  slice_cmd->add_option("--field", slice.field,
                        "Field to colour: cond (c(J); pathos2: cond(Jp)), cond_jo (pathos2: cond(Jo)), reach, residual, "
                        "iterations, status, method (IK method used per sample)")
      ->capture_default_str();
  slice_cmd->add_option("--contour", slice.contours,
                        "Condition-number levels drawn as contour lines (comma list; of cond_jo when that is shown)")
      ->delimiter(',')
      ->capture_default_str();
  slice_cmd->add_option("--range", slice.range, "Colour range min,max (default: 1,10 for cond; data range otherwise)")
      ->delimiter(',')
      ->expected(2);
  slice_cmd->add_flag("--linear", slice.linear, "Linear colour scale for cond and residual (default: log)");
  slice_cmd->add_flag("--figure", slice.figure, "Add axes with units, colour bar, legend and title (PNG, SVG or PDF)");
  slice_cmd->add_option("-o,--output", slice.output, "Output: .png or .csv; with --figure .png, .svg or .pdf")
      ->required();

  FieldCommandOptions field;
  CLI::App* field_cmd = app.add_subcommand(
      "field", "Sample c(J), reach margin and diagnostics on a 3-D grid; write VTK .vti or CSV");
  add_sampling_options(*field_cmd, field.sampling);
  field_cmd->add_option("--resolution", field.resolution, "Samples per axis: N or NXxNYxNZ")->capture_default_str();
  field_cmd->add_option("--box", field.box, "x_min,x_max,y_min,y_max,z_min,z_max; default the mechanism's box (+-(L1+L2); pathos2: +-0.6(l2+l3) around (0,0,l0/2))")
      ->delimiter(',')
      ->expected(6);
  field_cmd->add_option("-o,--output", field.output, "Output: .vti (ParaView) or .csv")->required();

  MeshOptions mesh;
  CLI::App* mesh_cmd = app.add_subcommand(
      "mesh", "Extract a workspace isosurface and write a mesh (STL, OBJ, PLY, OFF, VTP); prints its statistics");
  add_sampling_options(*mesh_cmd, mesh.sampling);
  mesh_cmd->add_option("--surface", mesh.surface,
                       "reach (boundary of the reachable set) or cond<T (well-conditioned region, e.g. cond<3)")
      ->capture_default_str();
  mesh_cmd->add_option("--resolution", mesh.resolution, "Samples per axis: N or NXxNYxNZ")->capture_default_str();
  mesh_cmd->add_option("--box", mesh.box, "x_min,x_max,y_min,y_max,z_min,z_max; default the mechanism's box (+-(L1+L2); pathos2: +-0.6(l2+l3) around (0,0,l0/2))")
      ->delimiter(',')
      ->expected(6);
  mesh_cmd->add_option("--decimate", mesh.decimate,
                       "Simplify the mesh; the largest allowed deviation in the length unit (0 = off)")
      ->capture_default_str();
  mesh_cmd->add_option("-o,--output", mesh.output, "Output: .stl, .obj, .ply, .off or .vtp")->required();

  const std::vector<DeviceCommand> device_commands = add_device_commands(app);

  BenchOptions bench;
  CLI::App* bench_cmd = app.add_subcommand(
      "bench",
      "Measure field throughput, slice/volume/isosurface times, peak memory, accuracy vs resolution, and every "
      "numerical method's time per evaluation against its error, with stability sweeps towards the singular sets");
  add_mechanism_options(*bench_cmd, bench.mechanism);
  bench_cmd->add_flag("--quick", bench.quick, "Small grids and single runs (a smoke test, not a measurement)");
  bench_cmd->add_option("--csv", bench.csv,
                        "Also write the figures to this CSV file (measurement,value,unit, every method included), "
                        "the method table to <stem>.methods.csv and the sweeps to <stem>.sweeps.csv");
  bench_cmd->add_option("--chart", bench.chart,
                        "Write the error-against-time chart of every method with its Pareto front (.png, .svg, .pdf)");
  bench_cmd->add_option("--sweeps", bench.sweeps,
                        "Write the error-against-distance chart of the sweeps towards each singular set "
                        "(.png, .svg, .pdf)");
  bench_cmd->footer(
      "parallel-12r planar fields use SIMD kernels with the best instruction set of the CPU. Environment, for\n"
      "every command:\n"
      "  LINKSCAPE_SIMD_TARGET=AVX2|SSE4|...|baseline   use at most this instruction set\n"
      "  LINKSCAPE_FIELD_KERNEL=scalar|vector|vector-mirrored   parallel-12r planar kernel (default vector-mirrored)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help/version or the error
    return code == 0 ? 0 : 2;
  }

  for (const CLI::App* command : app.get_subcommands()) reject_window_options(app, *command);
  // Headless commands report a failed write in one line with its reason
  // (the writers' error codes); VTK's own multi-line object dumps would
  // bury it.
  if (!app.get_subcommands().empty()) vtkObject::GlobalWarningDisplayOff();

  if (eval_cmd->parsed()) {
    if (!seed_text.empty()) eval.seed = parse_seed(seed_text);
    QCoreApplication qt(argc, argv);
    run_eval(eval, std::cin, std::cout);
    return 0;
  }

  if (slice_cmd->parsed()) {
    prepare_offscreen_painting();  // figures draw text with QPainter
    QGuiApplication qt(argc, argv);
    run_slice(slice);
    return 0;
  }
  if (field_cmd->parsed()) {
    QCoreApplication qt(argc, argv);
    run_field(field);
    return 0;
  }

  if (mesh_cmd->parsed()) {
    QCoreApplication qt(argc, argv);
    run_mesh(mesh, std::cout);
    return 0;
  }
  for (const DeviceCommand& command : device_commands) {
    if (!command.command->parsed()) continue;
    prepare_offscreen_painting();  // device commands may draw charts with QPainter
    QGuiApplication qt(argc, argv);
    command.run(std::cout);
    return 0;
  }
  if (bench_cmd->parsed()) {
    prepare_offscreen_painting();  // the charts draw text with QPainter
    for (const std::string* chart : {&bench.chart, &bench.sweeps}) {
      const std::string ext = std::filesystem::path(*chart).extension().string();
      if (!chart->empty() && ext != ".png" && ext != ".svg" && ext != ".pdf")
        throw std::invalid_argument("bench: --chart and --sweeps must end in .png, .svg or .pdf, got '" + *chart + "'");
    }
    QGuiApplication qt(argc, argv);
    run_bench(bench, std::cout);
    return 0;
  }

  if (!has_display()) {
    std::cerr << "linkscape: no display found (DISPLAY is not set), so the window cannot open.\n"
              << "Start it on a desktop, or under Xvfb: xvfb-run -a linkscape\n\n"
              << kHeadlessHint;
    return 1;
  }
  ensure_runtime_dir();
  return run_window(window, argc, argv);
}

}  // namespace linkscape::gui
