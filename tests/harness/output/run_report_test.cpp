// junit.xml of a run: every test case, passing or not, gives its measured
// value and its limit, so a CI's test view shows the margin.
#include "harness/output/run_report.h"

#include <catch2/catch.hpp>
#include <string>

TEST_CASE("every budget test case in junit.xml carries the measured value and the limit") {
  hb::ScenarioRun scenario;
  scenario.scenario_name = "press";
  hb::AlgorithmRun run;
  run.name = "penalty_analytic";
  run.label = "penalty";
  run.budgets.push_back({"force_err_rms_n", 1.0, 0.25, true, ""});
  run.budgets.push_back(
      {"tick_p99_us", 50.0, 75.5, false, "tick_p99_us = 75.5 exceeds the limit 50"});
  scenario.runs.push_back(run);
  const std::string xml = hb::junit_xml(scenario);
  INFO(xml);
  CHECK(xml.find("name=\"force_err_rms_n\"><system-out>force_err_rms_n = 0.25, limit 1"
                 "</system-out></testcase>") != std::string::npos);
  CHECK(xml.find("name=\"tick_p99_us\"><failure message=\"tick_p99_us = 75.5 exceeds the limit "
                 "50\">tick_p99_us = 75.5, limit 50</failure>") != std::string::npos);
  CHECK(xml.find("tests=\"3\" failures=\"1\"") != std::string::npos);  // with stability
}
