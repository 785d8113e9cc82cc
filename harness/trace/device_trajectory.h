// The device's samples on the 1 kHz clock, computed block by block when the
// replay asks for them: a run's length costs no memory for its trajectory.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "hapticbench/renderer.h"
#include "harness/trace/trace.h"

namespace hb {

class DeviceTrajectory {
 public:
  /// No ticks.
  DeviceTrajectory() = default;
  /// `source` resampled onto the 1 kHz clock by resample_to_ticks's rules,
  /// with `duration_ticks` ticks (0 = as many as the source covers). Throws
  /// InputError("", "samples", ...) for an empty source or more than
  /// kMaxRunDurationS of ticks.
  DeviceTrajectory(TraceSource source, int64_t duration_ticks);
  /// A stored trace (kept, shared by copies of the trajectory), resampled.
  static DeviceTrajectory of_trace(Trace trace, int64_t duration_ticks);
  /// Ticks given as they are (tests, benchmarks).
  static DeviceTrajectory of_samples(std::vector<DeviceSample> samples);

  int64_t ticks() const { return ticks_; }
  /// Ticks first .. first + out.size() - 1 (all < ticks()) into `out`.
  void fill(int64_t first, std::span<DeviceSample> out) const;
  DeviceSample at(int64_t tick) const;
  /// Every tick (tests and small tools only: this is what the class avoids).
  std::vector<DeviceSample> all() const;

  /// Calls `visit(sample)` for every tick in order, a block at a time.
  template <class Visit>
  void for_each(Visit&& visit) const {
    std::vector<DeviceSample> block;
    for (int64_t first = 0; first < ticks_; first += kBlockTicks) {
      block.resize(static_cast<std::size_t>(std::min(kBlockTicks, ticks_ - first)));
      fill(first, block);
      for (const DeviceSample& sample : block) visit(sample);
    }
  }

  /// Ticks per block in for_each and the replay loop.
  static constexpr int64_t kBlockTicks = 1024;

 private:
  struct Interpolated;
  Interpolated interpolated(int64_t tick, int64_t& segment, TraceSample& a, TraceSample& b) const;

  TraceSource source_;
  std::shared_ptr<const std::vector<DeviceSample>> given_;  ///< of_samples
  int64_t ticks_ = 0;
  TraceSample first_, last_;
  /// Ticks [span_begin_, span_end_) lie inside the source's time span.
  int64_t span_begin_ = 0, span_end_ = 0;
};

}  // namespace hb
