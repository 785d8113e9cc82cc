// The proxy with mass of the generic proxy model: a rigid body pulled by the
// virtual coupling towards the device and pushed by whatever contact forces
// an algorithm supplies, advanced once per haptic tick by either integrator.
#pragma once

#include <cstdint>

#include "hapticbench/proxy/force_model.h"
#include "hapticbench/proxy/integrator.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

class DynamicProxy {
 public:
  /// dt_s: tick length (s).
  DynamicProxy(const RigidBody& body, const CouplingGains& gains, IntegratorKind integrator,
               double dt_s);

  /// Puts the proxy's tool frame at `pose`, at rest.
  void reset(const Pose& pose);

  /// Advances one tick under coupling to `device` plus `contacts` (nullptr:
  /// none) and returns the raw displayed wrench: the reaction to the coupling
  /// force the step applied, i.e. at the state before the step for explicit
  /// Euler and after it for implicit Euler (N, N·m about the tool-frame
  /// origin, world). A non-finite
  /// device sample leaves the proxy where it is and returns a zero wrench
  /// with kFlagNonFiniteZeroed; a state that became non-finite is reset to
  /// the device pose (kFlagProxyReset).
  Wrench advance(const DeviceSample& device, ForceModel* contacts, uint32_t& flags);

  const RigidBody& body() const { return body_; }
  const RigidBodyState& state() const { return state_; }
  /// The proxy's tool frame in the world.
  Pose tool_pose() const { return hb::tool_pose(body_, state_); }

 private:
  RigidBody body_;
  CouplingGains gains_;
  IntegratorKind integrator_;
  double dt_s_;
  RigidBodyState state_;
};

}  // namespace hb
