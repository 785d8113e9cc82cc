#include "harness/replay/replay.h"

#include <chrono>
#include <memory>

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
}  // namespace

void replay(Renderer& renderer, std::span<const DeviceSample> samples,
            const ReplaySettings& settings, TickObserver& observer) {
  if (samples.empty()) return;
  renderer.reset(samples.front().pose);
  SlowLoop* slow_loop = renderer.slow_loop();

  std::optional<PendingSlowResult> pending;
  int64_t installed_start_tick = -1;

  for (const DeviceSample& sample : samples) {
    TickRecord record;
    record.device = &sample;
    bool installed_now = false;
    if (pending && pending->install_tick <= sample.tick) {
      slow_loop->install_slow_result(std::move(pending->result));
      installed_start_tick = pending->start_tick;
      pending.reset();
      installed_now = true;
    }

    const auto t0 = std::chrono::steady_clock::now();
    record.result = renderer.step(sample);
    const auto t1 = std::chrono::steady_clock::now();
    record.step_ns = elapsed_ns(t0, t1);
    record.contacts.assign(record.result.contacts.begin(), record.result.contacts.end());
    record.result.contacts = record.contacts;
    if (installed_now) record.result.flags |= kFlagSlowResultInstalled;
    record.slow_data_age_ticks = installed_start_tick < 0 ? -1 : sample.tick - installed_start_tick;

    if (slow_loop && !pending) {
      const auto s0 = std::chrono::steady_clock::now();
      std::unique_ptr<SlowLoop::Result> result = slow_loop->run_slow_update();
      const auto s1 = std::chrono::steady_clock::now();
      record.slow_started = true;
      record.slow_ns = elapsed_ns(s0, s1);
      int64_t latency = 1;
      if (settings.slow_loop_latency_ticks) {
        latency = *settings.slow_loop_latency_ticks;
      } else {
        latency = (record.slow_ns + kTickNs - 1) / kTickNs;
      }
      if (latency < 1) latency = 1;
      record.slow_latency_ticks = latency;
      pending = PendingSlowResult{std::move(result), sample.tick, sample.tick + latency};
    }
    observer.on_tick(record);
  }
}

}  // namespace hb
