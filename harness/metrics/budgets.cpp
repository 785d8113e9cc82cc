#include "harness/metrics/budgets.h"

#include <sstream>
#include <stdexcept>
#include <string_view>

#include "harness/metrics/metric_table.h"

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

namespace {
// A build under AddressSanitizer runs several times slower, with pauses of
// its own: its step times say nothing about the algorithm's.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kTimingsMeaningful = false;
#else
constexpr bool kTimingsMeaningful = true;
#endif

bool is_timing_budget(const std::string& name) {
  const MetricDefinition* metric = find_metric(name);
  return metric && std::string_view(metric->json_pointer).rfind("/timing/", 0) == 0;
}
}  // namespace

BudgetVerdict evaluate_budget(const std::string& name, double limit, const RunMetrics& metrics) {
  BudgetVerdict verdict{name, limit, budget_metric(name, metrics), false, ""};
  std::ostringstream text;
  if (!kTimingsMeaningful && is_timing_budget(name)) {
    verdict.pass = true;  // reported, not judged
    text << name << " not checked: a sanitized build's timings are not meaningful";
  } else if (!verdict.value) {
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
