// The results of running one scenario, and their files: summary.json
// (DESIGN.md contract keys, null where a metric does not apply) and
// junit.xml (one test case per budget per algorithm).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hapticbench/scene.h"
#include "harness/metrics/budgets.h"
#include "harness/metrics/run_metrics.h"
#include "harness/output/run_context.h"
#include "harness/replay/noise_floor.h"
#include "harness/metrics/stability_verdict.h"

namespace hb {

struct PreprocessInfo {
  double seconds = 0;        ///< wall time to build the renderer (s)
  int64_t memory_bytes = 0;  ///< memory its structures hold (0 when it builds none)
  bool cache_hit = false;
  /// The renderer's own figures (Renderer::build_report), name -> number.
  std::vector<std::pair<std::string, double>> details;
};

/// min / median / max of a figure over repeated timing passes.
struct Spread {
  double min = 0, median = 0, max = 0;
};
/// The spread of `values` (zeros when empty).
Spread spread_of(std::vector<double> values);

/// `run --repeat N`: the spread of step time percentiles over N timing passes.
struct TimingRepeats {
  int count = 0;
  Spread step_p50_ns, step_p99_ns;
};

/// `run --instructions`: user-space instructions callgrind counted inside
/// Renderer::step and inside slow-loop updates (nothing else).
struct InstructionCounts {
  int64_t ticks = 0;
  int64_t step_total = 0;
  bool has_slow_loop = false;
  int64_t slow_updates = 0;
  int64_t slow_update_total = 0;
};

/// One algorithm's run within a scenario.
/// How the mesh force reference (harness/run/force_reference.h) went, for
/// summary.json's "force_reference".
struct ForceReferenceDescription {
  std::string method;  ///< what it is, in one phrase
  int64_t every = 1;   ///< evaluated on ticks k with k % every == 0
  int64_t evaluated_ticks = 0;
  int64_t not_started_ticks = 0;  ///< sampled ticks before the device was first outside the scene
  int64_t unconverged_ticks = 0;
  int64_t infeasible_ticks = 0;
  int max_iterations = 0;       ///< most iterations one tick took
  double kkt_residual_max = 0;  ///< largest KKT residual over converged ticks
  int64_t tool_points = 0;      ///< tool vertices and samples kept outside
  double clearance_m = 0;       ///< ε
  /// The scene has μ > 0 and the reference applies it (Coulomb friction on
  /// the proxy's translation, the analytic reference's model).
  bool friction = false;
  int64_t sticking_ticks = 0;  ///< evaluated ticks on which friction held the proxy
  double seconds = 0;          ///< computing it (0 from the cache)
  bool cache_hit = false;
};

struct AlgorithmRun {
  std::string name;
  std::string label;
  bool renders_friction = false;  ///< its registry entry's renders_friction
  std::string plugin;             ///< the plugin file it came from; empty when built in
  std::string params_json;        ///< the params object as written in the scenario
  /// Closed loop: the mesh force reference that followed this run's own
  /// device (runs[].force_reference); nullopt otherwise.
  std::optional<ForceReferenceDescription> force_reference;
  /// "measured" (default), "1", "5" (fixed), "replayed"; empty without a slow loop.
  std::string slow_loop_latency;
  std::string schedule_file;    ///< schedule_<label>.csv in the run folder; empty without
  std::string schedule_source;  ///< the file a replayed schedule came from
  PreprocessInfo preprocess;
  RunMetrics metrics;
  NoiseFloor noise;                               ///< of the (first) timing pass
  std::optional<TimingRepeats> repeats;           ///< with --repeat N > 1
  std::optional<InstructionCounts> instructions;  ///< with --instructions
  std::vector<BudgetVerdict> budgets;
  /// Why this label's instability is expected (the scenario's
  /// "expected_unstable", or `run --expect-unstable`); nullopt: an unstable
  /// run fails the command.
  std::optional<std::string> unstable_expected;
  std::string ticks_file;  ///< file name inside the run folder
  std::string ticks_hash;  ///< determinism fingerprint (TicksCsvWriter)
  /// "separate": step times from a replay with no ground truth between
  /// ticks, metrics from a second replay that follows the first one's
  /// slow-loop schedule (the only mode since schedules are recorded).
  std::string timing_pass;
  /// Both passes computed the same displays and proxies.
  std::optional<bool> passes_agree;
  std::string analytic_reference;  ///< e.g. "sphere on box"; empty when none applies
  std::string reference_note;      ///< why a reference is absent, if it is
  std::string penetration_source;  ///< "analytic", "embree", "cgal" or empty
};

/// How the scenario's oracles were set up (shared by its runs).
struct OracleDescription {
  std::string backends;  ///< as the scenario says: a backend's name, "all" or "both" (all)
  int64_t exact_every = 0;
  int64_t tool_samples = 0;
  double sample_spacing_m = 0;
  std::vector<std::string> distance_only_objects;
  double build_seconds = 0;
};

/// A scene object or the tool as the report draws it: its bounds.
struct ObjectOutline {
  std::string name;
  std::string type;  ///< "box", "sphere", "capsule", "box_with_hole" or "mesh"
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();  ///< m: world frame (scene), tool frame (tool)
  bool distance_only = false;
};

struct ScenarioRun {
  std::string scenario_name;
  std::string scenario_path;
  std::string scenario_hash;
  std::string trace_description;
  std::string scenario_description;  ///< the scenario's "description" ("" when absent)
  /// Where things are, for the report's picture of the scene: each scene
  /// object's world-frame bounds (m), and the tool's in its own frame.
  std::vector<ObjectOutline> scene_outline;
  std::optional<ObjectOutline> tool_outline;
  std::vector<double> scene_friction;  ///< Coulomb μ of each scene object, in scene order
  std::vector<std::string> tags;       ///< the scenario's tags
  CouplingGains coupling;              ///< the scenario's virtual coupling
  RunContext context;
  std::optional<OracleDescription> oracle;
  std::optional<ForceReferenceDescription> force_reference;  ///< the mesh force reference
  std::vector<AlgorithmRun> runs;
  /// What the run may not measure as it seems to: the scenario's warnings
  /// (implausible settings, a point renderer given a mesh tool, a mesh
  /// scene without penetration truth), then what the runs showed (a tool
  /// that never reached the scene). summary.json "warnings".
  std::vector<std::string> warnings;

  bool all_budgets_pass() const;
  /// Every run stable, or unstable where that is expected.
  bool all_stable_or_expected() const;
};

/// The run's stability verdict: stability_verdict.h's, at its defaults.
StabilityResult run_stability(const AlgorithmRun& run);
/// Stable, or unstable where that is expected.
bool stability_passes(const AlgorithmRun& run);

/// summary.json content.
nlohmann::json summary_json(const ScenarioRun& run);
/// junit.xml content.
std::string junit_xml(const ScenarioRun& run);

}  // namespace hb
