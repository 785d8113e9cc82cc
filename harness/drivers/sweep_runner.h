// Running a sweep: every job validated first, then the jobs of a shard
// that have no summary.json yet, each in a worker process of this same
// binary (`hapticbench sweep SWEEP.json --run-job K`), at most N at a time.
// A worker writes its run folder through the same code as `hapticbench
// run`, plus the job's scenario.json.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "harness/progress/progress_display.h"
#include "harness/sweep/sweep_shard.h"

namespace hb {

struct SweepRunOptions {
  std::string sweep_file;
  std::size_t jobs = 1;             ///< worker processes at a time
  std::optional<SweepShard> shard;  ///< only these jobs; all when empty
  std::optional<std::string> out;   ///< output folder; default out/sweeps/<sweep name>/
  /// bar: one line redrawn in place; plain: a line per finished job; none: nothing.
  ProgressStyle progress = ProgressStyle::kPlain;
};

/// Runs job `job_index` alone, in this process (what each worker runs):
/// load, build, replay, write its run folder. Returns the exit code (0, or
/// 1 when a budget failed); throws InputError for bad input.
int run_sweep_job(const SweepRunOptions& options, std::size_t job_index);

/// Runs the sweep: validates every job, writes sweep.json and runs the
/// shard's missing jobs in worker processes. Returns the exit code: 0, 1
/// when a budget failed, 3 when a worker crashed; throws InputError for
/// bad input (before anything runs).
int run_sweep(const SweepRunOptions& options);

}  // namespace hb
