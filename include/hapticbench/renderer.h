// The plug-in point: every rendering algorithm is a Renderer. The replay
// loop calls step() once per 1 ms tick; only step() is timed.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

/// One device reading at a tick of the 1 kHz clock.
struct DeviceSample {
  int64_t tick = 0;  ///< tick index, 1 ms apart
  int64_t t_ns = 0;  ///< tick * 1'000'000
  Pose pose;         ///< device's tool frame in the world (m, qw,qx,qy,qz)
  Twist twist;       ///< velocity of the tool frame origin, world frame
};

/// A contact an algorithm reports, for the oracle to check.
struct Contact {
  Vec3 point;    ///< m, world frame
  Vec3 normal;   ///< world frame, unit length, pushes the tool out of the scene
  double depth;  ///< m, penetration along the normal (>= 0 when penetrating)
};

/// What a tick did, so run time can be explained: up to kSlots counts that
/// the algorithm names for what it does ("points_looked_up", "gjk_calls",
/// ...). The algorithm points `names` at a static table of its counter
/// names, in slot order; summary.json reports each run's totals under
/// contacts.work by those names. Plain integers, so that counting inside
/// step() costs an increment.
struct WorkCounters {
  static constexpr std::size_t kSlots = 16;
  using Names = std::array<std::string_view, kSlots>;  ///< "" marks an unused slot

  const Names* names = nullptr;  ///< null: nothing counted
  std::array<int64_t, kSlots> counts{};

  void add(std::size_t slot, int64_t count = 1) { counts[slot] += count; }
  /// The count named `name`; 0 when no slot has that name.
  int64_t get(std::string_view name) const {
    if (!names || name.empty()) return 0;
    for (std::size_t i = 0; i < kSlots; ++i)
      if ((*names)[i] == name) return counts[i];
    return 0;
  }
};

/// Bits of TickResult::flags.
enum TickFlag : uint32_t {
  kFlagNonFiniteZeroed = 1u << 0,      ///< a non-finite wrench was replaced by zero
  kFlagForceSaturated = 1u << 1,       ///< force clipped to the device's limit
  kFlagTorqueSaturated = 1u << 2,      ///< torque clipped to the device's limit
  kFlagProxyReset = 1u << 3,           ///< proxy state became non-finite and was reset
  kFlagSlowResultInstalled = 1u << 4,  ///< a slow-loop result was installed this tick
};

struct TickResult {
  Wrench display;  ///< what the device displays: N and N·m about the tool frame origin, world
  Pose proxy;      ///< proxy's tool frame in the world
  std::span<const Contact> contacts;  ///< valid until the next step()/reset()
  WorkCounters work;
  uint32_t flags = 0;
};

/// The slow part of a multi-rate algorithm (contact queries, god-object
/// update). The replay loop emulates its thread in virtual time: an update
/// started at tick k sees the renderer's state after step(k) and its result
/// is installed before step(k + L).
class SlowLoop {
 public:
  virtual ~SlowLoop() = default;
  /// Opaque result of one slow update.
  struct Result {
    virtual ~Result() = default;
  };
  /// Runs one slow update on the current state (timed by the caller).
  virtual std::unique_ptr<Result> run_slow_update() = 0;
  /// Makes a finished update's result visible to the next step().
  virtual void install_slow_result(std::unique_ptr<Result> result) = 0;
};

/// What building a renderer produced, for the run summary's "preprocess"
/// block (the harness measures the build's wall time itself).
struct BuildReport {
  int64_t memory_bytes = 0;  ///< bytes its precomputed structures hold
  bool cache_hit = false;    ///< everything came from an on-disk cache
  /// Further figures by name, units in the name (e.g. "pointshell_points",
  /// "voxmap_vdb_bytes"); flags as 0/1.
  std::vector<std::pair<std::string, double>> details;
};

class Renderer {
 public:
  virtual ~Renderer() = default;
  /// Puts the proxy at rest at the start pose and clears all state.
  virtual void reset(const Pose& start) = 0;
  /// One haptic tick; dt = 1 ms fixed by the clock.
  virtual TickResult step(const DeviceSample& device) = 0;
  /// The slow loop of a multi-rate algorithm, or nullptr.
  virtual SlowLoop* slow_loop() { return nullptr; }
  /// What building it produced (empty for a renderer that precomputes nothing).
  virtual BuildReport build_report() const { return {}; }
};

}  // namespace hb
