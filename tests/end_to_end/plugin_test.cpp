// End-to-end: renderers built outside hapticbench, loaded as plugins
// (include/hapticbench/plugin.h). The example renderer of
// examples/out_of_tree_renderer/ runs, lists, sweeps and reports like a
// built-in one; a missing file, a library without the entry point, another
// ABI version and a taken name are each refused with exit 2, the path and
// the reason, and leave no run folder.
#include "hapticbench/plugin.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::kSource;

namespace fs = std::filesystem;
using json = nlohmann::json;
using hb::test::CommandResult;

// The test plugins of the build this executable belongs to.
const fs::path kPlugins = hb::test::in_own_build("tests/plugins", HAPTICBENCH_TEST_PLUGINS_DIR);
const fs::path kExample = kSource / "examples/out_of_tree_renderer";
const std::string kVertexPenalty = (kPlugins / "vertex_penalty.so").string();
const std::string kOriginPenalty = (kPlugins / "origin_penalty.so").string();
const std::string kLeavesMark = (kPlugins / "plugin_leaves_mark.so").string();
const std::string kMisbehaving = (kPlugins / "plugin_misbehaving.so").string();

// The example's scenario, 0.3 s long, with the built-in penalty proxy
// beside the plugin's renderer, in the work folder.
void write_short_example_scenario(const fs::path& path) {
  json scenario = json::parse(hb::test::read_text_file(kExample / "sphere_press_box.json"));
  scenario["trace"]["duration_s"] = 0.3;
  scenario["algorithms"].push_back({{"name", "penalty_analytic"}, {"label", "penalty_implicit"}});
  scenario["budgets"] = json::object();
  std::ofstream(path) << scenario.dump(2);
}

TEST_CASE(
    "the one-page renderer of docs/plugins.md is the example's file, and its contacts check") {
  // The page shows the whole file: what a reader copies is what CI builds.
  const std::string source = hb::test::read_text_file(kExample / "origin_penalty.cpp");
  CHECK(hb::test::read_text_file(kSource / "docs/plugins.md").find(source) != std::string::npos);

  // Its origin pressed 1 mm into a box: the oracle finds each reported
  // contact's depth and normal where the renderer put them, and the damper
  // keeps the run passive (exit 0: stable).
  const hb::test::ScratchDir work_dir("e2e_plugin_origin");
  const fs::path& work = work_dir.path();
  json scenario = json::parse(hb::test::read_text_file(kExample / "sphere_press_box.json"));
  scenario["name"] = "origin_press";
  scenario["tool"] = {{"shape", {{"type", "sphere"}, {"radius", 0.001}, {"subdivisions", 2}}},
                      {"mass_kg", 0.01}};
  scenario["trace"]["duration_s"] = 0.5;
  scenario["trace"]["params"]["start"] = {0, 0, 0.002};  // the origin 2 mm above the top face
  scenario["trace"]["params"]["surface_distance"] = 0.002;
  scenario["trace"]["params"]["depth"] = 0.001;
  scenario["algorithms"] = {{{"name", "origin_penalty"}, {"params", {{"stiffness", 1000}}}}};
  scenario["reference"] = {{"oracle", "embree"}, {"exact_every", 1}, {"analytic", "none"}};
  scenario["budgets"] = json::object();
  std::ofstream(work / "origin.json") << scenario.dump(2);
  const CommandResult run = hb::test::run_hapticbench(
      "run origin.json --plugin " + kOriginPenalty + " --out runs --quiet", work);
  INFO(run.stderr_text);
  REQUIRE(run.exit_code == 0);
  const json summary = json::parse(hb::test::read_text_file(work / "runs/summary.json"));
  const json& oracle = summary.at("runs").at(0).at("oracle");
  INFO(oracle.dump());
  CHECK(oracle.at("contact_depth_err_max_m").get<double>() < 1e-9);
  CHECK(oracle.at("contact_normal_err_rms_deg").get<double>() < 1e-6);
  const json& contacts = summary.at("runs").at(0).at("contacts");
  CHECK(contacts.at("contact_ticks").get<int>() > 100);
}

TEST_CASE("a plugin's renderer runs like a built-in one and its summary names the plugin") {
  const hb::test::ScratchDir work_dir("e2e_plugin_run");
  const fs::path& work = work_dir.path();
  write_short_example_scenario(work / "press.json");
  const CommandResult run =
      hb::test::run_hapticbench("run press.json --plugin " + kVertexPenalty + " --out runs", work);
  INFO(run.stderr_text);
  REQUIRE(run.exit_code == 0);
  const json summary = json::parse(hb::test::read_text_file(work / "runs/summary.json"));
  const json& plugin_run = summary.at("runs").at(0);
  CHECK(plugin_run.at("algorithm") == "vertex_penalty");
  CHECK(plugin_run.at("plugin") == fs::canonical(kVertexPenalty).string());
  CHECK(summary.at("runs").at(1).at("plugin").is_null());  // the built-in penalty proxy
  // It pressed: a force against the analytic reference, no non-finite tick.
  CHECK(plugin_run.at("stability").at("nonfinite") == 0);
  CHECK(plugin_run.at("accuracy").at("force_err_rms_n").get<double>() >= 0);

  const CommandResult list = hb::test::run_hapticbench("list --plugin " + kVertexPenalty, work);
  CHECK(list.stdout_text.find("  vertex_penalty  -  example plugin") != std::string::npos);
  CHECK(list.stdout_text.find("[plugin " + fs::canonical(kVertexPenalty).string() + "]") !=
        std::string::npos);
}

TEST_CASE("a scenario names its plugins relative to itself, loaded only when allowed") {
  const hb::test::ScratchDir work_dir("e2e_plugin_field");
  const fs::path& work = work_dir.path();
  fs::create_directories(work / "scenarios" / "plugins");
  fs::copy_file(kVertexPenalty, work / "scenarios" / "plugins" / "vertex_penalty.so");
  write_short_example_scenario(work / "scenarios" / "press.json");
  json scenario = json::parse(hb::test::read_text_file(work / "scenarios" / "press.json"));
  scenario["plugins"] = {"plugins/vertex_penalty.so"};
  std::ofstream(work / "scenarios" / "press.json") << scenario.dump(2);

  const CommandResult refused =
      hb::test::run_hapticbench("run scenarios/press.json --out runs", work);
  CHECK(refused.exit_code == 2);
  CHECK(refused.stderr_text.find("/plugins/0") != std::string::npos);
  CHECK(refused.stderr_text.find("--allow-scenario-plugins") != std::string::npos);
  CHECK_FALSE(fs::exists(work / "runs"));

  for (const char* allow :
       {"--allow-scenario-plugins", "--plugin scenarios/plugins/vertex_penalty.so"}) {
    CAPTURE(allow);
    const CommandResult run = hb::test::run_hapticbench(
        "run scenarios/press.json --out runs " + std::string(allow), work);
    INFO(run.stderr_text);
    CHECK(run.exit_code == 0);
    CHECK(fs::exists(work / "runs/ticks_vertex_penalty.csv"));
  }
}

TEST_CASE("a data file alone never loads a library: scenarios, validate, sweeps, the variable") {
  // The library's constructor leaves a mark when it is loaded, whatever
  // happens after: no mark, no code of its ran.
  const hb::test::ScratchDir work_dir("e2e_plugin_mark");
  const fs::path& work = work_dir.path();
  const fs::path mark = work / "mark.txt";
  const std::string with_mark = "export HAPTICBENCH_TEST_MARK='" + mark.string() + "' &&";
  write_short_example_scenario(work / "press.json");
  json scenario = json::parse(hb::test::read_text_file(work / "press.json"));
  scenario["algorithms"] = json::array({{{"name", "penalty_analytic"}}});
  std::ofstream(work / "trusted.json") << scenario.dump(2);
  scenario["plugins"] = {kLeavesMark};
  std::ofstream(work / "theirs.json") << scenario.dump(2);
  const auto run = [&](const std::string& args, const std::string& setup = "") {
    return hb::test::run_hapticbench_after(with_mark + setup, args, work);
  };

  const CommandResult refused = run("run theirs.json --out runs");
  CHECK(refused.exit_code == 2);
  CHECK(refused.stderr_text.find("theirs.json: /plugins/0") != std::string::npos);
  const CommandResult validated = run("validate theirs.json");
  INFO(validated.stderr_text);
  CHECK(validated.exit_code == 0);  // its built-in algorithm checked, the library not loaded
  CHECK(validated.stdout_text.find("OK: theirs.json") != std::string::npos);
  // A plugin algorithm in a scenario validate reads is left unchecked, and said so.
  scenario["algorithms"].push_back({{"name", "their_renderer"}});
  std::ofstream(work / "theirs_algorithm.json") << scenario.dump(2);
  const CommandResult unchecked = run("validate theirs_algorithm.json");
  CHECK(unchecked.exit_code == 0);
  CHECK(unchecked.stderr_text.find("\"their_renderer\" is not checked") != std::string::npos);

  std::ofstream(work / "sweep.json") << json{{"name", "grid_plugins"},
                                             {"scenarios", {"trusted.json"}},
                                             {"grid", {{"/plugins", {json::array({kLeavesMark})}}}}}
                                            .dump(2);
  const CommandResult sweep = run("sweep sweep.json --out sweep_runs");
  CHECK(sweep.exit_code == 2);
  CHECK(sweep.stderr_text.find("/grid/~1plugins") != std::string::npos);

  const CommandResult relative =
      run("list", "cd '" + kPlugins.string() + "' && export HAPTICBENCH_PLUGINS=" +
                      fs::path(kLeavesMark).filename().string() + " &&");
  CHECK(relative.exit_code == 2);
  CHECK(relative.stderr_text.find("HAPTICBENCH_PLUGINS: a relative plugin path") !=
        std::string::npos);
  CHECK_FALSE(fs::exists(mark));
  CHECK_FALSE(fs::exists(work / "runs"));
  CHECK_FALSE(fs::exists(work / "sweep_runs"));

  // Help comes even when the variable names something unusable.
  const CommandResult help = run("help", "export HAPTICBENCH_PLUGINS=/no/such.so &&");
  CHECK(help.exit_code == 0);
  CHECK(help.stdout_text.find("usage: hapticbench") != std::string::npos);

  // Asked for, it loads: the mark shows it.
  const CommandResult allowed = run("run theirs.json --out runs --allow-scenario-plugins");
  CHECK(allowed.exit_code == 2);  // not a hapticbench plugin, but loaded as asked
  CHECK(fs::exists(mark));
}

TEST_CASE("a sweep's jobs load the plugin given to the sweep") {
  const hb::test::ScratchDir work_dir("e2e_plugin_sweep");
  const fs::path& work = work_dir.path();
  write_short_example_scenario(work / "press.json");
  std::ofstream(work / "sweep.json") << json{
      {"name", "plugin_grid"},
      {"scenarios", {"press.json"}},
      {"grid", {{"/algorithms/0/params/contact_stiffness", {1000, 3000}}}},
      {"only_algorithms",
       {"vertex_penalty"}}}.dump(2);
  const CommandResult sweep = hb::test::run_hapticbench(
      "sweep sweep.json --jobs 2 --out runs --plugin " + kVertexPenalty, work);
  INFO(sweep.stderr_text);
  REQUIRE(sweep.exit_code == 0);
  const json index = json::parse(hb::test::read_text_file(work / "runs/sweep.json"));
  REQUIRE(index.at("jobs").size() == 2);
  for (const json& job : index.at("jobs")) {
    CHECK(job.at("status") == "ok");
    const json summary = json::parse(hb::test::read_text_file(
        work / "runs" / job.at("name").get<std::string>() / "summary.json"));
    CHECK(summary.at("runs").at(0).at("algorithm") == "vertex_penalty");
  }
  // The report draws plugin runs as it draws the others.
  const CommandResult report =
      hb::test::run_hapticbench("report runs --out report.html --quiet", work);
  INFO(report.stderr_text);
  CHECK(report.exit_code == 0);
  CHECK(hb::test::read_text_file(work / "report.html").find("vertex_penalty") != std::string::npos);
}

TEST_CASE("a plugin that crashes, exits or throws is named, and nothing passes") {
  // In `run` (inside step()), `stability` (inside step()) and `validate`
  // (when the renderer is created): each runs the plugin in a child it
  // watches.
  struct Case {
    const char* command;
    const char* when;
  };
  for (const Case c : {Case{"run press.json --out runs", "step"},
                       Case{"stability press.json --label bad_renderer --param /coupling/k_t "
                            "--range 1000 3000 --out runs",
                            "step"},
                       Case{"validate press.json", "create"}})
    for (const char* failure : {"crash", "exit_0", "throw"}) {
      CAPTURE(c.command, failure);
      const hb::test::ScratchDir work_dir("e2e_plugin_failure");
      const fs::path& work = work_dir.path();
      write_short_example_scenario(work / "press.json");
      json scenario = json::parse(hb::test::read_text_file(work / "press.json"));
      scenario["algorithms"] =
          json::array({{{"name", "penalty_analytic"}},
                       {{"name", "misbehaving"},
                        {"label", "bad_renderer"},
                        {"params", {{"failure", failure}, {"when", c.when}}}}});
      std::ofstream(work / "press.json") << scenario.dump(2);
      const CommandResult run =
          hb::test::run_hapticbench(std::string(c.command) + " --plugin " + kMisbehaving, work);
      INFO(run.stdout_text << run.stderr_text);
      CHECK(run.exit_code == 3);
      CHECK(run.stderr_text.find("\"bad_renderer\" of plugin " +
                                 fs::canonical(kMisbehaving).string()) != std::string::npos);
      CHECK(run.stdout_text.find("OK") == std::string::npos);
      CHECK_FALSE(fs::exists(work / "runs"));
    }
}

TEST_CASE("a plugin that cannot be used is exit 2 with its path and the reason") {
  struct Case {
    std::string name, plugin, reason;
  };
  const std::vector<Case> cases = {
      {"missing file", (kPlugins / "no_such_plugin.so").string(), "no such file"},
      {"not a shared library", (kExample / "sphere_press_box.json").string(),
       "cannot load the plugin as a shared library"},
      {"no entry point", (kPlugins / "plugin_without_entry_point.so").string(),
       "exports no hapticbench_plugin()"},
      {"another ABI version", (kPlugins / "plugin_other_abi.so").string(),
       "built for plugin ABI version " + std::to_string(hb::kPluginAbiVersion + 1) +
           ", but this hapticbench loads version " + std::to_string(hb::kPluginAbiVersion)},
      {"a taken name", (kPlugins / "plugin_taken_name.so").string(),
       "the algorithm name \"god_object\" is taken by a built-in algorithm"},
  };
  for (const Case& c : cases) {
    SECTION(c.name) {
      const hb::test::ScratchDir work_dir("e2e_plugin_refused");
      const fs::path& work = work_dir.path();
      write_short_example_scenario(work / "press.json");
      const CommandResult run =
          hb::test::run_hapticbench("run press.json --plugin " + c.plugin + " --out runs", work);
      INFO(run.stderr_text);
      CHECK(run.exit_code == 2);
      CHECK(run.stderr_text.find(c.plugin) != std::string::npos);
      CHECK(run.stderr_text.find(c.reason) != std::string::npos);
      CHECK_FALSE(fs::exists(work / "runs"));
      // Refused whole: none of its algorithms is listed.
      const CommandResult list = hb::test::run_hapticbench("list --plugin " + c.plugin, work);
      CHECK(list.exit_code == 2);
      CHECK(list.stdout_text.find("fresh_name") == std::string::npos);
    }
  }
  SECTION("HAPTICBENCH_PLUGINS naming a missing file") {
    const hb::test::ScratchDir work_dir("e2e_plugin_variable");
    const CommandResult list = hb::test::run_hapticbench_after(
        "export HAPTICBENCH_PLUGINS=/no/such/plugin.so &&", "list", work_dir.path());
    CHECK(list.exit_code == 2);
    CHECK(list.stderr_text.find("/no/such/plugin.so: HAPTICBENCH_PLUGINS: cannot load the "
                                "plugin: no such file") != std::string::npos);
  }
  SECTION("--plugin without a path") {
    const hb::test::ScratchDir work_dir("e2e_plugin_no_path");
    const CommandResult list = hb::test::run_hapticbench("list --plugin", work_dir.path());
    CHECK(list.exit_code == 2);
    CHECK(list.stderr_text.find("--plugin: expected the path of a plugin file") !=
          std::string::npos);
  }
}

}  // namespace
