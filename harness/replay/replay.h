// The replay loop: a fixed 1 kHz virtual clock that feeds device samples to
// a renderer, times only its step(), and emulates the slow thread of
// multi-rate algorithms deterministically in virtual time.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "algorithms/proxy/renderer.h"

namespace hb {

/// Virtual clock period: one haptic tick.
inline constexpr int64_t kTickNs = 1'000'000;

struct ReplaySettings {
  /// Ticks between the start of a slow update and the installation of its
  /// result (>= 1); nullopt means "measured": ceil(wall time of the update / 1 ms).
  std::optional<int64_t> slow_loop_latency_ticks = 1;
};

/// Everything the replay loop knows about one tick, handed to the observer
/// after the timed window closed.
struct TickRecord {
  const DeviceSample* device = nullptr;
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

/// Resets the renderer at the first sample's pose and replays every sample.
/// At tick k: install a pending slow result whose installation tick is k;
/// time step(sample k); if the renderer has a slow loop and no update is in
/// flight, run one on the state after step k (timed apart) and schedule its
/// installation at k + L; hand the record to the observer.
void replay(Renderer& renderer, std::span<const DeviceSample> samples,
            const ReplaySettings& settings, TickObserver& observer);

}  // namespace hb
