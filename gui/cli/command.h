// The headless commands (`linkscape NAME ...`), each one file that registers
// itself: a new command is a new file in gui/cli/commands/ (or, for a
// device's own study, gui/cli/mechanisms/<device>/), nothing else to edit.
//
//   namespace {
//   Command add_verify(CLI::App& program, const DeviceHelp& devices) {
//     auto options = std::make_shared<VerifyOptions>();
//     CLI::App* app = program.add_subcommand("verify", "...");
//     add_sampling_options(*app, options->sampling, devices);   // if it samples a device
//     return {app, Runs::Headless, "linkscape verify ...   what it does",
//             [options](std::istream&, std::ostream& out) { run_verify(*options, out); }};
//   }
//   const RegisterCommand registered{75, add_verify};
//   }  // namespace
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "gui/cli/device_help.h"

namespace linkscape::gui {

// What a command needs around it while it runs.
enum class Runs {
  Headless,  // a QCoreApplication
  Painting,  // draws text or charts with QPainter: a QGuiApplication on the offscreen platform (no display)
};

struct Command {
  CLI::App* app = nullptr;  // the subcommand: parsed() after parsing
  Runs runs = Runs::Headless;
  // Its line(s) in the program's "Headless commands" footer, without the
  // leading "  "; empty: "linkscape NAME   description".
  std::string example;
  // Runs it with the parsed options. Throws std::invalid_argument for bad
  // input (exit 2).
  std::function<void(std::istream& in, std::ostream& out)> run;
};

using AddCommand = Command (*)(CLI::App& program, const DeviceHelp& devices);

// A static `const RegisterCommand registered{order, add};` in a command's
// file adds it to every program; commands are listed by `order` (eval 10,
// slice 20, field 30, mesh 40, fit 50, sweep 60, design 70, bench 80).
struct RegisterCommand {
  RegisterCommand(int order, AddCommand add);
};

// Adds every registered command to `program`, in their order.
std::vector<Command> add_registered_commands(CLI::App& program, const DeviceHelp& devices);

}  // namespace linkscape::gui
