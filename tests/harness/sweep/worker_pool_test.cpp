// Worker processes: exit codes and signals told apart, output captured,
// never more than N at a time.
#include "harness/sweep/worker_pool.h"

#include <catch2/catch.hpp>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/scratch_dir.h"

namespace {

namespace fs = std::filesystem;

hb::WorkerLaunch shell(const std::string& script) { return {{"/bin/sh", "-c", script}}; }

}  // namespace

TEST_CASE("a worker's end is its exit code, or the signal that killed it") {
  const hb::test::ScratchDir scratch("worker_pool_ends");
  const fs::path& dir = scratch.path();
  const std::vector<hb::WorkerResult> results = hb::run_worker_processes(
      {shell("exit 0"), shell("exit 3"), shell("kill -SEGV $$"), shell("echo out; echo err >&2")},
      2, dir, {});
  REQUIRE(results.size() == 4);
  CHECK(results[0].end.exited);
  CHECK(results[0].end.exit_code == 0);
  CHECK(results[1].end.exited);
  CHECK(results[1].end.exit_code == 3);
  CHECK(results[1].end.description() == "exit code 3");
  CHECK_FALSE(results[2].end.exited);
  CHECK(results[2].end.signal == SIGSEGV);
  CHECK(results[2].end.description().find("signal 11") != std::string::npos);
  CHECK(results[3].stdout_text == "out\n");
  CHECK(results[3].stderr_text == "err\n");
  CHECK(fs::is_empty(dir));  // captured output files are removed
}

TEST_CASE("no more than N workers run at a time, and results come in launch order") {
  const hb::test::ScratchDir scratch("worker_pool_limit");
  const fs::path& dir = scratch.path();
  const fs::path running = dir / "running";
  fs::create_directories(running);
  // Each worker marks itself running, counts the marks it sees, unmarks.
  std::vector<hb::WorkerLaunch> launches;
  for (int i = 0; i < 6; ++i)
    launches.push_back(shell("touch '" + running.string() + "/" + std::to_string(i) +
                             "'; sleep 0.05; ls '" + running.string() + "' | wc -l; rm '" +
                             running.string() + "/" + std::to_string(i) + "'; echo " +
                             std::to_string(i)));
  std::vector<std::size_t> started, finished;
  hb::WorkerCallbacks callbacks;
  callbacks.on_start = [&](std::size_t i) { started.push_back(i); };
  callbacks.on_finish = [&](std::size_t i, const hb::WorkerResult&) { finished.push_back(i); };
  const std::vector<hb::WorkerResult> results =
      hb::run_worker_processes(launches, 2, dir, callbacks);
  REQUIRE(results.size() == 6);
  CHECK(started == std::vector<std::size_t>{0, 1, 2, 3, 4, 5});
  CHECK(finished.size() == 6);
  for (int i = 0; i < 6; ++i) {
    INFO("worker " << i);
    std::istringstream lines(results[i].stdout_text);
    int seen_running = 0, index = -1;
    lines >> seen_running >> index;
    CHECK(seen_running >= 1);
    CHECK(seen_running <= 2);
    CHECK(index == i);
  }
}

TEST_CASE("a program that cannot start is an error, not a silent success") {
  const hb::test::ScratchDir scratch("worker_pool_missing");
  const fs::path& dir = scratch.path();
  CHECK_THROWS_AS(hb::run_worker_processes({{{"/nonexistent/program"}}}, 1, dir, {}),
                  std::runtime_error);
}
