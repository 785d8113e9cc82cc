#include "harness/replay/noise_floor.h"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <vector>

namespace hb {

namespace {

int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

// A fixed amount of dependent floating-point work (~10 µs on a 2020s core),
// which neither the compiler nor the memory system can shorten.
double calibration_workload() {
  double x = 0.5;
  for (int i = 0; i < 4000; ++i) x = x * 3.9 * (1.0 - x);
  return x;
}

// Runnable tasks besides this one, from /proc/loadavg's "running/total"
// field (this thread counts one); −1 when it cannot be read.
int other_runnable_tasks() {
  std::ifstream file("/proc/loadavg");
  double one = 0, five = 0, fifteen = 0;
  int running = 0;
  char slash = 0;
  if (!(file >> one >> five >> fifteen >> running >> slash) || slash != '/') return -1;
  return std::max(0, running - 1);
}

struct CalibrationBatch {
  double p50_ns = 0, p90_ns = 0;
};

CalibrationBatch time_calibration() {
  constexpr int kRepetitions = 101;
  std::vector<double> ns(kRepetitions);
  volatile double sink = 0;
  for (double& t : ns) {
    const auto t0 = std::chrono::steady_clock::now();
    sink = sink + calibration_workload();
    const auto t1 = std::chrono::steady_clock::now();
    t = std::chrono::duration<double, std::nano>(t1 - t0).count();
  }
  std::sort(ns.begin(), ns.end());
  return {ns[kRepetitions / 2], ns[kRepetitions * 9 / 10]};
}

// Reads the monotonic clock back to back for spin_ns.
Interruptions measure_interruptions(int64_t spin_ns) {
  InterruptionCounter counter;
  const int64_t start = clock_ns(CLOCK_MONOTONIC);
  for (int64_t now = start; now - start < spin_ns; now = clock_ns(CLOCK_MONOTONIC))
    counter.add(now);
  return counter.result();
}

}  // namespace

void InterruptionCounter::add(int64_t read_ns) {
  if (started_ && read_ns - last_ns_ >= kInterruptionGapNs) gaps_ns_.push_back(read_ns - last_ns_);
  if (!started_) first_ns_ = read_ns;
  started_ = true;
  last_ns_ = read_ns;
}

Interruptions InterruptionCounter::result() const {
  Interruptions out;
  const int64_t span = last_ns_ - first_ns_;
  if (span <= 0 || gaps_ns_.empty()) return out;
  std::vector<int64_t> sorted = gaps_ns_;
  std::sort(sorted.begin(), sorted.end());
  out.rate_hz = static_cast<double>(sorted.size()) * 1e9 / static_cast<double>(span);
  out.p50_ns = static_cast<double>(sorted[(sorted.size() - 1) / 2]);
  out.max_ns = static_cast<double>(sorted.back());
  return out;
}

NoiseFloorProbe::NoiseFloorProbe() {
  std::ifstream("/proc/loadavg") >> load_average_1m_;
  logical_cores_ = std::max(1, static_cast<int>(::sysconf(_SC_NPROCESSORS_ONLN)));
  other_runnable_start_ = other_runnable_tasks();
  const CalibrationBatch before = time_calibration();
  calibration_before_ns_ = before.p50_ns;
  calibration_before_p90_ns_ = before.p90_ns;
  wall_start_ns_ = clock_ns(CLOCK_MONOTONIC);
  cpu_start_ns_ = clock_ns(CLOCK_THREAD_CPUTIME_ID);
}

NoiseFloor NoiseFloorProbe::finish() const {
  NoiseFloor noise;
  const int64_t wall = clock_ns(CLOCK_MONOTONIC) - wall_start_ns_;
  const int64_t cpu = clock_ns(CLOCK_THREAD_CPUTIME_ID) - cpu_start_ns_;
  noise.cpu_share =
      wall > 0 ? std::min(1.0, static_cast<double>(cpu) / static_cast<double>(wall)) : 1.0;
  const CalibrationBatch after = time_calibration();
  noise.interruptions = measure_interruptions(kInterruptionSpinNs);
  noise.calibration_before_ns = calibration_before_ns_;
  noise.calibration_after_ns = after.p50_ns;
  const double p50 = std::min(calibration_before_ns_, after.p50_ns);
  const double p90 = std::max(calibration_before_p90_ns_, after.p90_ns);
  noise.calibration_spread = p50 > 0 ? p90 / p50 - 1 : 0;
  noise.calibration_drift =
      calibration_before_ns_ > 0 ? std::abs(after.p50_ns / calibration_before_ns_ - 1) : 0;
  noise.load_average_1m = load_average_1m_;
  noise.logical_cores = logical_cores_;
  const int other_runnable_end = other_runnable_tasks();
  noise.other_runnable = other_runnable_start_ < 0 || other_runnable_end < 0
                             ? -1
                             : std::max(other_runnable_start_, other_runnable_end);
  noise.quiet = noise.cpu_share >= kQuietCpuShare && noise.calibration_spread <= kQuietSpread &&
                noise.calibration_drift <= kQuietDrift &&
                noise.load_average_1m <= logical_cores_ - 0.5 &&
                noise.other_runnable <= std::max(0, logical_cores_ - 2);
  return noise;
}

}  // namespace hb
