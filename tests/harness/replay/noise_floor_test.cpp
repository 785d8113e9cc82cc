// The noise floor (harness/replay/noise_floor.h) sees a busy neighbour at
// once: another runnable task during the pass makes it not quiet, whatever
// the load average (which lags by a minute) says. Interruptions are counted
// from clock reads as their definition says.
#include "harness/replay/noise_floor.h"

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <thread>

namespace hb {
namespace {

TEST_CASE("a busy neighbour thread is counted and the pass is not quiet") {
  std::atomic<bool> stop{false};
  std::atomic<bool> running{false};
  std::thread busy([&] {
    running = true;
    while (!stop) {
    }
  });
  while (!running) std::this_thread::yield();
  const NoiseFloorProbe probe;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(20);
  while (std::chrono::steady_clock::now() < until) {
  }
  const NoiseFloor noise = probe.finish();
  stop = true;
  busy.join();
  INFO("other runnable " << noise.other_runnable << ", logical cores " << noise.logical_cores);
  REQUIRE(noise.other_runnable >= 0);  // /proc/loadavg is readable here
  CHECK(noise.other_runnable >= 1);    // the spinning thread
  if (noise.logical_cores <= 2) CHECK_FALSE(noise.quiet);
}

TEST_CASE("interruptions: the gaps of at least a microsecond between clock reads") {
  // Reads 30 ns apart for 10 ms, with nine gaps of 20, 30 and 25 µs in
  // turn, one of exactly the threshold and one just below it.
  InterruptionCounter counter;
  int64_t t = 5'000;
  const int64_t first = t;
  const int64_t long_gaps[] = {20'000, 30'000, 25'000};
  int next_gap = 0;
  while (t - first < 10'000'000) {
    counter.add(t);
    const int64_t since = t - first;
    if (since > 0 && since % 1'000'020 < 30 && next_gap < 9) {
      t += long_gaps[next_gap++ % 3];
    } else if (since == 30 * 1000) {
      t += kInterruptionGapNs;  // counts
    } else if (since == 30 * 2000 + kInterruptionGapNs) {
      t += kInterruptionGapNs - 1;  // does not
    } else {
      t += 30;
    }
  }
  counter.add(t);
  REQUIRE(next_gap == 9);
  const Interruptions found = counter.result();
  const double span_s = static_cast<double>(t - first) * 1e-9;
  CHECK(found.rate_hz == Approx(10 / span_s).epsilon(1e-12));
  CHECK(found.p50_ns == 25'000);  // of 1 µs, 3 × 20, 3 × 25, 3 × 30 µs
  CHECK(found.max_ns == 30'000);

  InterruptionCounter steady;
  for (int64_t r = 0; r < 1'000'000; r += 40) steady.add(r);
  CHECK(steady.result().rate_hz == 0);
  CHECK(steady.result().p50_ns == 0);
}

}  // namespace
}  // namespace hb
