// hapticbench: benchmarks and validates 6-DOF haptic rendering algorithms.
#include <algorithm>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "algorithms/core/build_progress.h"
#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/command_table.h"
#include "harness/cli/commands.h"
#include "harness/output/run_context.h"
#include "harness/plugins/plugin_loader.h"
#include "harness/process/activity_report.h"
#include "harness/process/interrupt.h"
#include "harness/process/memory_limit.h"

namespace {
// Takes `--memory-limit MB` out of the arguments (anywhere after the
// command): MB, or the default when absent; 0 with a message on stderr when
// the value is not a whole number in [64, 2^40].
std::uint64_t take_memory_limit(std::vector<std::string>& args) {
  const auto at = std::find(args.begin(), args.end(), "--memory-limit");
  if (at == args.end()) return hb::default_memory_limit_mb();
  const std::string value = at + 1 != args.end() ? *(at + 1) : "";
  const std::optional<long long> mb = hb::parse_whole_number(value, 64, 1LL << 40);
  if (!mb) {
    std::cerr << "error: --memory-limit expects a whole number of MB in [64, 2^40], got \"" << value
              << "\"\n";
    return 0;
  }
  args.erase(at, at + 2);
  return static_cast<std::uint64_t>(*mb);
}
// Loads the plugins HAPTICBENCH_PLUGINS lists, then takes every `--plugin
// PATH` out of the arguments (anywhere after the command) and loads it, and
// takes --allow-scenario-plugins (validate loads none a scenario names).
void load_plugins(const std::string& command, std::vector<std::string>& args) {
  const auto allow = std::find(args.begin(), args.end(), hb::kAllowScenarioPluginsFlag);
  const bool allowed = allow != args.end();
  if (allowed) args.erase(allow);
  if (command == "validate")
    hb::set_scenario_plugins(hb::ScenarioPlugins::kNotLoaded);
  else if (allowed)
    hb::set_scenario_plugins(hb::ScenarioPlugins::kAllowed);
  hb::load_plugins_from_environment();
  for (auto at = std::find(args.begin(), args.end(), "--plugin"); at != args.end();
       at = std::find(args.begin(), args.end(), "--plugin")) {
    if (at + 1 == args.end())
      throw hb::InputError("", "--plugin", "expected the path of a plugin file (.so)");
    const std::string path = *(at + 1);
    args.erase(at, at + 2);
    hb::load_plugin(path, "--plugin");
  }
}
}  // namespace

static int run_command_line(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << hb::top_level_usage();
    return hb::kExitBadInput;
  }
  const std::string command = argv[1];
  hb::install_interrupt_handlers();
  hb::set_build_stop_check(&hb::throw_if_interrupted);
  std::vector<std::string> args(argv + 2, argv + argc);
  const std::uint64_t memory_limit_mb = take_memory_limit(args);
  if (memory_limit_mb == 0) return hb::kExitBadInput;
  hb::apply_memory_limit(memory_limit_mb);
  if (command == "-h" || command == "--help" || command == "help") {
    std::cout << hb::top_level_usage();  // loads no plugin: a bad one must not hide the help
    return hb::kExitOk;
  }
  if (command == "--version" || command == "version") {
    std::cout << hb::version_line() << "\n";
    return hb::kExitOk;
  }
  try {
    load_plugins(command, args);
    const hb::CommandEntry* entry = hb::find_command(command);
    if (entry != nullptr) return entry->run(args);
    std::cerr << "error: unknown command \"" << command << "\"\n" << hb::top_level_usage();
    return hb::kExitBadInput;
  } catch (const hb::Interrupted& interrupted) {
    // Unwinding removed the staging folders and stopped the workers.
    std::cerr << "hapticbench " << command << ": " << interrupted.what()
              << "; nothing half-written was left (finished run folders and sweep jobs are kept)\n";
    return 128 + interrupted.signal;
  } catch (const hb::InputError& error) {
    std::cerr << "error: " << error.what() << "\n";
    return hb::kExitBadInput;
  } catch (const std::filesystem::filesystem_error& error) {
    // A path that cannot be created, read or written (read-only, under
    // /proc, a file where a folder is needed): the user's to fix.
    std::cerr << "error: " << error.path1().string() << ": " << error.code().message() << " ("
              << error.what() << ")\n";
    return hb::kExitBadInput;
  } catch (const std::bad_alloc&) {
    // Every reader bounds what it allocates by what its file can hold; an
    // input that still asks for more than the ceiling ends here.
    std::cerr << "error: " << hb::memory_limit_message() << "\n";
    return hb::kExitBadInput;
  } catch (const std::system_error& error) {
    // A thread or a mapping refused under the ceiling is the same case.
    if (hb::applied_memory_limit_mb() != 0 &&
        (error.code() == std::errc::not_enough_memory ||
         error.code() == std::errc::resource_unavailable_try_again)) {
      std::cerr << "error: " << hb::memory_limit_message() << " (" << error.what() << ")\n";
      return hb::kExitBadInput;
    }
    std::cerr << "internal error: " << error.what() << "\n";
    return hb::kExitInternal;
  } catch (const std::exception& error) {
    std::cerr << "internal error: " << error.what() << "\n";
    return hb::kExitInternal;
  }
}

int main(int argc, char** argv) {
  // A command run in a child (plugin_isolation.h) tells its parent that main
  // returned, and with which code: any other end is the plugin's doing.
  hb::take_activity_report_fd();
  const int code = run_command_line(argc, argv);
  hb::report_activity("ended " + std::to_string(code));
  return code;
}
