// End-to-end: the god-object renderers in hapticbench runs, against the
// analytic ideal rigid contact and the mesh oracles.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"
#include "tests/support/summary_runs.h"

namespace {

using hb::test::kSource;

namespace fs = std::filesystem;
using nlohmann::json;

// One numeric column of a ticks CSV.
std::vector<double> ticks_column(const fs::path& path, const std::string& name) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::stringstream header(line);
  int index = -1, i = 0;
  for (std::string field; std::getline(header, field, ','); ++i)
    if (field == name) index = i;
  REQUIRE(index >= 0);
  std::vector<double> values;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string field;
    for (int k = 0; k <= index; ++k) std::getline(row, field, ',');
    // strtod, not stod: a subnormal value (a torque of 1e-320 N·m) is a number too.
    values.push_back(field.empty() ? 0.0 : std::strtod(field.c_str(), nullptr));
  }
  return values;
}

using hb::test::run_labelled;

TEST_CASE("god-object: a tilted cube held 4 mm deep shows the ideal rigid contact within 1 %") {
  const hb::test::ScratchDir work_dir("e2e_god_object_box");
  const fs::path& work = work_dir.path();
  const hb::test::CommandResult result = hb::test::run_hapticbench(
      "run " + (kSource / "scenarios/smoke/box_press_box.json").string() + " --out run", work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  const fs::path ticks = work / "run/ticks_god_object.csv";
  const std::vector<double> z = ticks_column(ticks, "dev_pz");
  // The last tick of the hold at the deepest device position: settled.
  std::size_t deepest = 0;
  for (std::size_t k = 0; k < z.size(); ++k)
    if (z[k] <= z[deepest]) deepest = k;
  for (const char* axis : {"fx", "fy", "fz", "tx", "ty", "tz"}) {
    INFO(axis);
    const double rendered = ticks_column(ticks, axis)[deepest];
    const double ideal = ticks_column(ticks, std::string("ref_") + axis)[deepest];
    const double scale = axis[0] == 'f' ? 1.0 : 0.02;  // a torque as force × 2 cm
    CHECK(std::abs(rendered - ideal) <= 0.01 * std::max(std::abs(ideal), 1.0 * scale));
  }
  CHECK(ticks_column(ticks, "fz")[deepest] > 5.0);  // the press is real: k_t · 4 mm ≈ 8 N

  const json summary = json::parse(hb::test::read_text_file(work / "run/summary.json"));
  const json& run = run_labelled(summary, "god_object");
  // Hard non-penetration: the exact box tool never enters the exact box.
  CHECK(run.at("accuracy").at("penetration_max_m").get<double>() == 0.0);
  // The update runs on the slow loop; its time is reported.
  const json& slow = run.at("timing").at("slow_loop");
  CHECK(slow.at("update_ns").at("count").get<int>() > 1000);
  // Its work, by the names the god-object gives it.
  const json& work_done = run.at("contacts").at("work");
  CHECK(work_done.at("ccd_primitive_queries").get<int64_t>() > 0);
  CHECK(work_done.at("ccd_moves").get<int64_t>() > 0);
  CHECK(work_done.at("qp_iterations").get<int64_t>() > 0);
  CHECK_FALSE(work_done.contains("points_tested"));
  // Installed as many ticks after it started as it took (the default), and
  // its cost shows in the CPU time per tick that comparisons use.
  CHECK(slow.at("latency_ticks") == "measured");
  CHECK(slow.at("schedule") == "measured");
  CHECK(slow.at("schedule_file") == "schedule_god_object.csv");
  CHECK(fs::exists(work / "run/schedule_god_object.csv"));
  const json& cpu = run.at("timing").at("cpu_per_tick_ns");
  CHECK(cpu.at("mean").get<double>() > run.at("timing").at("step_ns").at("p50").get<double>() +
                                           slow.at("update_ns").at("p50").get<double>() / 2);
}

TEST_CASE("god-object: no drag in free space, with the slow loop every tick or every ten") {
  // The constraint solve runs every haptic tick, so in free space the proxy
  // is where the device is: the free-space force is far below the
  // k_t · v · Δt = 0.2 N of a proxy a tick behind at 0.1 m/s, also when the
  // slow loop's results arrive only every 10 ticks. Fixed latencies: the
  // measured schedule would make the result depend on how busy the machine is.
  const hb::test::ScratchDir work_dir("e2e_god_object_free_space");
  const fs::path& work = work_dir.path();
  json scenario =
      json::parse(hb::test::read_text_file(kSource / "scenarios/smoke/box_press_box.json"));
  scenario["algorithms"] = json::parse(R"([
    { "name": "god_object", "label": "every_tick", "params": { "slow_loop_latency": 1 } },
    { "name": "god_object", "label": "every_tenth", "params": { "slow_loop_latency": 10 } },
    { "name": "penalty_analytic", "label": "quasi_static", "params": { "proxy": "quasi_static", "contact_stiffness": 3000 } }
  ])");
  scenario["reference"] = json::parse(R"({ "oracle": "none", "analytic": "auto" })");
  std::ofstream(work / "free_space.json") << scenario.dump(2);
  const hb::test::CommandResult result =
      hb::test::run_hapticbench("run free_space.json --out run", work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  const json summary = json::parse(hb::test::read_text_file(work / "run/summary.json"));
  const double baseline = run_labelled(summary, "quasi_static")
                              .at("transparency")
                              .at("free_space_force_rms_n")
                              .get<double>();
  for (const char* label : {"every_tick", "every_tenth"}) {
    INFO(label);
    const json& run = run_labelled(summary, label);
    const json& transparency = run.at("transparency");
    CHECK(transparency.at("free_space_ticks").get<int>() > 500);
    CHECK(transparency.at("free_space_force_rms_n").get<double>() <= 0.005);
    CHECK(transparency.at("free_space_force_rms_n").get<double>() <= baseline);
    CHECK(run.at("accuracy").at("penetration_max_m").get<double>() == 0.0);
    CHECK(run.at("contacts").at("work").at("pairs_evaluated").get<int64_t>() > 0);
  }
}

}  // namespace
