// End-to-end: `hapticbench export --format gbench` writes Google Benchmark's
// JSON. The file is checked with that format's own field rules (what its
// compare.py and dashboards read): a context object and a list of
// benchmarks, each with a string name, a whole positive number of
// iterations, numeric real_time and cpu_time and a time_unit of ns, us, ms
// or s; counters are plain numbers.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::kSource;

namespace fs = std::filesystem;
using hb::test::run_hapticbench;
using nlohmann::json;

TEST_CASE("export --format gbench follows Google Benchmark's JSON field rules") {
  const hb::test::ScratchDir work("e2e_export");
  const std::string scenarios = (kSource / "scenarios/smoke/sphere_press_box.json").string() + " " +
                                (kSource / "scenarios/smoke/box_press_box.json").string();
  REQUIRE(run_hapticbench("run " + scenarios + " --out runs", work.path()).exit_code == 0);
  const auto exported =
      run_hapticbench("export --format gbench runs --out bench.json", work.path());
  INFO(exported.stderr_text);
  REQUIRE(exported.exit_code == 0);

  const json file = json::parse(hb::test::read_text_file(work / "bench.json"));
  REQUIRE(file.is_object());
  REQUIRE(file.at("context").is_object());
  CHECK(file.at("context").at("num_cpus").is_number_integer());
  CHECK(file.at("context").at("library_build_type").is_string());
  const json& benchmarks = file.at("benchmarks");
  REQUIRE(benchmarks.is_array());
  std::set<std::string> names;
  for (const json& b : benchmarks) {
    REQUIRE(b.at("name").is_string());
    names.insert(b.at("name").get<std::string>());
    CHECK(b.at("run_name") == b.at("name"));
    CHECK(b.at("run_type") == "iteration");
    CHECK(b.at("iterations").is_number_integer());
    CHECK(b.at("iterations").get<int64_t>() == 2000);  // one per tick
    CHECK(b.at("real_time").is_number());
    CHECK(b.at("cpu_time").is_number());
    CHECK(b.at("real_time").get<double>() > 0);
    CHECK(std::set<std::string>{"ns", "us", "ms", "s"}.count(b.at("time_unit")) == 1);
    for (const auto& [key, value] : b.items())
      if (key != "name" && key != "run_name" && key != "run_type" && key != "time_unit")
        CHECK(value.is_number());
    CHECK(b.at("step_p99_ns").get<double>() > 0);
    // The headline accuracy: the force error here (every smoke scenario has a reference).
    CHECK(b.at("headline_accuracy") == b.at("force_err_rms_n"));
    CHECK(b.at("headline_accuracy_is_fallback") == 0);
  }
  CHECK(names.count("sphere_press_box/penalty_implicit") == 1);
  CHECK(names.count("box_press_box/god_object") == 1);
  CHECK(names.size() == benchmarks.size());  // names are unique

  // Its own file is replaced; a file of the user's is not.
  CHECK(run_hapticbench("export --format gbench runs --out bench.json", work.path()).exit_code ==
        0);
  std::ofstream(work / "mine.json") << "{}";
  CHECK(run_hapticbench("export --format gbench runs --out mine.json", work.path()).exit_code == 2);
  CHECK(hb::test::read_text_file(work / "mine.json") == "{}");
  CHECK(run_hapticbench("export --format csv runs", work.path()).exit_code == 2);
}

}  // namespace
