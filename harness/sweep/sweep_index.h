// DIR/sweep.json: every job of a sweep with its grid values, run folder and
// status, rewritten (atomically) as jobs finish, so that a report, a
// resumed sweep or another shard sees where the sweep stands.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/sweep/sweep_jobs.h"
#include "harness/sweep/sweep_shard.h"
#include "harness/sweep/sweep_spec.h"

namespace hb {

enum class SweepJobStatus {
  kPending,       ///< not run yet (or run by another shard that has not finished it)
  kOk,            ///< summary.json written, every budget met
  kBudgetFailed,  ///< summary.json written, a budget or the stability verdict failed
  kFailed,        ///< the worker stopped on an error it named (exit 2: a full disk, bad input)
  kCrashed,       ///< the worker ended otherwise without writing its run folder
};

/// "pending", "ok", "budget_failed", "failed", "crashed".
const char* sweep_job_status_name(SweepJobStatus status);

struct SweepJobState {
  SweepJobStatus status = SweepJobStatus::kPending;
  bool done_earlier = false;  ///< its summary.json existed before this invocation started
  std::string detail;         ///< how a crashed worker ended, e.g. "killed by signal 11 (...)"
  /// The scenario hash its summary.json records ("" without one): a run
  /// folder is the job's only when it equals the job's scenario hash.
  std::string scenario_hash;
};

/// The state a job's run folder records: kOk or kBudgetFailed from the
/// budgets in its summary.json, kPending without a readable summary.
SweepJobState sweep_job_state_on_disk(const std::filesystem::path& run_folder);

/// sweep.json: the sweep's name, file, grid and, per job in job order, its
/// index, name (= run folder under the output folder), scenario, grid
/// values, status (and "done_earlier", "detail" when they apply).
nlohmann::ordered_json sweep_index_json(const SweepSpec& spec, const std::vector<SweepJob>& jobs,
                                        const std::vector<SweepJobState>& states,
                                        const SweepShard& shard);

/// Writes out_dir/sweep.json through a temporary file and a rename, so a
/// reader (or a shard writing at the same time) never sees half a file.
void write_sweep_index(const std::filesystem::path& out_dir, const nlohmann::ordered_json& index);

/// Whether `path` is a sweep.json that write_sweep_index wrote (a JSON
/// object with its "jobs" and "written_by_shard" keys), so that a later
/// sweep may replace it.
bool is_sweep_index_file(const std::filesystem::path& path);

}  // namespace hb
