// The cross-job table of a sweep: rows in numeric order of the grid values,
// figures read back from each job's summary.json in the console's units,
// and sweep.md marked as hapticbench's.
#include "harness/sweep/sweep_table.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/scratch_dir.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

/// A job's summary with one run: force error `force_n`, penetration 1 mm,
/// step p50 800 ns and p99 3000 ns, stable unless `failed` names a check.
void write_job(const fs::path& folder, double force_n, const std::string& failed = "") {
  fs::create_directories(folder);
  Json verdict = {{"stable", failed.empty()}, {"pass", failed.empty()}};
  verdict["failed"] = failed.empty() ? Json(nullptr) : Json(failed);
  verdict["expected_unstable"] = nullptr;
  const Json run = {{"label", "stiff"},
                    {"accuracy", {{"force_err_rms_n", force_n}, {"penetration_max_m", 0.001}}},
                    {"timing", {{"step_ns", {{"p50", 800.0}, {"p99", 3000.0}}}}},
                    {"stability", {{"verdict", verdict}}},
                    {"budgets", {{{"name", "nonfinite"}, {"pass", true}}}}};
  std::ofstream(folder / "summary.json") << Json{{"runs", {run}}}.dump();
}

}  // namespace

TEST_CASE("the sweep table orders jobs by grid value as numbers and reads each summary") {
  const hb::test::ScratchDir scratch("sweep_table_order");
  const fs::path& dir = scratch.path();
  hb::SweepSpec spec;
  spec.path = (dir / "grid.json").string();
  spec.name = "grid";
  spec.scenario_entries = {"a.json"};
  spec.scenario_paths = {(dir / "a.json").string()};
  // Listed in text order, as a folder listing would give them.
  const std::vector<int> values = {1000, 10000, 100000, 2000};
  spec.grid = {{"/algorithms/0/params/contact_stiffness", {}}};
  std::vector<hb::SweepJob> jobs(values.size());
  std::vector<hb::SweepJobState> states(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    spec.grid[0].values.push_back(values[i]);
    jobs[i].index = i;
    jobs[i].name = "a__contact_stiffness=" + std::to_string(values[i]);
    jobs[i].grid_values = {{"/algorithms/0/params/contact_stiffness", Json(values[i])}};
    states[i].status = hb::SweepJobStatus::kOk;
    if (values[i] != 100000) write_job(dir / jobs[i].name, 1e4 / values[i], "");
  }
  write_job(dir / jobs[1].name, 1.0, "chatter");
  states[2].status = hb::SweepJobStatus::kCrashed;  // no summary written

  const auto rows = hb::sweep_table_rows(spec, jobs, states, dir);
  REQUIRE(rows.size() == 4);
  CHECK(rows[0].grid_cells == std::vector<std::string>{"1000"});
  CHECK(rows[1].grid_cells == std::vector<std::string>{"2000"});
  CHECK(rows[2].grid_cells == std::vector<std::string>{"10000"});
  CHECK(rows[3].grid_cells == std::vector<std::string>{"100000"});
  CHECK(rows[0].force_err_rms_n == Approx(10.0));
  CHECK(rows[1].force_err_rms_n == Approx(5.0));
  CHECK(rows[0].penetration_max_mm == Approx(1.0));
  CHECK(rows[0].step_p50_us == Approx(0.8));
  CHECK(rows[0].step_p99_us == Approx(3.0));
  CHECK(rows[0].stability == "stable");
  CHECK(rows[2].stability == "chatter");
  CHECK(rows[0].budgets == "1/1 pass");
  CHECK(rows[3].label.empty());
  CHECK(rows[3].status == "crashed");

  std::ostringstream console;
  hb::print_sweep_table(console, spec, rows);
  const std::string text = console.str();
  INFO(text);
  CHECK(text.find("contact_stiffness label") != std::string::npos);
  CHECK(text.find("1000 ") < text.find("2000 "));
  CHECK(text.find("2000 ") < text.find("10000 "));
  CHECK(text.find("crashed") != std::string::npos);

  const std::string markdown = hb::sweep_table_markdown(spec, rows);
  CHECK(markdown.find("| contact_stiffness | label | F_err_N | pen_max_mm |") != std::string::npos);
  CHECK(markdown.find("| 2000 | stiff | 5.0000 | 1.000 | 0.80 | 3.00 | stable | 1/1 pass |") !=
        std::string::npos);
  std::ofstream(dir / "sweep.md") << markdown;
  std::ofstream(dir / "notes.md") << "# my notes\n";
  CHECK(hb::is_sweep_table_file(dir / "sweep.md"));
  CHECK_FALSE(hb::is_sweep_table_file(dir / "notes.md"));
}
