// The replay loop: a fixed 1 kHz virtual clock that feeds device samples to
// a renderer, times only its step(), and emulates the slow thread of
// multi-rate algorithms deterministically in virtual time.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hapticbench/renderer.h"
#include "harness/closed_loop/closed_loop_model.h"
#include "harness/replay/slow_loop_schedule.h"
#include "harness/trace/device_trajectory.h"

namespace hb {

/// Virtual clock period: one haptic tick.
inline constexpr int64_t kTickNs = 1'000'000;

/// How the slow updates of a multi-rate algorithm are placed in virtual time.
enum class SlowLoopTiming {
  /// Each update is installed ceil(its wall time / 1 ms) ticks after it
  /// started (at least 1): what this machine would show. The default.
  kMeasured,
  /// Each update is installed a fixed number of ticks after it started: an
  /// idealised machine, reproducible anywhere.
  kFixed,
  /// The latencies of a recorded schedule, update by update.
  kReplayed,
};

/// "measured", "fixed", "replayed".
const char* slow_loop_timing_name(SlowLoopTiming timing);

/// Which calls the instruction counter (instruction_count.h) collects.
enum class CountedCalls { kNone, kStep, kSlowUpdate };

struct ReplaySettings {
  SlowLoopTiming slow_loop_timing = SlowLoopTiming::kMeasured;
  int64_t fixed_latency_ticks = 1;  ///< with kFixed (>= 1)
  /// With kReplayed: the schedule to follow. Its update k must start at the
  /// tick update k starts in this replay (ScheduleMismatch otherwise).
  const SlowLoopSchedule* replayed_schedule = nullptr;
  /// Under valgrind's callgrind: collect only these calls (no effect otherwise).
  CountedCalls counted = CountedCalls::kNone;
  /// Closed loop (closed_loop_device.h): the trajectory is the operator's
  /// intent, and step() sees what a device held by a hand reports. Null:
  /// open loop, the trajectory is the device.
  const ClosedLoopModel* closed_loop = nullptr;
};

/// Everything the replay loop knows about one tick, handed to the observer
/// after the timed window closed.
struct TickRecord {
  const DeviceSample* device = nullptr;  ///< what step() was given
  /// Closed loop: the operator's intent (the trajectory's sample) and the
  /// device's true pose, which `device` reports through its encoders. Null
  /// in open loop, where the trajectory's sample is the device.
  const DeviceSample* intent = nullptr;
  const Pose* device_actual = nullptr;
  /// Closed loop: the energy the device itself has taken in up to this
  /// tick (J; ClosedLoopDevice::absorbed_energy_j); 0 in open loop.
  double device_absorbed_j = 0;
  TickResult result;               ///< result.contacts points into `contacts`
  std::vector<Contact> contacts;   ///< copy of step()'s contacts, safe across the slow update
  int64_t step_ns = 0;             ///< wall time of step(), steady clock
  bool slow_started = false;       ///< a slow update started after this tick's step
  int64_t slow_ns = 0;             ///< wall time of that slow update (0 if none)
  int64_t slow_latency_ticks = 0;  ///< ticks until its result is installed
  /// Age in ticks of the slow-loop data step() used (tick - start tick of the
  /// installed update); -1 before the first installation or without a slow loop.
  int64_t slow_data_age_ticks = -1;
};

/// Receives each tick outside the timed window (ground truth, metrics, logs).
class TickObserver {
 public:
  virtual ~TickObserver() = default;
  virtual void on_tick(const TickRecord& record) = 0;
};

/// The device's true pose at a tick: in closed loop the device's own, else
/// the sample's.
inline const Pose& device_pose(const TickRecord& record) {
  return record.device_actual ? *record.device_actual : record.device->pose;
}

/// Resets the renderer at the first sample's pose and replays every sample.
/// At tick k: install a pending slow result whose installation tick is k;
/// time step(sample k); if the renderer has a slow loop and no update is in
/// flight, run one on the state after step k (timed apart) and schedule its
/// installation at k + L (L from the settings); hand the record to the
/// observer. Returns the schedule it followed (empty without a slow loop).
/// Throws ScheduleMismatch when a replayed schedule does not fit.
/// The device's samples are computed a block at a time, outside the timed
/// windows; record.device is valid only during on_tick. In closed loop the
/// device is advanced over each tick with the tick's displayed wrench after
/// on_tick, also outside the timed window.
SlowLoopSchedule replay(Renderer& renderer, const DeviceTrajectory& trajectory,
                        const ReplaySettings& settings, TickObserver& observer);
/// The same with every tick given.
SlowLoopSchedule replay(Renderer& renderer, std::span<const DeviceSample> samples,
                        const ReplaySettings& settings, TickObserver& observer);

}  // namespace hb
