// Runs every algorithm of a loaded scenario through the replay loop, with
// ground truth, metrics and tick logs outside the timed window.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/proxy/renderer.h"
#include "harness/output/run_report.h"
#include "harness/replay/replay.h"
#include "harness/scenario/scenario.h"

namespace hb {

/// An algorithm of the scenario, built and ready to replay.
struct PreparedAlgorithm {
  const AlgorithmSpec* spec = nullptr;
  std::unique_ptr<Renderer> renderer;
  ReplaySettings replay;
  std::string slow_loop_latency;  ///< as written: "1", "measured", ...
  PreprocessInfo preprocess;
};

/// Builds the renderers of the scenario (all of them, or those whose name or
/// label is `only`). Throws InputError naming the scenario file and the
/// field for unknown algorithms or bad parameters, before anything runs.
std::vector<PreparedAlgorithm> prepare_algorithms(const Scenario& scenario,
                                                  const std::optional<std::string>& only);

/// The outcome of a scenario: the report and each algorithm's ticks CSV.
struct ScenarioOutcome {
  ScenarioRun report;
  std::vector<std::string> ticks_csv;  ///< parallel to report.runs
};

/// Replays every prepared algorithm and evaluates metrics and budgets.
ScenarioOutcome run_prepared(const Scenario& scenario, std::vector<PreparedAlgorithm>& algorithms);

}  // namespace hb
