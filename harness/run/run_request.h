// One scenario run, as every driver asks for it (run, validate, a sweep
// job, a stability probe, the instruction counter): where the scenario
// comes from, the JSON-pointer edits made before it is read, the algorithms
// to run and how. Reading, preparing and running are the steps; each driver
// calls the ones it needs.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/run/scenario_runner.h"
#include "harness/scenario/scenario.h"

namespace hb {

/// Where a scenario comes from: a file read when the request is read, or a
/// document that did not come from a file of its own (a sweep job).
struct ScenarioSource {
  std::string path;                     ///< the file; for a document, what errors name
  std::optional<std::string> document;  ///< JSON text read in place of the file
  std::filesystem::path base_dir;       ///< relative paths of a document resolve here

  /// The file at `path`, read when the request is.
  static ScenarioSource file(std::string path);
  /// The file's text now (a regular file only: a FIFO would block), so that
  /// many requests edit one reading of it; its folder is the base.
  static ScenarioSource read_now(const std::string& path);
};

/// A value set at a JSON pointer of the scenario before it is read, e.g.
/// {"/coupling/k_t", 2000}.
struct ScenarioEdit {
  std::string pointer;
  nlohmann::ordered_json value;
};

/// One scenario to run.
struct RunRequest {
  ScenarioSource scenario;
  std::vector<ScenarioEdit> edits;  ///< applied in order
  AlgorithmSelection algorithms;    ///< empty: every algorithm of the scenario
  /// False: the oracles are switched off (nothing is evaluated against them).
  bool ground_truth = true;
  /// Recorded schedules the multi-rate algorithms follow (run --schedule).
  std::optional<std::string> schedule;
  RunOptions options;
};

/// Reads the request's scenario: the file or document with the edits made
/// (the JSON nesting-bounded and duplicate-checked as every scenario is),
/// then loads the plugins it names as the plugin policy allows
/// (plugin_loader.h) and checks every algorithm name against the registry.
/// Throws InputError naming the file and the field.
Scenario read_scenario(const RunRequest& request);

/// Loads the plugins `scenario` names under the plugin policy and checks its
/// algorithm names against the registry: an unknown name is InputError at
/// "/algorithms/<i>/name"; a name that only an unloaded plugin may register
/// (the policy kNotLoaded, as validate reads) is dropped with a warning that
/// it went unchecked.
void load_plugins_and_check_algorithms(Scenario& scenario);

/// Builds what the request runs of `scenario` (read_scenario's): the
/// selected renderers and the ground truth, following recorded schedules
/// when the request names them. Throws InputError as prepare_scenario does.
PreparedScenario prepare_request(const Scenario& scenario, const RunRequest& request);

/// A request's scenario and what running it gave.
struct RunResult {
  Scenario scenario;
  ScenarioOutcome outcome;
};

/// Reads, prepares and runs the request.
RunResult run_request(const RunRequest& request);

}  // namespace hb
