#include "harness/output/run_table.h"

#include <algorithm>
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
// Why a timing pass's machine was not quiet: the NoiseFloor criteria it missed.
std::string noise_reasons(const NoiseFloor& noise) {
  std::string reasons;
  const auto add = [&reasons](const std::string& text) {
    reasons += (reasons.empty() ? "" : ", ") + text;
  };
  if (noise.cpu_share < kQuietCpuShare) add("CPU share " + fixed(noise.cpu_share, 1, 2));
  if (noise.calibration_spread > kQuietSpread)
    add("calibration spread " + fixed(noise.calibration_spread, 1, 2));
  if (noise.calibration_drift > kQuietDrift)
    add("calibration drift " + fixed(noise.calibration_drift, 1, 2));
  if (noise.load_average_1m > noise.logical_cores - 0.5)
    add("load " + fixed(noise.load_average_1m, 1, 1) + " on " +
        std::to_string(noise.logical_cores) + " cores");
  if (noise.other_runnable > std::max(0, noise.logical_cores - 2))
    add(std::to_string(noise.other_runnable) + " other tasks runnable");
  return reasons.empty() ? "the noise probe's criteria" : reasons;
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
  std::string noisy;  // "label (why)" of each run timed on a machine that was not quiet
  for (const AlgorithmRun& r : run.runs)
    if (!r.noise.quiet)
      noisy += (noisy.empty() ? "" : ", ") + r.label + " (" + noise_reasons(r.noise) + ")";
  if (!noisy.empty())
    out << "  timing: the machine was not quiet while timing " << noisy
        << ": those step and CPU times are not comparable with a quiet run's (timing.noise; "
           "docs/performance.md)\n";
}

void print_run_table_legend(std::ostream& out) {
  struct Column {
    const char* name;
    const char* unit;
    const char* field;  ///< in summary.json's runs[]
    const char* meaning;
  };
  constexpr Column kColumns[] = {
      {"label", "-", "label", "the algorithm's label in the scenario"},
      {"ticks", "ticks", "timing.ticks", "1 ms ticks replayed"},
      {"p50_us", "µs", "timing.step_ns.p50", "median wall time of one step() (budget tick_p50_us)"},
      {"p99_us", "µs", "timing.step_ns.p99",
       "99th percentile of the step() wall time (budget tick_p99_us); against the 1 ms tick"},
      {"cpu99_us", "µs", "timing.cpu_per_tick_ns.p99",
       "99th percentile of the CPU a tick costs, slow-loop updates spread over their ticks "
       "(budget cpu_per_tick_p99_us)"},
      {"F_err_N", "N", "accuracy.force_err_rms_n",
       "RMS of the displayed force minus the reference's (budget force_err_rms_n); - without a "
       "reference"},
      {"pen_max_mm", "mm", "accuracy.penetration_max_m",
       "deepest penetration of the proxy's tool into the scene, analytic else Embree (budget "
       "max_penetration_mm)"},
      {"E_min_mJ", "mJ", "stability.passivity_energy_min_j",
       "least energy the coupling has taken from the user since the start; below 0 it gave "
       "energy (not passive; budget passivity_energy_min_mj)"},
      {"nonfin", "ticks", "stability.nonfinite", "ticks whose wrench was not finite (zeroed)"},
      {"stability", "-", "stability.verdict",
       "stable, or the check the run failed: nonfinite, diverged, tunnelled, passivity, chatter, "
       "limit_cycle; * where the scenario expects it"},
      {"budgets", "-", "budgets", "budgets met of those given, pass or FAIL"},
  };
  out << "| column | unit | summary.json (runs[]) | meaning |\n| --- | --- | --- | --- |\n";
  for (const Column& column : kColumns)
    out << "| `" << column.name << "` | " << column.unit << " | `" << column.field << "` | "
        << column.meaning << " |\n";
}

}  // namespace hb
