// End-to-end: docs/metric-table.md is what `hapticbench list --metrics`
// prints, so the documented table cannot drift from the code's; and a
// metric of the table appears in summary.json at its place and works as a
// budget.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "harness/metrics/metric_table.h"
#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::kSource;

namespace fs = std::filesystem;

TEST_CASE("docs/metric-table.md holds the output of list --metrics") {
  const hb::test::ScratchDir work("e2e_metric_table");
  const auto listed = hb::test::run_hapticbench("list --metrics", work.path());
  REQUIRE(listed.exit_code == 0);
  const std::string doc = hb::test::read_text_file(kSource / "docs/metric-table.md");
  const std::size_t table = doc.find("| metric");
  REQUIRE(table != std::string::npos);
  CHECK(doc.substr(table) == listed.stdout_text);
}

TEST_CASE("every metric of the table is in a run's summary at its place") {
  const hb::test::ScratchDir work("e2e_metric_places");
  const auto run = hb::test::run_hapticbench(
      "run " + (kSource / "scenarios/smoke/box_press_box.json").string() + " --out run",
      work.path());
  REQUIRE(run.exit_code == 0);
  const nlohmann::json summary =
      nlohmann::json::parse(hb::test::read_text_file(work / "run/summary.json"));
  for (const nlohmann::json& r : summary.at("runs"))
    for (const hb::MetricDefinition& metric : hb::metric_table()) {
      INFO(r.at("label") << " " << metric.name);
      const nlohmann::json::json_pointer pointer{std::string(metric.json_pointer)};
      if (metric.compare_when_present && !r.contains(pointer)) continue;
      REQUIRE(r.contains(pointer));
      const nlohmann::json& value = r.at(pointer);
      if (metric.compare == hb::CompareRule::kFlag)
        CHECK(value.is_boolean());
      else
        CHECK((value.is_number() || value.is_null()));
    }
}

}  // namespace
