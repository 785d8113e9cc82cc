// Runs every algorithm of a loaded scenario through the replay loop, with
// ground truth, metrics and tick logs outside the timed window.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hapticbench/renderer.h"
#include "harness/output/run_report.h"
#include "harness/process/scratch_folder.h"
#include "harness/progress/progress_display.h"
#include "harness/reference/analytic_reference.h"
#include "harness/reference/oracle_evaluation.h"
#include "harness/replay/replay.h"
#include "harness/run/force_reference.h"
#include "harness/scenario/scenario.h"

namespace hb {

/// An algorithm of the scenario, built and ready to replay.
struct PreparedAlgorithm {
  const AlgorithmSpec* spec = nullptr;
  std::unique_ptr<Renderer> renderer;
  ReplaySettings replay;
  std::string slow_loop_latency;  ///< "measured" (the default), "1", ..., "replayed"
  /// With --schedule: the recorded schedule its slow loop follows, and the file.
  std::unique_ptr<SlowLoopSchedule> replayed_schedule;
  std::string schedule_source;
  PreprocessInfo preprocess;

  bool has_slow_loop() const { return renderer && renderer->slow_loop() != nullptr; }
};

/// The ground truth a scenario asks for, built once and shared by its algorithms.
struct GroundTruth {
  std::optional<AnalyticScene> analytic;
  std::string analytic_name;  ///< e.g. "ideal rigid contact: sphere tool on box"
  std::string analytic_note;  ///< why there is no analytic reference, if there is none
  std::unique_ptr<OracleEvaluator> oracle;  ///< null when reference.oracle is "none"
  /// The mesh force reference along the trajectory, where the closed forms
  /// do not cover the scene (reference.force "auto").
  std::optional<ForceReferenceTrack> force;
  /// Closed loop, where the closed forms do not cover the scene: the mesh
  /// reference follows each run's own device path during its evaluation
  /// pass (ForceReferenceFollower), not the trace, which is the operator's
  /// intent the device stops short of. The scenario it is built from.
  const Scenario* force_follows_device = nullptr;
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

/// The algorithms to run, by name or label or a shell pattern over them
/// (`run --algo NAME`, repeatable; `--algo 'vps*'`); empty: every algorithm
/// of the scenario.
using AlgorithmSelection = std::vector<std::string>;

/// True when `spec` is selected: `only` is empty, or one of its entries is
/// the name or label or a pattern (fnmatch) that matches one of them.
bool is_selected(const AlgorithmSelection& only, const AlgorithmSpec& spec);

/// Builds the renderers of the scenario (all of them, or those `only`
/// selects; InputError when it selects none of them) and its ground truth. Throws InputError naming
/// the scenario file (or the offending mesh) and the field for unknown algorithms, bad parameters
/// or a scene the oracles refuse, before anything runs. With `progress`: the tasks "<scenario> /
/// <label>" in the phase "preprocessing" (with the builds' stages) and "<scenario> / ground truth"
/// in the phase "oracle".
PreparedScenario prepare_scenario(const Scenario& scenario, const AlgorithmSelection& only,
                                  ProgressDisplay* progress = nullptr);

/// Makes every multi-rate algorithm of `prepared` follow a recorded
/// schedule (`hapticbench run --schedule PATH`). PATH is a schedule file
/// `schedule_<label>.csv` (for the algorithm with that label) or a folder
/// holding such files: a run folder, or a suite folder with one run folder
/// per scenario name. Throws InputError naming PATH when a multi-rate
/// algorithm finds no schedule there, or a file names no algorithm.
void use_recorded_schedules(PreparedScenario& prepared, const std::string& path);

/// How the timing passes run.
struct RunOptions {
  int repeat = 1;  ///< timing passes per algorithm (the first one's times are the metrics)
  /// Where the passes show their progress (task "<scenario> / <label>",
  /// phases "timing pass" and "evaluation pass"); none when null.
  ProgressDisplay* progress = nullptr;
};

/// The outcome of a scenario: the report and each algorithm's files.
struct ScenarioOutcome {
  ScenarioRun report;
  /// Holds the ticks logs, written as the run went (removed with the outcome).
  std::unique_ptr<ScratchFolder> scratch;
  std::vector<std::filesystem::path> ticks_files;  ///< in scratch, parallel to report.runs
  std::vector<std::string> schedule_csv;           ///< parallel; empty without a slow loop
  /// Closed loop: the operator's intent every 10th tick (intent.csv); empty otherwise.
  std::string intent_csv;
};

/// Replays every prepared algorithm and evaluates metrics and budgets:
/// per algorithm, `options.repeat` timing passes with nothing between the
/// steps (the first one records the slow loop's schedule), then an
/// evaluation pass with ground truth that replays that schedule. Throws
/// InputError when a recorded schedule does not fit the run.
ScenarioOutcome run_prepared(PreparedScenario& prepared, const RunOptions& options = {});

}  // namespace hb
