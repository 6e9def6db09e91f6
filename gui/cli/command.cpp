#include "gui/cli/command.h"

#include <algorithm>
#include <utility>

namespace linkscape::gui {
namespace {

// Filled by the commands' static registrations, before main() runs.
std::vector<std::pair<int, AddCommand>>& registry() {
  static std::vector<std::pair<int, AddCommand>> commands;
  return commands;
}

}  // namespace

RegisterCommand::RegisterCommand(int order, AddCommand add) { registry().emplace_back(order, add); }

std::vector<Command> add_registered_commands(CLI::App& program, const DeviceHelp& devices) {
  std::vector<std::pair<int, AddCommand>> ordered = registry();
  std::stable_sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Command> commands;
  for (const auto& [order, add] : ordered) commands.push_back(add(program, devices));
  return commands;
}

}  // namespace linkscape::gui
