// The results of running one scenario, and their files: summary.json
// (DESIGN.md contract keys, null where a metric does not apply) and
// junit.xml (one test case per budget per algorithm).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "harness/metrics/budgets.h"
#include "harness/metrics/run_metrics.h"
#include "harness/output/run_context.h"
#include "harness/scenario/scenario.h"

namespace hb {

struct PreprocessInfo {
  double seconds = 0;        ///< wall time to build the renderer (s)
  int64_t memory_bytes = 0;  ///< memory its structures hold (0 when it builds none)
  bool cache_hit = false;
  /// The renderer's own figures (Renderer::build_report), name -> number.
  std::vector<std::pair<std::string, double>> details;
};

/// One algorithm's run within a scenario.
struct AlgorithmRun {
  std::string name;
  std::string label;
  std::string params_json;        ///< the params object as written in the scenario
  std::string slow_loop_latency;  ///< "1", "5", "measured"; empty without a slow loop
  PreprocessInfo preprocess;
  RunMetrics metrics;
  std::vector<BudgetVerdict> budgets;
  std::string ticks_file;  ///< file name inside the run folder
  std::string ticks_hash;  ///< determinism fingerprint (TicksCsvWriter)
  /// "separate": step times from a replay with no ground truth between
  /// ticks, metrics from a second replay; "combined": one replay (measured
  /// slow-loop latency, whose result depends on timing).
  std::string timing_pass;
  /// With separate passes: both computed the same displays and proxies.
  std::optional<bool> passes_agree;
  std::string analytic_reference;  ///< e.g. "sphere on box"; empty when none applies
  std::string reference_note;      ///< why a reference is absent, if it is
  std::string penetration_source;  ///< "analytic", "embree", "cgal" or empty
};

/// How the scenario's oracles were set up (shared by its runs).
struct OracleDescription {
  std::string backends;  ///< "embree", "cgal" or "both"
  int64_t exact_every = 0;
  int64_t tool_samples = 0;
  double sample_spacing_m = 0;
  std::vector<std::string> distance_only_objects;
  double build_seconds = 0;
};

struct ScenarioRun {
  std::string scenario_name;
  std::string scenario_path;
  std::string scenario_hash;
  std::string trace_description;
  RunContext context;
  std::optional<OracleDescription> oracle;
  std::vector<AlgorithmRun> runs;

  bool all_budgets_pass() const;
};

/// summary.json content.
nlohmann::json summary_json(const ScenarioRun& run);
/// junit.xml content.
std::string junit_xml(const ScenarioRun& run);

}  // namespace hb
