// The massless proxy with soft constraints (lecture notes, taxonomy: massless
// proxy × soft constraints = quasi-static equilibrium). Each tick the proxy
// is placed where the spring forces on it balance:
//   F_c(x, θ) + Σ F_i(x, θ) = 0,   τ_c + Σ M_i = 0   (about the centre of mass)
// found by damped Newton steps on the 6×6 stiffness Jacobian
// K = ∂(F, τ)/∂(δx, δθ), warm-started from the previous tick's pose. Only
// springs enter the equilibrium: the coupling's dampers act on the proxy's
// motion between ticks, which is what the device displays.
#pragma once

#include <cstdint>

#include "hapticbench/proxy/force_model.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

struct QuasiStaticSettings {
  int max_iterations = 20;            ///< Newton steps per solve
  double force_tolerance_n = 1e-9;    ///< stop when |F| + |τ|/length_scale_m is below (N)
  double step_tolerance_m = 1e-12;    ///< stop when a step moves the COM less (m) ...
  double step_tolerance_rad = 1e-10;  ///< ... and turns the proxy less (rad)
  double length_scale_m = 0.05;       ///< converts torque to force in the residual (m)
};
/// The earlier name, kept so that renderers built against it still compile.
using QuasiStaticOptions [[deprecated("use QuasiStaticSettings")]] = QuasiStaticSettings;

struct QuasiStaticSolution {
  RigidBodyState state;  ///< the equilibrium found (velocities as given at the start)
  int iterations = 0;    ///< Newton steps taken
  bool converged = false;
};

/// Finds the pose where `springs` sums to zero, starting at `start`. Each
/// Newton step solves K Δ = −(F, τ) (minimum-norm when K is singular) and is
/// halved until the residual decreases.
QuasiStaticSolution solve_quasi_static(ForceModel& springs, const RigidBodyState& start,
                                       const QuasiStaticSettings& settings);

/// A massless proxy on the virtual coupling's springs. `frame` supplies only
/// the centre of mass the wrenches are taken about; mass and inertia are unused.
class QuasiStaticProxy {
 public:
  QuasiStaticProxy(const RigidBody& frame, const CouplingGains& gains, double dt_s,
                   const QuasiStaticSettings& settings);

  /// Puts the proxy's tool frame at `pose`, at rest.
  void reset(const Pose& pose);

  /// Solves the equilibrium with the device at `device` and the contact
  /// springs `contact_springs` (nullptr: none), warm-started from the last
  /// pose; returns the raw displayed wrench: the coupling's reaction, its
  /// dampers driven by the proxy's velocity over the tick (N, N·m about the
  /// tool-frame origin, world). Adds its Newton steps to newton_steps.
  /// Non-finite input or state is handled as in DynamicProxy::advance.
  Wrench advance(const DeviceSample& device, ForceModel* contact_springs, uint32_t& flags,
                 int64_t& newton_steps);

  const RigidBodyState& state() const { return state_; }
  Pose tool_pose() const { return hb::tool_pose(frame_, state_); }
  /// Whether the last solve met the tolerances.
  bool converged() const { return converged_; }

 private:
  RigidBody frame_;
  CouplingGains gains_;
  double dt_s_;
  QuasiStaticSettings settings_;
  RigidBodyState state_;
  bool converged_ = true;
};

}  // namespace hb
