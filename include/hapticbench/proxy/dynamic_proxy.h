// The proxy with mass of the generic proxy model: a rigid body pulled by the
// virtual coupling towards the device and pushed by whatever contact forces
// an algorithm supplies, advanced once per haptic tick by either integrator.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>

#include "hapticbench/proxy/force_model.h"
#include "hapticbench/proxy/integrator.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// How far a proxy that follows the device in free space may jump to it.
struct FreeSpaceFollowing {
  double tool_radius_m = 0;  ///< farthest tool point from the centre of mass (m)
  /// No tool point jumps farther than this (m): the width of a band in
  /// which the contact forces act before contact (VPS's proximity voxels,
  /// where braking acts), so that no jump steps over it.
  double max_point_step_m = std::numeric_limits<double>::infinity();
};

/// Whether a proxy leaving contact may jump to the device: the display the
/// jump takes away (`display`, N and N·m) is no more than the device's own
/// step since the last tick (from `last_device` to `device`, tool frames)
/// puts on the coupling spring, k_T |Δx| and k_R |Δθ|, or than 5 mN (and
/// 5 mN times `tool_radius_m`, m): the display jumps no more than it does at
/// an encoder step.
bool display_allows_jump_to_device(const CouplingGains& gains, const Wrench& display,
                                   const Pose& device, const Pose& last_device,
                                   double tool_radius_m);

class DynamicProxy {
 public:
  /// dt_s: tick length (s).
  DynamicProxy(const RigidBody& body, const CouplingGains& gains, IntegratorKind integrator,
               double dt_s);

  /// Out of contact the proxy is the device (pose and velocity), so the
  /// coupling displays nothing there: integrating a mass on the coupling in
  /// free space displays the device's encoder staircase (k_T times a count
  /// at each step: 0.44 N peaks at 21,000 N/m with the default device) and
  /// the virtual tool's inertia, neither of which is contact. A proxy
  /// leaving contact is integrated until the display a jump to the device
  /// would take away is no more than the device's own step since the last
  /// tick puts on the coupling spring (k_T |Δx|, k_R |Δθ|) or 5 mN (and
  /// 5 mN times the tool's radius): the display jumps no more than at an
  /// encoder step. It then stays the device while the contact forces exert
  /// nothing where it is and where the device is (a proxy pressing on a
  /// thin wall does not jump to a device beyond it) and no tool point
  /// jumps farther than the limit's max_point_step_m. Off by default (the
  /// coupling alone); never under gravity, whose weight the coupling
  /// displays.
  void follow_device_in_free_space(const FreeSpaceFollowing& limits);

  /// Puts the proxy's tool frame at `pose`, at rest.
  void reset(const Pose& pose);

  /// Advances one tick under coupling to `device` plus `contacts` (nullptr:
  /// none) and returns the raw displayed wrench: the reaction to the coupling
  /// force the step applied, i.e. at the state before the step for explicit
  /// Euler and after it for implicit Euler (N, N·m about the tool-frame
  /// origin, world), or, where the proxy then jumps to the device in free
  /// space, at the device. A non-finite device sample leaves the proxy where it is
  /// and returns a zero wrench with kFlagNonFiniteZeroed; a state that
  /// became non-finite is reset to the device pose (kFlagProxyReset).
  Wrench advance(const DeviceSample& device, ForceModel* contacts, uint32_t& flags);

  const RigidBody& body() const { return body_; }
  const RigidBodyState& state() const { return state_; }
  /// The proxy's tool frame in the world.
  Pose tool_pose() const { return hb::tool_pose(body_, state_); }

 private:
  double point_step(const RigidBodyState& from, const RigidBodyState& to) const;
  bool free_to_jump(const RigidBodyState& from, const RigidBodyState& at_device,
                    ForceModel* contacts) const;

  RigidBody body_;
  CouplingGains gains_;
  IntegratorKind integrator_;
  double dt_s_;
  RigidBodyState state_;
  std::optional<FreeSpaceFollowing> following_;
  std::optional<Pose> last_device_;  ///< the last finite device pose (tool frame)
  bool at_device_now_ = false;       ///< the proxy jumped to the device last tick
};

}  // namespace hb
