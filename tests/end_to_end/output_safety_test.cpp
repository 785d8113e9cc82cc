// End-to-end: no `--out` of any command destroys what hapticbench did not
// write. Each case puts something of the user's at the output path and
// checks the exit code (2), the message (names the path) and that the
// user's thing is untouched and nothing else was written.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::contains;
using hb::test::kBoxPress;
using hb::test::kPress;
using hb::test::kSource;
using hb::test::listing;
using hb::test::write_file;

namespace fs = std::filesystem;
using hb::test::CommandResult;
using hb::test::read_text_file;
using hb::test::run_hapticbench;
using hb::test::ScratchDir;

void check_refused_naming(const CommandResult& result, const std::string& path) {
  INFO(result.stdout_text << result.stderr_text);
  CHECK(result.exit_code == 2);
  CHECK(contains(result.stderr_text, path));
  CHECK(contains(result.stderr_text, "never replaces"));
}

TEST_CASE("run --out never replaces a folder, file, symlink or FIFO of the user's") {
  const ScratchDir work_dir("e2e_out_run");
  const fs::path& work = work_dir.path();
  fs::create_directory(work / "mine");
  write_file(work / "mine/precious.txt", "keep me");
  write_file(work / "file.csv", "a,b\n");
  fs::create_directory_symlink(work / "mine", work / "link");
  REQUIRE(::mkfifo((work / "fifo").c_str(), 0600) == 0);
  const std::set<std::string> before = listing(work);

  for (const char* out : {"mine", "file.csv", "link", "fifo"}) {
    INFO(out);
    check_refused_naming(run_hapticbench("run " + kPress + " --out " + out, work), out);
  }
  CHECK(listing(work) == before);
  CHECK(read_text_file(work / "mine/precious.txt") == "keep me");
  CHECK(listing(work / "mine") == std::set<std::string>{"precious.txt"});
  CHECK(read_text_file(work / "file.csv") == "a,b\n");
  CHECK(fs::is_symlink(work / "link"));
  CHECK(fs::is_fifo(work / "fifo"));
}

TEST_CASE("run --out onto a device node leaves the device in place") {
  if (::geteuid() != 0) {
    SUCCEED("creating a device node needs root; not checked here");
    return;
  }
  const ScratchDir work_dir("e2e_out_device");
  const fs::path& work = work_dir.path();
  // A second name for /dev/null (character device 1:3), inside the scratch folder.
  if (::mknod((work / "null").c_str(), S_IFCHR | 0600, makedev(1, 3)) != 0) return;
  check_refused_naming(run_hapticbench("run " + kPress + " --out null", work), "null");
  CHECK(fs::is_character_file(work / "null"));
}

TEST_CASE("run replaces its own earlier run folder, and says so") {
  const ScratchDir work_dir("e2e_out_rerun");
  const fs::path& work = work_dir.path();
  fs::create_directory(work / "empty");
  const CommandResult first = run_hapticbench("run " + kPress + " --out empty", work);
  INFO(first.stderr_text);
  REQUIRE(first.exit_code == 0);
  CHECK_FALSE(contains(first.stdout_text, "replaced"));
  const CommandResult second = run_hapticbench("run " + kPress + " --out empty", work);
  REQUIRE(second.exit_code == 0);
  CHECK(contains(second.stdout_text, "replaced the earlier run folder"));
  CHECK(fs::exists(work / "empty/summary.json"));

  // Once the user keeps a file of theirs in it, it is theirs.
  write_file(work / "empty/notes.txt", "analysis");
  check_refused_naming(run_hapticbench("run " + kPress + " --out empty", work), "empty");
  CHECK(read_text_file(work / "empty/notes.txt") == "analysis");
}

TEST_CASE("several scenarios: one folder in the way stops every run before any is written") {
  const ScratchDir work_dir("e2e_out_several");
  const fs::path& work = work_dir.path();
  fs::create_directories(work / "runs/box_press_box");
  write_file(work / "runs/box_press_box/precious.txt", "keep me");
  check_refused_naming(run_hapticbench("run " + kPress + " " + kBoxPress + " --out runs", work),
                       "runs/box_press_box");
  CHECK(listing(work / "runs") == std::set<std::string>{"box_press_box"});
  CHECK(listing(work / "runs/box_press_box") == std::set<std::string>{"precious.txt"});

  write_file(work / "a_file", "x");
  const CommandResult into_file =
      run_hapticbench("run " + kPress + " " + kBoxPress + " --out a_file", work);
  CHECK(into_file.exit_code == 2);
  CHECK(contains(into_file.stderr_text, "a_file"));
  CHECK(read_text_file(work / "a_file") == "x");
}

TEST_CASE(
    "generate never overwrites what it did not generate, nor its own trace with the sidecar") {
  const ScratchDir work_dir("e2e_out_generate");
  const fs::path& work = work_dir.path();
  const std::string generate = "generate press --duration 0.1 --out ";

  const CommandResult json_name = run_hapticbench(generate + "t.json", work);
  CHECK(json_name.exit_code == 2);
  CHECK(contains(json_name.stderr_text, "t.json"));
  CHECK(listing(work).empty());

  write_file(work / "recorded.csv", "t_ns,px,py,pz,qw,qx,qy,qz\n");
  check_refused_naming(run_hapticbench(generate + "recorded.csv", work), "recorded.csv");
  CHECK(read_text_file(work / "recorded.csv") == "t_ns,px,py,pz,qw,qx,qy,qz\n");
  CHECK_FALSE(fs::exists(work / "recorded.json"));

  write_file(work / "other.json", "{\"mine\": true}");
  check_refused_naming(run_hapticbench(generate + "other.csv", work), "other.json");
  CHECK(read_text_file(work / "other.json") == "{\"mine\": true}");
  CHECK_FALSE(fs::exists(work / "other.csv"));

  CHECK(run_hapticbench(generate + "gen.csv", work).exit_code == 0);
  CHECK(run_hapticbench("generate press --duration 0.2 --out gen.csv", work).exit_code == 0);
  CHECK(contains(read_text_file(work / "gen.json"), "\"samples\": 201"));
  // Edited by hand, it is no longer what generate wrote.
  write_file(work / "gen.csv", read_text_file(work / "gen.csv") + "\n");
  check_refused_naming(run_hapticbench(generate + "gen.csv", work), "gen.csv");
}

TEST_CASE("export and generate write through temporary names of their own, never a neighbour's") {
  // Names the writers once used for their temporary files, taken by the
  // user: a file of theirs, and a symlink to another of theirs.
  const ScratchDir work_dir("e2e_out_neighbours");
  const fs::path& work = work_dir.path();
  REQUIRE(run_hapticbench("run " + kPress + " --out run", work).exit_code == 0);
  write_file(work / "victim.txt", "precious");
  write_file(work / "bench.json.partial", "mine");
  fs::create_symlink("victim.txt", work / "other.json.partial");
  write_file(work / "t.csv.tmp", "mine too");
  fs::create_symlink("victim.txt", work / "t.json.tmp");
  const std::set<std::string> before = listing(work);

  CHECK(run_hapticbench("export --format gbench run --out bench.json", work).exit_code == 0);
  CHECK(run_hapticbench("export --format gbench run --out other.json", work).exit_code == 0);
  CHECK(run_hapticbench("generate press --duration 0.1 --out t.csv", work).exit_code == 0);

  CHECK(read_text_file(work / "bench.json.partial") == "mine");
  CHECK(read_text_file(work / "t.csv.tmp") == "mine too");
  CHECK(fs::is_symlink(work / "other.json.partial"));
  CHECK(fs::is_symlink(work / "t.json.tmp"));
  CHECK(read_text_file(work / "victim.txt") == "precious");
  CHECK(contains(read_text_file(work / "bench.json"), "\"benchmarks\""));
  CHECK(contains(read_text_file(work / "t.json"), "\"samples\": 101"));
  // Nothing else: the outputs, and no temporary file left behind.
  std::set<std::string> expected = before;
  expected.insert({"bench.json", "other.json", "t.csv", "t.json"});
  CHECK(listing(work) == expected);
}

// Holds an exclusive flock on <folder>/.hapticbench-lock while it lives, as
// a live hapticbench process does on the folders it works in.
struct HeldLock {
  explicit HeldLock(const fs::path& folder)
      : fd(::open((folder / ".hapticbench-lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600)) {
    REQUIRE(fd >= 0);
    REQUIRE(::flock(fd, LOCK_EX) == 0);
  }
  ~HeldLock() { ::close(fd); }
  int fd;
};

TEST_CASE("the next run removes what a killed run left, and nothing a live run holds") {
  // As SIGKILL leaves them: with hapticbench's markers and an unlocked lock
  // file, named after a process id that does not exist here (99999999 is
  // above any pid_max). The "live" ones are named the same way but their
  // lock is held, as by a run in another PID namespace (a container
  // sharing /tmp), where every id looks gone. A folder of the same form
  // without a marker is someone else's and stays.
  const ScratchDir work_dir("e2e_out_stale");
  const fs::path& work = work_dir.path();
  fs::create_directories(work / "tmp");
  const auto staging_at = [&](const std::string& name) {
    const fs::path staging = work / name;
    fs::create_directories(staging);
    write_file(staging / ".hapticbench-output",
               R"({"written_by": "hapticbench", "kind": "run folder", "files": ["ticks_a.csv"]})");
    write_file(staging / ".hapticbench-lock", "");
    write_file(staging / "ticks_a.csv", "tick\n");
    return staging;
  };
  const auto scratch_at = [&](const std::string& name) {
    const fs::path scratch = work / "tmp" / name;
    fs::create_directories(scratch);
    write_file(scratch / ".hapticbench-scratch", "scratch folder of hapticbench process\n");
    write_file(scratch / ".hapticbench-lock", "");
    write_file(scratch / "ticks_penalty.csv", std::string(100000, 'x'));
    return scratch;
  };
  const fs::path staging = staging_at("run.partial-99999999");
  const fs::path set_aside = staging_at("run.old-99999999-1");
  const fs::path scratch = scratch_at("hapticbench-run-99999999-AbC123");
  const fs::path live_staging = staging_at("run.partial-99999997");
  const fs::path live_scratch = scratch_at("hapticbench-run-99999997-DeF456");
  const HeldLock staging_held(live_staging), scratch_held(live_scratch);
  const fs::path foreign = work / "tmp/hapticbench-run-99999998-mine";
  fs::create_directories(foreign);
  write_file(foreign / "notes.txt", "mine");

  const CommandResult result = hb::test::run_hapticbench_after(
      "TMPDIR='" + (work / "tmp").string() + "'", "run " + kPress + " --out run --quiet", work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  CHECK_FALSE(fs::exists(staging));
  CHECK_FALSE(fs::exists(set_aside));
  CHECK_FALSE(fs::exists(scratch));
  CHECK(read_text_file(live_staging / "ticks_a.csv") == "tick\n");
  CHECK(fs::file_size(live_scratch / "ticks_penalty.csv") == 100000);
  CHECK(read_text_file(foreign / "notes.txt") == "mine");
  // Its own scratch folder is gone: only the live and the foreign are left.
  CHECK(listing(work / "tmp") ==
        std::set<std::string>{"hapticbench-run-99999997-DeF456", "hapticbench-run-99999998-mine"});
  CHECK(listing(work) == std::set<std::string>{"run", "run.partial-99999997", "tmp"});
}

TEST_CASE("a run in another PID namespace keeps its folders while a run here starts beside it") {
  // Where user and PID namespaces cannot be made (no unshare, or the kernel
  // forbids them), there is nothing to test.
  if (std::system("unshare -r -p -f true > /dev/null 2>&1") != 0) {
    WARN("skipped: unshare -r -p -f is not available here");
    return;
  }
  const ScratchDir work_dir("e2e_out_namespace");
  const fs::path& work = work_dir.path();
  fs::create_directories(work / "tmp");
  write_file(work / "long.json", read_text_file(kPress));
  // The run in the namespace gets a process id that no process has here:
  // the old rule (kill(pid, 0) fails, so the run is gone) took it for dead.
  const std::string inner =
      "unshare -r -p -f sh -c 'echo 4190000 > /proc/sys/kernel/ns_last_pid; "
      "TMPDIR=tmp \"$0\" run " +
      kPress + " --out run --quiet --repeat 20' '" + hb::test::hapticbench_bin() +
      "' > inner.txt 2>&1";
  int inner_status = -1;
  std::thread inner_run(
      [&] { inner_status = std::system(("cd '" + work.string() + "' && " + inner).c_str()); });
  bool started = false;
  for (int i = 0; i < 1000 && !started; ++i) {
    started = !fs::is_empty(work / "tmp");  // its scratch folder, holding its ticks
    if (!started) ::usleep(10000);
  }
  REQUIRE(started);
  const CommandResult outer = hb::test::run_hapticbench_after(
      "TMPDIR='" + (work / "tmp").string() + "'", "run " + kPress + " --out run --quiet", work);
  CHECK(outer.exit_code == 0);
  inner_run.join();
  // The run here started while the other ran: the other's ticks were kept.
  INFO(read_text_file(work / "inner.txt"));
  CHECK(WIFEXITED(inner_status));
  CHECK(WEXITSTATUS(inner_status) == 0);
  CHECK(fs::exists(work / "run/summary.json"));
  CHECK(listing(work / "tmp").empty());
}

TEST_CASE("report and compare never replace a file or folder of the user's") {
  const ScratchDir work_dir("e2e_out_report");
  const fs::path& work = work_dir.path();
  REQUIRE(run_hapticbench("run " + kPress + " --out run", work).exit_code == 0);
  write_file(work / "page.html", "<html>mine</html>");
  check_refused_naming(run_hapticbench("report run --out page.html", work), "page.html");
  CHECK(read_text_file(work / "page.html") == "<html>mine</html>");
  check_refused_naming(run_hapticbench("report run --out run", work), "run");

  // compare --out onto a run folder: a run folder is not a comparison.
  const CommandResult onto_run = run_hapticbench("compare run run --no-timing --out run", work);
  CHECK(onto_run.exit_code == 2);
  CHECK(contains(onto_run.stderr_text, "run folder"));
  CHECK(fs::exists(work / "run/summary.json"));
  fs::create_directory(work / "notes");
  write_file(work / "notes/todo.txt", "x");
  check_refused_naming(run_hapticbench("compare run run --no-timing --out notes", work), "notes");
  CHECK(read_text_file(work / "notes/todo.txt") == "x");
  // Its own comparison folder is replaced.
  CHECK(run_hapticbench("compare run run --no-timing --out cmp", work).exit_code == 0);
  CHECK(run_hapticbench("compare run run --no-timing --out cmp", work).exit_code == 0);
}

TEST_CASE("sweep never replaces a job folder or sweep.json of the user's") {
  const ScratchDir work_dir("e2e_out_sweep");
  const fs::path& work = work_dir.path();
  write_file(work / "grid.json", "{ \"name\": \"grid\", \"scenarios\": [\"" + kPress +
                                     "\"], \"grid\": { \"/coupling/k_t\": [1000, 2000] } }");
  fs::create_directories(work / "out");
  write_file(work / "out/sweep.json", "{\"mine\": true}");
  check_refused_naming(run_hapticbench("sweep grid.json --out out", work), "sweep.json");
  CHECK(read_text_file(work / "out/sweep.json") == "{\"mine\": true}");
  CHECK(listing(work / "out") == std::set<std::string>{"sweep.json"});

  const std::string job = "sphere_press_box__k_t=2000";
  fs::create_directories(work / "out2" / job);
  write_file(work / "out2" / job / "precious.txt", "keep me");
  check_refused_naming(run_hapticbench("sweep grid.json --out out2", work), job);
  CHECK(listing(work / "out2" / job) == std::set<std::string>{"precious.txt"});
  CHECK_FALSE(fs::exists(work / "out2/sphere_press_box__k_t=1000"));
}

}  // namespace
