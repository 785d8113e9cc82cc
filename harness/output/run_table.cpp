#include "harness/output/run_table.h"

#include <cstdio>
#include <optional>
#include <string>

namespace hb {

namespace {
std::string fixed(std::optional<double> value, double scale, int decimals) {
  if (!value) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, *value * scale);
  return text;
}
}  // namespace

void print_run_table(std::ostream& out, const ScenarioRun& run) {
  char line[256];
  std::snprintf(line, sizeof line, "  %-22s %6s %8s %8s %9s %10s %10s %9s %5s %-12s %s\n", "label",
                "ticks", "p50_us", "p99_us", "cpu99_us", "F_err_N", "pen_max_mm", "E_min_mJ",
                "nonfin", "stability", "budgets");
  out << line;
  for (const AlgorithmRun& r : run.runs) {
    const RunMetrics& m = r.metrics;
    int passed = 0;
    for (const BudgetVerdict& b : r.budgets) passed += b.pass ? 1 : 0;
    const std::string budgets =
        r.budgets.empty() ? "none"
                          : std::to_string(passed) + "/" + std::to_string(r.budgets.size()) +
                                (passed == static_cast<int>(r.budgets.size()) ? " pass" : " FAIL");
    // "stable", or the check the run failed ("chatter", "limit_cycle", …),
    // starred where that is expected.
    const StabilityResult stability = run_stability(r);
    const std::string stability_cell = stability.stable
                                           ? "stable"
                                           : std::string(stability_check_name(stability.failed)) +
                                                 (r.unstable_expected ? "*" : "");
    std::snprintf(
        line, sizeof line, "  %-22s %6lld %8s %8s %9s %10s %10s %9s %5lld %-12s %s\n",
        r.label.c_str(), static_cast<long long>(m.timing.ticks),
        fixed(m.timing.step_ns.p50, 1e-3, 2).c_str(), fixed(m.timing.step_ns.p99, 1e-3, 2).c_str(),
        fixed(m.timing.cpu_per_tick_ns.percentiles.p99, 1e-3, 2).c_str(),
        fixed(m.accuracy.force_err_rms_n, 1, 4).c_str(),
        fixed(m.accuracy.penetration_max_m, 1e3, 3).c_str(),
        fixed(m.stability.passivity_energy_min_j, 1e3, 3).c_str(),
        static_cast<long long>(m.stability.nonfinite), stability_cell.c_str(), budgets.c_str());
    out << line;
    if (!stability.stable)
      out << (r.unstable_expected ? "    unstable, as expected: " : "    UNSTABLE: ")
          << stability.reason
          << (r.unstable_expected ? " (" + *r.unstable_expected + ")"
                                  : std::string(" (fails the run)"))
          << "\n";
    for (const BudgetVerdict& b : r.budgets)
      if (!b.pass) out << "    budget failed: " << b.message << "\n";
    if (r.instructions) {
      const InstructionCounts& c = *r.instructions;
      out << "    instructions: " << (c.ticks > 0 ? c.step_total / c.ticks : 0) << " per step";
      if (c.has_slow_loop && c.slow_updates > 0)
        out << ", " << c.slow_update_total / c.slow_updates << " per slow update";
      out << "\n";
    }
    if (m.closed_loop) {
      const ClosedLoopMetrics& c = *m.closed_loop;
      const LimitCycleMetrics& cycles = c.limit_cycles;
      out << "    closed loop: device penetration " << fixed(c.device_penetration_max_m, 1e3, 3)
          << " mm, displayed stiffness " << fixed(c.displayed_stiffness_n_per_m, 1, 0)
          << " N/m, display energy min " << fixed(c.display_energy_min_j, 1e3, 3) << " mJ, "
          << (cycles.limit_cycle ? "LIMIT CYCLE " + fixed(cycles.amplitude_m, 1e3, 3) + " mm at " +
                                       fixed(cycles.frequency_hz, 1, 0) + " Hz"
                                 : std::string("no limit cycle"))
          << "\n";
    }
    if (r.passes_agree && !*r.passes_agree)
      out << "    NOT DETERMINISTIC: the timing and evaluation replays computed different forces\n";
  }
}

}  // namespace hb
