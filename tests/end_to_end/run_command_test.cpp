// End-to-end: the hapticbench binary on the shipped scenarios and on bad input.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "harness/output/ticks_csv.h"
#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"
#include "tests/support/shortened_scenario.h"
#include "tests/support/summary_runs.h"

namespace {

using hb::test::kSource;

namespace fs = std::filesystem;
using nlohmann::json;

// Rows of a ticks CSV as column name -> values.
std::map<std::string, std::vector<std::string>> read_ticks(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  std::map<std::string, std::vector<std::string>> columns;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::string field;
    std::stringstream row(line);
    while (std::getline(row, field, ',')) fields.push_back(field);
    while (fields.size() < names.size()) fields.push_back("");
    for (std::size_t i = 0; i < names.size(); ++i) columns[names[i]].push_back(fields[i]);
  }
  return columns;
}

using hb::test::run_labelled;

TEST_CASE("the smoke suite writes run folders with the contract keys") {
  const hb::test::ScratchDir work_dir("e2e_smoke");
  const fs::path& work = work_dir.path();
  const hb::test::CommandResult result = hb::test::run_hapticbench(
      "run " + (kSource / "scenarios/smoke").string() + "/*.json --out runs", work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  int folders = 0;
  for (const auto& entry : fs::directory_iterator(work / "runs")) {
    ++folders;
    const json summary = json::parse(hb::test::read_text_file(entry.path() / "summary.json"));
    CHECK(summary.at("schema_version") == 1);
    for (const char* key : {"commit", "build_type", "compiler", "cpu", "date"})
      CHECK(summary.at("context").contains(key));
    CHECK(summary.at("scenario").contains("name"));
    CHECK(summary.at("scenario").contains("hash"));
    CHECK(fs::exists(entry.path() / "junit.xml"));
    REQUIRE_FALSE(summary.at("runs").empty());
    for (const json& run : summary.at("runs")) {
      for (const char* key : {"algorithm", "label", "params", "preprocess", "timing", "accuracy",
                              "stability", "budgets"})
        CHECK(run.contains(key));
      for (const char* key : {"seconds", "memory_bytes", "cache_hit"})
        CHECK(run.at("preprocess").contains(key));
      for (const char* key : {"p50", "p90", "p99", "p999", "max"})
        CHECK(run.at("timing").at("step_ns").contains(key));
      CHECK(run.at("timing").contains("over_budget"));
      for (const char* key : {"force_err_rms_n", "force_dir_err_max_deg", "torque_err_rms_nm",
                              "penetration_max_m", "penetration_rms_m"})
        CHECK(run.at("accuracy").contains(key));
      for (const char* key :
           {"nonfinite", "diverged", "passivity_energy_min_j", "force_jump_max_n"})
        CHECK(run.at("stability").contains(key));
      CHECK(run.at("stability").at("nonfinite") == 0);
      // The timing pass and the evaluation pass computed the same forces.
      if (!run.at("determinism").at("passes_agree").is_null())
        CHECK(run.at("determinism").at("passes_agree") == true);
      CHECK(fs::exists(entry.path() / ("ticks_" + run.at("label").get<std::string>() + ".csv")));
    }
  }
  CHECK(folders >= 3);
}

TEST_CASE("the same scenario gives bit-identical ticks twice") {
  const hb::test::ScratchDir work_dir("e2e_determinism");
  const fs::path& work = work_dir.path();
  for (const char* out : {"first", "second"}) {
    const hb::test::CommandResult result = hb::test::run_hapticbench(
        "run " + (kSource / "scenarios/smoke/sphere_press_box.json").string() + " --out " + out,
        work);
    REQUIRE(result.exit_code == 0);
  }
  const json first = json::parse(hb::test::read_text_file(work / "first/summary.json"));
  const json second = json::parse(hb::test::read_text_file(work / "second/summary.json"));
  REQUIRE(first.at("runs").size() == second.at("runs").size());
  for (std::size_t i = 0; i < first.at("runs").size(); ++i) {
    const std::string label = first.at("runs")[i].at("label");
    CHECK(first.at("runs")[i].at("determinism").at("ticks_hash") ==
          second.at("runs")[i].at("determinism").at("ticks_hash"));
    auto a = read_ticks(work / "first" / ("ticks_" + label + ".csv"));
    auto b = read_ticks(work / "second" / ("ticks_" + label + ".csv"));
    // Every column but the wall-clock timings, compared as text: the
    // shortest round-trip representation, so equal text is equal bits.
    for (const auto& [name, values] : a) {
      const auto& timing = hb::ticks_csv_timing_columns();
      if (std::find(timing.begin(), timing.end(), name) != timing.end()) continue;
      INFO(label << " column " << name);
      CHECK(values == b[name]);
    }
  }
}

TEST_CASE("quasi-static press: series springs and the force error against rigid contact") {
  const hb::test::ScratchDir work_dir("e2e_press");
  const fs::path& work = work_dir.path();
  const hb::test::CommandResult result = hb::test::run_hapticbench(
      "run " + (kSource / "scenarios/smoke/sphere_press_box.json").string() + " --out run", work);
  REQUIRE(result.exit_code == 0);
  const double k_t = 2000, k_c = 3000, radius = 0.02;
  const json summary = json::parse(hb::test::read_text_file(work / "run/summary.json"));
  for (const char* label : {"penalty_quasi_static", "penalty_implicit", "penalty_explicit"}) {
    INFO(label);
    auto ticks = read_ticks(work / "run" / (std::string("ticks_") + label + ".csv"));
    const auto& z = ticks["dev_pz"];
    // The last tick of the hold at the deepest device position: settled.
    std::size_t deepest = 0;
    for (std::size_t k = 0; k < z.size(); ++k)
      if (std::stod(z[k]) <= std::stod(z[deepest])) deepest = k;
    const double depth = radius - std::stod(z[deepest]);
    REQUIRE(depth == Approx(0.005).epsilon(1e-6));
    const double series = k_t * k_c / (k_t + k_c) * depth;
    const double fz = std::stod(ticks["fz"][deepest]);
    // The device is pushed up (+z) by the series combination of coupling and contact springs.
    CHECK(fz == Approx(series).epsilon(1e-3));
    CHECK(std::stod(ticks["ref_fz"][deepest]) == Approx(k_t * depth).epsilon(1e-12));
    // Against ideal rigid contact the penalty rendering is softer by k_t^2 D / (k_t + k_c).
    const double expected_error = k_t * k_t / (k_t + k_c) * depth;
    CHECK(std::stod(ticks["ref_fz"][deepest]) - fz == Approx(expected_error).epsilon(2e-3));
    const json& run = run_labelled(summary, label);
    CHECK(run.at("accuracy").at("force_err_rms_n").get<double>() > 0.1 * expected_error);
  }
}

TEST_CASE("a stiff coupling diverges with explicit Euler and not with implicit Euler") {
  const hb::test::ScratchDir work_dir("e2e_stiff");
  const fs::path& work = work_dir.path();
  const hb::test::CommandResult result = hb::test::run_hapticbench(
      "run " + (kSource / "scenarios/smoke/stiff_coupling_explicit_vs_implicit.json").string() +
          " --out run",
      work);
  REQUIRE(result.exit_code == 0);
  const json summary = json::parse(hb::test::read_text_file(work / "run/summary.json"));
  const json& explicit_run = run_labelled(summary, "explicit_euler");
  const json& implicit_run = run_labelled(summary, "implicit_euler");
  CHECK(explicit_run.at("stability").at("diverged") == true);
  CHECK(implicit_run.at("stability").at("diverged") == false);
  CHECK(explicit_run.at("stability").at("nonfinite") == 0);
  // Whatever the proxy does, the device never sees more than its limit.
  auto ticks = read_ticks(work / "run/ticks_explicit_euler.csv");
  for (std::size_t k = 0; k < ticks["fx"].size(); ++k) {
    const double f =
        std::hypot(std::stod(ticks["fx"][k]), std::stod(ticks["fy"][k]), std::stod(ticks["fz"][k]));
    REQUIRE(std::isfinite(f));
    REQUIRE(f <= 20.0 * (1 + 1e-12));
  }
}

// Bad input: exit code 2, a message naming the file and the field or line,
// and no run folder.
std::string scenario_text(const std::string& scene, const std::string& trace,
                          const std::string& algorithm, const std::string& coupling) {
  return R"({ "name": "bad_input", "scene": [ )" + scene + R"( ],
  "tool": { "shape": { "type": "sphere", "radius": 0.02 }, "density": 1000 },
  "trace": )" +
         trace + R"(,
  "coupling": )" +
         coupling + R"(,
  "algorithms": [ )" +
         algorithm + R"( ] })";
}

TEST_CASE("bad input exits with 2, names file and field, and writes nothing") {
  const std::string box = R"({ "shape": { "type": "box", "size": [0.4, 0.4, 0.02] } })";
  const std::string press = R"({ "generator": "press", "duration_s": 0.2 })";
  const std::string algo = R"({ "name": "coupling_only" })";
  const std::string coupling = R"({ "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 })";
  const std::string header = "t_ns,px,py,pz,qw,qx,qy,qz\n";
  const std::string open_off =
      "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n";
  const std::string degenerate_off =
      "OFF\n4 4 0\n0 0 0\n1 0 0\n2 0 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

  struct Case {
    std::string name, scenario;
    std::map<std::string, std::string> files;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"missing_mesh",
       scenario_text(R"({ "mesh": "nowhere.off" })", press, algo, coupling),
       {},
       {"nowhere.off"}},
      {"malformed_json",
       "{ \"name\": \"bad_input\", \"scene\": [ \n",
       {},
       {"scenario.json", "line"}},
      {"unknown_algorithm",
       scenario_text(box, press, R"({ "name": "no_such_algorithm" })", coupling),
       {},
       {"scenario.json", "/algorithms/0/name", "no_such_algorithm"}},
      {"unknown_generator",
       scenario_text(box, R"({ "generator": "wiggle", "duration_s": 1 })", algo, coupling),
       {},
       {"scenario.json", "/trace/generator", "wiggle"}},
      {"nan_in_trace",
       scenario_text(box, R"({ "file": "trace.csv" })", algo, coupling),
       {{"trace.csv", header + "0,0,0,0.05,1,0,0,0\n1000000,nan,0,0.05,1,0,0,0\n"}},
       {"trace.csv", "line 3"}},
      {"non_unit_quaternion",
       scenario_text(box, R"({ "file": "trace.csv" })", algo, coupling),
       {{"trace.csv", header + "0,0,0,0.05,1,0,0,0\n1000000,0,0,0.05,0.5,0,0,0\n"}},
       {"trace.csv", "line 3"}},
      {"non_monotonic_time",
       scenario_text(box, R"({ "file": "trace.csv" })", algo, coupling),
       {{"trace.csv",
         header + "0,0,0,0.05,1,0,0,0\n2000000,0,0,0.05,1,0,0,0\n1000000,0,0,0.05,1,0,0,0\n"}},
       {"trace.csv", "line 4"}},
      {"open_mesh",
       scenario_text(R"({ "mesh": "open.off" })", press, algo, coupling),
       {{"open.off", open_off}},
       {"open.off", "edge"}},
      {"degenerate_mesh",
       scenario_text(R"({ "mesh": "flat.off" })", press, algo, coupling),
       {{"flat.off", degenerate_off}},
       {"flat.off", "triangle"}},
      {"negative_coupling_stiffness",
       scenario_text(box, press, algo, R"({ "k_t": -2000, "b_t": 5, "k_r": 5, "b_r": 0.05 })"),
       {},
       {"scenario.json", "/coupling/k_t"}},
      {"negative_contact_stiffness",
       scenario_text(box, press,
                     R"({ "name": "penalty_analytic", "params": { "contact_stiffness": -1 } })",
                     coupling),
       {},
       {"scenario.json", "contact_stiffness"}},
  };
  for (const Case& c : cases) {
    SECTION(c.name) {
      const hb::test::ScratchDir work_dir("e2e_bad_" + c.name);
      const fs::path& work = work_dir.path();
      std::ofstream(work / "scenario.json") << c.scenario;
      for (const auto& [name, text] : c.files) std::ofstream(work / name) << text;
      const hb::test::CommandResult result =
          hb::test::run_hapticbench("run scenario.json --out run", work);
      INFO(result.stderr_text);
      CHECK(result.exit_code == 2);
      for (const std::string& expected : c.expected)
        CHECK(result.stderr_text.find(expected) != std::string::npos);
      CHECK_FALSE(fs::exists(work / "run"));
      for (const auto& entry : fs::directory_iterator(work))
        CHECK(entry.path().filename().string().find("run") == std::string::npos);
      // validate reports the same problem.
      CHECK(hb::test::run_hapticbench("validate scenario.json", work).exit_code == 2);
    }
  }
}

TEST_CASE("every shipped scenario validates") {
  const hb::test::ScratchDir work_dir("e2e_validate_all");
  for (const char* suite : {"smoke", "analytic", "meshes", "stress"}) {
    const hb::test::CommandResult result = hb::test::run_hapticbench(
        "validate " + (kSource / "scenarios" / suite).string() + "/*.json", work_dir.path());
    INFO(suite << ": " << result.stderr_text);
    CHECK(result.exit_code == 0);
  }
}

// The stress suite in four parts (the sorted scenario files whose index
// modulo 4 is the part), so that a sanitized test run spreads it over the
// cores instead of running it as one long test.
namespace {
constexpr int kStressParts = 4;

std::vector<fs::path> stress_scenario_files() {
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(kSource / "scenarios/stress"))
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

void check_stress_part(int part) {
  const std::vector<fs::path> all = stress_scenario_files();
  REQUIRE(all.size() >= 18);
  // The part that holds it checks the thin wall at 4 m/s below.
  REQUIRE(std::count(all.begin(), all.end(), kSource / "scenarios/stress/thin_wall_4mps.json") ==
          1);
  // A scenario longer than 10 s (the 60-cycle contact release) runs its
  // first 10 cycles: a crash or a non-finite force needs no more. The
  // sanitizer pass (scripts/sanitize --quick) asks for 3 s
  // (HAPTICBENCH_TEST_STRESS_MAX_S): every other stress scenario is 3 s or
  // shorter, and the release's code paths all run in its first cycle.
  const char* max_s_text = std::getenv("HAPTICBENCH_TEST_STRESS_MAX_S");
  const double max_s = max_s_text != nullptr ? std::atof(max_s_text) : 10.0;
  REQUIRE(max_s > 0);
  // The sanitizer pass also turns the penetration oracle off
  // (HAPTICBENCH_TEST_STRESS_NO_ORACLE), which is more than half of a run
  // under AddressSanitizer: this test checks the algorithms, and the
  // oracle's code runs sanitized in the smoke suite and the oracle tests.
  // Scenarios whose checks read it keep it: the thin wall at 4 m/s
  // (tunnelling) and those with a penetration budget (the hook turns).
  const bool no_oracle = std::getenv("HAPTICBENCH_TEST_STRESS_NO_ORACLE") != nullptr;
  const hb::test::ScratchDir work_dir("e2e_stress_suite_" + std::to_string(part));
  const fs::path& work = work_dir.path();
  fs::create_directories(work / "scenarios");
  std::string arguments;
  std::vector<fs::path> files;
  for (std::size_t i = static_cast<std::size_t>(part); i < all.size(); i += kStressParts) {
    files.push_back(all[i]);
    const fs::path shortened = hb::test::shortened_scenario(all[i], max_s, work / "scenarios");
    if (no_oracle) {
      json scenario = json::parse(hb::test::read_text_file(shortened));
      const bool oracle_checked =
          all[i].stem() == "thin_wall_4mps" || scenario.value("budgets", json::object()).size() > 1;
      if (!oracle_checked) {
        REQUIRE(scenario.at("budgets").contains("nonfinite"));
        scenario["reference"] = {{"oracle", "none"}};
        std::ofstream(shortened) << scenario.dump(2);
      }
    }
    arguments += " '" + shortened.string() + "'";
  }
  // Which runs are unstable depends on the slow loops' measured schedules
  // (a sanitized build's differ); this test is about crashes and non-finite
  // forces, so every label's instability is expected here.
  const hb::test::CommandResult result =
      hb::test::run_hapticbench("run" + arguments + " --out stress --expect-unstable all", work);
  INFO(result.stderr_text);
  CHECK(result.exit_code == 0);  // every nonfinite budget (0) holds
  for (const fs::path& file : files) {
    const json scenario = json::parse(hb::test::read_text_file(file));
    const std::string name = scenario.at("name");
    const json summary =
        json::parse(hb::test::read_text_file(work / "stress" / name / "summary.json"));
    INFO(name);
    REQUIRE(summary.at("runs").size() == scenario.at("algorithms").size());
    for (const json& run : summary.at("runs")) {
      INFO(run.at("label").get<std::string>());
      CHECK(run.at("stability").at("nonfinite") == 0);
      CHECK(run.at("timing").at("ticks").get<int64_t>() > 0);
    }
    // The thin wall at 4 m/s: the device (coupling only) passes through the
    // plate, the god-object does not.
    if (name != "thin_wall_4mps") continue;
    for (const json& run : summary.at("runs")) {
      const std::string label = run.at("label");
      if (label == "coupling_only") CHECK(run.at("stability").at("tunnelled").get<int64_t>() >= 1);
      if (label == "god_object") CHECK(run.at("stability").at("tunnelled").get<int64_t>() == 0);
    }
  }
}
}  // namespace

TEST_CASE(
    "every stress scenario runs every algorithm it lists without a crash or a non-finite "
    "force, part 1 of 4") {
  check_stress_part(0);
}
TEST_CASE(
    "every stress scenario runs every algorithm it lists without a crash or a non-finite "
    "force, part 2 of 4") {
  check_stress_part(1);
}
TEST_CASE(
    "every stress scenario runs every algorithm it lists without a crash or a non-finite "
    "force, part 3 of 4") {
  check_stress_part(2);
}
TEST_CASE(
    "every stress scenario runs every algorithm it lists without a crash or a non-finite "
    "force, part 4 of 4") {
  check_stress_part(3);
}

TEST_CASE("usage errors exit with 2") {
  const hb::test::ScratchDir work_dir("e2e_usage");
  const fs::path& work = work_dir.path();
  CHECK(hb::test::run_hapticbench("", work).exit_code == 2);
  CHECK(hb::test::run_hapticbench("frobnicate", work).exit_code == 2);
  CHECK(hb::test::run_hapticbench("run", work).exit_code == 2);
  CHECK(hb::test::run_hapticbench("run --bogus x.json", work).exit_code == 2);
  CHECK(hb::test::run_hapticbench("run does_not_exist.json", work).exit_code == 2);
  // A forgotten value is not taken from the next option.
  const std::string press = (kSource / "scenarios/smoke/sphere_press_box.json").string();
  const hb::test::CommandResult forgotten =
      hb::test::run_hapticbench("run '" + press + "' --out --quiet", work);
  CHECK(forgotten.exit_code == 2);
  CHECK(forgotten.stderr_text.find("--out needs a value") != std::string::npos);
  CHECK_FALSE(fs::exists(work / "--quiet"));
}

TEST_CASE("runs that measure less than they seem to say so: console, summary and report") {
  // A hook (mesh) tool held 50 cm above a hook (mesh) scene: the 3-DOF
  // god-object renders only the tool's origin, no reference block means no
  // penetration truth, and nothing ever touches.
  const hb::test::ScratchDir work_dir("e2e_sanity_warnings");
  const fs::path& work = work_dir.path();
  const std::string hook = (kSource / "scenarios/stress/meshes/hook.off").string();
  json scenario = {{"name", "far_above"},
                   {"scene", {{{"mesh", hook}, {"pose", {{"p", {0, 0, 0}}, {"q", {1, 0, 0, 0}}}}}}},
                   {"tool", {{"mesh", hook}, {"density", 1000}}},
                   {"trace",
                    {{"generator", "rest"},
                     {"duration_s", 0.2},
                     {"seed", 1},
                     {"params", {{"p", {0, 0, 0.5}}, {"q", {1, 0, 0, 0}}}}}},
                   {"algorithms",
                    {{{"name", "god_object_3dof"}, {"label", "point"}},
                     {{"name", "god_object"}, {"label", "god_object"}}}}};
  std::ofstream(work / "far_above.json") << scenario.dump(2);
  const hb::test::CommandResult result =
      hb::test::run_hapticbench("run far_above.json --out run", work);
  INFO(result.stdout_text << result.stderr_text);
  REQUIRE(result.exit_code == 0);
  CHECK(result.stderr_text.find("/algorithms/0: point (god_object_3dof) renders the tool's origin "
                                "only") != std::string::npos);
  CHECK(result.stderr_text.find("/reference: absent, and the scene has meshes") !=
        std::string::npos);
  CHECK(result.stdout_text.find("warning: no algorithm reported a contact") != std::string::npos);
  const json summary = json::parse(hb::test::read_text_file(work / "run/summary.json"));
  REQUIRE(summary.at("warnings").size() == 3);
  CHECK(summary.at("warnings").at(2).get<std::string>().find("never reach the scene") !=
        std::string::npos);
  // validate says the scenario's own two.
  const hb::test::CommandResult validated =
      hb::test::run_hapticbench("validate far_above.json", work);
  CHECK(validated.exit_code == 0);
  CHECK(validated.stderr_text.find("renders the tool's origin only") != std::string::npos);
  // ... and where the trace takes the tool: never near the scene.
  CHECK(validated.stdout_text.find("clearance of the tool from the scene at the device's pose") !=
        std::string::npos);
  CHECK(validated.stderr_text.find("the trace never brings the tool to the scene") !=
        std::string::npos);
  // The report lists all three.
  const hb::test::CommandResult report = hb::test::run_hapticbench("report run", work);
  REQUIRE(report.exit_code == 0);
  const std::string html = hb::test::read_text_file(work / "report.html");
  CHECK(html.find("3 warnings: what a run may not measure as it seems to.") != std::string::npos);
  CHECK(html.find("never reach the scene") != std::string::npos);
}

TEST_CASE("run takes --algo more than once, and --version names the build") {
  const hb::test::ScratchDir work_dir("e2e_algo_twice");
  const fs::path& work = work_dir.path();
  const std::string press = (kSource / "scenarios/smoke/sphere_press_box.json").string();
  const hb::test::CommandResult two = hb::test::run_hapticbench(
      "run '" + press + "' --algo penalty_implicit --algo coupling_only --out two --quiet", work);
  INFO(two.stderr_text);
  REQUIRE(two.exit_code == 0);
  const json summary = json::parse(hb::test::read_text_file(work / "two/summary.json"));
  std::vector<std::string> labels;
  for (const json& run : summary.at("runs")) labels.push_back(run.at("label"));
  CHECK(labels == std::vector<std::string>{"coupling_only", "penalty_implicit"});  // scenario order
  // A pattern over the labels.
  const hb::test::CommandResult pattern = hb::test::run_hapticbench(
      "run '" + press + "' --algo 'penalty_*' --out pattern --quiet", work);
  REQUIRE(pattern.exit_code == 0);
  CHECK(json::parse(hb::test::read_text_file(work / "pattern/summary.json")).at("runs").size() ==
        3);
  const hb::test::CommandResult none = hb::test::run_hapticbench(
      "run '" + press + "' --algo nothing --algo neither --out none --quiet", work);
  CHECK(none.exit_code == 2);
  CHECK(none.stderr_text.find("\"nothing\" or \"neither\"") != std::string::npos);

  const hb::test::CommandResult version = hb::test::run_hapticbench("--version", work);
  CHECK(version.exit_code == 0);
  CHECK(version.stdout_text.rfind("hapticbench 0.", 0) == 0);
  CHECK(version.stdout_text.find("(commit ") != std::string::npos);
  CHECK(version.stdout_text.find(" build)") != std::string::npos);
}

TEST_CASE("run --scenario filters the files by pattern, --explain prints the columns' legend") {
  const hb::test::ScratchDir work_dir("e2e_scenario_filter");
  const fs::path& work = work_dir.path();
  const std::string smoke = (kSource / "scenarios/smoke").string();
  const std::string files = "'" + smoke + "/sphere_press_box.json' '" + smoke +
                            "/press_drag_friction.json' '" + smoke + "/slow_contact_loop.json'";
  const hb::test::CommandResult one = hb::test::run_hapticbench(
      "run " + files + " --scenario '*press_box' --algo coupling_only --out one --quiet", work);
  INFO(one.stderr_text);
  REQUIRE(one.exit_code == 0);
  CHECK(fs::exists(work / "one/summary.json"));  // one scenario: the folder is its run folder
  CHECK(one.stdout_text.find("scenario sphere_press_box") != std::string::npos);
  CHECK(one.stdout_text.find("press_drag_friction") == std::string::npos);
  CHECK(one.stdout_text.find("hapticbench run --explain") != std::string::npos);
  const hb::test::CommandResult none =
      hb::test::run_hapticbench("run " + files + " --scenario 'nothing*' --quiet", work);
  CHECK(none.exit_code == 2);
  CHECK(none.stderr_text.find("no scenario file of the 3 given matches") != std::string::npos);
  // A label no scenario has, given to --expect-unstable: most likely a typo.
  const hb::test::CommandResult typo = hb::test::run_hapticbench(
      "run '" + smoke + "/sphere_press_box.json' --expect-unstable penalty_implict --quiet", work);
  CHECK(typo.exit_code == 2);
  CHECK(typo.stderr_text.find("no scenario given has the label \"penalty_implict\"") !=
        std::string::npos);

  const hb::test::CommandResult legend = hb::test::run_hapticbench("run --explain", work);
  REQUIRE(legend.exit_code == 0);
  for (const char* column :
       {"p50_us", "p99_us", "cpu99_us", "F_err_N", "pen_max_mm", "E_min_mJ", "nonfin", "stability"})
    CHECK(legend.stdout_text.find(std::string("| `") + column + "` |") != std::string::npos);
  // docs/metrics.md holds the legend as the command prints it.
  CHECK(hb::test::read_text_file(kSource / "docs/metrics.md").find(legend.stdout_text) !=
        std::string::npos);
}

TEST_CASE("an algorithm that cannot render the scene is an error at its /algorithms entry") {
  const hb::test::ScratchDir work_dir("e2e_algorithm_scene");
  const fs::path& work = work_dir.path();
  json scenario =
      json::parse(hb::test::read_text_file(kSource / "scenarios/smoke/sphere_press_box.json"));
  scenario["scene"][0] = {
      {"mesh", (kSource / "tests/harness/scenario/data/cube_2units.off").string()}, {"scale", 0.1}};
  scenario["algorithms"] = {{{"name", "coupling_only"}},
                            {{"name", "penalty_analytic"}, {"label", "pa"}}};
  std::ofstream(work / "mesh_scene.json") << scenario.dump(2);
  for (const char* command : {"validate mesh_scene.json", "run mesh_scene.json --quiet"}) {
    const hb::test::CommandResult result = hb::test::run_hapticbench(command, work);
    INFO(command << ": " << result.stderr_text);
    CHECK(result.exit_code == 2);
    CHECK(result.stderr_text.find("mesh_scene.json: /algorithms/1: penalty_analytic (label pa) "
                                  "cannot run on this scenario: /scene/0: ") != std::string::npos);
  }
}

}  // namespace
