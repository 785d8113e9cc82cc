// What the comparison reads from one summary.json (DESIGN.md contract),
// checked and typed: the build context, the scenario and, per algorithm
// run, the metrics the gate compares. Everything else in the file is
// ignored, so summaries may grow new keys freely.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace hb {

/// The summary schema this comparison understands.
inline constexpr int kComparedSchemaVersion = 1;

/// Where a summary was produced; two summaries with the same commit,
/// compiler and build type come from the same build.
struct BuildContext {
  std::string commit;  ///< `git describe --always --dirty`, "unknown" outside git
  std::string compiler;
  std::string build_type;
  std::string cpu;
};

/// One algorithm run of a scenario. Optional metrics are null in the summary
/// where they do not apply.
struct RunSummary {
  std::string label;
  std::string ticks_file;  ///< file name inside the run folder
  /// The algorithm's "params" object as the summary gives it; null when absent.
  nlohmann::ordered_json params;

  // Timing of Renderer::step (ns).
  std::optional<double> step_ns_p50;
  std::optional<double> step_ns_p99;
  /// Evenly spaced sample of per-tick step times (ns), in tick order.
  std::vector<double> step_ns_sample;
  /// timing.noise: whether the machine was quiet while the steps were timed
  /// and the calibration workload's median (ns); empty in summaries without it.
  std::optional<bool> timing_quiet;
  std::optional<double> calibration_ns;
  std::string noise_text;  ///< e.g. "cpu share 0.62, load 2.9": why a run was not quiet

  // Instruction counts (timing.instructions), empty without --instructions.
  std::optional<double> instructions_step_per_tick;
  std::optional<double> instructions_slow_update_per_call;

  /// The metrics `compare` checks (metric_table() rows whose rule is not
  /// kNone), by metric name: null where the run has none. Flags are 1 or 0.
  std::map<std::string, std::optional<double>, std::less<>> metrics;

  /// determinism.ticks_hash: equal for runs that computed the same numbers.
  std::string ticks_hash;
};

/// One summary.json: one scenario, its runs in file order.
struct ScenarioSummary {
  std::string source;  ///< the summary.json path (or a description), named in messages
  /// The run folder the summary came from, where ticks_<label>.csv files may
  /// be; empty for a summary given as a file or built in memory.
  std::optional<std::filesystem::path> run_folder;
  BuildContext context;
  std::string scenario_name;
  std::string scenario_hash;
  /// scenario.coupling ({k_t, b_t, k_r, b_r}); null when absent.
  nlohmann::ordered_json coupling;
  std::vector<RunSummary> runs;

  /// The run with this label, or nullptr.
  const RunSummary* find_run(const std::string& label) const;
};

/// Checks and types a parsed summary. Throws InputError(source, JSON
/// pointer, what was expected) for a missing or mistyped contract key, a
/// schema_version other than 1 or a label used twice.
ScenarioSummary scenario_summary_from_json(const nlohmann::ordered_json& document,
                                           const std::string& source);

/// Reads, parses and checks one summary.json. Throws InputError naming the
/// file: unreadable, malformed JSON (with line and column), or as above.
ScenarioSummary read_scenario_summary(const std::filesystem::path& summary_file);

}  // namespace hb
