#include "harness/output/run_table.h"

#include <catch2/catch.hpp>
#include <sstream>
#include <string>

namespace {

hb::ScenarioRun one_run(const hb::NoiseFloor& noise) {
  hb::ScenarioRun scenario;
  scenario.scenario_name = "press";
  hb::AlgorithmRun run;
  run.name = "penalty_analytic";
  run.label = "penalty";
  run.noise = noise;
  scenario.runs.push_back(run);
  return scenario;
}

std::string table_of(const hb::ScenarioRun& scenario) {
  std::ostringstream out;
  hb::print_run_table(out, scenario);
  return out.str();
}

}  // namespace

TEST_CASE("the run table says when the machine was not quiet, and why") {
  hb::NoiseFloor quiet;
  quiet.cpu_share = 0.99;
  quiet.load_average_1m = 0.3;
  quiet.logical_cores = 2;
  quiet.other_runnable = 0;
  quiet.quiet = true;
  CHECK(table_of(one_run(quiet)).find("not quiet") == std::string::npos);

  hb::NoiseFloor busy = quiet;
  busy.quiet = false;
  busy.cpu_share = 0.62;
  busy.load_average_1m = 2.9;
  const std::string table = table_of(one_run(busy));
  INFO(table);
  CHECK(table.find("timing: the machine was not quiet while timing penalty (CPU share 0.62, load "
                   "2.9 on 2 cores)") != std::string::npos);
  CHECK(table.find("not comparable with a quiet run's") != std::string::npos);
}
