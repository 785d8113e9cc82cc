// Paths of a tool origin near a 2 mm plate (|x|, |y| <= 0.1 m, |z| <= 1 mm,
// in the plate's frame, m) and how many times each passes through it: shared
// by the tests of the closed-form and the oracle tunnelling detectors, so
// both are held to one definition (harness/reference/tunnelling.h).
#pragma once

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "hapticbench/pose.h"

namespace hb::test {

struct TunnellingPath {
  std::string what;
  std::vector<Vec3> points;  ///< m, plate frame, one per tick
  int passes;
};

inline std::vector<TunnellingPath> plate_tunnelling_paths() {
  std::vector<Vec3> round;  // from +z over the +x edge to −z, 1 mm steps
  for (int k = 0; k <= 40; ++k) {
    const double a = std::numbers::pi * k / 40;
    round.push_back(Vec3(0.1 + 0.005 * std::sin(a), 0, 0.005 * std::cos(a)));
  }
  return {
      {"straight through in one tick (4 mm a tick)",
       {{0, 0, 0.01}, {0, 0, 0.006}, {0, 0, 0.002}, {0, 0, -0.002}, {0, 0, -0.006}},
       1},
      {"through over ticks spent inside",
       {{0, 0, 0.002}, {0, 0, 0.0005}, {0, 0, -0.0005}, {0, 0, -0.002}},
       1},
      {"down through and back up", {{0, 0, 0.003}, {0, 0, -0.003}, {0, 0, 0.003}}, 2},
      {"into the plate and back out the way it came",
       {{0, 0, 0.002}, {0, 0, 0.0005}, {0, 0, 0.0002}, {0, 0, 0.002}},
       0},
      {"round the plate's edge", round, 0},
      // The side turns by nearly 180° but the path misses the plate.
      {"past its edge in one tick, 0.05 mm outside it",
       {{0.10005, 0, 0.002}, {0.10005, 0, -0.002}},
       0},
      {"a non-finite position is skipped", {{0, 0, 0.01}, {std::nan(""), 0, 0}, {0, 0, 0.01}}, 0},
      // From above the top face to beside the side face in one tick, the
      // straight path cutting the edge 0.36 mm deep: the sides turn by only
      // 90°, but the tick skipped the solid.
      {"across the edge's corner in one tick", {{0.098, 0, 0.0015}, {0.1015, 0, -0.0005}}, 1},
      {"sliding along the top face 10 µm above it",
       {{-0.02, 0, 0.00101}, {-0.01, 0, 0.00101}, {0, 0, 0.00101}, {0.01, 0, 0.00101}},
       0},
  };
}

}  // namespace hb::test
