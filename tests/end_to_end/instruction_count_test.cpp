// End-to-end: `run --instructions` counts the instructions of step() under
// callgrind; the counts repeat exactly, grow with the work done, and a real
// regression in them fails `compare --gate`, naming the metric.
#include "harness/replay/instruction_count.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"
#include "tests/support/summary_runs.h"

namespace {

using hb::test::kSource;

namespace fs = std::filesystem;
using hb::test::run_hapticbench;
using nlohmann::json;

// The smoke press with one implicit-Euler penalty proxy; `integrator` and
// `duration_s` change the work per tick and the number of ticks.
void write_press(const fs::path& file, const std::string& integrator, double duration_s) {
  json scenario =
      json::parse(hb::test::read_text_file(kSource / "scenarios/smoke/sphere_press_box.json"));
  scenario["trace"]["duration_s"] = duration_s;
  scenario["reference"] = {{"oracle", "none"}, {"analytic", "auto"}};
  json algorithm = {{"name", "penalty_analytic"},
                    {"label", "penalty"},
                    {"params",
                     {{"integrator", integrator},
                      {"proxy_mass_kg", 0.2},
                      {"contact_stiffness", 3000},
                      {"contact_damping", 2}}}};
  scenario["algorithms"] = json::array({algorithm});
  std::ofstream(file) << scenario.dump(2);
}

json instructions_of(const fs::path& run_folder) {
  const json summary = json::parse(hb::test::read_text_file(run_folder / "summary.json"));
  return hb::test::run_labelled(summary, "penalty").at("timing").at("instructions");
}

TEST_CASE("instruction counts repeat exactly and grow with the work done") {
  const hb::test::ScratchDir work("e2e_instructions");
  write_press(work / "press.json", "explicit_euler", 1.0);
  write_press(work / "longer.json", "explicit_euler", 2.0);
  for (const char* out : {"a", "b"}) {
    const auto result =
        run_hapticbench("run press.json --instructions --out " + std::string(out), work.path());
    INFO(result.stdout_text << result.stderr_text);
    REQUIRE(result.exit_code == 0);
  }
  REQUIRE(run_hapticbench("run longer.json --instructions --out longer", work.path()).exit_code ==
          0);
  const json a = instructions_of(work / "a"), b = instructions_of(work / "b");
  CHECK(a.at("step_total").get<int64_t>() > 0);
  CHECK(a.at("step_total") == b.at("step_total"));
  CHECK(a.at("step_per_tick_mean") == b.at("step_per_tick_mean"));
  CHECK(a.at("slow_update_per_call_mean").is_null());  // no slow loop
  // Twice the ticks: more instructions in total.
  CHECK(instructions_of(work / "longer").at("step_total").get<int64_t>() >
        a.at("step_total").get<int64_t>() * 3 / 2);
}

TEST_CASE("a real instruction-count regression fails the gate, naming the metric") {
  const hb::test::ScratchDir work("e2e_instructions_gate");
  // The candidate's step does strictly more: implicit Euler solves a linear
  // system per tick where explicit Euler does not.
  write_press(work / "press.json", "explicit_euler", 0.5);
  REQUIRE(run_hapticbench("run press.json --instructions --out baseline", work.path()).exit_code ==
          0);
  write_press(work / "press.json", "implicit_euler", 0.5);
  REQUIRE(run_hapticbench("run press.json --instructions --out candidate", work.path()).exit_code ==
          0);
  const auto gate =
      run_hapticbench("compare baseline candidate --gate --no-timing --rel-tol 1e9", work.path());
  INFO(gate.stdout_text << gate.stderr_text);
  CHECK(gate.exit_code == 1);
  CHECK(gate.stdout_text.find("timing.instructions.step_per_tick_mean") != std::string::npos);
  // Against itself it passes.
  CHECK(run_hapticbench("compare baseline baseline --gate --no-timing", work.path()).exit_code ==
        0);
}

// The counting child run by hand under callgrind, as `run --instructions`
// runs it, with the given progress style; returns the step count of `label`.
int64_t counted_steps(const fs::path& work, const std::string& scenario, const std::string& style,
                      const std::string& label) {
  const fs::path dumps = work / ("dumps_" + style), schedules = work / "schedules";
  fs::create_directories(dumps);
  fs::create_directories(schedules);
  const auto result = hb::test::run_hapticbench_after(
      "valgrind --tool=callgrind --instr-atstart=no --collect-atstart=no --dump-instr=no "
      "--dump-line=no --callgrind-out-file='" +
          (dumps / "callgrind.%p").string() + "'",
      "count-instructions " + scenario + " --schedule schedules --out counts_" + style +
          ".json --progress " + style + " 2> progress_" + style + ".txt",
      work);
  INFO(hb::test::read_text_file(work / "stderr.txt"));
  REQUIRE(result.exit_code == 0);
  const std::map<std::string, int64_t> counts = hb::read_callgrind_dumps(dumps);
  REQUIRE(counts.count("step:" + label) == 1);
  return counts.at("step:" + label);
}

TEST_CASE("showing progress costs no instruction inside the counted steps") {
  const hb::test::ScratchDir work("e2e_instructions_progress");
  write_press(work / "press.json", "implicit_euler", 5.0);
  const int64_t without = counted_steps(work.path(), "press.json", "none", "penalty");
  const int64_t with_bar = counted_steps(work.path(), "press.json", "bar", "penalty");
  // The display did draw during the counted pass (from the tick counter,
  // between the ticks), and the count of step() is the same to the instruction.
  const std::string drawn = hb::test::read_text_file(work / "progress_bar.txt");
  INFO(drawn);
  CHECK(std::regex_search(drawn, std::regex("counted pass [1-9][0-9,]*/5,000 ticks")));
  CHECK(hb::test::read_text_file(work / "progress_none.txt").find("pass") == std::string::npos);
  CHECK(without > 0);
  CHECK(with_bar == without);
}

TEST_CASE("run --instructions without valgrind on PATH is a clear usage error") {
  const hb::test::ScratchDir work("e2e_instructions_no_valgrind");
  write_press(work / "press.json", "explicit_euler", 0.2);
  const auto result =
      run_hapticbench("list > /dev/null; env PATH=/nonexistent '" + hb::test::hapticbench_bin() +
                          "' run press.json --instructions --out run2",
                      work.path());
  CHECK(result.exit_code == 2);
  CHECK(result.stderr_text.find("valgrind") != std::string::npos);
  CHECK_FALSE(fs::exists(work / "run2"));
}

}  // namespace
