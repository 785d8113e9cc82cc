// Timing of one run against its baseline: the ratios of the step time p50
// and p99, and whether the per-tick step times are shifted upwards beyond
// what noise explains (one-sided Mann–Whitney U test). A timing regression
// needs both: a ratio above CompareOptions::timing_ratio and p < alpha.
#pragma once

#include <vector>

#include "harness/compare/comparison.h"
#include "harness/compare/scenario_summary.h"

namespace hb {

/// Calibration workloads within this share of each other: the two machines
/// (or one machine at two times) ran at comparable speed.
inline constexpr double kCalibrationMatch = 0.10;

/// Rows timing.step_ns.p50, timing.step_ns.p99 (value in ns, change as the
/// ratio candidate/baseline) and timing.step_ns.mann_whitney (the sample
/// sizes, change as the one-sided p-value). The step times tested are the
/// full step_ns columns of the ticks CSVs when both summaries come from run
/// folders that hold them, else each summary's timing.step_ns_sample.
/// Throws InputError for a malformed ticks CSV.
std::vector<CheckRow> timing_checks(const ScenarioSummary& baseline_scenario,
                                    const RunSummary& baseline,
                                    const ScenarioSummary& candidate_scenario,
                                    const RunSummary& candidate, const CompareOptions& options);

/// Rows timing.instructions.step_per_tick_mean and
/// timing.instructions.slow_update_per_call_mean, where either side counted
/// instructions: a regression beyond CompareOptions::instructions_rel_tol
/// between builds of one compiler and build type, else information.
std::vector<CheckRow> instruction_checks(const ScenarioSummary& baseline_scenario,
                                         const RunSummary& baseline,
                                         const ScenarioSummary& candidate_scenario,
                                         const RunSummary& candidate,
                                         const CompareOptions& options);

}  // namespace hb
