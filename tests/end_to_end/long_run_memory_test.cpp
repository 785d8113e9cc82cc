// End-to-end: a run's memory does not grow with its length. A 600 s run of
// the coupling alone, in free space above a scene with the analytic
// reference off (so that the mesh force reference follows every tick),
// peaks at most a few tens of MB above a 60 s run of the same scenario
// (before streaming, each second of ticks cost about 1.2 MB; before the
// force reference was spilled and cached in parts, 112 bytes a tick more),
// and its ticks log holds every tick.
#include <sys/resource.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/cli_runner.h"

namespace {

namespace fs = std::filesystem;
using hb::test::run_hapticbench;
using hb::test::ScratchDir;

std::string scenario_text(int seconds) {
  return R"({
  "name": "long_)" +
         std::to_string(seconds) + R"(",
  "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] }, "pose": { "p": [0, 0, -0.01], "q": [1, 0, 0, 0] } } ],
  "tool": { "shape": { "type": "sphere", "radius": 0.02, "subdivisions": 2 }, "density": 1000 },
  "trace": { "generator": "rub", "duration_s": )" +
         std::to_string(seconds) + R"(, "seed": 1,
             "params": { "centre": [0, 0, 0.5], "surface_distance": 0.01, "depth": 0.004, "radius": 0.02, "turns": )" +
         std::to_string(seconds) + R"( } },
  "coupling": { "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 },
  "algorithms": [ { "name": "coupling_only", "label": "coupling_only" } ],
  "reference": { "oracle": "none", "analytic": "none" }
})";
}

// Largest resident set of any finished child process so far (KiB).
long children_peak_kib() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  return usage.ru_maxrss;
}

std::size_t line_count(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::size_t lines = 0;
  std::string line;
  while (std::getline(in, line)) ++lines;
  return lines;
}

TEST_CASE("a ten times longer run peaks at nearly the same memory") {
  ScratchDir work("long_run_memory");
  // A cache of its own: the force reference is computed, and written in parts.
  struct OwnCache {
    explicit OwnCache(const fs::path& folder) {
      ::setenv("HAPTICBENCH_CACHE_DIR", folder.c_str(), 1);
    }
    ~OwnCache() { ::unsetenv("HAPTICBENCH_CACHE_DIR"); }
  } own_cache(work.path() / "cache");
  std::ofstream(work.path() / "short.json") << scenario_text(60);
  std::ofstream(work.path() / "long.json") << scenario_text(600);

  const auto short_run = run_hapticbench("run short.json --out short", work.path());
  REQUIRE(short_run.exit_code == 0);
  const long short_peak_kib = children_peak_kib();
  const auto long_run = run_hapticbench("run long.json --out long", work.path());
  REQUIRE(long_run.exit_code == 0);
  const long long_peak_kib = children_peak_kib();  // max of both runs
  INFO("60 s run " << short_peak_kib / 1024 << " MB, 600 s run " << long_peak_kib / 1024 << " MB");
  CHECK(line_count(work.path() / "long" / "ticks_coupling_only.csv") == 600'001);
  // The mesh force reference was computed, over every tick.
  const nlohmann::json summary =
      nlohmann::json::parse(hb::test::read_text_file(work.path() / "long" / "summary.json"));
  CHECK(summary.at("force_reference").at("evaluated_ticks").get<int64_t>() == 600'000);
  // AddressSanitizer's shadow memory and quarantine make RSS meaningless.
  if (!hb::test::tool_runs_with_asan()) {
    CHECK(long_peak_kib <= short_peak_kib + 64 * 1024);
    CHECK(long_peak_kib <= 300 * 1024);
  }
}

}  // namespace
