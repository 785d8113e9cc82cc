// End-to-end: the ideal rendering displays the whole coupling, its damper
// included. A box pressed at constant speed into a box's face: both
// references (the closed form, and the mesh reference with the closed form
// switched off) display k_T · depth + b_T · speed once the ideal proxy rests
// on the face, read from the ticks log's ref_fz.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/cli_runner.h"
#include "tests/support/end_to_end.h"

namespace force_reference_test {

namespace fs = std::filesystem;
using hb::test::run_hapticbench;
using hb::test::ScratchDir;
using hb::test::write_file;

constexpr double kStiffness = 2000;  // k_T, N/m
constexpr double kDamping = 5;       // b_T, N·s/m
constexpr double kSpeed = 0.05;      // m/s, into the face
constexpr double kHalf = 0.02;       // m, half the tool cube's side
constexpr double kStartZ = 0.025;    // m, the cube's centre 5 mm above contact

TEST_CASE("both references display the coupling's damper on a press at constant speed") {
  const ScratchDir work("e2e_reference_damper");
  // 0.3 s at 5 cm/s from 5 mm above the face: 15 mm of travel, 10 mm past contact.
  std::string trace = "t_ns,px,py,pz,qw,qx,qy,qz\n";
  for (int tick = 0; tick <= 300; ++tick)
    trace += std::to_string(tick * 1000000LL) + ",0.01,-0.02," +
             std::to_string(kStartZ - kSpeed * tick * 1e-3) + ",1,0,0,0\n";
  write_file(work.path() / "press.csv", trace);
  for (const char* analytic : {"auto", "none"}) {
    CAPTURE(analytic);
    write_file(work.path() / "scenario.json", R"({
  "name": "damper_press",
  "scene": [ { "shape": { "type": "box", "size": [0.4, 0.4, 0.02] }, "pose": { "p": [0, 0, -0.01] } } ],
  "tool": { "shape": { "type": "box", "size": [0.04, 0.04, 0.04] }, "density": 500 },
  "trace": { "file": "press.csv" },
  "coupling": { "k_t": 2000, "b_t": 5, "k_r": 5, "b_r": 0.05 },
  "algorithms": [ { "name": "coupling_only" } ],
  "reference": { "oracle": "none", "analytic": ")" +
                                                  std::string(analytic) +
                                                  R"(", "force_every": 1 }
})");
    const auto result = run_hapticbench("run scenario.json --out run --quiet", work.path());
    INFO(result.stderr_text);
    REQUIRE(result.exit_code == 0);
    auto columns = hb::test::read_tick_columns(work.path() / "run/ticks_coupling_only.csv");
    const std::vector<double>& z = columns["dev_pz"];
    const std::vector<double>& ref_fz = columns["ref_fz"];
    REQUIRE(z.size() == ref_fz.size());
    int checked = 0;
    for (std::size_t tick = 0; tick < z.size(); ++tick) {
      const double depth = kHalf - z[tick];
      // Resting on the face since the tick before (the first contact tick
      // differences a free pose with a resting one).
      if (depth <= 2 * kSpeed * 1e-3) continue;
      CAPTURE(tick, depth);
      // The mesh reference keeps 1 µm of clearance: 2 mN of spring.
      CHECK(ref_fz[tick] == Approx(kStiffness * depth + kDamping * kSpeed).margin(3e-3));
      ++checked;
    }
    CHECK(checked > 150);
  }
}

}  // namespace force_reference_test
