// End-to-end: `hapticbench stability` against the closed form of explicit
// Euler on the free-space virtual coupling, and its bad input.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace {

using hb::test::kSource;

namespace fs = std::filesystem;
using nlohmann::json;

// The free-space 1 cm pose jump of the smoke suite (0.2 kg proxy, b_t =
// 5 N·s/m), 10 s long so that slow growth near the limit shows.
void write_jump_scenario(const fs::path& path) {
  std::ifstream in(kSource / "scenarios/smoke/stiff_coupling_explicit_vs_implicit.json");
  json scenario = json::parse(in);
  scenario["trace"]["duration_s"] = 10.0;
  std::ofstream(path) << scenario.dump(2);
}

// Runs `hapticbench stability ARGS --out OUT` in `work`; requires exit 0
// and returns OUT/stability.json with the command's output.
struct SearchedMargin {
  hb::test::CommandResult result;
  json search;
  double stable = 0, unstable = 0;
};
SearchedMargin searched_margin(const std::string& args, const std::string& out,
                               const fs::path& work) {
  SearchedMargin margin;
  margin.result = hb::test::run_hapticbench("stability " + args + " --out " + out, work);
  INFO(margin.result.stderr_text);
  REQUIRE(margin.result.exit_code == 0);
  margin.search = json::parse(hb::test::read_text_file(work / out / "stability.json"));
  margin.stable = margin.search.at("largest_stable").get<double>();
  if (!margin.search.at("smallest_unstable").is_null())
    margin.unstable = margin.search.at("smallest_unstable").get<double>();
  return margin;
}

TEST_CASE("the stability search finds explicit Euler's coupling limit k_t < b_t / dt") {
  const hb::test::ScratchDir work_dir("e2e_stability_coupling");
  const fs::path& work = work_dir.path();
  write_jump_scenario(work / "jump.json");
  const SearchedMargin found = searched_margin(
      "jump.json --label explicit_euler --param /coupling/k_t --range 1000 100000 "
      "--tolerance 0.02",
      "margin", work);
  const hb::test::CommandResult& result = found.result;
  const json& margin = found.search;
  const double stable = found.stable, unstable = found.unstable;
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
  CHECK(implicit.stdout_text.find("stable up to the range's top (100000)") != std::string::npos);
  CHECK(all.at("note").get<std::string>().find("range's top") != std::string::npos);

  // Unstable at the bottom of the range: said, not just "none in range".
  const hb::test::CommandResult too_high = hb::test::run_hapticbench(
      "stability jump.json --label explicit_euler --param /coupling/k_t --range 20000 100000 "
      "--out too_high",
      work);
  REQUIRE(too_high.exit_code == 0);
  CHECK(too_high.stdout_text.find("unstable already at the range's bottom (20000)") !=
        std::string::npos);
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
  const SearchedMargin found =
      searched_margin((kSource / "scenarios/margins/sphere_on_box.json").string() +
                          " --label penalty_explicit --param /algorithms/0/params/contact_stiffness"
                          " --range 1000 100000 --tolerance 0.02",
                      "contact", work);
  const json& margin = found.search;
  const double stable = found.stable, unstable = found.unstable;
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

// A 2 cm sphere over the top face (z = 0) of a box, the device moving
// z = −1 mm − 1 mm·sin(2π 20 Hz t) for 1 s (20 cycles, in contact 0–2 mm
// deep), with its exact velocity, rendered by the god-object: a proxy at
// rest on the face and a sampled coupling spring behind it.
void write_wall_scenario(const fs::path& folder) {
  std::ofstream trace(folder / "oscillation.csv");
  trace << "t_ns,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";
  const double amplitude = 1e-3, omega = 2 * M_PI * 20, radius = 0.02;
  for (int n = 0; n <= 1000; ++n) {
    const double t = 1e-3 * n;
    const double z = radius - amplitude - amplitude * std::sin(omega * t);
    const double vz = -amplitude * omega * std::cos(omega * t);
    trace << n * 1'000'000LL << ",0,0," << std::setprecision(17) << z << ",1,0,0,0,0,0," << vz
          << ",0,0,0\n";
  }
  std::ofstream(folder / "wall.json") << R"({
    "name": "sampled_wall",
    "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] },
                 "pose": { "p": [0, 0, -0.01], "q": [1, 0, 0, 0] } } ],
    "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 3 }, "density": 1000 },
    "trace": { "file": "oscillation.csv" },
    "coupling": { "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 },
    "algorithms": [ { "name": "god_object", "label": "god_object" } ] })";
}

TEST_CASE("the held-force port energy changes sign at the sampled wall's limit k_t = 2 b_t / T") {
  // Colgate & Schenkel 1997: a wall behind a spring sampled every T with
  // damping b is passive only while k T / 2 < b. With the exact velocity of
  // a sinusoid of θ = ωT a tick the held-force energy per tick in contact is
  // ≈ Δx² (b / T − k / 2), so the limit is 2 b_t / T = 10,000 N/m (within
  // θ²/12 = 0.1 %). The earlier observer (F_n · v_n T) saw only the damping
  // and called every stiffness passive.
  const hb::test::ScratchDir work_dir("e2e_stability_wall");
  const fs::path& work = work_dir.path();
  write_wall_scenario(work);
  const SearchedMargin found = searched_margin(
      "wall.json --label god_object --param /coupling/k_t --range 2000 50000 --tolerance 0.01",
      "margin", work);
  const json& margin = found.search;
  const double stable = found.stable, unstable = found.unstable;
  const double limit = 2 * 5.0 / 1e-3;
  CHECK(stable == Approx(limit).epsilon(0.02));
  CHECK(unstable == Approx(limit).epsilon(0.02));
  for (const json& run : margin.at("runs")) {
    INFO(run.dump());
    CHECK(run.at("stable").get<bool>() == (run.at("value").get<double>() <= stable));
    // Passivity, not divergence or chatter, decides: the proxy rests on the face.
    CHECK_FALSE(run.at("diverged").get<bool>());
  }
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
