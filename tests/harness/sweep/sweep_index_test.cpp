// sweep.json: job states read back from run folders, and the listing.
#include "harness/sweep/sweep_index.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/scratch_dir.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

void write_summary(const fs::path& folder, const std::string& runs) {
  fs::create_directories(folder);
  std::ofstream(folder / "summary.json") << R"({"schema_version": 1, "runs": )" << runs << "}";
}

}  // namespace

TEST_CASE("a job's state on disk follows the budgets in its summary") {
  const hb::test::ScratchDir scratch("sweep_index_state");
  const fs::path& dir = scratch.path();
  write_summary(dir / "pass",
                R"([{"budgets": [{"name": "nonfinite", "pass": true}]}, {"budgets": []}])");
  write_summary(dir / "fail", R"([{"budgets": [{"name": "a", "pass": true}]},
                                  {"budgets": [{"name": "b", "pass": false}]}])");
  fs::create_directories(dir / "unfinished");
  write_summary(dir / "garbled", "[");
  CHECK(hb::sweep_job_state_on_disk(dir / "pass").status == hb::SweepJobStatus::kOk);
  CHECK(hb::sweep_job_state_on_disk(dir / "fail").status == hb::SweepJobStatus::kBudgetFailed);
  CHECK(hb::sweep_job_state_on_disk(dir / "unfinished").status == hb::SweepJobStatus::kPending);
  CHECK(hb::sweep_job_state_on_disk(dir / "absent").status == hb::SweepJobStatus::kPending);
  CHECK(hb::sweep_job_state_on_disk(dir / "garbled").status == hb::SweepJobStatus::kPending);
}

TEST_CASE("sweep.json lists every job with its grid values and status") {
  const hb::test::ScratchDir scratch("sweep_index_listing");
  const fs::path& dir = scratch.path();
  hb::SweepSpec spec;
  spec.path = (dir / "grid.json").string();
  spec.name = "grid";
  spec.scenario_entries = {"../a.json"};
  spec.scenario_paths = {(dir / "../a.json").string()};
  spec.grid = {{"/coupling/k_t", {Json(1000), Json(2000)}}};
  std::vector<hb::SweepJob> jobs(2);
  std::vector<hb::SweepJobState> states(2);
  for (std::size_t i = 0; i < 2; ++i) {
    jobs[i].index = i;
    jobs[i].name = "a__k_t=" + std::to_string(1000 * (i + 1));
    jobs[i].grid_values = {{"/coupling/k_t", Json(1000 * (i + 1))}};
  }
  states[0].status = hb::SweepJobStatus::kOk;
  states[0].done_earlier = true;
  states[1].status = hb::SweepJobStatus::kCrashed;
  states[1].detail = "killed by signal 9 (Killed)";

  hb::write_sweep_index(dir, hb::sweep_index_json(spec, jobs, states, {1, 3}));
  std::ifstream in(dir / "sweep.json");
  const Json index = Json::parse(in);
  CHECK(index["name"] == "grid");
  CHECK(index["grid"]["/coupling/k_t"] == Json({1000, 2000}));
  CHECK(index["written_by_shard"] == "1/3");
  CHECK_FALSE(index.contains("only_algorithms"));
  REQUIRE(index["jobs"].size() == 2);
  CHECK(index["jobs"][0]["name"] == "a__k_t=1000");
  CHECK(index["jobs"][0]["scenario"] == "../a.json");
  CHECK(index["jobs"][0]["grid"]["/coupling/k_t"] == 1000);
  CHECK(index["jobs"][0]["status"] == "ok");
  CHECK(index["jobs"][0]["done_earlier"] == true);
  CHECK(index["jobs"][1]["status"] == "crashed");
  CHECK(index["jobs"][1]["detail"] == "killed by signal 9 (Killed)");
  CHECK_FALSE(index["jobs"][1].contains("done_earlier"));
  // Only sweep.json: the temporary it went through is gone.
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  CHECK(files == 1);
}
