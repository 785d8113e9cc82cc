// The last stage of every renderer: numerical health as data, not a crash.
// A non-finite wrench is never sent to a device; a force or torque beyond the
// device's limits is clipped along its own direction; a proxy whose state
// became non-finite is put back at the device's pose.
#pragma once

#include <cstdint>

#include "hapticbench/pose.h"
#include "hapticbench/proxy/rigid_body.h"
#include "hapticbench/renderer.h"
#include "hapticbench/scene.h"

namespace hb {

/// What the device may show for a raw displayed wrench (N, N·m about the
/// tool-frame origin, world frame). A wrench with any non-finite coefficient
/// becomes zero and sets kFlagNonFiniteZeroed; a force (torque) longer than
/// limits.max_force_n (max_torque_nm) is scaled down to that length, keeping
/// its direction, and sets kFlagForceSaturated (kFlagTorqueSaturated).
Wrench device_output(const Wrench& raw, const DeviceLimits& limits, uint32_t& flags);

/// True when the sample's pose and twist are finite. A renderer must not let a
/// non-finite reading into its state.
bool is_finite(const DeviceSample& sample);

/// When `state` has a non-finite coefficient, replaces it by the device's
/// tool-frame pose at rest, sets kFlagProxyReset and returns true. The device
/// pose must be finite.
bool reset_non_finite_proxy(const RigidBody& body, const Pose& device_pose, RigidBodyState& state,
                            uint32_t& flags);

}  // namespace hb
