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

namespace {

// One `hapticbench run`: every scenario read and built before any runs, so
// that bad input anywhere stops the command before a run folder is written.
class RunCommand {
 public:
  explicit RunCommand(const RunArguments& parsed)
      : parsed_(parsed), progress_(make_progress_display(parsed.progress)) {
    for (const std::string& path : parsed.scenarios) {
      RunRequest& request = requests_.emplace_back();
      request.scenario = ScenarioSource::file(path);
      request.algorithms = parsed.algos;
      request.schedule = parsed.schedule;
      request.options = parsed.options;
      request.options.progress = &progress_;
    }
  }

  // Reads every scenario; says whether a plugin names an algorithm to run
  // (the scenarios then run in a watched child: plugin_isolation.h).
  bool read_all_and_ask_for_isolation() {
    for (const RunRequest& request : requests_) {
      const std::string& path = request.scenario.path;
      show_scenario(scenarios_.size());
      progress_.task(path);
      progress_.phase("loading");
      scenarios_.push_back(read_scenario(request));
      progress_.finish_task();
      for (const std::string& warning : scenarios_.back().warnings)
        warnings_.push_back("warning: " + path + ": " + warning + "\n");
      for (std::size_t i = 0; i + 1 < scenarios_.size(); ++i)
        if (scenarios_[i].name == scenarios_.back().name)
          throw InputError(path, "/name",
                           "scenario name \"" + scenarios_.back().name + "\" is also used by " +
                               scenarios_[i].path + "; run folders would collide");
    }
    check_expected_labels(parsed_, scenarios_);
    std::vector<std::string> names;
    for (const Scenario& scenario : scenarios_)
      for (const AlgorithmSpec& spec : scenario.algorithms)
        if (is_selected(parsed_.algos, spec)) names.push_back(spec.name);
    if (!should_isolate_plugins(names)) return false;
    progress_.close();
    return true;
  }

  // Says the scenarios' warnings, checks every run folder may be written
  // without destroying anything hapticbench did not write, builds every run.
  void prepare_all() {
    for (const std::string& warning : warnings_) progress_.print_above(std::cerr, warning);
    warnings_.clear();
    if (parsed_.out && scenarios_.size() > 1) create_output_container(*parsed_.out);
    for (const Scenario& scenario : scenarios_)
      require_replaceable_folder(run_folder_for(parsed_, scenario), OutputFolderKind::kRun);
    for (std::size_t s = 0; s < scenarios_.size(); ++s) {
      show_scenario(s);
      prepared_.push_back(prepare_request(scenarios_[s], requests_[s]));
    }
  }

  // Runs scenario `s`, writes its run folder and prints its table.
  void run(std::size_t s) {
    const Scenario& scenario = scenarios_[s];
    show_scenario(s);
    ScenarioOutcome outcome = run_prepared(prepared_[s], requests_[s].options);
    if (parsed_.instructions) {
      progress_.task(scenario.name);
      progress_.phase("instruction count under callgrind");
      count_instructions(scenario.path, parsed_.algos, outcome);
      progress_.finish_task();
    }
    apply_expected_instability(parsed_, outcome.report);
    const fs::path folder = run_folder_for(parsed_, scenario);
    progress_.task(scenario.name);
    progress_.phase("writing " + folder.string() + "/");
    const bool replaced = write_scenario_run_folder(folder, outcome);
    progress_.finish_task();

    std::ostringstream table;
    table << "scenario " << scenario.name << " -> " << folder.string() << "/"
          << (replaced ? " (replaced the earlier run folder)" : "") << "\n";
    print_run_table(table, outcome.report);
    // What the runs showed (the scenario's own warnings were said when it loaded).
    for (std::size_t w = scenario.warnings.size(); w < outcome.report.warnings.size(); ++w)
      table << "  warning: " << outcome.report.warnings[w] << "\n";
    progress_.print_above(std::cout, table.str());
    all_pass_ = all_pass_ && outcome.report.all_budgets_pass();
    for (const AlgorithmRun& run : outcome.report.runs)
      if (!stability_passes(run))
        unstable_.push_back(scenario.name + " " + run.label + " (" + run_stability(run).reason +
                            ")");
  }

  // The closing lines and the exit code.
  int finish() {
    progress_.print_above(std::cout,
                          "(columns, units and summary fields: hapticbench run --explain)\n");
    if (!unstable_.empty()) {
      std::ostringstream text;
      text << unstable_.size() << " unstable run" << (unstable_.size() == 1 ? "" : "s")
           << " (exit 1; a scenario's \"expected_unstable\" or --expect-unstable LABEL says "
              "where that is the point):\n";
      for (const std::string& line : unstable_) text << "  " << line << "\n";
      progress_.print_above(std::cerr, text.str());
    }
    return all_pass_ && unstable_.empty() ? kExitOk : kExitBudgetFailed;
  }

  // The warnings not said yet, then the error, on lines of their own.
  int report_error(const InputError& error) {
    for (const std::string& warning : warnings_) progress_.print_above(std::cerr, warning);
    progress_.close();
    std::cerr << "error: " << error.what() << "\n";
    return kExitBadInput;
  }

  std::size_t scenario_count() const { return scenarios_.size(); }

 private:
  void show_scenario(std::size_t s) {
    std::ostringstream prefix;
    if (requests_.size() > 1) prefix << "[" << s + 1 << "/" << requests_.size() << "] ";
    progress_.set_prefix(prefix.str());
  }

  const RunArguments& parsed_;
  ProgressDisplay progress_;
  std::vector<RunRequest> requests_;
  std::vector<Scenario> scenarios_;
  std::vector<PreparedScenario> prepared_;
  // Said once it is known whether a child runs the scenarios (it says them
  // itself); an error says them first.
  std::vector<std::string> warnings_;
  bool all_pass_ = true;
  std::vector<std::string> unstable_;  // "scenario label (reason)" of runs failing stability
};

}  // namespace

int run_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const std::optional<RunArguments> parsed =
      parse_command_line([&] { return parse_run_arguments(args); }, run_usage(), exit_code);
  if (!parsed) return exit_code;
  if (parsed->explain) {
    print_run_table_legend(std::cout);
    return kExitOk;
  }
  RunCommand command(*parsed);
  try {
    if (command.read_all_and_ask_for_isolation())
      return run_plugins_isolated("run", args);  // the child says the warnings
    command.prepare_all();
    for (std::size_t s = 0; s < command.scenario_count(); ++s) command.run(s);
  } catch (const InputError& error) {
    return command.report_error(error);
  }
  return command.finish();
}

}  // namespace hb
