#include "harness/drivers/sweep_runner.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "algorithms/core/replacing_file.h"
#include "hapticbench/input_error.h"
#include "harness/output/output_ownership.h"
#include "harness/output/run_folder.h"
#include "harness/output/run_table.h"
#include "harness/process/scratch_folder.h"
#include "harness/run/run_request.h"
#include "harness/run/scenario_run_folder.h"
#include "harness/sweep/sweep_index.h"
#include "harness/sweep/sweep_jobs.h"
#include "harness/sweep/sweep_progress.h"
#include "harness/sweep/sweep_spec.h"
#include "harness/sweep/sweep_table.h"
#include "harness/sweep/worker_pool.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

// A job's run: its scenario with the grid's values set, every algorithm.
RunRequest sweep_job_request(const SweepJob& job) {
  RunRequest request;
  request.scenario.path = job.scenario_path;
  request.scenario.document = sweep_job_scenario_text(job);
  request.scenario.base_dir = job.base_dir;
  return request;
}

// Exit codes of a sweep and its workers (harness/cli/commands.h has the list).
constexpr int kSweepOk = 0, kSweepBudgetFailed = 1, kSweepFailed = 2, kSweepCrashed = 3;

fs::path output_folder(const SweepRunOptions& args, const SweepSpec& spec) {
  return args.out ? fs::path(*args.out) : fs::path("out") / "sweeps" / spec.name;
}

}  // namespace

int run_sweep_job(const SweepRunOptions& args, std::size_t job_index) {
  const SweepSpec spec = load_sweep_spec(args.sweep_file);
  const std::vector<SweepJob> jobs = expand_sweep_jobs(spec);
  if (job_index >= jobs.size())
    throw InputError(args.sweep_file, "--run-job",
                     "no job " + std::to_string(job_index) + "; the sweep has " +
                         std::to_string(jobs.size()) + " jobs (0 to " +
                         std::to_string(jobs.size() - 1) + ")");
  const SweepJob& job = jobs[job_index];
  RunResult run;
  try {
    run = run_request(sweep_job_request(job));
  } catch (const InputError& error) {
    throw sweep_job_error(spec, job, error);
  }
  const Scenario& scenario = run.scenario;
  const ScenarioOutcome& outcome = run.outcome;
  const fs::path folder = output_folder(args, spec) / job.name;
  write_scenario_run_folder(folder, outcome, {{"scenario.json", sweep_job_scenario_text(job)}},
                            /*sweep_job=*/true);
  std::cout << "scenario " << scenario.name << " -> " << folder.string() << "/\n";
  print_run_table(std::cout, outcome.report);
  return outcome.report.all_budgets_pass() && outcome.report.all_stable_or_expected()
             ? kSweepOk
             : kSweepBudgetFailed;
}

namespace {

// Every job loads and builds (renderers, ground truth) before any runs, so
// that a bad value in the last job stops the sweep before the first. The
// oracles (the costly part: a second or so on real meshes) depend only on
// the scene, the tool and the reference settings, so they are built once
// per distinct combination; most grids vary algorithm parameters or the
// coupling and share one.
// Checks every job's scenario as a run would; returns each job's scenario
// content hash, by job index.
std::vector<std::string> validate_jobs(const SweepSpec& spec, const std::vector<SweepJob>& jobs) {
  std::set<std::string> checked_ground_truth;
  std::vector<std::string> hashes(jobs.size());
  SweepErrors errors(spec.path);  // every job is checked: all errors at once
  for (const SweepJob& job : jobs) {
    try {
      const RunRequest request = sweep_job_request(job);
      Scenario scenario = read_scenario(request);
      hashes[job.index] = scenario.content_hash;
      std::string ground_truth_key;
      for (const char* key : {"scene", "tool", "reference"})
        ground_truth_key += job.scenario.contains(key) ? job.scenario[key].dump() : "-";
      if (!checked_ground_truth.insert(ground_truth_key).second)
        scenario.reference.switch_off_oracle();
      prepare_request(scenario, request);
    } catch (const InputError& error) {
      errors.add_for_job(job.name, error);
    }
  }
  errors.throw_if_any();
  return hashes;
}

// Staging folders an interrupted worker left beside a job's run folder
// (<job>.partial-<pid>, <job>.old-<pid>) whose lock no live process holds;
// only this shard's jobs are looked at, and only folders that carry
// hapticbench's ownership marker are removed.
void remove_stale_staging(const fs::path& out_dir, const std::vector<std::string>& job_names) {
  std::error_code error;
  if (!fs::is_directory(out_dir, error)) return;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(out_dir, error)) {
    const std::string file = entry.path().filename().string();
    for (const std::string& job : job_names)
      if (is_staging_sibling(file, job)) stale.push_back(entry.path());
  }
  for (const fs::path& path : stale) remove_abandoned_staging(path);
}

std::string last_lines(const std::string& text, std::size_t count) {
  std::size_t start = text.size();
  if (start > 0 && text[start - 1] == '\n') --start;
  for (std::size_t lines = 0; start > 0; --start)
    if (text[start - 1] == '\n' && ++lines == count) break;
  return text.substr(start);
}

}  // namespace

namespace {

// Which jobs of this shard to run and which an earlier invocation finished.
struct SweepPlan {
  std::vector<SweepJobState> states;  ///< by job index, as found on disk
  std::vector<std::size_t> to_run;    ///< job indices, in order
  std::size_t in_this_shard = 0, done_earlier = 0;
};

SweepPlan plan_sweep(const std::vector<SweepJob>& jobs,
                     const std::vector<std::string>& scenario_hashes, const SweepShard& shard,
                     const fs::path& out_dir) {
  SweepPlan plan;
  plan.states.resize(jobs.size());
  for (const SweepJob& job : jobs) {
    plan.states[job.index] = sweep_job_state_on_disk(out_dir / job.name);
    if (!in_shard(job.index, shard)) continue;
    ++plan.in_this_shard;
    // A finished run folder is this job's only when it ran this job's
    // scenario: another sweep into the same folder (another algorithm or
    // grid value under the same job name) is run again, not reused.
    if (fs::exists(out_dir / job.name / "summary.json") &&
        plan.states[job.index].scenario_hash == scenario_hashes[job.index]) {
      plan.states[job.index].done_earlier = true;
      ++plan.done_earlier;
    } else {
      plan.to_run.push_back(job.index);
    }
  }
  return plan;
}

// One worker process per job to run: this program, `sweep FILE --run-job I`.
std::vector<WorkerLaunch> worker_launches(const SweepRunOptions& args,
                                          const std::vector<std::size_t>& to_run,
                                          const fs::path& out_dir) {
  const std::string executable = this_executable().string();
  const std::string sweep_file = fs::absolute(args.sweep_file).lexically_normal().string();
  const std::string out_text = fs::absolute(out_dir).lexically_normal().string();
  std::vector<WorkerLaunch> launches;
  for (std::size_t index : to_run)
    launches.push_back(
        {{executable, "sweep", sweep_file, "--run-job", std::to_string(index), "--out", out_text}});
  return launches;
}

// How many jobs ended in each way, this invocation.
struct SweepTally {
  std::size_t ok = 0, budget_failed = 0, failed = 0, crashed = 0;
};

// A finished worker's job status from how it ended and whether it wrote its
// run folder; counted in `tally`.
void classify_worker_end(const WorkerResult& result, bool wrote_folder, SweepJobState& state,
                         SweepTally& tally) {
  if (result.end.exited && result.end.exit_code == kSweepOk && wrote_folder) {
    state.status = SweepJobStatus::kOk;
    ++tally.ok;
  } else if (result.end.exited && result.end.exit_code == kSweepBudgetFailed && wrote_folder) {
    state.status = SweepJobStatus::kBudgetFailed;
    ++tally.budget_failed;
  } else if (result.end.exited && result.end.exit_code == kSweepFailed) {
    // The worker said what went wrong (a full disk, a job's bad input).
    state.status = SweepJobStatus::kFailed;
    state.detail = "exit code 2, an error the worker named";
    ++tally.failed;
  } else {
    state.status = SweepJobStatus::kCrashed;
    state.detail = result.end.description() + (wrote_folder ? "" : ", no run folder written");
    ++tally.crashed;
  }
}

// Says how a job ended: the worker's run table, the end of its stderr when
// it went wrong, and the progress line.
void report_worker_end(const SweepJob& job, const SweepJobState& state, const WorkerResult& result,
                       bool terminal, SweepProgress& progress) {
  const bool went_wrong =
      state.status == SweepJobStatus::kCrashed || state.status == SweepJobStatus::kFailed;
  if (terminal) std::cerr << "\r\033[K" << std::flush;
  std::cout << result.stdout_text << std::flush;
  if (went_wrong && !result.stderr_text.empty())
    std::cerr << "job " << job.name << ": the worker's stderr, last lines:\n"
              << last_lines(result.stderr_text, 20) << "\n";
  const char* verdict = state.status == SweepJobStatus::kOk ? "ok"
                        : state.status == SweepJobStatus::kBudgetFailed
                            ? "budgets or stability failed"
                        : state.status == SweepJobStatus::kFailed ? "FAILED"
                                                                  : "CRASHED";
  progress.finished(
      job.name,
      went_wrong ? std::string(verdict) + " (" + state.detail + ")" : std::string(verdict),
      result.seconds, !went_wrong);
}

// The sweep's exit code: a crash, then a failure, then a failed budget in this shard.
int sweep_exit_code(const SweepTally& tally, const std::vector<SweepJob>& jobs,
                    const std::vector<SweepJobState>& states, const SweepShard& shard) {
  if (tally.crashed > 0) return kSweepCrashed;
  if (tally.failed > 0) return kSweepFailed;
  for (const SweepJob& job : jobs)
    if (in_shard(job.index, shard) && states[job.index].status == SweepJobStatus::kBudgetFailed)
      return kSweepBudgetFailed;
  return kSweepOk;
}

}  // namespace

int run_sweep(const SweepRunOptions& args) {
  const SweepSpec spec = load_sweep_spec(args.sweep_file);
  const std::vector<SweepJob> jobs = expand_sweep_jobs(spec);
  const std::vector<std::string> scenario_hashes = validate_jobs(spec, jobs);

  const SweepShard shard = args.shard.value_or(SweepShard{});
  const fs::path out_dir = output_folder(args, spec);
  create_output_container(out_dir);
  require_replaceable_file(out_dir / "sweep.json", "sweep index", is_sweep_index_file);
  require_replaceable_file(out_dir / "sweep.md", "sweep table", is_sweep_table_file);

  SweepPlan plan = plan_sweep(jobs, scenario_hashes, shard, out_dir);
  std::vector<SweepJobState>& states = plan.states;
  const std::vector<std::size_t>& to_run = plan.to_run;
  // Nothing is written unless every job folder to write may be written.
  for (std::size_t index : to_run)
    require_replaceable_folder(out_dir / jobs[index].name, OutputFolderKind::kRun);
  std::vector<bool> ran_here(jobs.size(), false);
  // Jobs this invocation does not run (other shards') are read back from
  // their run folders at the start and at the end, not after every job.
  auto write_index = [&](bool reread_others) {
    if (reread_others)
      for (const SweepJob& job : jobs)
        if (!ran_here[job.index] && !states[job.index].done_earlier)
          states[job.index] = sweep_job_state_on_disk(out_dir / job.name);
    write_sweep_index(out_dir, sweep_index_json(spec, jobs, states, shard));
  };
  write_index(false);

  std::cerr << "sweep " << spec.name << ": " << jobs.size() << " jobs";
  if (shard.count > 1)
    std::cerr << ", shard " << shard_text(shard) << " has " << plan.in_this_shard;
  std::cerr << "; " << plan.done_earlier << " done earlier, " << to_run.size() << " to run, "
            << std::min(args.jobs, std::max<std::size_t>(to_run.size(), 1)) << " at a time -> "
            << out_dir.string() << "/\n";

  std::vector<std::string> names;
  for (std::size_t index : to_run) names.push_back(jobs[index].name);
  remove_stale_staging(out_dir, names);

  const bool terminal = args.progress == ProgressStyle::kBar;
  std::ostream silent(nullptr);  // --progress none: everything written is dropped
  SweepProgress progress(args.progress == ProgressStyle::kNone ? silent : std::cerr, to_run.size(),
                         terminal, terminal_width());
  SweepTally tally;
  WorkerCallbacks callbacks;
  callbacks.on_start = [&](std::size_t launch) { progress.started(names[launch]); };
  callbacks.on_wait = [&] { progress.refresh(); };
  callbacks.on_finish = [&](std::size_t launch, const WorkerResult& result) {
    const SweepJob& job = jobs[to_run[launch]];
    ran_here[job.index] = true;
    const bool wrote_folder = fs::exists(out_dir / job.name / "summary.json");
    classify_worker_end(result, wrote_folder, states[job.index], tally);
    report_worker_end(job, states[job.index], result, terminal, progress);
    write_index(false);
  };
  {
    const ScratchFolder scratch("hapticbench-sweep");
    run_worker_processes(worker_launches(args, to_run, out_dir), args.jobs, scratch.path(),
                         callbacks);
  }
  progress.close();
  write_index(true);
  const std::vector<SweepTableRow> table = sweep_table_rows(spec, jobs, states, out_dir);
  print_sweep_table(std::cout, spec, table);
  write_file_replacing(out_dir / "sweep.md", sweep_table_markdown(spec, table));

  std::cout << "sweep " << spec.name << " -> " << out_dir.string()
            << "/sweep.json: " << to_run.size() << " ran (" << tally.ok << " ok, "
            << tally.budget_failed << " failed a budget or the stability verdict, " << tally.failed
            << " failed, " << tally.crashed << " crashed), " << plan.done_earlier
            << " done earlier\n";
  return sweep_exit_code(tally, jobs, states, shard);
}

}  // namespace hb
