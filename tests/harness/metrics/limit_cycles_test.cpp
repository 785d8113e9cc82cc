// The limit-cycle detector against sinusoids of known amplitude and frequency.
#include "harness/metrics/limit_cycles.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <functional>

namespace hb {
namespace {

constexpr double kTickS = 1e-3;

// Feeds `ticks` ticks: the device at z = device(t), the intent at
// z = intent(t), a force along +z, in contact when `contact` says so.
LimitCycleMetrics detect(
    int ticks, const std::function<double(double)>& device,
    const std::function<double(double)>& intent,
    const std::function<bool(int)>& contact = [](int) { return true; }) {
  LimitCycleDetector detector;
  for (int n = 0; n < ticks; ++n) {
    const double t = n * kTickS;
    detector.add(Vec3(0, 0, device(t)), Vec3(0, 0, intent(t)), Vec3(0, 0, 1), contact(n));
  }
  return detector.finish();
}

TEST_CASE(
    "a sustained 50 Hz oscillation of 0.2 mm is a limit cycle of that amplitude and frequency") {
  const double amplitude = 2e-4, frequency = 50;
  const LimitCycleMetrics m = detect(
      2000,
      [&](double t) {
        return 0.01 - 1e-3 * t + amplitude * std::sin(2 * M_PI * frequency * t + 0.3);
      },
      [](double t) { return -1e-3 * t; });
  CHECK(m.contact_blocks == 20);
  CHECK(m.oscillating_blocks == 20);
  CHECK(m.share == 1);
  CHECK(m.limit_cycle);
  REQUIRE(m.amplitude_m);
  CHECK(*m.amplitude_m == Approx(amplitude).epsilon(0.02));
  CHECK(*m.frequency_hz == Approx(frequency));
}

TEST_CASE("an oscillation the intent makes is no limit cycle") {
  const auto wave = [](double t) { return 1e-3 * std::sin(2 * M_PI * 40 * t); };
  const LimitCycleMetrics m = detect(
      2000, [&](double t) { return 0.8 * wave(t); }, wave);
  CHECK(m.oscillating_blocks == 0);
  CHECK_FALSE(m.limit_cycle);
  CHECK_FALSE(m.amplitude_m);
}

TEST_CASE("a dying oscillation is no limit cycle, a growing one is") {
  for (double rate : {-4.0, 1.0}) {
    const LimitCycleMetrics m = detect(
        2000, [&](double t) { return 1e-4 * std::exp(rate * t) * std::sin(2 * M_PI * 30 * t); },
        [](double) { return 0.0; });
    CHECK(m.oscillating_blocks > 5);
    CHECK(m.limit_cycle == (rate > 0));
  }
}

TEST_CASE("only contact blocks count, and oscillations below the floor do not") {
  const auto wave = [](double t) { return 2e-4 * std::sin(2 * M_PI * 50 * t); };
  const LimitCycleMetrics free = detect(
      2000, wave, [](double) { return 0.0; },
      [](int n) {
        return n % 100 < 5;  // 5 % of each block: below kMinContactShare
      });
  CHECK(free.contact_blocks == 0);
  CHECK_FALSE(free.limit_cycle);
  const LimitCycleMetrics bouncing = detect(
      2000, wave, [](double) { return 0.0; }, [](int n) { return n % 20 < 4; });  // 20 %
  CHECK(bouncing.contact_blocks == 20);
  CHECK(bouncing.limit_cycle);
  const LimitCycleMetrics tiny = detect(
      2000, [](double t) { return 1e-6 * std::sin(2 * M_PI * 50 * t); },
      [](double) { return 0.0; });
  CHECK(tiny.oscillating_blocks == 0);
}

TEST_CASE("a 20 Hz bounce is a limit cycle in any phase, also when a release ends the run") {
  // The default hand bounces at 20 Hz: two periods a block, which four
  // sign changes missed in some phases. A press, a bounce through the hold,
  // then quiet contact as the device is released: the quiet blocks are no
  // decay of the bounce.
  for (const double phase : {0.0, 0.4, 0.8, 1.2, 1.6}) {
    CAPTURE(phase);
    const LimitCycleMetrics m = detect(
        2000,
        [&](double t) {
          const double bounce = t < 1.5 ? 2.5e-3 * std::sin(2 * M_PI * 20 * t + phase) : 0.0;
          return 0.01 + bounce;
        },
        [](double) { return 0.01; });
    CHECK(m.oscillating_blocks >= 14);
    CHECK(m.limit_cycle);
    REQUIRE(m.frequency_hz);
    // Sign changes per block: a resolution of one change, 5 Hz.
    CHECK(*m.frequency_hz == Approx(20).margin(5.01));
  }
}

}  // namespace
}  // namespace hb
