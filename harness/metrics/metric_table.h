// The one table of scalar metrics: for each, its name (as a budget and in
// messages), where summary.json keeps it within a run, its unit, which way
// is better, whether it can be a budget, how `compare` checks it, and how to
// read it from RunMetrics. Budgets, the scenario's budget names, the summary
// writer, the summary reader of `compare`, its check rows, `hapticbench
// list --metrics` and the report all read this table: adding a metric is
// one row here plus its computation in MetricsAccumulator.
//
// Only headers are included, so that readers of summaries (compare) can use
// the table without linking the metrics code.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "harness/metrics/run_metrics.h"

namespace hb {

enum class Better { kLower, kHigher };

/// How `compare` checks a metric between a baseline and a candidate.
enum class CompareRule {
  kNone,       ///< not compared (timing has its own checks)
  kTolerance,  ///< worse by more than max(abs_tol, rel_tol |baseline|) regresses
  kCount,      ///< any increase regresses (ticks with a non-finite wrench)
  kFlag,       ///< false -> true regresses (divergence)
  /// An energy whose part below zero is energy generated: that part (the
  /// value, or 0 when the value is not below zero) compared as kTolerance
  /// with higher better, so more energy generated regresses and less
  /// energy absorbed does not (a proxy freed from sticking absorbs less).
  kGeneratedEnergy,
};

/// How summary.json writes a metric's value.
enum class ValueKind {
  kNumber,  ///< a number
  kCount,   ///< a whole number (ticks, passes)
  kFlag,    ///< true or false (read as 1 or 0)
};

/// One row of the table; written with designated initializers, naming only
/// what differs from these defaults.
struct MetricDefinition {
  std::string_view name;  ///< e.g. "force_err_rms_n"; the budget name
  std::string_view
      json_pointer;       ///< within a run of summary.json, e.g. "/accuracy/force_err_rms_n"
  std::string_view unit;  ///< of the summary's value, e.g. "N", "ns", "ticks"
  ValueKind kind = ValueKind::kNumber;
  Better better = Better::kLower;
  bool budget = true;  ///< may appear in a scenario's "budgets"
  /// The unit of the metric's name, in which budgets, the console, the
  /// report and compare's tolerances files give it; empty: `unit`.
  std::string_view budget_unit;
  double budget_scale = 1;  ///< value in budget_unit = summary value × this (1e-3: ns → µs)
  CompareRule compare = CompareRule::kNone;
  double abs_tol = 0;  ///< kTolerance: a change below this never regresses
  bool compare_when_present =
      false;  ///< compared only when a side has it (else always, n/a when null)
  /// The summary's value from the run's metrics; nullopt where it does not apply.
  std::optional<double> (*read)(const RunMetrics&) = nullptr;
  std::string_view description;
  bool report_column = false;  ///< a column of the report's summary table
  /// What compare's count and flag rows call it ("ticks with a non-finite
  /// wrench"); empty: the name.
  std::string_view counted_as;
  /// The report's headline role: "accuracy" (the accuracy axis of its
  /// figures and verdicts), "accuracy_fallback" (where that one does not
  /// apply); empty for the others.
  std::string_view headline;
};

/// A compare rule's name in data ("tolerance", "count", "flag",
/// "generated_energy", "none") and its meaning for people ("any increase", ...).
const char* compare_rule_name(CompareRule rule);
const char* compare_rule_meaning(CompareRule rule);

/// The metric whose headline role is `role` ("accuracy", "accuracy_fallback"),
/// or nullptr.
const MetricDefinition* headline_metric(std::string_view role);

/// Every metric, in the order summaries, tables and comparisons list them.
std::span<const MetricDefinition> metric_table();

/// The metric with this name, or nullptr.
const MetricDefinition* find_metric(std::string_view name);

/// The table as data, for readers outside C++ (the report): name,
/// pointer, unit, better, budget, report_column, compare ("tolerance",
/// "count", "flag", "generated_energy" or "none"), abs_tol, description per
/// metric.
nlohmann::json metric_table_json();

/// The check name `compare` prints: the JSON pointer with dots
/// ("/accuracy/force_err_rms_n" -> "accuracy.force_err_rms_n").
std::string metric_check_name(const MetricDefinition& metric);

}  // namespace hb
