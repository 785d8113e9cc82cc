// Runs every algorithm of a loaded scenario through the replay loop, with
// ground truth, metrics and tick logs outside the timed window.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/proxy/renderer.h"
#include "harness/output/run_report.h"
#include "harness/reference/analytic_reference.h"
#include "harness/reference/oracle_evaluation.h"
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

/// The ground truth a scenario asks for, built once and shared by its algorithms.
struct GroundTruth {
  std::optional<AnalyticScene> analytic;
  std::string analytic_name;  ///< e.g. "ideal rigid contact: sphere tool on box"
  std::string analytic_note;  ///< why there is no analytic reference, if there is none
  std::unique_ptr<OracleEvaluator> oracle;  ///< null when reference.oracle is "none"
  double oracle_build_seconds = 0;
};

/// A scenario with everything built: nothing left that bad input could stop.
struct PreparedScenario {
  const Scenario* scenario = nullptr;
  /// What the renderers were built from: the scenario's context with its
  /// reach box. Renderers may keep references into it, so it outlives them.
  std::unique_ptr<RenderContext> context;
  std::vector<PreparedAlgorithm> algorithms;
  GroundTruth truth;
};

/// Builds the renderers of the scenario (all of them, or those whose name or
/// label is `only`) and its ground truth. Throws InputError naming the
/// scenario file (or the offending mesh) and the field for unknown
/// algorithms, bad parameters or a scene the oracles refuse, before
/// anything runs.
PreparedScenario prepare_scenario(const Scenario& scenario, const std::optional<std::string>& only);

/// The outcome of a scenario: the report and each algorithm's ticks CSV.
struct ScenarioOutcome {
  ScenarioRun report;
  std::vector<std::string> ticks_csv;  ///< parallel to report.runs
};

/// Replays every prepared algorithm and evaluates metrics and budgets.
ScenarioOutcome run_prepared(PreparedScenario& prepared);

}  // namespace hb
