// The commands of `hapticbench`, one row each: main.cpp dispatches through
// the table and prints the top-level usage from it; `hapticbench list
// --commands` prints every command's reference from it
// (docs/command-line.md).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "harness/cli/command_syntax.h"

namespace hb {

struct CommandEntry {
  std::string_view name;      ///< "compare"
  std::string_view summary;   ///< one line: what it does
  std::string_view synopsis;  ///< its main arguments, for the top-level usage
  int (*run)(const std::vector<std::string>& args);
  /// Its option table's rows and text (its --help and reference).
  const CommandSyntax& (*syntax)();
  bool internal = false;  ///< started by hapticbench itself: not listed
};

/// Every command, in the order the usage lists them.
const std::vector<CommandEntry>& command_table();

/// The command named `name`; nullptr when there is none.
const CommandEntry* find_command(std::string_view name);

/// The options main.cpp takes before any command sees its arguments
/// (--memory-limit, --plugin, --allow-scenario-plugins), for the texts.
const std::vector<OptionSpec>& global_options();

/// `hapticbench --help`: the commands with their synopses, the options of
/// every command and the exit codes.
std::string top_level_usage();

/// Every listed command's reference, with the options of every command and
/// the exit codes, in Markdown (`hapticbench list --commands`).
std::string command_reference_markdown();

}  // namespace hb
