// End-to-end: a run or sweep stopped by a real SIGINT or SIGTERM exits with
// 128 + the signal, says so, and leaves no half-written folder; finished
// sweep jobs are kept and a second sweep runs only what is missing.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

extern char** environ;

namespace {

using hb::test::write_file;

namespace fs = std::filesystem;
using hb::test::ScratchDir;

// A press scenario whose trace lasts `duration_s` (long enough to be
// stopped while it runs).
std::string press_scenario(double duration_s) {
  return R"({
  "name": "long_press",
  "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] }, "pose": { "p": [0, 0, -0.01] } } ],
  "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 2 }, "density": 1000 },
  "trace": { "generator": "press", "duration_s": )" +
         std::to_string(duration_s) + R"(, "seed": 1,
             "params": { "start": [0, 0, 0.03], "axis": [0, 0, -1], "surface_distance": 0.01, "depth": 0.005 } },
  "coupling": { "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 },
  "algorithms": [
    { "name": "coupling_only", "params": { "integrator": "implicit_euler" } },
    { "name": "penalty_analytic", "label": "penalty", "params": { "proxy": "quasi_static" } }
  ]
})";
}

// hapticbench ARGS started in `work`, stderr to work/stderr.txt.
struct Started {
  pid_t pid = -1;
};

Started start(const std::vector<std::string>& args, const fs::path& work) {
  std::vector<std::string> argv = {hb::test::hapticbench_bin()};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> raw;
  for (std::string& arg : argv) raw.push_back(arg.data());
  raw.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, work.c_str());
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, (work / "stdout.txt").c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, (work / "stderr.txt").c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  // A process group of its own, as a job a shell starts: a signal to the
  // group (a terminal's Ctrl-C) reaches it and what it starts, not this test.
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setpgroup(&attributes, 0);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  Started started;
  const int error = posix_spawn(&started.pid, raw[0], &actions, &attributes, raw.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  REQUIRE(error == 0);
  return started;
}

int exit_code_of(pid_t pid) {
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 1000 + WTERMSIG(status);
}

// Names in `folder` (files and folders), but the runner's own output files.
std::vector<std::string> entries(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name != "stdout.txt" && name != "stderr.txt") names.push_back(name);
  }
  return names;
}

bool wait_for(const std::function<bool()>& condition, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return condition();
}

TEST_CASE("SIGINT during a run: exit 130, a message, and no run folder or staging folder") {
  const ScratchDir work("interrupt_run");
  write_file(work.path() / "long.json", press_scenario(600));
  const Started run = start({"run", "long.json", "--out", "out"}, work.path());
  // Stopped a second in: loading or replaying (the run takes far longer);
  // either way the signal is honoured at the next tick of a replay.
  std::this_thread::sleep_for(std::chrono::seconds(1));
  REQUIRE(kill(run.pid, SIGINT) == 0);
  CHECK(exit_code_of(run.pid) == 128 + SIGINT);
  const std::string err = hb::test::read_text_file(work.path() / "stderr.txt");
  INFO(err);
  CHECK(err.find("interrupted") != std::string::npos);
  CHECK(entries(work.path()) == std::vector<std::string>{"long.json"});
}

// Signals the run once `stage` shows in `err`, and checks that it
// ends within moments with the signal's exit code and says so.
void check_stopped_in_stage(const Started& run, const fs::path& err, const std::string& stage) {
  REQUIRE(wait_for([&] { return hb::test::read_text_file(err).find(stage) != std::string::npos; },
                   600));
  REQUIRE(kill(run.pid, SIGTERM) == 0);
  int status = 0;
  const bool ended = wait_for([&] { return waitpid(run.pid, &status, WNOHANG) == run.pid; }, 10);
  if (!ended) {
    kill(run.pid, SIGKILL);
    waitpid(run.pid, &status, 0);
  }
  INFO(hb::test::read_text_file(err));
  CHECK(ended);
  CHECK((WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGTERM));
  CHECK(hb::test::read_text_file(err).find("interrupted") != std::string::npos);
}

TEST_CASE("SIGTERM during a voxmap build ends it within moments") {
  // A cold cache and a 0.1 mm voxmap of the bunny around the armadillo:
  // some 90 s and 5 GB uninterrupted. Most of it is OpenVDB's narrow-band
  // expansion, which polls no interrupter; the mesh adapter's stop check
  // ends it (a few seconds at most, for the leaf merge under way).
  const ScratchDir work("interrupt_voxmap");
  const fs::path models = fs::path(HAPTICBENCH_SOURCE_DIR) / "models";
  write_file(work.path() / "fine_voxmap.json", R"({
    "name": "fine_voxmap",
    "scene": [ { "mesh": ")" + (models / "bunny00.off").string() +
                                                   R"(", "scale": 0.3 } ],
    "tool": { "mesh": ")" + (models / "armadillo.off").string() +
                                                   R"(", "scale": 0.0003305,
              "density": 1000 },
    "trace": { "generator": "rest", "duration_s": 0.01, "params": { "p": [0, 0, 0.02] } },
    "algorithms": [ { "name": "voxmap_pointshell",
                      "params": { "voxel_size": 0.0001, "pointshell_spacing": 0.002 } } ] })");
  ::setenv("HAPTICBENCH_CACHE_DIR", (work.path() / "cache").c_str(), 1);
  const Started run = start({"validate", "fine_voxmap.json", "--progress", "plain"}, work.path());
  ::unsetenv("HAPTICBENCH_CACHE_DIR");
  check_stopped_in_stage(run, work.path() / "stderr.txt", "voxmap: building");
}

TEST_CASE("SIGTERM during a convex hierarchy build ends it within moments") {
  // A cold cache: armadillo_on_bunny builds the sensation-preserving
  // hierarchies of the armadillo and of the bunny (75k triangles, some 18 s
  // here); the signal comes once the bunny's build has run for a second.
  // A build that ignored it ran to its end (114 s for 50k triangles once).
  const ScratchDir work("interrupt_hierarchy");
  const fs::path scenario =
      fs::path(HAPTICBENCH_SOURCE_DIR) / "scenarios/meshes/armadillo_on_bunny.json";
  ::setenv("HAPTICBENCH_CACHE_DIR", (work.path() / "cache").c_str(), 1);
  const Started run = start({"validate", scenario.string(), "--progress", "plain"}, work.path());
  ::unsetenv("HAPTICBENCH_CACHE_DIR");
  check_stopped_in_stage(run, work.path() / "stderr.txt",
                         "convex hierarchy of bunny00.off: building");
}

// A free-space rub of `duration_s` above a box, with the analytic
// reference off: the mesh force reference follows every tick.
std::string free_space_mesh_reference_scenario(double duration_s) {
  return R"({
  "name": "free_space",
  "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] }, "pose": { "p": [0, 0, -0.01] } } ],
  "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 2 }, "density": 1000 },
  "trace": { "generator": "rub", "duration_s": )" +
         std::to_string(duration_s) + R"(, "seed": 1,
             "params": { "centre": [0, 0, 0.5], "surface_distance": 0.01, "depth": 0.004, "radius": 0.02, "turns": 100 } },
  "coupling": { "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 },
  "algorithms": [ { "name": "coupling_only" } ],
  "reference": { "oracle": "none", "analytic": "none" }
})";
}

TEST_CASE("a stop signal during the mesh force reference ends it there, in run and validate") {
  // The reference of an hour's trace takes minutes; it once polled no
  // signal: run stopped only when it was done (48 s late), and validate
  // printed OK. Stopped in the phase, it leaves no cache file behind.
  for (const char* command : {"run", "validate"}) {
    SECTION(command) {
      const ScratchDir work("interrupt_force_reference");
      write_file(work.path() / "long.json", free_space_mesh_reference_scenario(3600));
      ::setenv("HAPTICBENCH_CACHE_DIR", (work.path() / "cache").c_str(), 1);
      const Started run = start({command, "long.json", "--progress", "plain"}, work.path());
      ::unsetenv("HAPTICBENCH_CACHE_DIR");
      check_stopped_in_stage(run, work.path() / "stderr.txt", "force reference");
      const std::string out = hb::test::read_text_file(work.path() / "stdout.txt");
      CHECK(out.find("OK") == std::string::npos);
      bool cached = false;
      if (fs::exists(work.path() / "cache"))
        for (const auto& entry : fs::directory_iterator(work.path() / "cache"))
          cached = cached || entry.path().filename().string().rfind("force_reference", 0) == 0;
      CHECK_FALSE(cached);
      CHECK_FALSE(fs::exists(work.path() / "out"));
    }
  }
}

TEST_CASE("report stops its renderer on a stop signal: no page, no traceback, 128 + the signal") {
  // A renderer that takes its time; it would leave a mark had it finished.
  const ScratchDir work("interrupt_report");
  write_file(work.path() / "renderer" / "render_report.py",
             "import time\ntime.sleep(30)\nopen('finished.txt', 'w').write('done')\n");
  write_file(work.path() / "long.json", press_scenario(0.2));
  REQUIRE(std::system(("cd '" + work.path().string() + "' && '" + hb::test::hapticbench_bin() +
                       "' run long.json --out run --quiet > /dev/null 2>&1")
                          .c_str()) == 0);
  ::setenv("HAPTICBENCH_REPORTS_DIR", (work.path() / "renderer").c_str(), 1);
  for (const int signal : {SIGTERM, SIGINT}) {
    CAPTURE(signal);
    const Started report = start({"report", "run", "--out", "r.html"}, work.path());
    // Once the renderer runs (a second is ample for hapticbench's checks).
    std::this_thread::sleep_for(std::chrono::seconds(1));
    // To the process alone, as `timeout` sends it; SIGINT to its process
    // group, as a terminal's Ctrl-C does.
    REQUIRE(kill(signal == SIGINT ? -report.pid : report.pid, signal) == 0);
    CHECK(exit_code_of(report.pid) == 128 + signal);
    const std::string err = hb::test::read_text_file(work.path() / "stderr.txt");
    INFO(err);
    CHECK(err.find("Traceback") == std::string::npos);
    CHECK_FALSE(fs::exists(work.path() / "r.html"));
    CHECK_FALSE(fs::exists(work.path() / "finished.txt"));
    for (const auto& entry : fs::directory_iterator(work.path()))
      CHECK(entry.path().filename().string().find(".tmp-") == std::string::npos);
  }
  ::unsetenv("HAPTICBENCH_REPORTS_DIR");
}

TEST_CASE("a stability search stopped midway keeps the runs that finished") {
  // Eleven runs of a 20 s press; stopped after the second finished.
  const ScratchDir work("interrupt_stability");
  write_file(work.path() / "long.json", press_scenario(20));
  const Started search = start({"stability", "long.json", "--label", "penalty", "--param",
                                "/coupling/k_t", "--range", "100", "100000", "--out", "out"},
                               work.path());
  const fs::path err = work.path() / "stderr.txt";
  const auto finished_runs = [&] {
    const std::string text = hb::test::read_text_file(err);
    std::size_t count = 0;
    for (std::size_t at = text.find("stability: /coupling/k_t"); at != std::string::npos;
         at = text.find("stability: /coupling/k_t", at + 1))
      ++count;
    return count;
  };
  REQUIRE(wait_for([&] { return finished_runs() >= 2; }, 120));
  REQUIRE(kill(search.pid, SIGTERM) == 0);
  CHECK(exit_code_of(search.pid) == 128 + SIGTERM);
  INFO(hb::test::read_text_file(err));
  CHECK_FALSE(
      fs::exists(work.path() / "out/stability.json"));  // no verdict: the search did not end
  const fs::path partial = work.path() / "out/stability.partial.json";
  REQUIRE(fs::exists(partial));
  const std::string kept = hb::test::read_text_file(partial);
  CHECK(kept.find("\"interrupted\": true") != std::string::npos);
  CHECK(kept.find("\"param\": \"/coupling/k_t\"") != std::string::npos);
  CHECK(kept.find("\"runs\": [") != std::string::npos);
}

TEST_CASE("SIGTERM during a sweep keeps finished jobs, and the next sweep runs only the rest") {
  const ScratchDir work("interrupt_sweep");
  write_file(work.path() / "scenarios" / "long.json", press_scenario(40));
  write_file(work.path() / "sweeps" / "grid.json", R"({
    "name": "grid",
    "scenarios": ["../scenarios/long.json"],
    "grid": { "/coupling/k_t": [1000, 1500, 2000, 2500] }
  })");
  const fs::path out = work.path() / "sweeps" / "out";
  const Started sweep =
      start({"sweep", "sweeps/grid.json", "--jobs", "1", "--out", "sweeps/out"}, work.path());
  auto finished_jobs = [&] {
    std::size_t count = 0;
    if (fs::exists(out))
      for (const auto& entry : fs::directory_iterator(out))
        if (fs::exists(entry.path() / "summary.json")) ++count;
    return count;
  };
  const bool one_finished = wait_for([&] { return finished_jobs() >= 1; }, 120);
  INFO(hb::test::read_text_file(work.path() / "stderr.txt"));
  REQUIRE(one_finished);
  REQUIRE(kill(sweep.pid, SIGTERM) == 0);
  CHECK(exit_code_of(sweep.pid) == 128 + SIGTERM);
  const std::size_t kept = finished_jobs();
  CHECK(kept >= 1);
  CHECK(kept < 4);
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    INFO(name);
    CHECK(name.find(".partial-") == std::string::npos);  // no half-written job folder
  }

  const hb::test::CommandResult again =
      hb::test::run_hapticbench("sweep sweeps/grid.json --jobs 1 --out sweeps/out", work.path());
  INFO(again.stderr_text);
  CHECK(again.exit_code == 0);
  CHECK(again.stderr_text.find(std::to_string(kept) + " done earlier, " + std::to_string(4 - kept) +
                               " to run") != std::string::npos);
  CHECK(finished_jobs() == 4);
}

}  // namespace
