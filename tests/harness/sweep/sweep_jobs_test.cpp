// Expanding a sweep into jobs: order, names, values set by JSON pointer,
// only_algorithms, absolute file paths, and the errors of each.
#include "harness/sweep/sweep_jobs.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/sweep/job_name.h"
#include "harness/sweep/sweep_spec.h"
#include "tests/support/scratch_dir.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

void write_file(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

// A small valid scenario: a sphere pressed onto a box, two penalty
// algorithms, 0.2 s.
Json press_scenario(const std::string& name) {
  return Json::parse(R"({
    "name": ")" + name +
                     R"(",
    "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] }, "pose": { "p": [0, 0, -0.01] } } ],
    "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 2 }, "density": 1000 },
    "trace": { "generator": "press", "duration_s": 0.2, "seed": 1 },
    "coupling": { "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 },
    "algorithms": [
      { "name": "penalty_analytic", "label": "soft", "params": { "contact_stiffness": 1000 } },
      { "name": "penalty_analytic", "label": "stiff", "params": { "contact_stiffness": 5000 } },
      { "name": "coupling_only" }
    ]
  })");
}

// Writes scenario files and a sweep file; returns the sweep's path.
std::string write_sweep(const fs::path& dir, const std::vector<Json>& scenarios,
                        const Json& sweep) {
  // The sweep sits in a folder of its own: scenario paths are relative to it.
  Json with_entries = sweep;
  with_entries["scenarios"] = Json::array();
  for (const Json& scenario : scenarios) {
    const std::string file = scenario["name"].get<std::string>() + ".json";
    write_file(dir / "scenarios" / file, scenario.dump(2));
    with_entries["scenarios"].push_back("../scenarios/" + file);
  }
  const fs::path path = dir / "sweeps" / "grid.json";
  write_file(path, with_entries.dump(2));
  return path.string();
}

std::vector<hb::SweepJob> expand(const std::string& path) {
  return hb::expand_sweep_jobs(hb::load_sweep_spec(path));
}

}  // namespace

// A job's scenario as a sweep reads it, errors re-anchored on the sweep file.
hb::Scenario job_scenario(const hb::SweepSpec& spec, const hb::SweepJob& job) {
  try {
    return hb::load_scenario_json(hb::sweep_job_scenario_text(job), job.scenario_path,
                                  job.base_dir);
  } catch (const hb::InputError& error) {
    throw hb::sweep_job_error(spec, job, error);
  }
}

TEST_CASE("jobs are scenarios x grid values, scenarios first, the last grid key fastest") {
  const hb::test::ScratchDir scratch("sweep_jobs_order");
  const fs::path& dir = scratch.path();
  const std::vector<int> k_t = {1000, 2000};
  const std::vector<int> stiffness = {10, 20, 30};
  const std::string path = write_sweep(
      dir, {press_scenario("a"), press_scenario("b")},
      {{"name", "order"},
       {"grid", {{"/coupling/k_t", k_t}, {"/algorithms/0/params/contact_stiffness", stiffness}}}});
  const std::vector<hb::SweepJob> jobs = expand(path);
  REQUIRE(jobs.size() == 2 * 2 * 3);

  std::size_t index = 0;
  for (const std::string scenario : {"a", "b"})
    for (int k : k_t)
      for (int s : stiffness) {
        const hb::SweepJob& job = jobs[index];
        INFO("job " << index);
        CHECK(job.index == index);
        const std::string expected_name =
            scenario + "__k_t=" + std::to_string(k) + "__contact_stiffness=" + std::to_string(s);
        CHECK(job.name == expected_name);
        CHECK(job.scenario["name"] == expected_name);
        CHECK(job.scenario["coupling"]["k_t"] == k);
        CHECK(job.scenario["algorithms"][0]["params"]["contact_stiffness"] == s);
        // Values the grid does not name stay as written.
        CHECK(job.scenario["algorithms"][1]["params"]["contact_stiffness"] == 5000);
        CHECK(job.scenario["coupling"]["b_t"] == 5);
        CHECK(fs::path(job.scenario_path).filename() == scenario + ".json");
        REQUIRE(job.grid_values.size() == 2);
        CHECK(job.grid_values[0].first == "/coupling/k_t");
        CHECK(job.grid_values[0].second == k);
        CHECK(job.grid_values[1].second == s);
        ++index;
      }
}

TEST_CASE("a sweep without a grid has one job per scenario, named as the scenario") {
  const hb::test::ScratchDir scratch("sweep_jobs_no_grid");
  const fs::path& dir = scratch.path();
  const std::vector<hb::SweepJob> jobs =
      expand(write_sweep(dir, {press_scenario("a"), press_scenario("b")}, {{"name", "plain"}}));
  REQUIRE(jobs.size() == 2);
  CHECK(jobs[0].name == "a");
  CHECK(jobs[1].name == "b");
}

TEST_CASE("a missing last key of an existing object is added: a new parameter") {
  const hb::test::ScratchDir scratch("sweep_jobs_new_leaf");
  const fs::path& dir = scratch.path();
  const std::vector<hb::SweepJob> jobs = expand(write_sweep(
      dir, {press_scenario("a")},
      {{"name", "leaf"}, {"grid", {{"/algorithms/0/params/proxy_mass_kg", {0.1, 0.3}}}}}));
  REQUIRE(jobs.size() == 2);
  CHECK(jobs[0].scenario["algorithms"][0]["params"]["proxy_mass_kg"] == 0.1);
  CHECK(jobs[1].scenario["algorithms"][0]["params"]["proxy_mass_kg"] == 0.3);
  CHECK(jobs[1].scenario["algorithms"][0]["params"]["contact_stiffness"] == 1000);
  CHECK(jobs[1].name == "a__proxy_mass_kg=0.3");
}

TEST_CASE("a section with documented defaults that the scenario omits is created for a grid key") {
  const hb::test::ScratchDir scratch("sweep_jobs_defaulted_section");
  const fs::path& dir = scratch.path();
  Json scenario = press_scenario("a");
  scenario.erase("coupling");
  const std::vector<hb::SweepJob> jobs = expand(
      write_sweep(dir, {scenario},
                  {{"name", "defaults"},
                   {"grid", {{"/coupling/k_t", {1000, 3000}}, {"/algorithms/2/params/x", {1}}}}}));
  REQUIRE(jobs.size() == 2);
  CHECK(jobs[1].scenario["coupling"] == Json{{"k_t", 3000}});
  CHECK(jobs[1].scenario["algorithms"][2]["params"] == Json{{"x", 1}});
  // Not a section with defaults: still an error naming the missing key.
  const std::string path = write_sweep(
      dir, {press_scenario("b")}, {{"name", "bad"}, {"grid", {{"/closed_loop/hand/k_t", {1}}}}});
  CHECK_THROWS_WITH(expand(path), Catch::Contains("has no key \"closed_loop\""));
}

TEST_CASE("every bad grid key and label is reported at once") {
  const hb::test::ScratchDir scratch("sweep_jobs_all_errors");
  const fs::path& dir = scratch.path();
  const std::string path =
      write_sweep(dir, {press_scenario("a")},
                  {{"name", "bad"},
                   {"grid", {{"/couplingg/k_t", {1, 2}}, {"/tool/nope/x", {1}}}},
                   {"only_algorithms", {"soft", "missing"}}});
  try {
    expand(path);
    FAIL("expected an InputError");
  } catch (const hb::InputError& error) {
    const std::string message = error.message();
    INFO(message);
    CHECK(message.find("3 errors:") == 0);
    CHECK(message.find("/grid/~1couplingg~1k_t") != std::string::npos);
    CHECK(message.find("/grid/~1tool~1nope~1x") != std::string::npos);
    CHECK(message.find("/only_algorithms/1: label \"missing\"") != std::string::npos);
  }
}

TEST_CASE("a grid key whose parent is missing names the sweep file, the key and the scenario") {
  const hb::test::ScratchDir scratch("sweep_jobs_missing_parent");
  const fs::path& dir = scratch.path();
  struct Case {
    std::string pointer;
    std::string location;  // the grid key's JSON pointer in the sweep file
    std::string why;
  };
  for (const Case& c :
       {Case{"/couplingg/k_t", "/grid/~1couplingg~1k_t", "has no key \"couplingg\""},
        Case{"/algorithms/3/params/contact_stiffness",
             "/grid/~1algorithms~13~1params~1contact_stiffness", "has 3 elements, no element 3"},
        Case{"/algorithms/x/params", "/grid/~1algorithms~1x~1params", "not an element index"},
        Case{"/coupling/k_t/x", "/grid/~1coupling~1k_t~1x", "is a number, not an object or array"},
        Case{"/algorithms/2/params/a/b", "/grid/~1algorithms~12~1params~1a~1b",
             "\"/algorithms/2/params\" has no key \"a\""}}) {
    INFO(c.pointer);
    const std::string path =
        write_sweep(dir, {press_scenario("a")}, {{"name", "bad"}, {"grid", {{c.pointer, {1}}}}});
    try {
      expand(path);
      FAIL("expected an InputError");
    } catch (const hb::InputError& error) {
      CHECK(error.source() == path);
      CHECK(error.location() == c.location);
      const std::string message = error.message();
      CHECK(message.find("\"" + c.pointer + "\"") != std::string::npos);
      CHECK(message.find("a.json") != std::string::npos);
      CHECK(message.find(c.why) != std::string::npos);
    }
  }
}

TEST_CASE("only_algorithms keeps the listed labels, after the grid is applied") {
  const hb::test::ScratchDir scratch("sweep_jobs_only");
  const fs::path& dir = scratch.path();
  const std::vector<hb::SweepJob> jobs =
      expand(write_sweep(dir, {press_scenario("a")},
                         {{"name", "only"},
                          {"grid", {{"/algorithms/1/params/contact_stiffness", {7000}}}},
                          {"only_algorithms", {"coupling_only", "stiff"}}}));
  REQUIRE(jobs.size() == 1);
  const Json& algorithms = jobs[0].scenario["algorithms"];
  REQUIRE(algorithms.size() == 2);
  // Scenario order, not list order; the label defaults to the name.
  CHECK(algorithms[0]["label"] == "stiff");
  CHECK(algorithms[0]["params"]["contact_stiffness"] == 7000);
  CHECK(algorithms[1]["name"] == "coupling_only");
}

TEST_CASE("an only_algorithms label found in no scenario is named") {
  const hb::test::ScratchDir scratch("sweep_jobs_only_missing");
  const fs::path& dir = scratch.path();
  const std::string path = write_sweep(dir, {press_scenario("a")},
                                       {{"name", "only"}, {"only_algorithms", {"soft", "sotf"}}});
  try {
    expand(path);
    FAIL("expected an InputError");
  } catch (const hb::InputError& error) {
    CHECK(error.source() == path);
    CHECK(error.location() == "/only_algorithms/1");
    CHECK(error.message().find("\"sotf\"") != std::string::npos);
  }
}

TEST_CASE("job names are folder-safe and two jobs may not share one") {
  CHECK(hb::grid_value_name_text(Json("implicit_euler")) == "implicit_euler");
  CHECK(hb::grid_value_name_text(Json(0.5)) == "0.5");
  CHECK(hb::grid_value_name_text(Json(-3)) == "-3");
  CHECK(hb::grid_value_name_text(Json::parse("[0.01, 0, 0]")) == "0.01_0_0");
  CHECK(hb::grid_value_name_text(Json("a/b c")) == "a_bc");
  CHECK(hb::sweep_job_name("s", {{"/a~1b", Json(1)}}) == "s__a_b=1");
  CHECK(hb::is_safe_folder_name("s__k_t=1000"));
  CHECK_FALSE(hb::is_safe_folder_name(".."));
  CHECK_FALSE(hb::is_safe_folder_name("a/b"));
  CHECK_FALSE(hb::is_safe_folder_name(std::string(256, 'a')));

  const hb::test::ScratchDir scratch("sweep_jobs_collision");
  const fs::path& dir = scratch.path();
  const std::string path =
      write_sweep(dir, {press_scenario("a")},
                  {{"name", "collide"}, {"grid", {{"/algorithms/0/label", {"x y", "xy"}}}}});
  try {
    expand(path);
    FAIL("expected an InputError");
  } catch (const hb::InputError& error) {
    CHECK(error.source() == path);
    CHECK(error.message().find("\"a__label=xy\"") != std::string::npos);
  }
}

TEST_CASE("mesh and trace paths become absolute, resolved against the scenario's folder") {
  const hb::test::ScratchDir scratch("sweep_jobs_paths");
  const fs::path& dir = scratch.path();
  const fs::path data = fs::path(HAPTICBENCH_SOURCE_DIR) / "tests/harness/scenario/data";
  fs::create_directories(dir / "scenarios" / "assets");
  fs::copy_file(data / "cube_2units.off", dir / "scenarios" / "assets" / "cube.off");
  fs::copy_file(data / "line_trace.csv", dir / "scenarios" / "assets" / "line.csv");
  const Json scenario = Json::parse(R"({
    "name": "meshes",
    "scene": [ { "mesh": "assets/cube.off", "scale": 0.01, "pose": { "p": [0, 0, -0.02] } } ],
    "tool": { "mesh": "assets/cube.off", "scale": 0.01, "mass_kg": 0.5 },
    "trace": { "file": "assets/line.csv", "duration_s": 0.05 },
    "algorithms": [ { "name": "coupling_only" } ]
  })");
  const std::string path = write_sweep(dir, {scenario}, {{"name", "paths"}});
  const hb::SweepSpec spec = hb::load_sweep_spec(path);
  const std::vector<hb::SweepJob> jobs = hb::expand_sweep_jobs(spec);
  REQUIRE(jobs.size() == 1);
  const fs::path assets = fs::absolute(dir / "scenarios" / "assets").lexically_normal();
  CHECK(jobs[0].scenario["scene"][0]["mesh"] == (assets / "cube.off").string());
  CHECK(jobs[0].scenario["tool"]["mesh"] == (assets / "cube.off").string());
  CHECK(jobs[0].scenario["trace"]["file"] == (assets / "line.csv").string());

  // The job's text loads on its own, wherever it is read from.
  const hb::Scenario loaded =
      hb::load_scenario_json(hb::sweep_job_scenario_text(jobs[0]), "elsewhere.json", "/");
  CHECK(loaded.name == "meshes");
  CHECK(loaded.path == "elsewhere.json");
  CHECK(loaded.trajectory.ticks() == 50);
  CHECK(job_scenario(spec, jobs[0]).content_hash == loaded.content_hash);
}

TEST_CASE("load_scenario_json resolves relative paths against base_dir, errors name source_path") {
  const hb::test::ScratchDir scratch("sweep_jobs_base_dir");
  const fs::path& dir = scratch.path();
  const fs::path data = fs::path(HAPTICBENCH_SOURCE_DIR) / "tests/harness/scenario/data";
  fs::copy_file(data / "line_trace.csv", dir / "line.csv");
  const std::string text = R"({
    "name": "relative",
    "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] } } ],
    "tool": { "shape": { "type": "sphere", "radius": 0.02 } },
    "trace": { "file": "line.csv" },
    "algorithms": [ { "name": "coupling_only" } ]
  })";
  const hb::Scenario scenario = hb::load_scenario_json(text, "in-memory.json", dir);
  CHECK(scenario.trace_description.find((dir / "line.csv").string()) != std::string::npos);
  // The same text with the file's own folder as base is the same scenario.
  write_file(dir / "relative.json", text);
  CHECK(hb::load_scenario((dir / "relative.json").string()).content_hash == scenario.content_hash);

  try {
    hb::load_scenario_json(text, "in-memory.json", dir / "nowhere");
    FAIL("expected an InputError");
  } catch (const hb::InputError& error) {
    CHECK(error.source() == "in-memory.json");
    CHECK(error.location() == "/trace/file");
  }
}

TEST_CASE("a job whose values the scenario rejects names the sweep, the job and the field") {
  const hb::test::ScratchDir scratch("sweep_jobs_bad_value");
  const fs::path& dir = scratch.path();
  const std::string path = write_sweep(
      dir, {press_scenario("a")}, {{"name", "bad"}, {"grid", {{"/coupling/k_t", {1000, -5}}}}});
  const hb::SweepSpec spec = hb::load_sweep_spec(path);
  const std::vector<hb::SweepJob> jobs = hb::expand_sweep_jobs(spec);
  REQUIRE(jobs.size() == 2);
  CHECK(job_scenario(spec, jobs[0]).context.coupling.k_t == 1000);
  try {
    job_scenario(spec, jobs[1]);
    FAIL("expected an InputError");
  } catch (const hb::InputError& error) {
    CHECK(error.source() == path);
    CHECK(error.location() == "job a__k_t=-5");
    CHECK(error.message().find("a.json: /coupling/k_t:") != std::string::npos);
  }
}

TEST_CASE("a malformed scenario file is named, with the sweep entry that lists it") {
  const hb::test::ScratchDir scratch("sweep_jobs_malformed_scenario");
  const fs::path& dir = scratch.path();
  write_file(dir / "scenarios" / "broken.json", "{\n  \"name\": \"broken\",\n}");
  write_file(dir / "sweeps" / "grid.json",
             R"({"name": "g", "scenarios": ["../scenarios/broken.json"]})");
  try {
    expand((dir / "sweeps" / "grid.json").string());
    FAIL("expected an InputError");
  } catch (const hb::InputError& error) {
    CHECK(fs::path(error.source()).filename() == "broken.json");
    CHECK(error.location().find("line 3") == 0);
    CHECK(error.message().find("grid.json at /scenarios/0") != std::string::npos);
  }
}
