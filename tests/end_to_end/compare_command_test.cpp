// End-to-end: `hapticbench compare` on run folders written by `hapticbench run`.
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <system_error>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"
#include "tests/support/scratch_dir.h"

namespace {

using hb::test::CommandResult;

using hb::test::contains;
using hb::test::kSource;

namespace fs = std::filesystem;
using nlohmann::json;

using ScratchFolder = hb::test::ScratchDir;

// Runs a shipped smoke scenario into work/<folder>.
void run_scenario(const std::string& scenario, const std::string& folder, const fs::path& work) {
  const CommandResult result = hb::test::run_hapticbench(
      "run " + (kSource / "scenarios/smoke" / (scenario + ".json")).string() + " --out " + folder,
      work);
  INFO("stdout: " << result.stdout_text << "\nstderr: " << result.stderr_text);
  REQUIRE(result.exit_code == 0);
}

// The table line of one check of one run, or "" when there is none.
std::string table_line(const std::string& table, const std::string& label,
                       const std::string& check) {
  std::istringstream lines(table);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string scenario, line_label, line_check;
    words >> scenario >> line_label >> line_check;
    if (line_label == label && line_check == check) return line;
  }
  return "";
}

void edit_summary(const fs::path& summary_file, const std::function<void(json&)>& edit) {
  json summary = json::parse(hb::test::read_text_file(summary_file));
  edit(summary);
  std::ofstream(summary_file) << summary.dump(2);
}

TEST_CASE("two runs of one build pass the gate") {
  const ScratchFolder scratch("same");
  const fs::path& work = scratch.path();
  run_scenario("sphere_press_box", "first", work);
  run_scenario("sphere_press_box", "second", work);

  const CommandResult result =
      hb::test::run_hapticbench("compare first second --gate --no-timing", work);
  INFO(result.stdout_text << result.stderr_text);
  CHECK(result.exit_code == 0);
  CHECK(contains(result.stdout_text, "verdict: pass"));
  // Every run of the scenario is matched and its forces are bit-identical.
  for (const char* label :
       {"coupling_only", "penalty_implicit", "penalty_explicit", "penalty_quasi_static"}) {
    const std::string line = table_line(result.stdout_text, label, "determinism.ticks_hash");
    INFO(label);
    CHECK(contains(line, "equal"));
    CHECK(table_line(result.stdout_text, label, "timing.step_ns.p50").empty());
  }

  // With timing the verdict depends on the machine's noise; only the rows
  // are certain.
  const CommandResult timed = hb::test::run_hapticbench("compare first second --gate", work);
  CHECK((timed.exit_code == 0 || timed.exit_code == 1));
  CHECK_FALSE(table_line(timed.stdout_text, "penalty_implicit", "timing.step_ns.p50").empty());
  CHECK(contains(table_line(timed.stdout_text, "penalty_implicit", "timing.step_ns.mann_whitney"),
                 "2000"));

  // A summary.json file and a suite folder are accepted too.
  CHECK(hb::test::run_hapticbench("compare first/summary.json second --gate --no-timing", work)
            .exit_code == 0);
  fs::create_directories(work / "suite_a");
  fs::create_directories(work / "suite_b");
  fs::copy(work / "first", work / "suite_a/sphere_press_box", fs::copy_options::recursive);
  fs::copy(work / "second", work / "suite_b/sphere_press_box", fs::copy_options::recursive);
  CHECK(hb::test::run_hapticbench("compare suite_a suite_b --gate --no-timing", work).exit_code ==
        0);

  // After an intended change of the scenario (here written into a copy's
  // summary: the coupling's k_t, a label's stiffness, and so its forces),
  // the ticks hash is information, and the scenario row says what changed.
  fs::copy(work / "second", work / "changed", fs::copy_options::recursive);
  edit_summary(work / "changed/summary.json", [](json& summary) {
    summary["scenario"]["hash"] = "0123456789abcdef";
    summary["scenario"]["coupling"]["k_t"] = 3000;
    for (json& run : summary["runs"]) {
      if (run["label"] != "penalty_implicit") continue;
      run["params"]["contact_stiffness"] = 10000;
      run["determinism"]["ticks_hash"] = "fedcba9876543210";
    }
  });
  const CommandResult changed =
      hb::test::run_hapticbench("compare first changed --gate --no-timing --out changes", work);
  INFO(changed.stdout_text << changed.stderr_text);
  CHECK(changed.exit_code == 0);
  const std::string hash_line =
      table_line(changed.stdout_text, "penalty_implicit", "determinism.ticks_hash");
  CHECK(contains(hash_line, "info"));
  const std::string table = hb::test::read_text_file(work / "changes/compare.md");
  CHECK(contains(table, "the scenario changed (scenario.hash), so the forces may differ"));
  CHECK(contains(table, "/coupling/k_t 2000.0 → 3000"));
  CHECK(contains(table, "penalty_implicit params/contact_stiffness 3000 → 10000"));
}

TEST_CASE("a 20 percent worse force error fails the gate and the table names it") {
  const ScratchFolder scratch("worse");
  const fs::path& work = scratch.path();
  run_scenario("sphere_press_box", "baseline", work);
  run_scenario("sphere_press_box", "candidate", work);
  double baseline_error = 0;
  edit_summary(work / "candidate/summary.json", [&baseline_error](json& summary) {
    for (json& run : summary["runs"])
      if (run["label"] == "penalty_implicit") {
        baseline_error = run["accuracy"]["force_err_rms_n"].get<double>();
        run["accuracy"]["force_err_rms_n"] = baseline_error * 1.2;
      }
  });
  REQUIRE(baseline_error > 0);

  const CommandResult gated =
      hb::test::run_hapticbench("compare baseline candidate --gate --no-timing", work);
  INFO(gated.stdout_text << gated.stderr_text);
  CHECK(gated.exit_code == 1);
  const std::string line =
      table_line(gated.stdout_text, "penalty_implicit", "accuracy.force_err_rms_n");
  CHECK(contains(line, "REGRESSION"));
  CHECK(contains(line, "+20.0%"));
  CHECK(contains(gated.stdout_text, "verdict: REGRESSION: 1 of"));
  // Only that row: the other runs' force errors are unchanged.
  CHECK(contains(table_line(gated.stdout_text, "penalty_explicit", "accuracy.force_err_rms_n"),
                 "pass"));

  // An accuracy regression fails whatever the timing does.
  CHECK(hb::test::run_hapticbench("compare baseline candidate --gate", work).exit_code == 1);
  // Without --gate: the same report, exit 0.
  const CommandResult report =
      hb::test::run_hapticbench("compare baseline candidate --no-timing", work);
  CHECK(report.exit_code == 0);
  CHECK(contains(report.stdout_text, "REGRESSION"));
  // A looser tolerance lets it through.
  CHECK(hb::test::run_hapticbench("compare baseline candidate --gate --no-timing --rel-tol 0.25",
                                  work)
            .exit_code == 0);
  // The regression is listed first, before the rows that pass.
  const std::size_t regression = gated.stdout_text.find("REGRESSION");
  const std::size_t first_pass = gated.stdout_text.find(" pass");
  CHECK(regression < first_pass);

  // Per-metric tolerances from a file: this metric's, the others' stay.
  std::ofstream(work / "tolerances.json") << R"({"force_err_rms_n": {"rel_tol": 0.25}})";
  CHECK(hb::test::run_hapticbench(
            "compare baseline candidate --gate --no-timing --tolerances tolerances.json", work)
            .exit_code == 0);
  std::ofstream(work / "other.json") << R"({"max_penetration_mm": 0.5})";
  CHECK(hb::test::run_hapticbench(
            "compare baseline candidate --gate --no-timing --tolerances other.json", work)
            .exit_code == 1);
  // The CI recipe's file (examples/ci/) reads, and holds force errors to 5 %.
  CHECK(hb::test::run_hapticbench("compare baseline candidate --gate --no-timing --tolerances '" +
                                      (kSource / "examples/ci/tolerances.json").string() + "'",
                                  work)
            .exit_code == 1);
  std::ofstream(work / "typo.json") << R"({"force_error": 0.5})";
  const CommandResult typo = hb::test::run_hapticbench(
      "compare baseline candidate --no-timing --tolerances typo.json", work);
  CHECK(typo.exit_code == 2);
  CHECK(contains(typo.stderr_text, "typo.json: /force_error: unknown metric"));
  std::ofstream(work / "count.json") << R"({"nonfinite": 0.5})";
  CHECK(contains(hb::test::run_hapticbench(
                     "compare baseline candidate --no-timing --tolerances count.json", work)
                     .stderr_text,
                 "/nonfinite: not compared by tolerance"));
}

TEST_CASE("the out folder gets compare.json and compare.md and junit.xml") {
  const ScratchFolder scratch("out");
  const fs::path& work = scratch.path();
  run_scenario("sphere_press_box", "baseline", work);
  run_scenario("sphere_press_box", "candidate", work);
  edit_summary(work / "candidate/summary.json", [](json& summary) {
    for (json& run : summary["runs"])
      if (run["label"] == "penalty_explicit") run["stability"]["diverged"] = true;
  });
  const CommandResult result =
      hb::test::run_hapticbench("compare baseline candidate --gate --no-timing --out report", work);
  INFO(result.stdout_text << result.stderr_text);
  CHECK(result.exit_code == 1);

  const json report = json::parse(hb::test::read_text_file(work / "report/compare.json"));
  CHECK(report["verdict"] == "regression");
  CHECK(report["failing"] == 1);
  int failing_rows = 0;
  for (const json& row : report["rows"])
    if (row["verdict"] == "regression") {
      ++failing_rows;
      CHECK(row["label"] == "penalty_explicit");
      CHECK(row["check"] == "stability.diverged");
    }
  CHECK(failing_rows == 1);

  const std::string md = hb::test::read_text_file(work / "report/compare.md");
  CHECK(md.rfind("**hapticbench compare: REGRESSION", 0) == 0);
  CHECK(md.find("stability.diverged") < md.find("<details>"));

  const std::string junit = hb::test::read_text_file(work / "report/junit.xml");
  CHECK(contains(junit, "failures=\"1\""));
  // A passing case carries its figures as well.
  CHECK(contains(junit, "<system-out>pass: baseline "));
  CHECK(contains(junit, "tests=\"" + std::to_string(report["rows"].size()) + "\""));
  // Written all at once: no staging folder left beside it.
  for (const auto& entry : fs::directory_iterator(work))
    CHECK_FALSE(contains(entry.path().filename().string(), ".partial-"));
}

TEST_CASE("bad input exits with 2 naming the file and writes nothing") {
  const ScratchFolder scratch("bad");
  const fs::path& work = scratch.path();
  run_scenario("sphere_press_box", "sphere", work);
  // One case after another on the same run folder.
  {
    INFO("runs of different scenarios");
    run_scenario("box_press_box", "box", work);
    const CommandResult result = hb::test::run_hapticbench("compare sphere box --out report", work);
    CHECK(result.exit_code == 2);
    CHECK(contains(result.stderr_text,
                   "different scenarios: baseline sphere_press_box, candidate box_press_box"));
    CHECK_FALSE(fs::exists(work / "report"));
  }
  {
    INFO("a corrupt summary.json");
    fs::copy(work / "sphere", work / "corrupt", fs::copy_options::recursive);
    const std::string text = hb::test::read_text_file(work / "corrupt/summary.json");
    std::ofstream(work / "corrupt/summary.json") << text.substr(0, text.size() / 2);
    const CommandResult result =
        hb::test::run_hapticbench("compare sphere corrupt --out report", work);
    CHECK(result.exit_code == 2);
    CHECK(contains(result.stderr_text, "corrupt/summary.json"));
    CHECK(contains(result.stderr_text, "line "));
    CHECK_FALSE(fs::exists(work / "report"));
  }
  {
    INFO("schema_version 2");
    fs::copy(work / "sphere", work / "future", fs::copy_options::recursive);
    edit_summary(work / "future/summary.json",
                 [](json& summary) { summary["schema_version"] = 2; });
    const CommandResult result =
        hb::test::run_hapticbench("compare future sphere --out report", work);
    CHECK(result.exit_code == 2);
    CHECK(contains(result.stderr_text, "future/summary.json"));
    CHECK(contains(result.stderr_text, "/schema_version"));
    CHECK_FALSE(fs::exists(work / "report"));
  }
  {
    INFO("a missing contract key");
    fs::copy(work / "sphere", work / "partial", fs::copy_options::recursive);
    edit_summary(work / "partial/summary.json",
                 [](json& summary) { summary["runs"][1]["stability"].erase("diverged"); });
    const CommandResult result = hb::test::run_hapticbench("compare sphere partial", work);
    CHECK(result.exit_code == 2);
    CHECK(contains(result.stderr_text, "partial/summary.json: /runs/1/stability/diverged"));
  }
  {
    INFO("a missing path");
    const CommandResult result = hb::test::run_hapticbench("compare sphere nowhere", work);
    CHECK(result.exit_code == 2);
    CHECK(contains(result.stderr_text, "nowhere"));
  }
  {
    INFO("usage");
    CHECK(hb::test::run_hapticbench("compare sphere", work).exit_code == 2);
    CHECK(hb::test::run_hapticbench("compare sphere sphere extra", work).exit_code == 2);
    CHECK(hb::test::run_hapticbench("compare sphere sphere --bogus", work).exit_code == 2);
    CHECK(hb::test::run_hapticbench("compare sphere sphere --alpha 2", work).exit_code == 2);
    CHECK(hb::test::run_hapticbench("compare sphere sphere --rel-tol -1", work).exit_code == 2);
    CHECK(hb::test::run_hapticbench("compare sphere sphere --timing-ratio 0.5", work).exit_code ==
          2);
    CHECK(hb::test::run_hapticbench("compare sphere sphere --out", work).exit_code == 2);
  }
}

}  // namespace
