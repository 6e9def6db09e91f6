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

#include "core/preset.h"
#include "core/spelling.h"
#include "gui/cli/command.h"
#include "gui/cli/completion.h"
#include "gui/cli/sampling.h"
#include "gui/cli/terminal.h"
#include "gui/cli/window_request.h"

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

// The program's footer: every command's example (the command line, then
// what it does, indented below it), then the devices. The man page's
// EXAMPLES section is read from here.
std::string headless_hint(const DeviceHelp& help, const std::vector<Command>& commands) {
  std::string hint = "Examples (headless: no display needed):\n";
  for (const Command& command : commands) {
    if (command.example.empty()) {
      hint += "  linkscape " + command.app->get_name() + "\n      " + command.app->get_description() + "\n";
      continue;
    }
    // Each example line is "linkscape ... <three or more spaces> what it does".
    std::istringstream examples(command.example);
    for (std::string example; std::getline(examples, example);) {
      const std::size_t gap = example.find("   ");
      hint += "  " + example.substr(0, gap) + "\n";
      if (gap != std::string::npos) hint += "      " + example.substr(example.find_first_not_of(' ', gap)) + "\n";
    }
  }
  hint += "\nDevices (--mechanism NAME): " + help.per_device([](const MechanismInfo& i) { return i.title; }) + ".\n";
  std::string described;
  for (const std::string& name : described_presets()) described += (described.empty() ? "" : ", ") + name;
  hint += "Devices written as files (linkscape describe NAME): " + described + "; or your own .json file.\n";
  return hint + "Run 'linkscape --help' or 'linkscape eval --help' for every option.\n";
}

// Options of the window given before a command would be ignored by it (a
// silent wrong answer: `linkscape --param L1=12 eval` ran with L1 = 15).
void reject_window_options(const CLI::App& app, const CLI::App& command) {
  for (const CLI::Option* option : app.get_options()) {
    if (option->count() == 0 || option->get_name() == "--help" || option->get_name() == "--version") continue;
    const std::string name = option->get_name();
    if (name.rfind("--", 0) == 0 && command.get_option_no_throw(name))
      throw std::invalid_argument("option " + name + " belongs after the command: linkscape " + command.get_name() +
                                  " " + name + " ...");
    if (!option->nonpositional())
      throw std::invalid_argument("a file before the command opens the window; for " + command.get_name() +
                                  " give the device after it: linkscape " + command.get_name() + " -m FILE ...");
    throw std::invalid_argument("option " + name + " is the window's, and " + command.get_name() +
                                " has no such option (see linkscape " + command.get_name() + " --help)");
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

// The window's options that ask for one run (a screenshot, a view image, the
// latency, the shortcuts) exclude each other; options that serve another
// would be quietly dropped.
void check_window_options(const CLI::App& app, const WindowOptions& window, bool shortcuts) {
  const auto given = [&](const char* option) { return app.get_option(option)->count() > 0; };
  for (const char* option : {"--screenshot", "--view-image", "--session"})
    if (given(option) && app.get_option(option)->as<std::string>().empty())
      throw std::invalid_argument(std::string(option) + " is empty; give a file");
  std::vector<std::string> runs;
  for (const auto& [option, asked] : {std::pair{"--screenshot", !window.screenshot.empty()},
                                      {"--view-image", !window.view_image.empty()},
                                      {"--latency", window.latency},
                                      {"--shortcuts", shortcuts}})
    if (asked) runs.push_back(option);
  if (runs.size() > 1) throw std::invalid_argument(runs[0] + " and " + runs[1] + " each ask for a run of their own; give one");
  if (given("--criterion") && window.task.empty())
    throw std::invalid_argument("--criterion sets the criteria of --task, which is not given");
  if (!window.session.empty() && (given("--mechanism") || given("--param")))
    throw std::invalid_argument("a session brings its own mechanism and design: give --session without --mechanism or "
                                "--param, and change the design in the window");
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
                 "--view-size (rendered at that size, not scaled; text and the colour bar grow with it, so the picture is the "
                 "view's, sharper), and exit");
  app.add_option("--view-size", window.view_size, "Pixel size of --view-image, WIDTHxHEIGHT")->capture_default_str();
  app.add_option("--task", window.task,
                 "Show a task volume in the Task tab: sphere:diameter=D or box:size=X,Y,Z, optionally ,centre=x,y,z "
                 "(else placed in the largest sphere or box where the criteria hold)");
  app.add_option("--criterion", window.criteria, "Criteria of --task (repeatable), quoted for the shell, e.g. 'cond<3' 'force_iso>1'");
  std::string complete_option;  // for the shell's completion script; not in --help
  app.add_option("--complete-values", complete_option, "The values an option takes, one per line")->group("");
  bool shortcuts = false;
  app.add_flag("--shortcuts", shortcuts, "Print the window's keyboard shortcuts and exit");
  app.add_flag("--latency", window.latency,
               "Open the window, measure slider-to-frame, link-length-to-slice and isosurface latencies, print them and exit");

  const std::vector<Command> commands = add_registered_commands(app, help);
  const std::string hint = headless_hint(help, commands);
  app.footer(hint);

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

  for (const Command& command : commands) {
    if (!command.app->parsed()) continue;
    if (command.runs == Runs::Painting) {
      prepare_offscreen_painting();
      QGuiApplication qt(argc, argv);
      return command.run(std::cin, std::cout);
    }
    QCoreApplication qt(argc, argv);
    return command.run(std::cin, std::cout);
  }

  if (!complete_option.empty()) {
    for (const std::string& value : completion_values(complete_option, help)) std::cout << value << "\n";
    return 0;
  }
  check_window_options(app, window, shortcuts);
  if (shortcuts) {
    if (!launcher) {
      std::cerr << "linkscape: this build has no window (built with -DLINKSCAPE_WINDOW=OFF), so no shortcuts\n";
      return 1;
    }
    ensure_runtime_dir();
    return launcher->print_shortcuts(argc, argv);
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
