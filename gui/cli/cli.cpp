#include "gui/cli/cli.h"

#include <QCoreApplication>
#include <QGuiApplication>
#include <CLI/CLI.hpp>
#include <vtkObject.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/csv.h"
#include "core/mechanism.h"
#include "core/preset.h"
#include "gui/cli/fit_command.h"
#include "gui/cli/mechanisms/commands.h"
#include "gui/cli/sweep_command.h"
#include "gui/cli/headless.h"
#include "gui/cli/window_request.h"
#include "core/spelling.h"
#include "gui/cli/terminal.h"

namespace linkscape::gui {
namespace {

constexpr const char* kDescription =
    "Linkscape: kinematic design of parallel haptic-device mechanisms.\n"
    "Without a command it opens the window; with one it runs headless.";

// Help wrapped to the terminal (80 columns in a pipe and in the man page):
// descriptions break at spaces within the right column, and the commands'
// and the program's descriptions within the width.
class WrappingFormatter : public CLI::Formatter {
 public:
  WrappingFormatter() : width_(terminal_width()) { column_width(std::min<std::size_t>(30, width_ / 3)); }
  std::string make_option_desc(const CLI::Option* option) const override {
    return wrap_text(CLI::Formatter::make_option_desc(option), right_width());
  }
  std::string make_subcommand(const CLI::App* sub) const override {
    std::stringstream out;
    CLI::detail::format_help(out, sub->get_display_name(true), wrap_text(sub->get_description(), right_width()),
                             get_column_width());
    return out.str();
  }
  std::string make_description(const CLI::App* app) const override {
    return wrap_text(CLI::Formatter::make_description(app), width_);
  }
  std::string make_footer(const CLI::App* app) const override {
    return wrap_text(CLI::Formatter::make_footer(app), width_);
  }

 private:
  std::size_t right_width() const { return width_ - get_column_width(); }
  std::size_t width_;
};

// What the help says each device accepts comes from the devices themselves:
// every registered device, made from its shipped preset.
struct DeviceHelp {
  std::vector<std::shared_ptr<const Mechanism>> devices;

  // "name: text; name: text" over the devices (those for which `text` says something).
  std::string per_device(const std::function<std::string(const MechanismInfo&)>& text) const {
    std::string out;
    for (const auto& device : devices)
      if (const std::string t = text(device->info()); !t.empty())
        out += (out.empty() ? "" : "; ") + device->info().name + ": " + t;
    return out;
  }
};

DeviceHelp device_help() {
  DeviceHelp help;
  for (const std::string& name : registered_mechanisms()) {
    try {
      help.devices.push_back(make_mechanism(load_preset(name)));
    } catch (const std::exception&) {
      // No usable shipped preset of that name: the help leaves the device out.
    }
  }
  return help;
}

// Item names joined by `separator`, each followed by " (description)" if `described`.
template <class Items>
std::string names(const Items& items, const char* separator, bool described = false) {
  std::string out;
  for (const auto& item : items)
    out += (out.empty() ? "" : separator) + item.name + (described ? " (" + item.description + ")" : "");
  return out;
}

// "x,y,z (cm), rx,ry,rz (rad)": the names, each run of one unit followed by it.
std::string with_units(const std::vector<Quantity>& items) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k) {
    out += items[k].name;
    const bool last = k + 1 == items.size();
    const bool unit = !items[k].unit.empty() && (last || items[k + 1].unit != items[k].unit);
    if (unit) out += " (" + items[k].unit + ")";
    if (!last) out += unit ? ", " : ",";
  }
  return out;
}

std::string headless_hint(const DeviceHelp& help, const std::vector<DeviceCommand>& device_commands) {
  std::string hint =
      "Headless commands (no display needed):\n"
      "  linkscape eval --mechanism NAME --ik targets.csv     inverse kinematics of each row's task coordinates\n"
      "  linkscape eval --mechanism NAME --fk actuators.csv   forward kinematics of each row's actuator values\n"
      "  linkscape slice --plane x=0.25 --output slice.png    condition-number slice image\n"
      "  linkscape field --resolution 128 --output volume.vti sampled volume for ParaView\n"
      "  linkscape mesh --surface 'cond<3' --output ws.stl    workspace isosurface mesh\n"
      "  linkscape fit --task sphere:diameter=15 --criterion 'cond<3' -o fit.csv   the smallest design that serves a task\n"
      "  linkscape sweep --task sphere:diameter=15 --grid 5 -o sweep.csv   score a grid of designs (also under mpirun)\n"
      "  linkscape bench --chart m.png --sweeps s.png --csv b.csv   speed and accuracy of every method\n";
  for (const DeviceCommand& command : device_commands)
    hint += "  linkscape " + command.command->get_name() + "   " + command.command->get_description() + "\n";
  hint += "Devices (--mechanism NAME): " + help.per_device([](const MechanismInfo& i) { return i.title; }) + "\n";
  return hint + "Run 'linkscape --help' or 'linkscape eval --help' for every option.\n";
}

std::string branches_help(const DeviceHelp& help) {
  return help.per_device([](const MechanismInfo& i) {
    std::string out;
    for (const std::string& branch : i.branches) out += (out.empty() ? "" : ", ") + branch;
    return out;
  });
}

}  // namespace

void add_mechanism_options(CLI::App& app, PresetChoice& choice) {
  std::string presets;
  for (const auto& n : available_presets()) presets += (presets.empty() ? "" : ", ") + n;
  app.add_option("-m,--mechanism", choice.name_or_path,
                 "Preset name (" + presets + ") or path to a preset .json file")
      ->capture_default_str();
  app.add_option("-p,--param", choice.params,
                 "Override a model parameter, key=value in the preset's unit (repeatable), e.g. L1=1");
}

namespace {

void add_sampling_options(CLI::App& app, SamplingOptions& s, const DeviceHelp& help) {
  add_mechanism_options(app, s.mechanism);
  app.add_option("--method", s.method,
                 "IK method per sample, one of the device's (default: its first; " +
                     help.per_device([](const MechanismInfo& i) { return names(i.ik_methods, ", "); }) +
                     "); where a method falls back to another, the one that served is recorded per sample")
      ->capture_default_str();
  app.add_option("--branch", s.branch, "Assembly branch evaluated, an index of the device's (" + branches_help(help) + ")")
      ->capture_default_str();
  app.add_option("--tolerance", s.tolerance,
                 "Accept a sample's IK solution when its residual <= tolerance * the device's size; a tighter value "
                 "shows where each method gives up")
      ->capture_default_str();
  app.add_option("--pose", s.pose,
                 "The task pose, all of the device's task coordinates comma separated (" +
                     help.per_device([](const MechanismInfo& i) { return i.task.size() > 3 ? with_units(i.task) : ""; }) +
                     "): the coordinates after x, y, z are held fixed over the grid, the default slice passes "
                     "through the position (default: the device's home pose)");
  app.add_option("--torque", s.torque,
                 "Torque limit of the haptic fields (force_iso, force_max): continuous or peak, from the preset's "
                 "actuator_data (docs/haptic-measures.md)")
      ->capture_default_str();
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

// The names a mistyped word in `command` may have meant: its options (and,
// at the top, the commands).
std::vector<std::string> known_words(const CLI::App& command) {
  std::vector<std::string> words;
  for (const CLI::Option* option : command.get_options()) {
    for (const std::string& name : option->get_lnames()) words.push_back("--" + name);
    for (const std::string& name : option->get_snames()) words.push_back("-" + name);
  }
  for (const CLI::App* sub : command.get_subcommands({})) words.push_back(sub->get_name());
  return words;
}

// One style for every error: "linkscape: error: ...", a suggestion for a
// mistyped word, and where to read more.
std::string parse_error_message(const CLI::App& app, const CLI::Error& e) {
  const std::vector<CLI::App*> parsed = app.get_subcommands();
  const CLI::App& command = parsed.empty() ? app : *parsed.back();
  // The words to check: those nobody took, and a file argument that is no
  // file (`linkscape evl --fk a.csv` takes "evl" as the file to open).
  std::vector<std::string> words = app.remaining(true);
  std::error_code ec;
  for (const std::string& file : app.get_option("file")->as<std::vector<std::string>>())
    if (!std::filesystem::exists(file, ec)) words.insert(words.begin(), file);
  std::string message = std::string("linkscape: error: ") + e.what() + "\n";
  for (const std::string& word : words) {
    if (const auto meant = closest_name(word.substr(0, word.find('=')), known_words(command))) {
      const bool is_command = meant->front() != '-';
      message += "Did you mean '" + (is_command ? "linkscape " + *meant : *meant) + "'?\n";
      break;
    }
  }
  const std::string name = parsed.empty() ? "linkscape" : "linkscape " + command.get_name();
  return message + "Run '" + name + " --help' for every option.\n";
}

// `linkscape FILE` (the desktop entry's %F): a session or a preset, which the
// window resolves. A word that is no file is most likely a mistyped command.
void check_file_argument(const CLI::App& app, const WindowOptions& window) {
  if (window.file.empty()) return;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(window.file, ec)) {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
    const auto meant = closest_name(window.file, names);
    throw std::invalid_argument("'" + window.file + "' is neither a command nor a file" +
                                (meant ? "; did you mean 'linkscape " + *meant + "'?" : std::string()));
  }
  if (!window.session.empty() || app.get_option("--mechanism")->count() > 0)
    throw std::invalid_argument("give a file to open, --session or --mechanism, not two of them");
}

void check_image_outputs(const WindowOptions& window) {
  for (const auto& [option, path] : {std::pair{"--view-image", window.view_image}, {"--screenshot", window.screenshot}})
    if (!path.empty() && std::filesystem::path(path).extension() != ".png")
      throw std::invalid_argument(std::string(option) + " writes PNG: the file must end in .png, got '" + path + "'");
}

}  // namespace

int run(int argc, char** argv, const WindowLauncher* launcher) {
  CLI::App app(kDescription, "linkscape");
  app.formatter(std::make_shared<WrappingFormatter>());
  app.set_version_flag("--version", std::string("linkscape ") + LINKSCAPE_VERSION);
  const DeviceHelp help = device_help();

  WindowOptions window;
  add_mechanism_options(app, window.mechanism);
  app.add_option("--session", window.session, "Open a saved session (.json) at start, with its mechanism");
  app.add_option("file", window.file,
                 "A session (.json saved by File > Save) or a mechanism preset (.json) to open, as the desktop entry "
                 "passes it; the window reads the preset again when its file changes (File > Reload mechanism, F5)");
  app.add_option("--screenshot", window.screenshot,
                 "Open the window, wait until the fields are computed, save it as PNG to this file and exit");
  app.add_option("--size", window.size, "Window size for --screenshot and --latency, WIDTHxHEIGHT")->capture_default_str();
  app.add_option("--view-image", window.view_image,
                 "Open the window, wait until the fields are computed, save the 3-D view alone as PNG, drawn at "
                 "--view-size (not scaled), and exit");
  app.add_option("--view-size", window.view_size, "Pixel size of --view-image, WIDTHxHEIGHT")->capture_default_str();
  app.add_option("--task", window.task,
                 "Show a task volume in the Task tab: sphere:diameter=D or box:size=X,Y,Z, optionally ,centre=x,y,z "
                 "(else placed in the largest sphere or box where the criteria hold)");
  app.add_option("--criterion", window.criteria, "Criteria of --task (repeatable), quoted for the shell, e.g. 'cond<3' 'force_iso>1'");
  app.add_flag("--latency", window.latency,
               "Open the window, measure slider-to-frame, link-length-to-slice and isosurface latencies, print them and exit");

  EvalOptions eval;
  std::string seed_text;
  CLI::App* eval_cmd = app.add_subcommand(
      "eval", "Evaluate kinematics for each CSV row; writes CSV (stdout by default)");
  add_mechanism_options(*eval_cmd, eval.mechanism);
  auto* ik = eval_cmd->add_option(
      "--ik", eval.ik_file,
      "Inverse kinematics of the targets in a CSV whose header names the device's task coordinates (" +
          help.per_device([](const MechanismInfo& i) { return with_units(i.task); }) +
          "; '-' = stdin). Writes one row per branch found: the target, branch, status, actuators, measures and "
          "diagnostics, as far as the device reports them");
  auto* fk = eval_cmd->add_option(
      "--fk", eval.fk_file,
      "Forward kinematics of a CSV whose header names the device's actuators and FK inputs (" +
          help.per_device([](const MechanismInfo& i) {
            std::vector<Quantity> header = i.actuators;
            for (const Quantity& q : i.task)
              if (std::count(i.fk_inputs.begin(), i.fk_inputs.end(), q.name)) header.push_back(q);
            return with_units(header);
          }) +
          "). Iterative FK starts from the home pose, or from the row's seed_<coordinate> columns when given, so "
          "each row's answer depends on that row alone; writes the actuators, the task coordinates, and the "
          "status, measures and diagnostics as far as the device reports them");
  ik->excludes(fk);
  eval_cmd->add_option("--method", eval.method,
                       "IK method, one of the device's (default: its first). " +
                           help.per_device([](const MechanismInfo& i) { return names(i.ik_methods, ", ", true); }))
      ->capture_default_str();
  eval_cmd->add_option("--branch", eval.branch, "Only this assembly branch, an index of the device's (" + branches_help(help) + ")");
  eval_cmd->add_option("--seed", seed_text,
                       "Start for iterative IK methods (closed forms do not use it): the device's actuator values, "
                       "comma separated (default: each branch's home pose)");
  eval_cmd->add_option("--tolerance", eval.tolerance, "Accept a solution when residual <= tolerance * the device's size")
      ->capture_default_str();
  eval_cmd->add_option("--max-iterations", eval.max_iterations, "Iteration limit for newton/dls")
      ->capture_default_str();
  eval_cmd->add_option("-o,--output", eval.output, "Output CSV file (written atomically); '-' = stdout")
      ->capture_default_str();
  eval_cmd->add_flag("-q,--quiet", eval.quiet, "No summary on stderr (there is none when the rows go to stdout)");

  SliceOptions slice;
  CLI::App* slice_cmd = app.add_subcommand(
      "slice", "Sample a field on a plane and write a colour-mapped image or CSV (no display needed)");
  add_sampling_options(*slice_cmd, slice.sampling, help);
  slice_cmd->add_option("--plane", slice.plane,
                        "Plane as axis=position in the length unit, e.g. x=0.25 (default: the device's first slice "
                        "plane for the pose)");
  slice_cmd->add_option("--extent", slice.extent,
                        "u_min,u_max,v_min,v_max of the plane's axes (x: y,z; y: x,z; z: x,y); default the "
                        "device's sampling box")
      ->delimiter(',')
      ->expected(4);
  slice_cmd->add_option("--size", slice.size, "Samples along u and v, WIDTHxHEIGHT")->capture_default_str();
  slice_cmd->add_option(
                "--field", slice.field,
                "Field to colour: cond (the device's main measure: " +
                    help.per_device([](const MechanismInfo& i) { return i.measures.front().title; }) +
                    "), the second measure by its name where the device has one (" +
                    help.per_device([](const MechanismInfo& i) {
                      return i.measures.size() > 1 ? i.measures[1].name + " = " + i.measures[1].title : "";
                    }) +
                    "), reach, residual, iterations, status, method (IK method used per sample, where the device "
                    "has several), or a haptic measure: force_iso (N, in every direction), force_max (N, in some "
                    "direction), resolution (mm per encoder count), inertia (kg, reflected rotor inertia)")
      ->capture_default_str();
  slice_cmd->add_option("--contour", slice.contours,
                        "Condition-number levels drawn as contour lines (comma list; of cond_jo when that is shown)")
      ->delimiter(',')
      ->capture_default_str();
  slice_cmd->add_option("--range", slice.range, "Colour range min,max (default: 1,10 for cond; data range otherwise)")
      ->delimiter(',')
      ->expected(2);
  slice_cmd->add_flag("--linear", slice.linear, "Linear colour scale for cond and residual (default: log)");
  slice_cmd->add_option("--colour-map", slice.colour_map,
                        "viridis, cividis (also for colour vision deficiency) or diverging (blue-grey-red; a signed "
                        "field's automatic range is symmetric about 0, e.g. --field reach)")
      ->capture_default_str();
  slice_cmd->add_flag("--figure", slice.figure, "Add axes with units, colour bar, legend and title (PNG, SVG or PDF)");
  slice_cmd->add_option("-o,--output", slice.output, "Output: .png or .csv; with --figure .png, .svg or .pdf")
      ->required();

  FieldCommandOptions field;
  CLI::App* field_cmd = app.add_subcommand(
      "field", "Sample c(J), reach margin and diagnostics on a 3-D grid; write VTK .vti or CSV");
  add_sampling_options(*field_cmd, field.sampling, help);
  field_cmd->add_option("--resolution", field.resolution, "Samples per axis: N or NXxNYxNZ")->capture_default_str();
  field_cmd->add_option("--box", field.box, "x_min,x_max,y_min,y_max,z_min,z_max; default the device's sampling box")
      ->delimiter(',')
      ->expected(6);
  field_cmd->add_option("--field", field.fields,
                        "Also write these haptic arrays (comma list): force_iso, force_max (N), resolution (mm), "
                        "inertia (kg); the kinematic arrays are always written")
      ->delimiter(',');
  field_cmd->add_option("-o,--output", field.output, "Output: .vti (ParaView) or .csv")->required();

  MeshOptions mesh;
  CLI::App* mesh_cmd = app.add_subcommand(
      "mesh", "Extract a workspace isosurface and write a mesh (STL, OBJ, PLY, OFF, VTP); prints its statistics");
  add_sampling_options(*mesh_cmd, mesh.sampling, help);
  mesh_cmd->add_option("--surface", mesh.surface,
                       "reach (boundary of the reachable set), cond<T (well-conditioned region, e.g. 'cond<3', "
                       "quoted for the shell), or the region meeting a haptic criterion: force_iso>F, force_max>F "
                       "(N), resolution<R (mm), inertia<M (kg)")
      ->capture_default_str();
  mesh_cmd->add_option("--resolution", mesh.resolution, "Samples per axis: N or NXxNYxNZ")->capture_default_str();
  mesh_cmd->add_option("--box", mesh.box, "x_min,x_max,y_min,y_max,z_min,z_max; default the device's sampling box")
      ->delimiter(',')
      ->expected(6);
  mesh_cmd->add_option("--decimate", mesh.decimate,
                       "Simplify the mesh; the largest allowed deviation in the length unit (0 = off)")
      ->capture_default_str();
  mesh_cmd->add_option("-o,--output", mesh.output, "Output: .stl, .obj, .ply, .off or .vtp")->required();

  const FitCommand fit_cmd = add_fit_command(app);
  const SweepCommand sweep_cmd = add_sweep_command(app);
  const std::vector<DeviceCommand> device_commands = add_device_commands(app);
  const std::string hint = headless_hint(help, device_commands);
  app.footer(hint);

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
  bench_cmd->add_option("--compare", bench.compare,
                        "Measure the methods and sweeps of these presets beside the chosen device (side by side in "
                        "--chart and --sweeps), e.g. -m delta-described --compare delta; default: every registered "
                        "device")
      ->delimiter(',');
  bench_cmd->footer(
      "parallel-12r (planar IK), delta (closed IK) and pathos2 fields use SIMD kernels with the best instruction set\n"
      "of the CPU. Environment, for every command:\n"
      "  LINKSCAPE_SIMD_TARGET=AVX2|SSE4|...|baseline   use at most this instruction set\n"
      "  LINKSCAPE_FIELD_KERNEL=scalar|vector|vector-mirrored   those kernels: scalar = the reference, one sample at\n"
      "    a time; vector = without the mirror symmetries (12R in x, Delta in y); default vector-mirrored");

  app.failure_message([&](const CLI::App*, const CLI::Error& e) { return parse_error_message(app, e); });
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
  if (fit_cmd.command->parsed()) {
    prepare_offscreen_painting();  // the Pareto chart draws with QPainter
    QGuiApplication qt(argc, argv);
    run_fit(*fit_cmd.options, std::cout);
    return 0;
  }
  if (sweep_cmd.command->parsed()) {
    prepare_offscreen_painting();  // the Pareto chart draws with QPainter
    QGuiApplication qt(argc, argv);
    run_sweep(*sweep_cmd.options, std::cout);
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

  check_file_argument(app, window);
  check_image_outputs(window);
  if (!launcher) {
    std::cerr << "linkscape: this build has no window (built with -DLINKSCAPE_WINDOW=OFF); "
                 "the commands work:\n\n" << hint;
    return 1;
  }
  launcher->prepare(window);  // bad files and parameters are input errors (exit 2), with a display or without
  window.size_given = app.get_option("--size")->count() > 0;
  if (!has_display()) {
    std::cerr << "linkscape: no display found (DISPLAY is not set), so the window cannot open.\n"
              << "Start it on a desktop, or under Xvfb: xvfb-run -a linkscape\n\n"
              << hint;
    return 1;
  }
  ensure_runtime_dir();
  return launcher->run(window, argc, argv);
}

}  // namespace linkscape::gui
