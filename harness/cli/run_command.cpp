// hapticbench run SCENARIO... [--algo NAME] [--out DIR]: reads, builds and
// runs each scenario (harness/run/run_request.h) and writes its run folder;
// the arguments: run_arguments.h.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/plugin_isolation.h"
#include "harness/cli/run_arguments.h"
#include "harness/output/output_ownership.h"
#include "harness/output/run_table.h"
#include "harness/run/instruction_counting.h"
#include "harness/run/run_request.h"
#include "harness/run/scenario_run_folder.h"
#include "harness/run/scenario_runner.h"
#include "harness/scenario/scenario.h"

namespace hb {

namespace fs = std::filesystem;

int run_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const std::optional<RunArguments> parsed =
      parse_command_line([&] { return parse_run_arguments(args); }, run_usage(), exit_code);
  if (!parsed) return exit_code;
  if (parsed->explain) {
    print_run_table_legend(std::cout);
    return kExitOk;
  }

  // Read and build everything first: bad input anywhere stops the command
  // before any run folder is written.
  ProgressDisplay progress = make_progress_display(parsed->progress);
  std::vector<RunRequest> requests;
  for (const std::string& path : parsed->scenarios) {
    RunRequest& request = requests.emplace_back();
    request.scenario = ScenarioSource::file(path);
    request.algorithms = parsed->algos;
    request.schedule = parsed->schedule;
    request.options = parsed->options;
    request.options.progress = &progress;
  }
  std::vector<Scenario> scenarios;
  std::vector<PreparedScenario> prepared;
  // Scenario warnings wait until it is known whether a child process runs
  // the scenarios (plugins: it says them itself); an error says them first.
  std::vector<std::string> warnings;
  // Errors end the live line first, so that they stand on lines of their own.
  const auto report_error = [&progress, &warnings](const InputError& error) {
    for (const std::string& warning : warnings) progress.print_above(std::cerr, warning);
    progress.close();
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  };
  const auto show_scenario = [&](std::size_t s) {
    std::ostringstream prefix;
    const std::size_t count = parsed->scenarios.size();
    if (count > 1) prefix << "[" << s + 1 << "/" << count << "] ";
    progress.set_prefix(prefix.str());
  };
  try {
    for (const RunRequest& request : requests) {
      const std::string& path = request.scenario.path;
      show_scenario(scenarios.size());
      progress.task(path);
      progress.phase("loading");
      scenarios.push_back(read_scenario(request));
      progress.finish_task();
      for (const std::string& warning : scenarios.back().warnings)
        warnings.push_back("warning: " + path + ": " + warning + "\n");
      for (std::size_t i = 0; i + 1 < scenarios.size(); ++i)
        if (scenarios[i].name == scenarios.back().name)
          throw InputError(path, "/name",
                           "scenario name \"" + scenarios.back().name + "\" is also used by " +
                               scenarios[i].path + "; run folders would collide");
    }
    check_expected_labels(*parsed, scenarios);
    // Plugins run in a child that this process watches (plugin_isolation.h).
    std::vector<std::string> names;
    for (const Scenario& scenario : scenarios)
      for (const AlgorithmSpec& spec : scenario.algorithms)
        if (is_selected(parsed->algos, spec)) names.push_back(spec.name);
    if (should_isolate_plugins(names)) {
      progress.close();
      return run_plugins_isolated("run", args);  // the child says the warnings
    }
    for (const std::string& warning : warnings) progress.print_above(std::cerr, warning);
    warnings.clear();
    // Every run folder must be writable without destroying anything
    // hapticbench did not write, before any scenario runs.
    if (parsed->out && scenarios.size() > 1) create_output_container(*parsed->out);
    for (const Scenario& scenario : scenarios)
      require_replaceable_folder(run_folder_for(*parsed, scenario), OutputFolderKind::kRun);
    for (std::size_t s = 0; s < scenarios.size(); ++s) {
      show_scenario(s);
      prepared.push_back(prepare_request(scenarios[s], requests[s]));
    }
  } catch (const InputError& error) {
    return report_error(error);
  }

  bool all_pass = true;
  std::vector<std::string> unstable;  // "scenario label (reason)" of runs that fail stability
  for (std::size_t s = 0; s < scenarios.size(); ++s) {
    const Scenario& scenario = scenarios[s];
    show_scenario(s);
    ScenarioOutcome outcome;
    try {
      outcome = run_prepared(prepared[s], requests[s].options);
      if (parsed->instructions) {
        progress.task(scenario.name);
        progress.phase("instruction count under callgrind");
        count_instructions(scenario.path, parsed->algos, outcome);
        progress.finish_task();
      }
    } catch (const InputError& error) {
      return report_error(error);
    }
    apply_expected_instability(*parsed, outcome.report);
    const fs::path folder = run_folder_for(*parsed, scenario);
    progress.task(scenario.name);
    progress.phase("writing " + folder.string() + "/");
    const bool replaced = write_scenario_run_folder(folder, outcome);
    progress.finish_task();

    std::ostringstream table;
    table << "scenario " << scenario.name << " -> " << folder.string() << "/"
          << (replaced ? " (replaced the earlier run folder)" : "") << "\n";
    print_run_table(table, outcome.report);
    // What the runs showed (the scenario's own warnings were said when it loaded).
    for (std::size_t w = scenario.warnings.size(); w < outcome.report.warnings.size(); ++w)
      table << "  warning: " << outcome.report.warnings[w] << "\n";
    progress.print_above(std::cout, table.str());
    all_pass = all_pass && outcome.report.all_budgets_pass();
    for (const AlgorithmRun& run : outcome.report.runs)
      if (!stability_passes(run))
        unstable.push_back(scenario.name + " " + run.label + " (" + run_stability(run).reason +
                           ")");
  }
  progress.print_above(std::cout,
                       "(columns, units and summary fields: hapticbench run --explain)\n");
  if (!unstable.empty()) {
    std::ostringstream text;
    text << unstable.size() << " unstable run" << (unstable.size() == 1 ? "" : "s")
         << " (exit 1; a scenario's \"expected_unstable\" or --expect-unstable LABEL says where "
            "that is the point):\n";
    for (const std::string& line : unstable) text << "  " << line << "\n";
    progress.print_above(std::cerr, text.str());
  }
  return all_pass && unstable.empty() ? kExitOk : kExitBudgetFailed;
}

}  // namespace hb
