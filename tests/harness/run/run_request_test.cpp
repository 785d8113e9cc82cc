// The run request: reading applies the JSON-pointer edits to one reading of
// the file, refuses what is not a regular file, loads no plugin the
// policy does not allow (parsing alone loads none), and checks algorithm
// names against the registry with the file and field named.
#include "harness/run/run_request.h"

#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "hapticbench/input_error.h"
#include "harness/plugins/plugin_loader.h"
#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

using Json = nlohmann::ordered_json;

Json press_scenario() {
  return Json::parse(R"({
    "name": "press_box",
    "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] },
                 "pose": { "p": [0, 0, -0.01], "q": [1, 0, 0, 0] } } ],
    "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 3 }, "density": 1000 },
    "trace": { "generator": "press", "duration_s": 0.05, "seed": 3 },
    "coupling": { "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 },
    "algorithms": [ { "name": "coupling_only", "label": "first" } ],
    "reference": { "oracle": "embree" }
  })");
}

std::string write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

// The InputError `read` throws (FAIL when it throws none).
InputError error_of(const RunRequest& request) {
  try {
    read_scenario(request);
  } catch (const InputError& error) {
    return error;
  }
  FAIL("read_scenario accepted the request");
  return InputError("", "", "");
}

TEST_CASE("a request's edits are made to one reading of the file, in order") {
  const test::ScratchDir work("run_request_edits");
  const std::string path = write_file(work / "press.json", press_scenario().dump());
  RunRequest request;
  request.scenario = ScenarioSource::read_now(path);
  // The file changes after it was read: the request keeps its reading.
  write_file(path, "not JSON");
  request.edits = {{"/coupling/k_t", 3000}, {"/coupling/k_t", 4500}, {"/coupling/b_t", 7}};
  const Scenario scenario = read_scenario(request);
  CHECK(scenario.context.coupling.k_t == 4500);
  CHECK(scenario.context.coupling.b_t == 7);
  CHECK(scenario.path == path);
  CHECK_FALSE(scenario.reference.oracle_backends.empty());

  request.ground_truth = false;
  CHECK(read_scenario(request).reference.oracle_backends.empty());

  request.edits = {{"/coupling/no_such/k", 1}};
  const InputError error = error_of(request);
  CHECK(error.source() == path);
  CHECK(error.location() == "/coupling/no_such/k");
  CHECK(std::string(error.what()).find("cannot set it") != std::string::npos);
}

TEST_CASE("a request reads only a regular file") {
  const test::ScratchDir work("run_request_fifo");
  const std::string fifo = (work / "scenario.json").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  try {
    ScenarioSource::read_now(fifo);
    FAIL("a FIFO was read");
  } catch (const InputError& error) {
    CHECK(error.source() == fifo);
    CHECK(std::string(error.what()).find("not a regular file") != std::string::npos);
  }
  RunRequest request;
  request.scenario = ScenarioSource::file((work / "missing.json").string());
  CHECK(std::string(error_of(request).what()).find("file not found") != std::string::npos);
}

TEST_CASE("an unknown algorithm is caught when a request reads the scenario") {
  const test::ScratchDir work("run_request_unknown");
  Json document = press_scenario();
  document["algorithms"].push_back({{"name", "no_such_algorithm"}});
  const std::string path = write_file(work / "press.json", document.dump());
  // Parsing alone does not consult the registry.
  CHECK(load_scenario(path).algorithms.size() == 2);
  RunRequest request;
  request.scenario = ScenarioSource::file(path);
  const InputError error = error_of(request);
  INFO(error.what());
  CHECK(error.source() == path);
  CHECK(error.location() == "/algorithms/1/name");
  CHECK(std::string(error.what()).find("unknown algorithm \"no_such_algorithm\" (known: ") !=
        std::string::npos);
  CHECK(std::string(error.what()).find("coupling_only") != std::string::npos);
  CHECK(std::string(error.what()).find("loads with --plugin PATH.so") != std::string::npos);
}

TEST_CASE("reading a scenario loads no plugin it names, the run request asks the policy") {
  const test::ScratchDir work("run_request_plugins");
  // Not a library at all: loading it would fail loudly, parsing must not try.
  write_file(work / "stranger.so", "not a shared library");
  Json document = press_scenario();
  document["plugins"] = {"stranger.so"};
  document["algorithms"].push_back({{"name", "strangers_renderer"}});
  const std::string path = write_file(work / "press.json", document.dump());

  const Scenario parsed = load_scenario(path);
  REQUIRE(parsed.plugins.size() == 1);
  CHECK(parsed.plugins[0].path == (work / "stranger.so").string());
  CHECK(parsed.plugins[0].pointer == "/plugins/0");
  CHECK(loaded_plugins().empty());

  RunRequest request;
  request.scenario = ScenarioSource::file(path);
  SECTION("by default a plugin a scenario names is refused, at its field") {
    const InputError error = error_of(request);
    CHECK(error.source() == path);
    CHECK(error.location() == "/plugins/0");
    CHECK(std::string(error.what()).find(kAllowScenarioPluginsFlag) != std::string::npos);
  }
  SECTION("as validate reads, the plugin stays unloaded and its algorithm unchecked") {
    set_scenario_plugins(ScenarioPlugins::kNotLoaded);
    const Scenario scenario = read_scenario(request);
    set_scenario_plugins(ScenarioPlugins::kOnlyLoaded);
    REQUIRE(scenario.algorithms.size() == 1);
    CHECK(scenario.algorithms[0].label == "first");
    REQUIRE_FALSE(scenario.warnings.empty());
    CHECK(scenario.warnings[0].find("/algorithms/1/name: algorithm \"strangers_renderer\" is not "
                                    "checked") == 0);
  }
  CHECK(loaded_plugins().empty());
}

}  // namespace
}  // namespace hb
