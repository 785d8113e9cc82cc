// `hapticbench run --instructions`: instruction counts of Renderer::step
// and of slow-loop updates, from a second process of this binary run under
// valgrind's callgrind (`hapticbench count-instructions`, internal). The
// child replays each algorithm without ground truth, following the slow-loop
// schedules the timing pass recorded, with collection switched on only
// around the measured calls; counts are deterministic for one build.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "harness/run/scenario_runner.h"

namespace hb {

/// Counts instructions for the runs of `outcome` (scenario file
/// `scenario_path`, algorithms restricted to `only` when given) and stores
/// them in each run's `instructions`. Throws InputError when valgrind is not
/// installed, std::runtime_error when the child fails.
void count_instructions(const std::string& scenario_path, const AlgorithmSelection& only,
                        ScenarioOutcome& outcome);

/// The child's work, in the process callgrind runs: loads the scenario
/// (no ground truth), makes its multi-rate algorithms follow the schedules
/// in `schedule_dir`, and for each algorithm (or `only`) replays once to
/// warm up, once collecting step() and once collecting slow updates,
/// dumping "step:<label>" and "slow:<label>"; writes {label: {ticks,
/// slow_updates}} to `out`. Progress shows on `progress` as in a run's
/// timing pass (between ticks, from the tick counter), so that the counts
/// tell whether showing it costs anything inside the measured calls.
void count_instructions_here(const std::string& scenario_path, const AlgorithmSelection& only,
                             const std::string& schedule_dir, const std::string& out,
                             ProgressDisplay* progress = nullptr);

}  // namespace hb
