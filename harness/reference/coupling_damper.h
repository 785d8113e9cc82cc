// The virtual coupling's damper on the ideal proxy. Every algorithm displays
// the whole coupling between its proxy and the device: k_T (x_p − x_d) +
// b_T (v_p − v_d), and k_R θ + b_R (ω_p − ω_d) (algorithms/proxy/
// virtual_coupling.cpp). The references give the spring part at the ideal
// proxy; this adds the damper part, with the ideal proxy's velocity taken
// from its own path, so that the damper is not charged to the algorithms as
// error (b_T = 5 N·s/m made 0.05–0.19 N RMS on the mesh suite). Units: m,
// rad, s, N, N·m; world frame.
#pragma once

#include <cstdint>
#include <optional>

#include "hapticbench/pose.h"
#include "hapticbench/scene.h"
#include "harness/reference/analytic_reference.h"

namespace hb {

class IdealCouplingDamper {
 public:
  /// `gains`: the scenario's coupling (only b_t, N·s/m, and b_r,
  /// N·m·s/rad, are used); `dt_s`: the tick (s).
  IdealCouplingDamper(const CouplingGains& gains, double dt_s) : gains_(gains), dt_s_(dt_s) {}

  /// Adds b_t (v_p − v_d) to ideal.display.force and b_r (ω_p − ω_d) to
  /// its torque, for the device sample at `tick` with twist `device`. The
  /// ideal proxy's velocity v_p, ω_p is the backward difference of its pose
  /// since the previous call (over the ticks in between: a reference sampled
  /// every n ticks differences over n ticks); it is the device's own while
  /// the ideal proxy is the device (out of contact) and on the first call.
  void apply(int64_t tick, const Twist& device, IdealRendering& ideal);

 private:
  CouplingGains gains_;
  double dt_s_;
  std::optional<Pose> last_proxy_;  ///< the ideal proxy at the last call
  int64_t last_tick_ = 0;
};

}  // namespace hb
