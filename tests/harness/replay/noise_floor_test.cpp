// The noise floor (harness/replay/noise_floor.h) sees a busy neighbour at
// once: another runnable task during the pass makes it not quiet, whatever
// the load average (which lags by a minute) says.
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

}  // namespace
}  // namespace hb
