#include "harness/metrics/budgets.h"

#include "harness/metrics/metric_table.h"

#include <sstream>
#include <stdexcept>

namespace hb {

std::optional<double> budget_metric(const std::string& name, const RunMetrics& m) {
  const MetricDefinition* metric = find_metric(name);
  if (!metric || !metric->budget) throw std::invalid_argument("unknown budget " + name);
  const std::optional<double> value = metric->read(m);
  if (!value) return std::nullopt;
  return *value * metric->budget_scale;
}

bool budget_is_lower_bound(const std::string& name) {
  const MetricDefinition* metric = find_metric(name);
  return metric && metric->better == Better::kHigher;
}

BudgetVerdict evaluate_budget(const std::string& name, double limit, const RunMetrics& metrics) {
  BudgetVerdict verdict{name, limit, budget_metric(name, metrics), false, ""};
  std::ostringstream text;
  if (!verdict.value) {
    text << name << " does not apply to this run (no reference for it), so it cannot pass";
  } else if (budget_is_lower_bound(name)) {
    verdict.pass = *verdict.value >= limit;
    if (!verdict.pass) text << name << " = " << *verdict.value << " is below the limit " << limit;
  } else {
    verdict.pass = *verdict.value <= limit;
    if (!verdict.pass) text << name << " = " << *verdict.value << " exceeds the limit " << limit;
  }
  verdict.message = text.str();
  return verdict;
}

}  // namespace hb
