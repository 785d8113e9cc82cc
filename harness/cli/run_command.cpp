// hapticbench run SCENARIO... [--algo NAME] [--out DIR]
#include <fnmatch.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include "hapticbench/input_error.h"
#include "harness/cli/command_line.h"
#include "harness/cli/commands.h"
#include "harness/cli/plugin_isolation.h"
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
const std::string kRunUsage =
    "usage: hapticbench run SCENARIO.json... [--algo NAME]... [--scenario PATTERN]...\n"
    "                      [--out DIR] [--repeat N] [--instructions] [--schedule PATH]\n"
    "                      [--expect-unstable LABEL] [--progress STYLE] [--quiet]\n"
    "       hapticbench run --explain\n"
    "  --algo NAME     run only the algorithms with this name or label, or a pattern\n"
    "                  over them ('vps*'); repeatable\n"
    "  --scenario PATTERN\n"
    "                  run only the scenario files whose name (without .json) or path\n"
    "                  matches the shell pattern ('*press*'); repeatable\n"
    "  --explain       print what each column of the run table means, its unit and the\n"
    "                  summary.json field it shows, and exit\n"
    "  --out DIR       run folder (one scenario) or parent of <scenario name>/ (several);\n"
    "                  default out/<scenario name>/\n"
    "  --repeat N      N timing passes per algorithm; the summary gives the spread of\n"
    "                  their step time p50 and p99 (the first pass's times are the metrics)\n"
    "  --instructions  also count the instructions of step() and of slow-loop updates\n"
    "                  under valgrind's callgrind (deterministic; needs valgrind)\n"
    "  --schedule PATH multi-rate algorithms follow the slow-loop schedule recorded in\n"
    "                  PATH: a schedule_<label>.csv, a run folder or a suite of them\n"
    "  --expect-unstable LABEL\n"
    "                  an unstable run of LABEL (\"all\": of every label) does not fail the\n"
    "                  command (exit 1 otherwise); repeatable. A scenario says it with\n"
    "                  \"expected_unstable\": {LABEL: why}\n" +
    std::string(kProgressUsage);

constexpr int kMaxRepeat = 1000;

struct RunArguments {
  std::vector<std::string> scenarios;
  AlgorithmSelection algos;                    ///< --algo NAME, each; empty: every algorithm
  std::vector<std::string> scenario_patterns;  ///< --scenario PATTERN, each; empty: every file
  bool explain = false;
  std::optional<std::string> out;
  std::optional<std::string> schedule;
  bool instructions = false;
  std::vector<std::string> expect_unstable;  ///< labels, or "all"
  std::optional<ProgressStyle> progress;
  RunOptions options;
};

constexpr const char* kExpectedOnCommandLine = "expected on the command line (--expect-unstable)";

// Whether the shell pattern matches the scenario file's stem or its path.
bool matches_file_pattern(const std::string& pattern, const std::string& path) {
  const std::string stem = fs::path(path).stem().string();
  return ::fnmatch(pattern.c_str(), stem.c_str(), 0) == 0 ||
         ::fnmatch(pattern.c_str(), path.c_str(), 0) == 0;
}

// Throws UsageError or HelpRequested.
RunArguments parse_run_arguments(const std::vector<std::string>& args) {
  RunArguments parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    check_help(a);
    if (a == "--algo") {
      parsed.algos.push_back(option_value(args, i));
    } else if (a == "--scenario") {
      parsed.scenario_patterns.push_back(option_value(args, i));
    } else if (a == "--explain") {
      parsed.explain = true;
    } else if (a == "--out" || a == "--schedule" || a == "--repeat") {
      const std::string& value = option_value(args, i);
      if (a == "--repeat") {
        const std::optional<long long> repeat = parse_whole_number(value, 1, kMaxRepeat);
        if (!repeat)
          throw UsageError{"--repeat: expected a whole number in [1, " +
                           std::to_string(kMaxRepeat) + "], got \"" + value + "\""};
        parsed.options.repeat = static_cast<int>(*repeat);
      } else {
        (a == "--out" ? parsed.out : parsed.schedule) = value;
      }
    } else if (a == "--expect-unstable") {
      parsed.expect_unstable.push_back(option_value(args, i));
    } else if (a == "--instructions") {
      parsed.instructions = true;
    } else if (parse_progress_option(args, i, parsed.progress)) {
    } else if (a.rfind("--", 0) == 0) {
      throw UsageError{"unknown option " + a};
    } else {
      parsed.scenarios.push_back(a);
    }
  }
  if (parsed.explain) return parsed;
  if (parsed.scenarios.empty()) throw UsageError{"no scenario given"};
  if (!parsed.scenario_patterns.empty()) {
    std::vector<std::string> kept;
    for (const std::string& path : parsed.scenarios)
      for (const std::string& pattern : parsed.scenario_patterns)
        if (matches_file_pattern(pattern, path)) {
          kept.push_back(path);
          break;
        }
    if (kept.empty())
      throw UsageError{"--scenario: no scenario file of the " +
                       std::to_string(parsed.scenarios.size()) +
                       " given matches the patterns (a pattern matches a file's name without "
                       ".json, e.g. 'sphere_*', or its path)"};
    parsed.scenarios = std::move(kept);
  }
  return parsed;
}

// Marks the runs whose instability the command line expects.
void apply_expected_instability(const RunArguments& args, ScenarioRun& report) {
  for (AlgorithmRun& run : report.runs)
    for (const std::string& label : args.expect_unstable)
      if ((label == "all" || label == run.label) && !run.unstable_expected)
        run.unstable_expected = kExpectedOnCommandLine;
}

fs::path run_folder_for(const RunArguments& args, const Scenario& scenario) {
  if (!args.out) return fs::path("out") / scenario.name;
  if (args.scenarios.size() == 1) return fs::path(*args.out);
  return fs::path(*args.out) / scenario.name;
}
}  // namespace

int run_command(const std::vector<std::string>& args) {
  int exit_code = 0;
  const std::optional<RunArguments> parsed =
      parse_command_line([&] { return parse_run_arguments(args); }, kRunUsage, exit_code);
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
    // An --expect-unstable label that no scenario has is most likely a typo.
    for (const std::string& label : parsed->expect_unstable) {
      bool found = label == "all";
      for (const Scenario& scenario : scenarios)
        for (const AlgorithmSpec& spec : scenario.algorithms) found = found || spec.label == label;
      if (!found)
        throw InputError(
            "", "--expect-unstable",
            "no scenario given has the label \"" + label + "\" (\"all\" stands for every label)");
    }
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
