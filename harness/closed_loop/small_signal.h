// The small-signal stability limit of a closed loop: the hand and the
// device (one mass, the hand's spring and damper, the device's viscous
// friction; harness/closed_loop/axis_propagator.h), the displayed force held
// over each tick (zero-order hold), a rigid proxy at a wall behind the
// coupling (force −k_t y − b_t v̂, y the device's travel into the wall), and
// the device's velocity estimate v̂ (its first-order filter on the backward
// difference). Linear: no Coulomb friction, no encoder quantisation. Its
// limit is where the sampled loop's eigenvalues leave the unit circle.
// A large-signal search (hapticbench stability) sees more: between the two,
// the device's friction can hold the encoder's force staircase, so that
// small oscillations die and only a larger bounce grows. Units: N/m, N·s/m,
// kg, s.
#pragma once

#include <optional>
#include <string>

#include "harness/closed_loop/closed_loop_model.h"

namespace hb {

/// The spectral radius of the sampled loop at coupling stiffness `k_t` and
/// damping `b_t` (the loop is stable when it is below 1).
double small_signal_spectral_radius(const ClosedLoopModel& model, double k_t, double b_t,
                                    double tick_s);

struct SmallSignalLimit {
  std::optional<double> k_t_n_per_m;  ///< the largest stable k_t; null: see note
  std::string note;                   ///< why there is none, or what the model leaves out
};

/// The largest k_t (N/m) at which the loop with damping `b_t` is stable, to
/// a relative 1e-6, searched over [1, 1e9] N/m. `algorithm`: the renderer;
/// only rigid proxies (god_object, constrained_dynamics) are modelled, the
/// others get a note instead of a number.
SmallSignalLimit small_signal_k_t_limit(const ClosedLoopModel& model, double b_t, double tick_s,
                                        const std::string& algorithm);

}  // namespace hb
