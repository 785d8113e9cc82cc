// Limit cycles of a device in closed loop: a sustained oscillation of the
// device while it is in contact that the operator's intent does not explain
// (the buzz of a sampled wall). The run is cut into blocks of kBlockTicks
// ticks; in each block with contact on at least kMinContactShare of its
// ticks (a buzzing device touches on only part of each period), the device's
// and the intent's positions along the block's mean displayed force are
// detrended (least-squares line) and their oscillation measured:
//   amplitude  = √2 × RMS of the residual (m; a sinusoid's amplitude),
//   frequency  = sign changes of the residual / (2 × block duration) (Hz).
// A block oscillates when the device's amplitude is at least the floor, at
// least kIntentRatio times the intent's, and the residual changes sign at
// least kMinSignChanges times (one and a half periods: 15 Hz and up for
// 100-tick blocks; four, which a 20 Hz bounce reaches only in some
// phases, missed the default hand's bounce). The run has a limit cycle
// when at least kMinShare of its contact blocks oscillate and the
// oscillation is not dying out: the mean amplitude of the last quarter of
// the oscillating blocks is at least kDecayRatio times that of the quarter
// before (of the oscillating blocks: the quiet blocks of a release at the
// end of a hold are no decay).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

struct LimitCycleMetrics {
  int64_t contact_blocks = 0;          ///< blocks with contact on kMinContactShare of their ticks
  int64_t oscillating_blocks = 0;      ///< of those, the blocks whose device oscillates
  double share = 0;                    ///< oscillating_blocks / contact_blocks (0 without contact)
  std::optional<double> amplitude_m;   ///< median amplitude of the oscillating blocks
  std::optional<double> frequency_hz;  ///< median frequency of the oscillating blocks
  bool limit_cycle = false;            ///< sustained, as defined above
};

class LimitCycleDetector {
 public:
  static constexpr int kBlockTicks = 100;
  static constexpr double kMinContactShare = 0.1;
  static constexpr double kIntentRatio = 2;
  static constexpr int kMinSignChanges = 3;
  static constexpr double kMinShare = 0.25;
  static constexpr double kDecayRatio = 0.9;
  static constexpr double kDefaultFloorM = 1e-5;

  /// `floor_m`: the smallest amplitude that counts (m); `tick_s`: the tick (s).
  explicit LimitCycleDetector(double floor_m = kDefaultFloorM, double tick_s = 1e-3);

  /// One tick: the device's true tool-frame origin and the intent's (m,
  /// world), the displayed force (N) and whether the tick is in contact.
  void add(const Vec3& device_p, const Vec3& intent_p, const Vec3& force, bool in_contact);

  LimitCycleMetrics finish() const;

 private:
  struct Block {
    double amplitude_m;
    double frequency_hz;
    bool oscillates;
  };
  void close_block();

  double floor_m_, tick_s_;
  std::vector<Vec3> device_, intent_;  ///< the current block's ticks
  Vec3 force_sum_ = Vec3::Zero();
  int contact_ticks_ = 0;
  std::vector<Block> contact_blocks_;  ///< in run order
};

}  // namespace hb
