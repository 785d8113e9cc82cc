// The checks of one algorithm run present in both the baseline and the
// candidate: accuracy, stability and determinism here, timing in
// timing_checks.h.
#pragma once

#include <vector>

#include "harness/compare/comparison.h"
#include "harness/compare/scenario_summary.h"

namespace hb {

/// True when two contexts name one build: the same commit, compiler and
/// build type, and a commit that identifies the code (not "unknown", not
/// "<commit>-dirty", whose uncommitted changes may differ between builds).
bool same_build(const BuildContext& a, const BuildContext& b);

/// Rows for one run matched by label: every compared metric of
/// metric_table() by its rule (tolerance: worse by more than max(abs tol,
/// rel_tol |baseline|); count: any increase; flag: false -> true),
/// determinism (ticks hashes must match on the same build, informative
/// otherwise) and, unless options.timing is false, timing.
std::vector<CheckRow> compare_runs(const ScenarioSummary& baseline_scenario,
                                   const RunSummary& baseline,
                                   const ScenarioSummary& candidate_scenario,
                                   const RunSummary& candidate, const CompareOptions& options);

}  // namespace hb
