// Runs commands in worker processes, at most N at a time: what `sweep
// --jobs N` uses, one process per job, so that jobs share no state and a
// job that crashes takes only itself down.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "harness/process/child_process.h"

namespace hb {

/// One command to run in a process of its own.
struct WorkerLaunch {
  std::vector<std::string> argv;  ///< argv[0]: the program's path
};

/// What a worker process left behind.
struct WorkerResult {
  ProcessEnd end;
  std::string stdout_text;
  std::string stderr_text;
  double seconds = 0;  ///< wall time from start to end as the pool saw it
};

struct WorkerCallbacks {
  std::function<void(std::size_t launch)> on_start;
  std::function<void(std::size_t launch, const WorkerResult&)> on_finish;
  std::function<void()> on_wait;  ///< while waiting for workers, about every 50 ms
};

/// Runs every launch, starting them in list order, at most `parallel` at a
/// time (parallel >= 1). Each worker's stdout and stderr go to files in
/// scratch_dir, read back into its result and removed. Results are in
/// launch order. Throws std::runtime_error when a process cannot start;
/// workers still running then are stopped (SIGTERM) and reaped.
std::vector<WorkerResult> run_worker_processes(const std::vector<WorkerLaunch>& launches,
                                               std::size_t parallel,
                                               const std::filesystem::path& scratch_dir,
                                               const WorkerCallbacks& callbacks);

}  // namespace hb
