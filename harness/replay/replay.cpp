#include "harness/replay/replay.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "harness/closed_loop/closed_loop_device.h"
#include "harness/process/interrupt.h"
#include "harness/replay/instruction_count.h"

namespace hb {

namespace {
int64_t elapsed_ns(std::chrono::steady_clock::time_point t0,
                   std::chrono::steady_clock::time_point t1) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count();
}

// A slow update that has finished in wall time but whose result becomes
// visible only at install_tick of the virtual clock.
struct PendingSlowResult {
  std::unique_ptr<SlowLoop::Result> result;
  int64_t start_tick = 0;
  int64_t install_tick = 0;
};

// Ticks from the start of update `index` (started at `start_tick`, took
// `update_ns`) to the installation of its result.
int64_t latency_ticks(const ReplaySettings& settings, std::size_t index, int64_t start_tick,
                      int64_t update_ns) {
  switch (settings.slow_loop_timing) {
    case SlowLoopTiming::kFixed:
      return std::max<int64_t>(1, settings.fixed_latency_ticks);
    case SlowLoopTiming::kMeasured:
      return std::max<int64_t>(1, (update_ns + kTickNs - 1) / kTickNs);
    case SlowLoopTiming::kReplayed:
      break;
  }
  const SlowLoopSchedule* schedule = settings.replayed_schedule;
  if (!schedule || index >= schedule->updates.size())
    throw ScheduleMismatch("the replayed schedule has " +
                           std::to_string(schedule ? schedule->updates.size() : 0) +
                           " updates; this run starts update " + std::to_string(index + 1) +
                           " at tick " + std::to_string(start_tick));
  const SlowLoopUpdate& recorded = schedule->updates[index];
  if (recorded.start_tick != start_tick)
    throw ScheduleMismatch("update " + std::to_string(index + 1) + " starts at tick " +
                           std::to_string(start_tick) + " in this run but at tick " +
                           std::to_string(recorded.start_tick) + " in the replayed schedule");
  return recorded.install_tick - recorded.start_tick;
}
}  // namespace

const char* slow_loop_timing_name(SlowLoopTiming timing) {
  switch (timing) {
    case SlowLoopTiming::kMeasured:
      return "measured";
    case SlowLoopTiming::kFixed:
      return "fixed";
    case SlowLoopTiming::kReplayed:
      return "replayed";
  }
  return "measured";
}

SlowLoopSchedule replay(Renderer& renderer, std::span<const DeviceSample> samples,
                        const ReplaySettings& settings, TickObserver& observer) {
  return replay(
      renderer,
      DeviceTrajectory::of_samples(std::vector<DeviceSample>(samples.begin(), samples.end())),
      settings, observer);
}

SlowLoopSchedule replay(Renderer& renderer, const DeviceTrajectory& trajectory,
                        const ReplaySettings& settings, TickObserver& observer) {
  SlowLoopSchedule followed;
  if (trajectory.ticks() == 0) return followed;
  // A block holds the samples of kBlockTicks ticks and the one after them,
  // which closed loop needs to advance the device over the block's last tick.
  std::vector<DeviceSample> block(
      static_cast<std::size_t>(std::min(DeviceTrajectory::kBlockTicks + 1, trajectory.ticks())));
  trajectory.fill(0, std::span<DeviceSample>(block.data(), 1));
  std::optional<ClosedLoopDevice> device;
  DeviceSample reported;
  if (settings.closed_loop) {
    device.emplace(*settings.closed_loop, static_cast<double>(kTickNs) * 1e-9);
    device->reset(block.front().pose);
    reported = device->report(0);
    renderer.reset(reported.pose);
  } else {
    renderer.reset(block.front().pose);
  }
  SlowLoop* slow_loop = renderer.slow_loop();
  const bool count_step = settings.counted == CountedCalls::kStep;
  const bool count_slow = settings.counted == CountedCalls::kSlowUpdate;

  std::optional<PendingSlowResult> pending;
  int64_t installed_start_tick = -1;

  for (int64_t tick = 0; tick < trajectory.ticks(); ++tick) {
    // The next block of device samples, computed between two ticks.
    const auto in_block = static_cast<std::size_t>(tick % DeviceTrajectory::kBlockTicks);
    if (in_block == 0) {
      const int64_t count = std::min(DeviceTrajectory::kBlockTicks + 1, trajectory.ticks() - tick);
      trajectory.fill(tick, std::span<DeviceSample>(block.data(), static_cast<std::size_t>(count)));
    }
    const DeviceSample& trajectory_sample = block[in_block];
    if (device) reported = device->report(trajectory_sample.tick);
    const DeviceSample& sample = device ? reported : trajectory_sample;
    // A stop request (SIGINT, SIGTERM) is honoured between ticks, every
    // 256 ticks: one load of a flag, outside the timed window.
    if ((sample.tick & 255) == 0) throw_if_interrupted();
    TickRecord record;
    record.device = &sample;
    if (device) {
      record.intent = &trajectory_sample;
      record.device_actual = &device->pose();
      record.device_absorbed_j = device->absorbed_energy_j();
    }
    bool installed_now = false;
    if (pending && pending->install_tick <= sample.tick) {
      slow_loop->install_slow_result(std::move(pending->result));
      installed_start_tick = pending->start_tick;
      pending.reset();
      installed_now = true;
    }

    const auto t0 = std::chrono::steady_clock::now();
    if (count_step) toggle_instruction_collection();
    record.result = renderer.step(sample);
    if (count_step) toggle_instruction_collection();
    const auto t1 = std::chrono::steady_clock::now();
    record.step_ns = elapsed_ns(t0, t1);
    record.contacts.assign(record.result.contacts.begin(), record.result.contacts.end());
    record.result.contacts = record.contacts;
    if (installed_now) record.result.flags |= kFlagSlowResultInstalled;
    record.slow_data_age_ticks = installed_start_tick < 0 ? -1 : sample.tick - installed_start_tick;

    if (slow_loop && !pending) {
      const auto s0 = std::chrono::steady_clock::now();
      if (count_slow) toggle_instruction_collection();
      std::unique_ptr<SlowLoop::Result> result = slow_loop->run_slow_update();
      if (count_slow) toggle_instruction_collection();
      const auto s1 = std::chrono::steady_clock::now();
      record.slow_started = true;
      record.slow_ns = elapsed_ns(s0, s1);
      const int64_t latency =
          latency_ticks(settings, followed.updates.size(), sample.tick, record.slow_ns);
      record.slow_latency_ticks = latency;
      followed.updates.push_back({sample.tick, sample.tick + latency, record.slow_ns});
      pending = PendingSlowResult{std::move(result), sample.tick, sample.tick + latency};
    }
    observer.on_tick(record);
    if (device && tick + 1 < trajectory.ticks()) {
      // The wrench is displayed until the next tick; a non-finite one (which
      // device_output() never lets out) would be zero on a real device.
      const Wrench& display = record.result.display;
      device->advance(is_finite(display) ? display : Wrench{}, trajectory_sample.pose,
                      block[in_block + 1].pose);
    }
  }
  return followed;
}

}  // namespace hb
