// End-to-end: `hapticbench stability` against the closed form of explicit
// Euler on the free-space virtual coupling, and its bad input.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/cli_runner.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kSource = HAPTICBENCH_SOURCE_DIR;

// The free-space 1 cm pose jump of the smoke suite (0.2 kg proxy, b_t =
// 5 N·s/m), 10 s long so that slow growth near the limit shows.
void write_jump_scenario(const fs::path& path) {
  std::ifstream in(kSource / "scenarios/smoke/stiff_coupling_explicit_vs_implicit.json");
  json scenario = json::parse(in);
  scenario["trace"]["duration_s"] = 10.0;
  std::ofstream(path) << scenario.dump(2);
}

TEST_CASE("the stability search finds explicit Euler's coupling limit k_t < b_t / dt") {
  const hb::test::ScratchDir work_dir("e2e_stability_coupling");
  const fs::path& work = work_dir.path();
  write_jump_scenario(work / "jump.json");
  const hb::test::CommandResult result = hb::test::run_hapticbench(
      "stability jump.json --label explicit_euler --param /coupling/k_t --range 1000 100000 "
      "--tolerance 0.02 --out margin",
      work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  const json margin = json::parse(hb::test::read_text_file(work / "margin/stability.json"));
  const double stable = margin.at("largest_stable").get<double>();
  const double unstable = margin.at("smallest_unstable").get<double>();
  const double limit = 5.0 / 1e-3;  // b_t / dt
  CHECK(unstable / stable - 1 <= 0.02);
  // Within the tolerance of the closed form (a finite run sees growth just
  // above the limit late, so the bracket may sit a little above it).
  CHECK(stable == Approx(limit).epsilon(0.02));
  CHECK(unstable == Approx(limit).epsilon(0.04));
  CHECK(stable < unstable);
  CHECK(margin.at("criterion").get<std::string>().find("diverge") != std::string::npos);
  const json& runs = margin.at("runs");
  CHECK(runs.size() >= 4);
  for (const json& run : runs)
    CHECK(run.at("stable").get<bool>() == (run.at("value").get<double>() <= stable));
  CHECK(result.stdout_text.find("largest stable") != std::string::npos);

  // Implicit Euler is stable over the whole range: no unstable value found.
  const hb::test::CommandResult implicit = hb::test::run_hapticbench(
      "stability jump.json --label implicit_euler --param /coupling/k_t --range 1000 100000 "
      "--out implicit",
      work);
  REQUIRE(implicit.exit_code == 0);
  const json all = json::parse(hb::test::read_text_file(work / "implicit/stability.json"));
  CHECK(all.at("largest_stable").get<double>() == 100000);
  CHECK(all.at("smallest_unstable").is_null());
}

TEST_CASE("the stability search finds explicit Euler's contact limit (k_t + k_c) dt < b_t + b_c") {
  // A sphere held 5 mm deep in a box face for 10 s by penalty_analytic with
  // explicit Euler. Linearised about the held contact, the proxy sees the
  // spring k_t + k_c and the damper b_t + b_c (the contact damping, 2 N·s/m
  // by default), so explicit Euler is stable while k_c < (b_t + b_c)/dt −
  // k_t = 7000 − 2000 = 5000 N/m. Above it the oscillation grows until it
  // lifts the proxy off the face, where it bounces in a bounded cycle: not
  // divergence, and not seen by the passivity observer with the device
  // held still; the chatter criterion sees it.
  const hb::test::ScratchDir work_dir("e2e_stability_contact");
  const fs::path& work = work_dir.path();
  const hb::test::CommandResult result = hb::test::run_hapticbench(
      "stability " + (kSource / "scenarios/margins/sphere_on_box.json").string() +
          " --label penalty_explicit --param /algorithms/0/params/contact_stiffness"
          " --range 1000 100000 --tolerance 0.02 --out contact",
      work);
  INFO(result.stderr_text);
  REQUIRE(result.exit_code == 0);
  const json margin = json::parse(hb::test::read_text_file(work / "contact/stability.json"));
  const double stable = margin.at("largest_stable").get<double>();
  const double unstable = margin.at("smallest_unstable").get<double>();
  const double limit = (5.0 + 2.0) / 1e-3 - 2000.0;
  CHECK(unstable / stable - 1 <= 0.02);
  // Just below the limit an oscillation dies out slowly, just above it
  // grows slowly: a 10 s run brackets the bound within a few per cent.
  CHECK(stable == Approx(limit).epsilon(0.05));
  CHECK(unstable == Approx(limit).epsilon(0.05));
  bool chatter_decided = false;
  for (const json& run : margin.at("runs"))
    if (!run.at("stable").get<bool>() && !run.at("diverged").get<bool>())
      chatter_decided = chatter_decided || run.at("chatters").get<bool>();
  CHECK(chatter_decided);  // some unstable run was bounded: chatter, not divergence, told
}

TEST_CASE("stability: bad input exits with 2, names what is wrong, and writes nothing") {
  const hb::test::ScratchDir work_dir("e2e_stability_bad");
  const fs::path& work = work_dir.path();
  write_jump_scenario(work / "jump.json");
  const auto refused = [&](const std::string& args, const std::string& named) {
    const hb::test::CommandResult result = hb::test::run_hapticbench(args + " --out margin", work);
    INFO(args << ": " << result.stderr_text);
    CHECK(result.exit_code == 2);
    CHECK(result.stderr_text.find(named) != std::string::npos);
    CHECK_FALSE(fs::exists(work / "margin"));
  };
  refused("stability jump.json --label nobody --param /coupling/k_t --range 1 10", "nobody");
  refused("stability jump.json --label explicit_euler --param /nothing/here --range 1 10",
          "/nothing/here");
  refused("stability jump.json --label explicit_euler --param coupling --range 1 10", "--param");
  refused("stability jump.json --label explicit_euler --param /coupling/k_t --range 10 1",
          "LO < HI");
  refused("stability jump.json --label explicit_euler --param /coupling/k_t --range 0 10",
          "--range LO");
  refused("stability jump.json --label explicit_euler --param /coupling/k_t", "--range");
  refused("stability missing.json --label explicit_euler --param /coupling/k_t --range 1 10",
          "missing.json");
  // A value the scenario refuses is named by its field.
  refused("stability jump.json --label explicit_euler --param /trace/duration_s --range 1e6 1e7",
          "/trace/duration_s");
  // A folder of the user's is not replaced.
  fs::create_directories(work / "mine");
  std::ofstream(work / "mine/notes.txt") << "keep";
  const hb::test::CommandResult mine = hb::test::run_hapticbench(
      "stability jump.json --label explicit_euler --param /coupling/k_t --range 1000 2000 "
      "--out mine",
      work);
  CHECK(mine.exit_code == 2);
  CHECK(hb::test::read_text_file(work / "mine/notes.txt") == "keep");
}

}  // namespace
