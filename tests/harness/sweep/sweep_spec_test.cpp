// Reading a sweep file: every rejection names the file and the field.
#include "harness/sweep/sweep_spec.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "hapticbench/input_error.h"
#include "tests/support/scratch_dir.h"

namespace {

namespace fs = std::filesystem;

// One folder per test process: ctest runs this file's cases side by side.
fs::path spec_scratch() {
  static const hb::test::ScratchDir folder("sweep_spec");
  const fs::path& dir = folder.path();
  fs::create_directories(dir / "scenarios");
  std::ofstream(dir / "scenarios" / "a.json") << "{}";
  std::ofstream(dir / "scenarios" / "b.json") << "{}";
  return dir;
}

// The InputError parse_sweep_spec throws for `text` (a sweep file in dir).
hb::InputError rejection(const fs::path& dir, const std::string& text) {
  const std::string path = (dir / "sweep.json").string();
  try {
    hb::parse_sweep_spec(text, path);
  } catch (const hb::InputError& error) {
    CHECK(error.source() == path);
    return error;
  }
  FAIL("expected an InputError for " << text);
  return hb::InputError("", "", "");
}

}  // namespace

TEST_CASE("a sweep file is read with scenario paths relative to it and grid keys in file order") {
  const fs::path dir = spec_scratch();
  const hb::SweepSpec spec = hb::parse_sweep_spec(R"({
    "name": "s1", "description": "two keys",
    "scenarios": ["scenarios/a.json", "scenarios/b.json"],
    "grid": { "/z/last": [1, 2], "/a/first": ["x"] },
    "only_algorithms": ["p"] })",
                                                  (dir / "sweep.json").string());
  CHECK(spec.name == "s1");
  REQUIRE(spec.scenario_paths.size() == 2);
  CHECK(spec.scenario_entries[0] == "scenarios/a.json");
  CHECK(spec.scenario_paths[1] == (dir / "scenarios" / "b.json").string());
  REQUIRE(spec.grid.size() == 2);
  CHECK(spec.grid[0].pointer == "/z/last");  // file order, not sorted
  CHECK(spec.grid[0].values.size() == 2);
  CHECK(spec.grid[1].values[0] == "x");
  REQUIRE(spec.only_algorithms.size() == 1);
  CHECK(spec.only_algorithms[0] == "p");
}

TEST_CASE("bad sweep files are rejected naming the field") {
  const fs::path dir = spec_scratch();
  const std::string scenarios = R"("scenarios": ["scenarios/a.json"])";
  struct Case {
    std::string text;
    std::string location;
    std::string says;
  };
  for (
      const Case& c : {
          Case{R"({"name": "s", )" + scenarios + R"(, "gird": {}})", "/gird",
               "did you mean \"grid\""},
          Case{R"({"name": "s"})", "/scenarios", "missing"},
          Case{R"({"name": "s/x", )" + scenarios + "}", "/name", "letters, digits"},
          Case{R"({)" + scenarios + "}", "/name", "missing"},
          Case{R"({"name": "s", "scenarios": []})", "/scenarios", "non-empty array"},
          Case{R"({"name": "s", "scenarios": ["scenarios/none.json"]})", "/scenarios/0",
               "not found"},
          Case{
              R"({"name": "s", "scenarios": ["scenarios/a.json", "scenarios/../scenarios/a.json"]})",
              "/scenarios/1", "also /scenarios/0"},
          Case{R"({"name": "s", )" + scenarios + R"(, "grid": [1]})", "/grid",
               "expected an object"},
          Case{R"({"name": "s", )" + scenarios + R"(, "grid": {"coupling/k_t": [1]}})",
               "/grid/coupling~1k_t", "not a JSON pointer"},
          Case{R"({"name": "s", )" + scenarios + R"(, "grid": {"/a~2": [1]}})", "/grid/~1a~02",
               "not a JSON pointer"},
          Case{R"({"name": "s", )" + scenarios + R"(, "grid": {"/name": ["x"]}})", "/grid/~1name",
               "names each job"},
          Case{R"({"name": "s", )" + scenarios + R"(, "grid": {"/coupling/k_t": []}})",
               "/grid/~1coupling~1k_t", "non-empty array"},
          Case{R"({"name": "s", )" + scenarios + R"(, "grid": {"/coupling/k_t": 1000}})",
               "/grid/~1coupling~1k_t", "non-empty array"},
          Case{R"({"name": "s", )" + scenarios + R"(, "grid": {"/coupling/k_t": [1, 2, 1]}})",
               "/grid/~1coupling~1k_t/2", "also element 0"},
          Case{R"({"name": "s", )" + scenarios + R"(, "only_algorithms": "p"})", "/only_algorithms",
               "array of algorithm labels"},
          Case{R"({"name": "s", )" + scenarios + R"(, "only_algorithms": ["p", "p"]})",
               "/only_algorithms/1", "listed twice"},
          Case{R"({"name": "s", )" + scenarios + R"(, "grid": {"/a": [1], "/a": [2]}})",
               "/grid/~1a", "given twice"},
          Case{"{\"name\": \"s\",\n  \"scenarios\": [}", "line 2, column 17", "malformed JSON"},
      }) {
    INFO(c.text);
    const hb::InputError error = rejection(dir, c.text);
    CHECK(error.location() == c.location);
    CHECK(error.message().find(c.says) != std::string::npos);
  }
}

TEST_CASE("a missing sweep file is named") {
  try {
    hb::load_sweep_spec("/nonexistent/sweep.json");
    FAIL("expected an InputError");
  } catch (const hb::InputError& error) {
    CHECK(error.source() == "/nonexistent/sweep.json");
  }
}
