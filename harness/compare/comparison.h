// A candidate's summaries against a baseline's: scenarios matched by name,
// runs by label, and one check row per compared metric with a verdict.
// This is what `hapticbench compare` prints, writes and gates on.
#pragma once

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/compare/scenario_summary.h"
#include "harness/compare/summary_set.h"
#include "harness/progress/progress_display.h"

namespace hb {

enum class Verdict {
  kPass,           ///< within tolerance
  kImproved,       ///< better than the baseline beyond tolerance
  kNotApplicable,  ///< null on both sides: the metric does not apply
  kInfo,           ///< worth reading, never fails (a metric appeared, builds differ, ...)
  kNew,            ///< a scenario or run only the candidate has
  kRegression,     ///< worse than the baseline beyond tolerance
  kFailure,        ///< something the baseline has is gone (scenario, run, metric)
};

/// "pass", "improved", "n/a", "info", "new", "regression", "failure".
const char* verdict_name(Verdict verdict);
/// Regressions and failures: what makes `compare --gate` exit 1.
bool is_failing(Verdict verdict);

/// One metric's tolerance in place of the defaults (compare --tolerances).
struct MetricTolerance {
  std::optional<double> rel_tol;  ///< share of |baseline|; default CompareOptions::rel_tol
  std::optional<double> abs_tol;  ///< in the metric's unit (its name's); default the table's
};

struct CompareOptions {
  /// Relative tolerance on accuracy and stability metrics: a candidate is
  /// worse when it exceeds the baseline by more than max(absolute
  /// tolerance of the metric's unit, rel_tol * |baseline|).
  double rel_tol = 0.05;
  /// A timing regression needs candidate/baseline of step_ns p50 or p99
  /// above this ratio ...
  double timing_ratio = 1.25;
  /// ... and a one-sided Mann–Whitney p-value (candidate slower) below alpha.
  double alpha = 0.01;
  /// False: no timing checks (e.g. baseline and candidate from different machines).
  bool timing = true;
  /// True: when the two summaries name different CPUs, timing rows inform
  /// but never regress (a committed baseline gated on another machine).
  bool timing_same_cpu_only = false;
  /// False (the default): wall-clock rows regress only when both runs
  /// measured a quiet machine (timing.noise.quiet) and their calibration
  /// workloads took within kCalibrationMatch of each other; otherwise they
  /// inform and say why. True (`--strict-timing`): they gate whatever the
  /// noise floor says. Instruction counts gate either way.
  bool strict_timing = false;
  /// Instruction counts (timing.instructions, deterministic) regress when
  /// the candidate's exceed the baseline's by more than this share, between
  /// builds of one compiler and build type.
  double instructions_rel_tol = 0.02;
  /// Per metric (by metric-table name): tolerances that replace the
  /// defaults for that metric's rows.
  std::map<std::string, MetricTolerance> tolerances;
};

/// Reads a tolerances file: a JSON object {metric name: {"rel_tol": x,
/// "abs_tol": y}} (either key may be left out; a bare number is rel_tol).
/// Throws InputError naming the file and the key for an unknown metric, a
/// metric compared otherwise than by tolerance (counts, flags, timing), or a
/// value that is not a number >= 0.
std::map<std::string, MetricTolerance> read_tolerances_file(const std::string& path);

/// One compared quantity of one run (or of a scenario, with an empty label).
struct CheckRow {
  std::string scenario;
  std::string label;         ///< run label; empty for a scenario-level row
  std::string check;         ///< e.g. "accuracy.force_err_rms_n" (its path in summary.json)
  nlohmann::json baseline;   ///< the baseline's value (null where it has none)
  nlohmann::json candidate;  ///< the candidate's value
  std::string change;        ///< e.g. "+20.0%", "x1.50", "false -> true", "p=3.1e-09"
  Verdict verdict = Verdict::kPass;
  std::string note;  ///< why this verdict, in words
  /// Check-specific figures for compare.json (difference, tolerance, ratio, p-value, ...).
  nlohmann::json detail = nlohmann::json::object();
};

/// A row of `check` for the run labelled `label` of `scenario`: values and
/// verdict still to fill.
CheckRow check_row(const std::string& scenario, const std::string& label, const std::string& check);

/// Fills in the row's values and, when either side is null, its verdict:
/// not applicable (both null), failure (the candidate lost the metric) or
/// information (the candidate gained it). Returns true when it settled the
/// verdict, false when both values are present and the caller compares them.
bool settle_null_values(CheckRow& row, std::optional<double> baseline,
                        std::optional<double> candidate);

struct Comparison {
  std::string baseline_path;
  std::string candidate_path;
  CompareOptions options;
  std::vector<CheckRow> rows;

  /// Rows whose verdict is a regression or a failure.
  std::size_t failing_rows() const;
  bool passed() const { return failing_rows() == 0; }
};

/// Compares two sides. Suites (and a suite against a single run) are
/// matched by scenario name: a baseline scenario the candidate lacks is a
/// failure, a candidate-only one is listed as new. Two single runs must be
/// of one scenario: otherwise throws InputError "different scenarios:
/// baseline X, candidate Y". Reading ticks CSVs for step times may throw
/// InputError too. With `progress`: the phase "comparing", one unit per
/// baseline scenario.
Comparison compare_summary_sets(const SummarySet& baseline, const SummarySet& candidate,
                                const CompareOptions& options, ProgressDisplay* progress = nullptr);

/// The rows of one scenario present on both sides: its hash, then per run
/// (matched by label) its checks; missing runs fail, new runs are listed.
std::vector<CheckRow> compare_scenarios(const ScenarioSummary& baseline,
                                        const ScenarioSummary& candidate,
                                        const CompareOptions& options);

/// How a value is shown in tables: numbers to 6 significant digits, text as
/// is, null as "null".
std::string display_value(const nlohmann::json& value);

}  // namespace hb
