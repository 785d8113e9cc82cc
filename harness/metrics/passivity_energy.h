// The energy at the device port, as the passivity observer counts it
// (Hannaford & Ryu 2002), exactly for a sampled device: the device holds
// the wrench of tick n (zero-order hold) while it moves from x_n to x_{n+1}
// and turns by Δθ_n, the rotation vector of q_{n+1} q_n⁻¹, so the energy
// the user supplies over the tick is
//   ΔE_n = −F_n·(x_{n+1} − x_n) − τ_n·Δθ_n.
// The product of a tick's force with the same tick's velocity (the form
// used before) misses the sampled spring's ½k|Δx|² a tick, which is exactly
// what makes a stiff sampled wall active (Colgate & Schenkel 1997: passive
// only while b > kT/2 + |B|): that observer saw no sign change at any
// stiffness.
//
// A run that starts in contact starts with energy the device never
// supplied, stored in the stretched coupling. The rule, here and nowhere
// else: E starts at the coupling's store at the first tick, computed from
// the first displayed wrench as |F_0|²/(2 k_t) + |τ_0|²/(2 k_r) (exact for
// a spring coupling at rest; a proxy behind a stiffer contact spring in
// series stores more, so the rule errs towards calling a run active). A
// run is passive while E ≥ 0.
#pragma once

#include "hapticbench/pose.h"

namespace hb {

class PortEnergy {
 public:
  /// The coupling's stiffnesses (N/m, N·m/rad); 0 counts no store.
  PortEnergy(double coupling_k_t, double coupling_k_r) : k_t_(coupling_k_t), k_r_(coupling_k_r) {}

  /// Adds the tick whose displayed wrench is `display` (N, N·m, at the
  /// tool origin, world frame) with the device at `device` (the wrench is
  /// held until the next tick's pose arrives). Returns E (J) up to this
  /// tick's pose: the energy of every earlier tick's held wrench.
  double add(const Wrench& display, const Pose& device);

  double energy_j() const { return energy_j_; }

 private:
  double k_t_, k_r_;
  bool started_ = false;
  Wrench held_;
  Pose held_at_;
  double energy_j_ = 0;
};

}  // namespace hb
