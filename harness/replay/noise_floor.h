// How noisy the machine was while a timing pass ran, measured in the same
// run: the share of wall time the replaying thread actually had a CPU, and
// the spread and drift of a fixed calibration workload timed before and
// after the pass. Wall-clock comparisons are trusted only from quiet runs.
#pragma once

#include <cstdint>

namespace hb {

struct NoiseFloor {
  /// Thread CPU time / wall time over the timing pass (1 = never preempted).
  double cpu_share = 1;
  /// Calibration workload, median ns per repetition before and after the pass.
  double calibration_before_ns = 0;
  double calibration_after_ns = 0;
  /// p90 / p50 - 1 of the calibration repetitions (both batches together).
  double calibration_spread = 0;
  /// |after / before - 1|.
  double calibration_drift = 0;
  /// /proc/loadavg (1 min) at the start of the pass, and the online logical CPUs.
  double load_average_1m = 0;
  int logical_cores = 1;
  /// Other runnable tasks (/proc/loadavg's running count less this one),
  /// the larger of the counts at the start and at the end of the pass; −1
  /// when unreadable. The load average lags by a minute; this does not, and
  /// a busy neighbour (an SMT sibling, a shared cache) slows the steps
  /// without taking this thread's CPU or slowing the calibration workload.
  int other_runnable = -1;
  /// cpu_share >= kQuietCpuShare, spread <= kQuietSpread, drift <= kQuietDrift,
  /// load_average_1m <= logical_cores - 0.5 (this process counts one) and
  /// other_runnable <= max(0, logical_cores - 2) (a core besides this one idle).
  bool quiet = false;
};

inline constexpr double kQuietCpuShare = 0.97;
inline constexpr double kQuietSpread = 0.10;
inline constexpr double kQuietDrift = 0.10;

/// Brackets one timing pass: construct before it, finish() after it.
class NoiseFloorProbe {
 public:
  NoiseFloorProbe();
  NoiseFloor finish() const;

 private:
  int64_t wall_start_ns_ = 0;
  int64_t cpu_start_ns_ = 0;
  double calibration_before_ns_ = 0;
  double calibration_before_p90_ns_ = 0;
  double load_average_1m_ = 0;
  int logical_cores_ = 1;
  int other_runnable_start_ = -1;
};

}  // namespace hb
