#include "harness/cli/run_arguments.h"

#include <fnmatch.h>

#include "hapticbench/input_error.h"
#include "harness/cli/commands.h"
#include "harness/cli/option_table.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

constexpr long long kMaxRepeat = 1000;

constexpr const char* kExpectedOnCommandLine = "expected on the command line (--expect-unstable)";

using Table = OptionTable<RunArguments>;

const Table& run_table() {
  static const Table table(
      {"run", {}, {}, {"--explain"}},
      {Table::positional("SCENARIO.json", "a scenario file", 0, kAnyCount,
                         &RunArguments::scenarios),
       Table::value("--algo", "NAME",
                    "run only the algorithms with this name or label, or a pattern over them "
                    "('vps*')",
                    &RunArguments::algos),
       Table::value("--scenario", "PATTERN",
                    "run only the scenario files whose name (without .json) or path matches the "
                    "shell pattern ('*press*')",
                    &RunArguments::scenario_patterns),
       Table::flag("--explain",
                   "print what each column of the run table means, its unit and the "
                   "summary.json field it shows, and exit",
                   &RunArguments::explain),
       Table::value("--out", "DIR",
                    "the run folder (one scenario) or the parent of `<scenario name>/` (several)",
                    &RunArguments::out)
           .with_default("`out/<scenario name>/`"),
       Table::whole("--repeat", "N",
                    "N timing passes per algorithm; the summary gives the spread of their step "
                    "time p50 and p99 (the first pass's times are the metrics)",
                    {1, kMaxRepeat, ""}, member_of(&RunArguments::options, &RunOptions::repeat))
           .with_default("1"),
       Table::flag("--instructions",
                   "also count the instructions of step() and of slow-loop updates under "
                   "valgrind's callgrind (deterministic; needs valgrind)",
                   &RunArguments::instructions),
       Table::value("--schedule", "PATH",
                    "multi-rate algorithms follow the slow-loop schedule recorded in PATH: a "
                    "`schedule_<label>.csv`, a run folder or a suite of them",
                    &RunArguments::schedule),
       Table::value("--expect-unstable", "LABEL",
                    "an unstable run of LABEL (\"all\": of every label) does not fail the "
                    "command (exit 1 otherwise); a scenario says it with "
                    "`\"expected_unstable\": {LABEL: why}`",
                    &RunArguments::expect_unstable),
       Table::progress(&RunArguments::progress), Table::quiet(&RunArguments::progress)});
  return table;
}

// Whether the shell pattern matches the scenario file's stem or its path.
bool matches_file_pattern(const std::string& pattern, const std::string& path) {
  const std::string stem = fs::path(path).stem().string();
  return ::fnmatch(pattern.c_str(), stem.c_str(), 0) == 0 ||
         ::fnmatch(pattern.c_str(), path.c_str(), 0) == 0;
}

}  // namespace

RunArguments parse_run_arguments(const std::vector<std::string>& args) {
  RunArguments parsed = run_table().parse(args);
  if (parsed.explain) return parsed;
  if (parsed.scenarios.empty()) throw UsageError{"no scenario given"};
  if (parsed.scenario_patterns.empty()) return parsed;
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
  return parsed;
}

std::string run_usage() { return run_table().usage(); }

void apply_expected_instability(const RunArguments& args, ScenarioRun& report) {
  for (AlgorithmRun& run : report.runs)
    for (const std::string& label : args.expect_unstable)
      if ((label == "all" || label == run.label) && !run.unstable_expected)
        run.unstable_expected = kExpectedOnCommandLine;
}

void check_expected_labels(const RunArguments& args, const std::vector<Scenario>& scenarios) {
  for (const std::string& label : args.expect_unstable) {
    bool found = label == "all";
    for (const Scenario& scenario : scenarios)
      for (const AlgorithmSpec& spec : scenario.algorithms) found = found || spec.label == label;
    if (!found)
      throw InputError(
          "", "--expect-unstable",
          "no scenario given has the label \"" + label + "\" (\"all\" stands for every label)");
  }
}

fs::path run_folder_for(const RunArguments& args, const Scenario& scenario) {
  if (!args.out) return fs::path("out") / scenario.name;
  if (args.scenarios.size() == 1) return fs::path(*args.out);
  return fs::path(*args.out) / scenario.name;
}

const CommandSyntax& run_syntax() { return run_table().syntax(); }

}  // namespace hb
