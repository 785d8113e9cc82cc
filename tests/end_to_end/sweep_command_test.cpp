// End-to-end: `hapticbench sweep` on a 2 x 2 grid of short presses: run
// folders, sweep.json, resuming, shards, parallel workers and bad input.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"
#include "tests/support/scratch_dir.h"

namespace {

using hb::test::CommandResult;

using hb::test::write_file;

namespace fs = std::filesystem;
using nlohmann::json;

// A sphere pressed 5 mm into a box over 0.2 s: coupling_only, and a
// quasi-static penalty proxy whose held force has a closed form.
constexpr const char* kPressScenario = R"({
  "name": "press",
  "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] }, "pose": { "p": [0, 0, -0.01] } } ],
  "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 2 }, "density": 1000 },
  "trace": { "generator": "press", "duration_s": 0.2, "seed": 1,
             "params": { "start": [0, 0, 0.03], "axis": [0, 0, -1], "surface_distance": 0.01, "depth": 0.005 } },
  "coupling": { "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 },
  "device": { "max_force_n": 20, "max_torque_nm": 1 },
  "algorithms": [
    { "name": "coupling_only", "params": { "integrator": "implicit_euler" } },
    { "name": "penalty_analytic", "label": "penalty", "params": { "proxy": "quasi_static", "contact_stiffness": 3000 } }
  ],
  "budgets": { "nonfinite": 0 }
})";

const std::vector<int> kCouplingStiffness = {1000, 2000};
const std::vector<int> kContactStiffness = {1000, 3000};

// The scenario and a sweep beside it, in folders of their own, as a user
// would keep them.
fs::path write_grid(const fs::path& work, const std::string& extra_grid = "") {
  write_file(work / "scenarios" / "press.json", kPressScenario);
  write_file(work / "sweeps" / "grid.json", R"({
    "name": "grid",
    "scenarios": ["../scenarios/press.json"],
    "grid": { "/coupling/k_t": [1000, 2000], "/algorithms/1/params/contact_stiffness": [1000, 3000])" +
                                                extra_grid + R"( }
  })");
  return work / "sweeps" / "grid.json";
}

// Job names in sweep order, from the grid as written: k_t turns slowest.
std::vector<std::string> expected_job_names() {
  std::vector<std::string> names;
  for (int k_t : kCouplingStiffness)
    for (int k_c : kContactStiffness)
      names.push_back("press__k_t=" + std::to_string(k_t) +
                      "__contact_stiffness=" + std::to_string(k_c));
  return names;
}

json summary_of(const fs::path& folder) {
  return json::parse(hb::test::read_text_file(folder / "summary.json"));
}

std::map<std::string, std::string> ticks_hashes(const fs::path& folder) {
  std::map<std::string, std::string> hashes;
  const json summary = summary_of(folder);
  for (const json& run : summary.at("runs"))
    hashes[run.at("label").get<std::string>()] =
        run.at("determinism").at("ticks_hash").get<std::string>();
  return hashes;
}

std::set<std::string> run_folders(const fs::path& out) {
  std::set<std::string> names;
  if (!fs::exists(out)) return names;
  for (const auto& entry : fs::directory_iterator(out))
    if (entry.is_directory() && fs::exists(entry.path() / "summary.json"))
      names.insert(entry.path().filename().string());
  return names;
}

}  // namespace

TEST_CASE("a 2 x 2 sweep writes one run folder per job, named by its grid values") {
  const hb::test::ScratchDir work_dir("e2e_sweep_grid");
  const fs::path& work = work_dir.path();
  write_grid(work);
  const CommandResult result = hb::test::run_hapticbench("sweep sweeps/grid.json --out runs", work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  CHECK(result.stderr_text.find("4 to run") != std::string::npos);

  const std::vector<std::string> names = expected_job_names();
  CHECK(run_folders(work / "runs") == std::set<std::string>(names.begin(), names.end()));
  std::size_t index = 0;
  for (int k_t : kCouplingStiffness)
    for (int k_c : kContactStiffness) {
      const fs::path folder = work / "runs" / names[index];
      INFO(folder);
      for (const char* file : {"summary.json", "junit.xml", "scenario.json",
                               "ticks_coupling_only.csv", "ticks_penalty.csv"})
        CHECK(fs::exists(folder / file));
      const json summary = summary_of(folder);
      CHECK(summary.at("scenario").at("name") == names[index]);
      const json scenario = json::parse(hb::test::read_text_file(folder / "scenario.json"));
      CHECK(scenario.at("name") == names[index]);
      CHECK(scenario.at("coupling").at("k_t") == k_t);
      CHECK(scenario.at("coupling").at("b_t") == 5);

      // The values reached the physics: held at the deepest point, the
      // quasi-static proxy pushes back with coupling and contact springs in
      // series, k_t k_c / (k_t + k_c) per metre of depth.
      auto ticks = hb::test::read_tick_columns(folder / "ticks_penalty.csv");
      REQUIRE(ticks["dev_pz"].size() == 200);
      std::size_t deepest = 0;
      for (std::size_t k = 0; k < ticks["dev_pz"].size(); ++k)
        if (ticks["dev_pz"][k] <= ticks["dev_pz"][deepest]) deepest = k;
      const double depth = 0.02 - ticks["dev_pz"][deepest];
      REQUIRE(depth == Approx(0.005).epsilon(1e-6));
      CHECK(ticks["fz"][deepest] == Approx(double(k_t) * k_c / (k_t + k_c) * depth).epsilon(1e-3));
      ++index;
    }

  const json index_file = json::parse(hb::test::read_text_file(work / "runs" / "sweep.json"));
  CHECK(index_file.at("name") == "grid");
  REQUIRE(index_file.at("jobs").size() == 4);
  for (std::size_t i = 0; i < 4; ++i) {
    const json& job = index_file.at("jobs")[i];
    CHECK(job.at("index") == i);
    CHECK(job.at("name") == names[i]);
    CHECK(job.at("status") == "ok");
    CHECK(job.at("grid").at("/coupling/k_t") == kCouplingStiffness[i / 2]);
    CHECK(job.at("grid").at("/algorithms/1/params/contact_stiffness") == kContactStiffness[i % 2]);
  }
  // The cross-job table: on the console and in sweep.md, a row per job and label.
  CHECK(result.stdout_text.find("sweep grid, every job") != std::string::npos);
  const std::string table = hb::test::read_text_file(work / "runs" / "sweep.md");
  CHECK(table.find("| k_t | contact_stiffness | label |") != std::string::npos);
  std::size_t rows = 0;
  for (std::size_t at = table.find("\n| "); at != std::string::npos;
       at = table.find("\n| ", at + 1))
    ++rows;
  CHECK(rows == 2 + 4 * 2);  // header, rule, 4 jobs x 2 labels
}

TEST_CASE("a job's scenario.json reruns with `hapticbench run` to the same ticks") {
  const hb::test::ScratchDir work_dir("e2e_sweep_rerun");
  const fs::path& work = work_dir.path();
  write_grid(work);
  REQUIRE(hb::test::run_hapticbench("sweep sweeps/grid.json --out runs", work).exit_code == 0);
  // From another folder: the mesh and trace paths in scenario.json do not
  // depend on where it is read from.
  const fs::path elsewhere = work / "elsewhere";
  fs::create_directories(elsewhere);
  for (const std::string& name : expected_job_names()) {
    INFO(name);
    const fs::path folder = work / "runs" / name;
    const CommandResult result = hb::test::run_hapticbench(
        "run '" + (folder / "scenario.json").string() + "' --out again", elsewhere);
    INFO(result.stderr_text);
    REQUIRE(result.exit_code == 0);
    CHECK(ticks_hashes(elsewhere / "again") == ticks_hashes(folder));
    CHECK(summary_of(elsewhere / "again").at("scenario").at("hash") ==
          summary_of(folder).at("scenario").at("hash"));
  }
}

TEST_CASE("two jobs at a time (--jobs 2) give every job the same ticks as one at a time") {
  const hb::test::ScratchDir work_dir("e2e_sweep_parallel");
  const fs::path& work = work_dir.path();
  write_grid(work);
  REQUIRE(hb::test::run_hapticbench("sweep sweeps/grid.json --jobs 1 --out one", work).exit_code ==
          0);
  const CommandResult result =
      hb::test::run_hapticbench("sweep sweeps/grid.json --jobs 2 --out two", work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  CHECK(result.stderr_text.find("2 at a time") != std::string::npos);
  std::set<std::string> distinct;
  for (const std::string& name : expected_job_names()) {
    INFO(name);
    const auto hashes = ticks_hashes(work / "one" / name);
    CHECK(hashes.size() == 2);
    CHECK(ticks_hashes(work / "two" / name) == hashes);
    distinct.insert(hashes.at("penalty"));
  }
  // The grid values change the ticks: four jobs, four penalty runs.
  CHECK(distinct.size() == 4);
}

TEST_CASE("running a sweep again skips finished jobs and runs only what is missing") {
  const hb::test::ScratchDir work_dir("e2e_sweep_resume");
  const fs::path& work = work_dir.path();
  write_grid(work);
  // Without --out: out/sweeps/<sweep name>/.
  REQUIRE(hb::test::run_hapticbench("sweep sweeps/grid.json", work).exit_code == 0);
  const fs::path out = work / "out" / "sweeps" / "grid";
  const std::vector<std::string> names = expected_job_names();
  REQUIRE(run_folders(out).size() == 4);
  std::map<std::string, fs::file_time_type> written;
  for (const std::string& name : names)
    written[name] = fs::last_write_time(out / name / "summary.json");
  const auto first_hashes = ticks_hashes(out / names[2]);

  const CommandResult again = hb::test::run_hapticbench("sweep sweeps/grid.json", work);
  INFO(again.stderr_text);
  REQUIRE(again.exit_code == 0);
  CHECK(again.stderr_text.find("4 done earlier, 0 to run") != std::string::npos);
  for (const std::string& name : names)
    CHECK(fs::last_write_time(out / name / "summary.json") == written[name]);
  const json index = json::parse(hb::test::read_text_file(out / "sweep.json"));
  for (const json& job : index.at("jobs")) {
    CHECK(job.at("status") == "ok");
    CHECK(job.at("done_earlier") == true);
  }

  // An interrupted job leaves no run folder, at most a staging folder
  // with hapticbench's marker and a lock no live process holds, which is
  // cleaned up; a folder of the same name without the marker is not
  // hapticbench's and stays.
  fs::remove_all(out / names[2]);
  const fs::path staging = out / (names[2] + ".partial-99999999");
  write_file(staging / ".hapticbench-output",
             R"({"written_by": "hapticbench", "kind": "run folder", "files": ["ticks_a.csv"]})");
  write_file(staging / ".hapticbench-lock", "");
  write_file(staging / "ticks_a.csv", "tick\n");
  const fs::path foreign = out / (names[2] + ".partial-99999998");
  write_file(foreign / "notes.txt", "mine");
  const CommandResult resumed = hb::test::run_hapticbench("sweep sweeps/grid.json", work);
  INFO(resumed.stderr_text);
  REQUIRE(resumed.exit_code == 0);
  CHECK(resumed.stderr_text.find("3 done earlier, 1 to run") != std::string::npos);
  CHECK(ticks_hashes(out / names[2]) == first_hashes);
  CHECK_FALSE(fs::exists(staging));
  CHECK(hb::test::read_text_file(foreign / "notes.txt") == "mine");
  for (const std::string& name : {names[0], names[1], names[3]})
    CHECK(fs::last_write_time(out / name / "summary.json") == written[name]);
}

TEST_CASE("another sweep into the same folder runs its own jobs, reusing none of the first's") {
  // Same scenario, same grid and so the same job names, but only the
  // penalty algorithm: a different scenario for every job.
  const hb::test::ScratchDir work_dir("e2e_sweep_other");
  const fs::path& work = work_dir.path();
  write_grid(work);
  write_file(work / "sweeps" / "penalty_only.json", R"({
    "name": "grid",
    "scenarios": ["../scenarios/press.json"],
    "only_algorithms": ["penalty"],
    "grid": { "/coupling/k_t": [1000, 2000], "/algorithms/1/params/contact_stiffness": [1000, 3000] }
  })");
  REQUIRE(hb::test::run_hapticbench("sweep sweeps/grid.json --out runs", work).exit_code == 0);
  const CommandResult other =
      hb::test::run_hapticbench("sweep sweeps/penalty_only.json --out runs", work);
  INFO(other.stderr_text);
  REQUIRE(other.exit_code == 0);
  CHECK(other.stderr_text.find("0 done earlier, 4 to run") != std::string::npos);
  for (const std::string& name : expected_job_names()) {
    const json runs = summary_of(work / "runs" / name).at("runs");
    REQUIRE(runs.size() == 1);
    CHECK(runs[0].at("label") == "penalty");
  }
  // Run again, the second sweep's jobs are its own: all reused.
  const CommandResult again =
      hb::test::run_hapticbench("sweep sweeps/penalty_only.json --out runs", work);
  CHECK(again.stderr_text.find("4 done earlier, 0 to run") != std::string::npos);
}

TEST_CASE("shards are disjoint, follow index % N, and together run every job") {
  const hb::test::ScratchDir work_dir("e2e_sweep_shards");
  const fs::path& work = work_dir.path();
  write_grid(work);
  const std::vector<std::string> names = expected_job_names();
  std::set<std::string> all;
  for (int shard = 0; shard < 3; ++shard) {
    const std::string out = "shard" + std::to_string(shard);
    const CommandResult result = hb::test::run_hapticbench(
        "sweep sweeps/grid.json --shard " + std::to_string(shard) + "/3 --out " + out, work);
    INFO(result.stderr_text);
    REQUIRE(result.exit_code == 0);
    std::set<std::string> expected;
    for (std::size_t i = 0; i < names.size(); ++i)
      if (static_cast<int>(i % 3) == shard) expected.insert(names[i]);
    const std::set<std::string> ran = run_folders(work / out);
    CHECK(ran == expected);
    for (const std::string& name : ran) CHECK(all.insert(name).second);  // disjoint
    // The shard's sweep.json still lists every job; others' are pending.
    const json index = json::parse(hb::test::read_text_file(work / out / "sweep.json"));
    REQUIRE(index.at("jobs").size() == names.size());
    for (const json& job : index.at("jobs"))
      CHECK(job.at("status") == (expected.count(job.at("name")) ? "ok" : "pending"));
  }
  CHECK(all == std::set<std::string>(names.begin(), names.end()));

  // Shards sharing one output folder, as a job array does, fill it.
  for (int shard = 0; shard < 2; ++shard)
    REQUIRE(hb::test::run_hapticbench(
                "sweep sweeps/grid.json --shard " + std::to_string(shard) + "/2 --out shared", work)
                .exit_code == 0);
  CHECK(run_folders(work / "shared") == all);
  const json index = json::parse(hb::test::read_text_file(work / "shared" / "sweep.json"));
  for (const json& job : index.at("jobs")) CHECK(job.at("status") == "ok");
}

TEST_CASE("a failed budget is reported, not gated: every job runs and the exit code is 1") {
  const hb::test::ScratchDir work_dir("e2e_sweep_budget");
  const fs::path& work = work_dir.path();
  write_grid(work, R"(, "/budgets/nonfinite": [0, -1])");
  const CommandResult result =
      hb::test::run_hapticbench("sweep sweeps/grid.json --jobs 2 --out runs", work);
  INFO(result.stderr_text);
  CHECK(result.exit_code == 1);
  const json index = json::parse(hb::test::read_text_file(work / "runs" / "sweep.json"));
  REQUIRE(index.at("jobs").size() == 8);
  CHECK(run_folders(work / "runs").size() == 8);
  for (const json& job : index.at("jobs")) {
    // nonfinite is 0 in every run: a limit of 0 passes, -1 fails.
    const bool fails = job.at("grid").at("/budgets/nonfinite") == -1;
    CHECK(job.at("status") == (fails ? "budget_failed" : "ok"));
  }
  // Still failed when every job was done earlier.
  CHECK(hb::test::run_hapticbench("sweep sweeps/grid.json --out runs", work).exit_code == 1);
}

TEST_CASE("a bad value in any job stops the sweep before anything runs, every bad job named") {
  const hb::test::ScratchDir work_dir("e2e_sweep_bad_job");
  const fs::path& work = work_dir.path();
  write_file(work / "scenarios" / "press.json", kPressScenario);
  // The first three jobs are fine; the fourth's contact stiffness is not.
  write_file(work / "sweeps" / "grid.json", R"({
    "name": "grid", "scenarios": ["../scenarios/press.json"],
    "grid": { "/coupling/k_t": [1000, 2000], "/algorithms/1/params/contact_stiffness": [1000, -3] }
  })");
  const CommandResult result = hb::test::run_hapticbench("sweep sweeps/grid.json --out runs", work);
  CHECK(result.exit_code == 2);
  // Both jobs with the bad value, listed in one error.
  CHECK(result.stderr_text.find("sweeps/grid.json: jobs press__k_t=1000__contact_stiffness=-3, "
                                "press__k_t=2000__contact_stiffness=-3: ") != std::string::npos);
  CHECK(result.stderr_text.find("/algorithms/1/params/contact_stiffness") != std::string::npos);
  CHECK_FALSE(fs::exists(work / "runs"));
}

TEST_CASE("bad sweep files and arguments exit 2 naming the file and the field") {
  const hb::test::ScratchDir work_dir("e2e_sweep_bad_input");
  const fs::path& work = work_dir.path();
  write_file(work / "scenarios" / "press.json", kPressScenario);
  struct Case {
    std::string sweep;
    std::string args;
    std::string says;
  };
  const std::string scenarios = R"("scenarios": ["../scenarios/press.json"])";
  for (const Case& c : {
           Case{R"({"name": "g", )" + scenarios + R"(, "gird": {}})", "", "grid.json: /gird:"},
           Case{R"({"name": "g", )" + scenarios + R"(, "grid": {"/couplingg/k_t": [1]}})", "",
                "grid.json: /grid/~1couplingg~1k_t: grid key \"/couplingg/k_t\" does not exist in "
                "scenario ../scenarios/press.json"},
           Case{R"({"name": "g", "scenarios": ["../scenarios/nope.json"]})", "",
                "grid.json: /scenarios/0: scenario file \"../scenarios/nope.json\" not found"},
           Case{R"({"name": "g", )" + scenarios + "}", "--shard 2/2", "--shard: expected I/N"},
           Case{R"({"name": "g", )" + scenarios + "}", "--jobs x", "--jobs: expected"},
           Case{R"({"name": "g", )" + scenarios + "}", "--frobnicate", "unknown option"},
       }) {
    INFO(c.sweep << " " << c.args);
    write_file(work / "sweeps" / "grid.json", c.sweep);
    const CommandResult result =
        hb::test::run_hapticbench("sweep sweeps/grid.json --out runs " + c.args, work);
    CHECK(result.exit_code == 2);
    CHECK(result.stderr_text.find(c.says) != std::string::npos);
    CHECK_FALSE(fs::exists(work / "runs"));
  }
  CHECK(hb::test::run_hapticbench("sweep", work).exit_code == 2);
  CHECK(hb::test::run_hapticbench("sweep sweeps/missing.json", work).exit_code == 2);
}
