#include "harness/compare/timing_checks.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "harness/compare/mann_whitney.h"
#include "harness/compare/step_times.h"
#include "harness/metrics/formatted_number.h"

namespace hb {

namespace {

using nlohmann::json;

// A p-value for people: tiny ones underflow to 0 in double, which would
// read as certainty.
std::string p_text(double p) { return p < 1e-300 ? "<1e-300" : formatted("%.2g", p); }

struct StepTimeSamples {
  std::vector<double> baseline;
  std::vector<double> candidate;
  std::string source;  ///< where they came from, for the note
};

StepTimeSamples step_time_samples(const ScenarioSummary& baseline_scenario,
                                  const RunSummary& baseline,
                                  const ScenarioSummary& candidate_scenario,
                                  const RunSummary& candidate) {
  if (baseline_scenario.run_folder && candidate_scenario.run_folder) {
    std::optional<std::vector<double>> b =
        read_ticks_step_ns(*baseline_scenario.run_folder / baseline.ticks_file);
    std::optional<std::vector<double>> c =
        read_ticks_step_ns(*candidate_scenario.run_folder / candidate.ticks_file);
    if (b && c && !b->empty() && !c->empty())
      return {std::move(*b), std::move(*c), "step_ns columns of the ticks CSVs"};
  }
  return {baseline.step_ns_sample, candidate.step_ns_sample, "timing.step_ns_sample"};
}

// The ratio row of one percentile. `slower` and `faster` are the one-sided
// tests in each direction, absent when a side has no step times.
CheckRow ratio_row(CheckRow row, std::optional<double> baseline, std::optional<double> candidate,
                   const std::optional<MannWhitneyResult>& slower,
                   const std::optional<MannWhitneyResult>& faster, const CompareOptions& options) {
  if (settle_null_values(row, baseline, candidate)) return row;
  if (!(*baseline > 0)) {
    row.verdict = Verdict::kInfo;
    row.note = "baseline is 0 ns: no ratio";
    return row;
  }
  const double ratio = *candidate / *baseline;
  const std::string limit = formatted("x%.2f", options.timing_ratio);
  row.change = formatted("x%.2f", ratio);
  row.detail = {{"ratio", ratio}, {"timing_ratio", options.timing_ratio}};
  if (slower) row.detail["p_value_slower"] = slower->p_value;
  if (faster) row.detail["p_value_faster"] = faster->p_value;

  if (ratio > options.timing_ratio) {
    if (!slower) {
      row.verdict = Verdict::kInfo;
      row.note = "slower than " + limit + "; no step times to test whether it is noise";
    } else if (slower->p_value < options.alpha) {
      row.verdict = Verdict::kRegression;
      row.note = "slower than " + limit +
                 " and significant (one-sided Mann-Whitney p = " + p_text(slower->p_value) + " < " +
                 formatted("%g", options.alpha) + ")";
    } else {
      row.verdict = Verdict::kInfo;
      row.note = "slower than " + limit + " but not significant (p = " + p_text(slower->p_value) +
                 " >= " + formatted("%g", options.alpha) + "): likely noise";
    }
  } else if (ratio < 1 / options.timing_ratio && faster && faster->p_value < options.alpha) {
    row.verdict = Verdict::kImproved;
    row.note = "faster than " + formatted("x%.2f", 1 / options.timing_ratio) +
               " and significant (p = " + p_text(faster->p_value) + ")";
  } else {
    row.note = "within " + limit;
  }
  return row;
}

CheckRow rank_test_row(CheckRow row, const StepTimeSamples& samples,
                       const std::optional<MannWhitneyResult>& slower,
                       const BuildContext& baseline_context, const BuildContext& candidate_context,
                       const CompareOptions& options) {
  row.baseline = samples.baseline.size();
  row.candidate = samples.candidate.size();
  std::string machines;
  if (baseline_context.cpu != candidate_context.cpu)
    machines = "; different CPUs (" + baseline_context.cpu + " vs " + candidate_context.cpu + ")";
  if (!slower) {
    row.verdict = Verdict::kNotApplicable;
    row.note = "no step times on one side (" + samples.source + " empty)" + machines;
    return row;
  }
  row.change = "p=" + p_text(slower->p_value);
  row.detail = {{"source", samples.source},
                {"u_candidate", slower->u_candidate},
                {"u_baseline", slower->u_baseline},
                {"u_mean", slower->u_mean},
                {"u_sd", slower->u_sd},
                {"z", slower->z},
                {"p_value", slower->p_value},
                {"alpha", options.alpha}};
  const std::string counts = std::to_string(samples.baseline.size()) + " vs " +
                             std::to_string(samples.candidate.size()) + " step times from " +
                             samples.source;
  if (slower->p_value < options.alpha) {
    row.verdict = Verdict::kInfo;
    row.note = "candidate significantly slower (one-sided, p < " + formatted("%g", options.alpha) +
               "); " + counts + machines;
  } else {
    row.note = "no significant slowdown; " + counts + machines;
  }
  return row;
}

// Why wall-clock rows of these two runs may not gate: empty when they may.
std::string wall_clock_ungated_reason(const RunSummary& baseline, const RunSummary& candidate) {
  if (!baseline.timing_quiet || !candidate.timing_quiet)
    return "no noise floor measured on " +
           std::string(!baseline.timing_quiet ? "the baseline" : "the candidate");
  if (!*baseline.timing_quiet) return "baseline machine not quiet (" + baseline.noise_text + ")";
  if (!*candidate.timing_quiet) return "candidate machine not quiet (" + candidate.noise_text + ")";
  if (baseline.calibration_ns && candidate.calibration_ns && *baseline.calibration_ns > 0) {
    const double ratio = *candidate.calibration_ns / *baseline.calibration_ns;
    if (std::abs(ratio - 1) > kCalibrationMatch)
      return "the calibration workload took " + formatted("x%.2f", ratio) +
             " the baseline's time: the machines run at different speeds";
  }
  return "";
}

CheckRow instructions_row(CheckRow row, std::optional<double> baseline,
                          std::optional<double> candidate, const BuildContext& baseline_context,
                          const BuildContext& candidate_context, const CompareOptions& options) {
  row.baseline = baseline ? nlohmann::json(*baseline) : nlohmann::json(nullptr);
  row.candidate = candidate ? nlohmann::json(*candidate) : nlohmann::json(nullptr);
  if (!baseline || !candidate) {
    row.verdict = baseline || candidate ? Verdict::kInfo : Verdict::kNotApplicable;
    if (baseline || candidate)
      row.note = std::string("counted on the ") + (baseline ? "baseline" : "candidate") +
                 " only (run with --instructions to compare)";
    return row;
  }
  const double ratio = *baseline > 0 ? *candidate / *baseline : 1.0;
  row.change = formatted("%+.2f%%", 100 * (ratio - 1));
  row.detail = {{"ratio", ratio}, {"rel_tol", options.instructions_rel_tol}};
  const std::string tolerance = formatted("%.1f%%", 100 * options.instructions_rel_tol);
  const bool comparable = baseline_context.compiler == candidate_context.compiler &&
                          baseline_context.build_type == candidate_context.build_type;
  if (ratio > 1 + options.instructions_rel_tol) {
    row.verdict = comparable ? Verdict::kRegression : Verdict::kInfo;
    row.note = "more instructions than the tolerance " + tolerance +
               (comparable ? "" : "; not gated: different compilers or build types");
  } else if (ratio < 1 - options.instructions_rel_tol) {
    row.verdict = comparable ? Verdict::kImproved : Verdict::kInfo;
    row.note = "fewer instructions, beyond " + tolerance;
  } else {
    row.note = "within " + tolerance;
  }
  return row;
}

}  // namespace

std::vector<CheckRow> timing_checks(const ScenarioSummary& baseline_scenario,
                                    const RunSummary& baseline,
                                    const ScenarioSummary& candidate_scenario,
                                    const RunSummary& candidate, const CompareOptions& options) {
  auto row = [&](const std::string& check) {
    return check_row(baseline_scenario.scenario_name, baseline.label, check);
  };
  const StepTimeSamples samples =
      step_time_samples(baseline_scenario, baseline, candidate_scenario, candidate);
  std::optional<MannWhitneyResult> slower, faster;
  if (!samples.baseline.empty() && !samples.candidate.empty()) {
    slower = mann_whitney_greater(samples.baseline, samples.candidate);
    faster = mann_whitney_greater(samples.candidate, samples.baseline);
  }
  std::vector<CheckRow> rows = {
      ratio_row(row("timing.step_ns.p50"), baseline.step_ns_p50, candidate.step_ns_p50, slower,
                faster, options),
      ratio_row(row("timing.step_ns.p99"), baseline.step_ns_p99, candidate.step_ns_p99, slower,
                faster, options),
      rank_test_row(row("timing.step_ns.mann_whitney"), samples, slower, baseline_scenario.context,
                    candidate_scenario.context, options),
  };
  std::string ungated;
  if (options.timing_same_cpu_only &&
      baseline_scenario.context.cpu != candidate_scenario.context.cpu)
    ungated = "measured on different CPUs";
  else if (!options.strict_timing)
    ungated = wall_clock_ungated_reason(baseline, candidate);
  if (!ungated.empty()) {
    for (CheckRow& r : rows) {
      if (r.verdict == Verdict::kRegression || r.verdict == Verdict::kImproved) {
        r.verdict = Verdict::kInfo;
        r.note += "; not gated: " + ungated;
      }
    }
  }
  return rows;
}

std::vector<CheckRow> instruction_checks(const ScenarioSummary& baseline_scenario,
                                         const RunSummary& baseline,
                                         const ScenarioSummary& candidate_scenario,
                                         const RunSummary& candidate,
                                         const CompareOptions& options) {
  auto row = [&](const std::string& check) {
    return check_row(baseline_scenario.scenario_name, baseline.label, check);
  };
  std::vector<CheckRow> rows;
  if (baseline.instructions_step_per_tick || candidate.instructions_step_per_tick)
    rows.push_back(instructions_row(row("timing.instructions.step_per_tick_mean"),
                                    baseline.instructions_step_per_tick,
                                    candidate.instructions_step_per_tick, baseline_scenario.context,
                                    candidate_scenario.context, options));
  if (baseline.instructions_slow_update_per_call || candidate.instructions_slow_update_per_call)
    rows.push_back(instructions_row(
        row("timing.instructions.slow_update_per_call_mean"),
        baseline.instructions_slow_update_per_call, candidate.instructions_slow_update_per_call,
        baseline_scenario.context, candidate_scenario.context, options));
  return rows;
}

}  // namespace hb
