// `hapticbench validate FILE...`: checks scenario, mesh and trace files the
// way a run would read them and says what is wrong and where, without
// running anything (file_validation.h). Every file is checked even after
// one fails.
#include <algorithm>
#include <exception>
#include <iostream>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/file_validation.h"
#include "harness/cli/option_table.h"
#include "harness/cli/plugin_isolation.h"
#include "harness/plugins/plugin_loader.h"
#include "harness/process/interrupt.h"
#include "harness/process/memory_limit.h"

namespace hb {

namespace {

struct ValidateArguments {
  std::vector<std::string> files;
  std::optional<ProgressStyle> progress;
};

using Table = OptionTable<ValidateArguments>;

const Table& validate_table() {
  static const Table table(
      {"validate",
       {"Checks each file as a run would read it, by extension: .json, a scenario (meshes, trace "
        "and algorithm parameters included); .off .obj .stl .ply, a triangle mesh (must bound a "
        "solid); .csv, a trace in hapticbench CSV; .txt .tum, a trace in TUM format."},
       {"Prints \"OK: FILE\" for each valid file; exit code 2 if any file is invalid."},
       {}},
      {Table::positional("FILE", "a scenario, mesh or trace file", 1, kAnyCount,
                         &ValidateArguments::files),
       Table::progress(&ValidateArguments::progress), Table::quiet(&ValidateArguments::progress)});
  return table;
}

}  // namespace

int validate_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const auto parsed_files = parse_command_line([&] { return validate_table().parse(args); },
                                               validate_table().usage(), exit_code);
  if (!parsed_files) return exit_code;
  const std::vector<std::string>& files = parsed_files->files;
  // Building renderers runs the code of the plugins given (--plugin,
  // HAPTICBENCH_PLUGINS): in a child this process watches.
  std::vector<std::string> plugin_algorithms;
  for (const LoadedPlugin& plugin : loaded_plugins())
    plugin_algorithms.insert(plugin_algorithms.end(), plugin.algorithms.begin(),
                             plugin.algorithms.end());
  if (should_isolate_plugins(plugin_algorithms)) return run_plugins_isolated("validate", args);

  // Building a scenario's renderers and oracles can take a while (meshes
  // without cached structures); progress shows when it takes over a second.
  ProgressDisplay progress = make_progress_display(parsed_files->progress, 1.0);
  int status = kExitOk;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const std::string& file = files[i];
    std::ostringstream prefix;
    if (files.size() > 1) prefix << "[" << i + 1 << "/" << files.size() << "] ";
    progress.set_prefix(prefix.str());
    std::ostringstream report;
    try {
      validate_file(file, report, progress);
      report << "OK: " << file << "\n";
      progress.print_above(std::cout, report.str());
    } catch (const InputError& error) {
      progress.finish_task();  // the file's line ends with it
      progress.print_above(std::cout, report.str());
      progress.print_above(std::cerr, "error: " + std::string(error.what()) + "\n");
      status = std::max<int>(status, kExitBadInput);
    } catch (const Interrupted&) {
      throw;  // main reports it and exits with 128 + the signal
    } catch (const std::bad_alloc&) {
      // An input that needs more memory than the ceiling: the user's.
      progress.finish_task();
      progress.print_above(std::cout, report.str());
      progress.print_above(std::cerr, "error: " + file + ": " + memory_limit_message() + "\n");
      status = std::max<int>(status, kExitBadInput);
    } catch (const std::exception& error) {
      progress.finish_task();
      progress.print_above(std::cout, report.str());
      progress.print_above(std::cerr, "internal error: " + file + ": " + error.what() + "\n");
      status = std::max<int>(status, kExitInternal);
    }
  }
  return status;
}

const CommandSyntax& validate_syntax() { return validate_table().syntax(); }

}  // namespace hb
