// A device held by a hand, integrated between ticks of closed-loop replay.
// The trace is the operator's intent; the hand (HandModel) pulls the device
// towards it; the device (DeviceModel) displays the renderer's wrench, held
// over the tick (zero-order hold), and reports what a real device reports:
// its encoders' pose and its own velocity estimate.
//
// Integration (docs/closed-loop.md): each axis of translation and of
// rotation is a linear mass–spring–damper driven by the intent's velocity
// and the held force, advanced by its exact propagator (axis_propagator.h):
// no integration error without Coulomb friction. With Coulomb friction the
// tick of that axis group (translation or rotation) is cut into
// kFrictionSubsteps substeps, each with the friction force
// held (stick when the velocity would reverse and the other forces stay
// within the friction). Rotation is advanced in the rotation vector of the
// device's offset from the intent, exact for rotations about a fixed axis;
// otherwise it errs at first order in the offset times the intent's rate of
// turn (docs/closed-loop.md).
#pragma once

#include <cstdint>

#include "hapticbench/pose.h"
#include "hapticbench/renderer.h"
#include "harness/closed_loop/axis_propagator.h"
#include "harness/closed_loop/closed_loop_model.h"

namespace hb {

class ClosedLoopDevice {
 public:
  /// Substeps per tick when the device has Coulomb friction.
  static constexpr int kFrictionSubsteps = 16;

  /// `tick_s`: the haptic tick (s). Masses and inertias > 0 (hand and
  /// device together), the rest >= 0: the scenario reader checks them.
  ClosedLoopDevice(const ClosedLoopModel& model, double tick_s);

  /// False when the model's motion over a substep is not representable
  /// (a non-finite propagator: absurd stiffness or damping for the masses).
  bool well_defined() const;

  /// The device at rest at the intent's pose, the hand relaxed.
  void reset(const Pose& intent);

  /// Integrates one tick: the device displays `wrench` (N, N·m, at the tool
  /// frame, world frame; the device's limits already applied) while the
  /// intent moves linearly from `intent_now` to `intent_next`.
  void advance(const Wrench& wrench, const Pose& intent_now, const Pose& intent_next);

  /// What the device reports for tick `tick`: the encoders' pose and the
  /// filtered backward-difference velocity (world frame).
  DeviceSample report(int64_t tick) const;

  /// The device's true state (what the encoders quantize).
  const Pose& pose() const { return pose_; }
  const Vec3& velocity() const { return velocity_; }                  ///< m/s
  const Vec3& angular_velocity() const { return angular_velocity_; }  ///< rad/s

  /// J: the energy the device itself has taken in since reset(): its
  /// kinetic energy (its own mass and inertia, not the hand's) plus what its
  /// viscous and Coulomb friction dissipated. The energy the hand put in
  /// through the grip is this plus the rendering's port energy
  /// (passivity_energy.h): the display's passivity (Colgate & Schenkel 1997).
  double absorbed_energy_j() const;

 private:
  void sense();

  ClosedLoopModel model_;
  double tick_s_;
  double filter_keep_;  ///< share of the previous velocity estimate kept each tick
  AxisPropagator translation_, rotation_;  ///< over a tick, or a substep with friction
  int translation_substeps_ = 1, rotation_substeps_ = 1;
  Pose pose_;
  Vec3 velocity_ = Vec3::Zero(), angular_velocity_ = Vec3::Zero();
  // What the device reports: the last two encoder poses and the estimate.
  Pose reported_, previous_reported_;
  Vec3 estimated_velocity_ = Vec3::Zero(), estimated_angular_velocity_ = Vec3::Zero();
  double dissipated_j_ = 0;
};

}  // namespace hb
