// How noisy the machine was while a timing pass ran, measured in the same
// run: the share of wall time the replaying thread actually had a CPU, and
// the spread and drift of a fixed calibration workload timed before and
// after the pass, and how often and how long the machine interrupts a
// running thread. Wall-clock comparisons are trusted only from quiet runs.
#pragma once

#include <cstdint>
#include <vector>

namespace hb {

/// The interruptions of a thread that only reads the clock: gaps between
/// two successive reads of at least kInterruptionGapNs (timer interrupts,
/// and on a virtual machine the exits they cause). A step of duration s
/// running back to back is hit on about s × rate_hz of the ticks; once that
/// passes 1 %, its p99 holds an interruption (s + p50_ns or more) whatever
/// the algorithm does.
struct Interruptions {
  double rate_hz = 0;  ///< gaps per second of the reads' span
  double p50_ns = 0;   ///< median gap, ns (0 without any)
  double max_ns = 0;   ///< longest gap, ns
};

/// A gap between two clock reads this long (ns) is an interruption: a read
/// costs tens of ns, a cache miss or a branch miss far less than this.
inline constexpr int64_t kInterruptionGapNs = 1000;

/// Counts the interruptions in a sequence of clock reads (ns, in the order
/// read), keeping only the gaps.
class InterruptionCounter {
 public:
  void add(int64_t read_ns);
  Interruptions result() const;

 private:
  int64_t first_ns_ = 0, last_ns_ = 0;
  bool started_ = false;
  std::vector<int64_t> gaps_ns_;
};

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
  /// Measured after the pass, by reading the clock for kInterruptionSpinNs.
  Interruptions interruptions;
  /// cpu_share >= kQuietCpuShare, spread <= kQuietSpread, drift <= kQuietDrift,
  /// load_average_1m <= logical_cores - 0.5 (this process counts one) and
  /// other_runnable <= max(0, logical_cores - 2) (a core besides this one idle).
  bool quiet = false;
};

inline constexpr double kQuietCpuShare = 0.97;
inline constexpr double kQuietSpread = 0.10;
inline constexpr double kQuietDrift = 0.10;
/// How long (ns) the probe reads the clock to find the interruptions: 25
/// of a 1 kHz timer's.
inline constexpr int64_t kInterruptionSpinNs = 25'000'000;

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
