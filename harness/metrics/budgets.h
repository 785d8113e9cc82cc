// Budgets: limits a scenario sets on metrics, and their verdicts.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "harness/metrics/run_metrics.h"

namespace hb {

struct BudgetVerdict {
  std::string name;
  double limit = 0;
  std::optional<double> value;  ///< empty when the metric does not apply (the budget then fails)
  bool pass = false;
  std::string message;  ///< why it failed, in words
};

/// The metric a budget name refers to, in the budget's unit (e.g.
/// tick_p99_us in microseconds); empty when it does not apply.
/// Throws std::invalid_argument for a name that is not a budget.
std::optional<double> budget_metric(const std::string& name, const RunMetrics& metrics);

/// True when the budget is a lower bound (value must be >= limit), e.g.
/// passivity_energy_min_j; all others are upper bounds.
bool budget_is_lower_bound(const std::string& name);

/// Verdict of one budget on a run.
BudgetVerdict evaluate_budget(const std::string& name, double limit, const RunMetrics& metrics);

}  // namespace hb
