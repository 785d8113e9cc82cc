// The arguments of `hapticbench run`: its option table, and what they say
// of each scenario's run folder and of the instability it expects.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "harness/progress/progress_display.h"
#include "harness/run/scenario_runner.h"
#include "harness/scenario/scenario.h"

namespace hb {

struct RunArguments {
  std::vector<std::string> scenarios;          ///< the files, those --scenario keeps
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

/// The arguments `args` give; throws UsageError or HelpRequested.
RunArguments parse_run_arguments(const std::vector<std::string>& args);

/// `hapticbench run --help`.
std::string run_usage();

/// Marks the runs whose instability the command line expects.
void apply_expected_instability(const RunArguments& args, ScenarioRun& report);

/// Throws InputError for an --expect-unstable label no scenario has (most
/// likely a typo; "all" stands for every label).
void check_expected_labels(const RunArguments& args, const std::vector<Scenario>& scenarios);

/// The run folder of `scenario`: --out for one scenario, the scenario's
/// name inside --out for several, out/<scenario name> without --out.
std::filesystem::path run_folder_for(const RunArguments& args, const Scenario& scenario);

}  // namespace hb
