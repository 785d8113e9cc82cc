// End-to-end: scripts/slurm-sweep on a one-node Slurm cluster of this
// machine (scripts/local-slurm, with a state dir and ports of its own). An
// 8-job sweep in 4 shards; shard 1 is cancelled while it runs, which leaves
// no staging folder; running the same command again completes only what is
// missing, and the result has the ticks of a local `hapticbench sweep` bit
// for bit, reads with `report` and `compare`. Needs root and Debian's
// slurm-wlm and munge (scripts/setup): a cluster that does not start fails
// the test with local-slurm's reason. Runs alone (RUN_SERIAL): the tasks
// take both cores.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::kSource;

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

const fs::path kSweep = kSource / "tests/end_to_end/data/slurm_sweep.json";
constexpr int kJobs = 8;
constexpr int kShards = 4;
// Away from local-slurm's defaults (16817/16818), so that a cluster someone
// started by hand keeps running beside the test's.
constexpr const char* kPorts = "HB_SLURM_CTLD_PORT=16917 HB_SLURM_SLURMD_PORT=16918";

std::string quoted(const fs::path& path) {
  std::string text = "'";
  text += path.string();
  text += '\'';
  return text;
}

// Runs a shell command in `work` with the cluster's environment (and
// slurm-sweep polling squeue every 0.5 s).
hb::test::CommandResult cluster_shell(const std::string& command, const fs::path& state,
                                      const fs::path& work) {
  const fs::path out = work / "shell_stdout.txt", err = work / "shell_stderr.txt";
  const std::string line = "cd " + quoted(work) + " && export " + kPorts +
                           " HB_SLURM_POLL=0.5 SLURM_CONF=" + quoted(state / "slurm.conf") +
                           " && (" + command + ") > " + quoted(out) + " 2> " + quoted(err);
  const int status = std::system(line.c_str());
  hb::test::CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.stdout_text = hb::test::read_text_file(out);
  result.stderr_text = hb::test::read_text_file(err);
  return result;
}

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \n\t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \n\t") - first + 1);
}

// Stops the cluster whatever happens to the checks (declared after the
// scratch folder holding its state, so it runs before that is removed).
class ClusterGuard {
 public:
  ClusterGuard(fs::path state, fs::path work) : state_(std::move(state)), work_(std::move(work)) {}
  ~ClusterGuard() {
    cluster_shell(quoted(kSource / "scripts/local-slurm") + " stop --clean " + quoted(state_),
                  state_, work_);
  }
  ClusterGuard(const ClusterGuard&) = delete;
  ClusterGuard& operator=(const ClusterGuard&) = delete;

 private:
  fs::path state_, work_;
};

// Polls `command` (every 0.1 s) until `done` says its stdout is what it
// waits for or `seconds` pass; returns the last stdout.
template <typename Done>
std::string poll(const std::string& command, const fs::path& state, const fs::path& work,
                 double seconds, Done done) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  std::string last;
  for (;;) {
    last = trimmed(cluster_shell(command, state, work).stdout_text);
    if (done(last) || Clock::now() > until) return last;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

// Job name -> (run label -> ticks hash), for every run folder of `out`.
std::map<std::string, std::map<std::string, std::string>> ticks_hashes_by_job(const fs::path& out) {
  std::map<std::string, std::map<std::string, std::string>> hashes;
  for (const auto& entry : fs::directory_iterator(out)) {
    const fs::path summary_file = entry.path() / "summary.json";
    if (!entry.is_directory() || !fs::exists(summary_file)) continue;
    const json summary = json::parse(hb::test::read_text_file(summary_file));
    auto& runs = hashes[entry.path().filename().string()];
    for (const json& run : summary.at("runs"))
      runs[run.at("label").get<std::string>()] =
          run.at("determinism").at("ticks_hash").get<std::string>();
  }
  return hashes;
}

// The jobs of shard I of N, by DIR/sweep.json's index (index % N == I),
// split into those with a run folder and those without.
std::pair<int, int> shard_jobs_done(const fs::path& out, int shard) {
  const json index = json::parse(hb::test::read_text_file(out / "sweep.json"));
  int done = 0, missing = 0;
  for (const json& job : index.at("jobs"))
    if (job.at("index").get<int>() % kShards == shard)
      (fs::exists(out / job.at("name").get<std::string>() / "summary.json") ? done : missing)++;
  return {done, missing};
}

std::set<std::string> staging_folders(const fs::path& out) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".partial-") != std::string::npos || name.find(".old-") != std::string::npos)
      names.insert(name);
  }
  return names;
}

}  // namespace

TEST_CASE("a sweep on a local Slurm cluster survives a cancelled shard and matches a local sweep") {
  const hb::test::ScratchDir work_dir("e2e_slurm_sweep");
  const fs::path& work = work_dir.path();
  const fs::path state = work / "cluster", out = work / "slurm_out", local = work / "local_out";
  const ClusterGuard guard(state, work);
  const std::string local_slurm = quoted(kSource / "scripts/local-slurm");

  const hb::test::CommandResult start =
      cluster_shell(local_slurm + " start " + quoted(state), state, work);
  if (start.exit_code != 0)
    FAIL("the local Slurm cluster did not start (scripts/local-slurm start, exit "
         << start.exit_code << "):\n"
         << start.stderr_text);
  REQUIRE(start.stdout_text.find("export SLURM_CONF=" + (state / "slurm.conf").string()) !=
          std::string::npos);

  const std::string sweep_command = quoted(kSource / "scripts/slurm-sweep") + " " + quoted(kSweep) +
                                    " --shards " + std::to_string(kShards) + " --out " +
                                    quoted(out) + " --hapticbench '" + hb::test::hapticbench_bin() +
                                    "'";
  const hb::test::CommandResult submitted =
      cluster_shell(sweep_command + " --no-wait", state, work);
  INFO(submitted.stderr_text);
  REQUIRE(submitted.exit_code == 0);
  const std::string job = trimmed(submitted.stdout_text);
  REQUIRE(!job.empty());
  REQUIRE(job.find_first_not_of("0123456789") == std::string::npos);

  // Cancel shard 1 in its first job: once it runs and hapticbench has
  // loaded its two jobs ("2 to run" in its log), which take seconds each.
  const std::string shard1 = job + "_1";
  const std::string shard1_state =
      poll("squeue -h -j " + shard1 + " -o %T", state, work, 60, [](const std::string& s) {
        // "" is a transient no-answer too: poll on.
        return !s.empty() && s != "PENDING";
      });
  INFO("shard 1 was " << (shard1_state.empty() ? "not answered for" : shard1_state)
                      << " when polled");
  const fs::path shard1_log = out / "slurm" / (shard1 + ".out");
  bool started = false;
  if (shard1_state == "RUNNING") {
    for (const auto until = Clock::now() + std::chrono::seconds(10);;) {
      started = hb::test::read_text_file(shard1_log).find("2 to run") != std::string::npos;
      if (started || Clock::now() > until) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    const hb::test::CommandResult cancel = cluster_shell("scancel " + shard1, state, work);
    INFO(cancel.stderr_text);
    REQUIRE(cancel.exit_code == 0);
  } else {
    WARN("shard 1 was not seen running (" << shard1_state << "): nothing cancelled");
  }

  // The whole array ends: shards 0, 2 and 3 complete, shard 1 was cancelled.
  const std::string left = poll("squeue -h -j " + job + " -o %i", state, work, 90,
                                [](const std::string& s) { return s.empty(); });
  INFO("still queued: " << left);
  REQUIRE(left.empty());
  CHECK(staging_folders(out) == std::set<std::string>{});
  for (int shard : {0, 2, 3}) {
    INFO("shard " << shard);
    const auto [done, missing] = shard_jobs_done(out, shard);
    CHECK(done == 2);
    CHECK(missing == 0);
  }
  const auto [done_before, missing_before] = shard_jobs_done(out, 1);
  CHECK(done_before + missing_before == 2);
  const std::string shard1_said = hb::test::read_text_file(shard1_log);
  INFO("shard 1's log:\n" << shard1_said);
  if (missing_before > 0) CHECK(shard1_said.find("CANCELLED") != std::string::npos);
  if (missing_before == 2 && started)
    WARN("the cancel landed in shard 1's first job: both of its jobs missing");
  if (missing_before == 2 && !started)
    WARN("the cancel landed before hapticbench had loaded shard 1's jobs: both missing");
  if (missing_before == 1) WARN("the cancel landed in shard 1's second job: one job missing");
  if (missing_before == 0) WARN("shard 1 finished before the cancel: nothing to resubmit");

  // The same command again submits only shard 1 and waits for it.
  const hb::test::CommandResult resumed =
      cluster_shell("timeout 120 " + sweep_command, state, work);
  INFO(resumed.stderr_text);
  REQUIRE(resumed.exit_code == 0);
  if (missing_before > 0)
    CHECK(resumed.stderr_text.find("shards 1 (the shards with jobs still missing) of 4") !=
          std::string::npos);
  else
    CHECK(resumed.stderr_text.find("nothing to submit") != std::string::npos);
  CHECK(staging_folders(out) == std::set<std::string>{});

  // The same sweep on this machine, one job at a time: the same run folders
  // with the same ticks.
  const hb::test::CommandResult local_run =
      hb::test::run_hapticbench("sweep " + quoted(kSweep) + " --jobs 1 --out local_out", work);
  INFO(local_run.stderr_text);
  REQUIRE(local_run.exit_code == 0);
  const auto slurm_hashes = ticks_hashes_by_job(out), local_hashes = ticks_hashes_by_job(local);
  CHECK(slurm_hashes.size() == std::size_t(kJobs));
  CHECK(slurm_hashes == local_hashes);

  const hb::test::CommandResult report =
      hb::test::run_hapticbench("report slurm_out --out slurm_out/report.html", work);
  INFO(report.stderr_text);
  CHECK(report.exit_code == 0);
  CHECK(fs::exists(out / "report.html"));
  const hb::test::CommandResult compare =
      hb::test::run_hapticbench("compare local_out slurm_out", work);
  INFO(compare.stdout_text << compare.stderr_text);
  CHECK(compare.exit_code == 0);
}
