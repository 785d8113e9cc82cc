// The checks of one algorithm run present in both the baseline and the
// candidate: accuracy, stability and determinism here, timing in
// timing_checks.h.
#pragma once

#include <vector>

#include "harness/compare/comparison.h"
#include "harness/compare/scenario_summary.h"

namespace hb {

/// Absolute tolerances, one per unit, below which a change in an accuracy
/// or stability metric is never a regression (rel_tol can only widen them).
inline constexpr double kForceAbsTolN = 1e-6;
inline constexpr double kAngleAbsTolDeg = 0.01;
inline constexpr double kTorqueAbsTolNm = 1e-9;
inline constexpr double kLengthAbsTolM = 1e-7;
inline constexpr double kEnergyAbsTolJ = 1e-9;

/// True when two contexts name one build: the same commit, compiler and
/// build type, and a commit that identifies the code (not "unknown", not
/// "<commit>-dirty", whose uncommitted changes may differ between builds).
bool same_build(const BuildContext& a, const BuildContext& b);

/// Rows for one run matched by label: accuracy metrics (a regression when
/// the candidate is larger by more than max(abs tol, rel_tol |baseline|)),
/// oracle.embree.penetration_max_m when either side has it, stability
/// (nonfinite: any increase; diverged: false -> true; passivity energy: a
/// decrease beyond tolerance; force jump: an increase beyond tolerance),
/// determinism (ticks hashes must match on the same build, informative
/// otherwise) and, unless options.timing is false, timing.
std::vector<CheckRow> compare_runs(const ScenarioSummary& baseline_scenario,
                                   const RunSummary& baseline,
                                   const ScenarioSummary& candidate_scenario,
                                   const RunSummary& candidate, const CompareOptions& options);

}  // namespace hb
