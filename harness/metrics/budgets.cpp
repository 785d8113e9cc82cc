#include "harness/metrics/budgets.h"

#include <sstream>
#include <stdexcept>

namespace hb {

std::optional<double> budget_metric(const std::string& name, const RunMetrics& m) {
  const auto us = [](double ns) { return ns * 1e-3; };
  if (name == "tick_p50_us") return us(m.timing.step_ns.p50);
  if (name == "tick_p99_us") return us(m.timing.step_ns.p99);
  if (name == "tick_p999_us") return us(m.timing.step_ns.p999);
  if (name == "tick_max_us") return us(m.timing.step_ns.max);
  if (name == "cpu_per_tick_p99_us") return us(m.timing.cpu_per_tick_ns.percentiles.p99);
  if (name == "over_budget_ticks") return static_cast<double>(m.timing.over_budget);
  if (name == "max_penetration_m") return m.accuracy.penetration_max_m;
  if (name == "penetration_rms_m") return m.accuracy.penetration_rms_m;
  if (name == "force_err_rms_n") return m.accuracy.force_err_rms_n;
  if (name == "force_dir_err_deg") return m.accuracy.force_dir_err_max_deg;
  if (name == "torque_err_rms_nm") return m.accuracy.torque_err_rms_nm;
  if (name == "nonfinite") return static_cast<double>(m.stability.nonfinite);
  if (name == "force_jump_max_n") return m.stability.force_jump_max_n;
  if (name == "free_space_force_max_n") return m.transparency.free_space_force_max_n;
  if (name == "passivity_energy_min_j") return m.stability.passivity_energy_min_j;
  if (name == "diverged") return m.stability.diverged ? 1.0 : 0.0;
  throw std::invalid_argument("unknown budget " + name);
}

bool budget_is_lower_bound(const std::string& name) { return name == "passivity_energy_min_j"; }

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
