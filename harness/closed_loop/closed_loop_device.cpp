#include "harness/closed_loop/closed_loop_device.h"

#include <cmath>
#include <numbers>

namespace hb {

namespace {

double quantize(double value, double resolution) {
  return resolution > 0 ? resolution * std::round(value / resolution) : value;
}

Pose encoder_reading(const Pose& pose, const DeviceModel& device) {
  Pose reading;
  for (int axis = 0; axis < 3; ++axis) reading.p[axis] = quantize(pose.p[axis], device.encoder_m);
  if (device.encoder_rad > 0) {
    Vec3 angles = rotation_vector(pose.q);
    for (int axis = 0; axis < 3; ++axis) angles[axis] = quantize(angles[axis], device.encoder_rad);
    reading.q = quat_from_rotation_vector(angles);
  } else {
    reading.q = pose.q;
  }
  return reading;
}

// One axis group (translation or rotation) of the model.
struct AxisGroup {
  const AxisPropagator& propagator;
  double k_hand, b_hand, b_device, friction;
};

// One step of an axis group with Coulomb friction of magnitude
// `group.friction` held over the step. At rest, the device stays stuck while
// the other forces on it (the hand's spring and damper at zero velocity, the
// display) stay within the friction; moving, friction opposes the velocity,
// and a velocity that would reverse within the step stops instead. Returns
// the energy the device's own friction dissipated (J).
double advance_axes(const AxisGroup& group, double step_s, Vec3& y, Vec3& v, const Vec3& w,
                    const Vec3& f) {
  Vec3 friction_force = Vec3::Zero();
  if (group.friction > 0) {
    if (v.squaredNorm() == 0) {
      const Vec3 driving = -group.k_hand * y + group.b_hand * w + f;
      const double driving_norm = driving.norm();
      if (driving_norm <= group.friction) {
        y -= w * step_s;  // stuck: the device stays, the intent moves on
        return 0;
      }
      friction_force = -group.friction * driving / driving_norm;
    } else {
      friction_force = -group.friction * v.normalized();
    }
  }
  const Vec3 applied = f + friction_force;
  const double viscous =
      group.b_device > 0
          ? group.b_device * group.propagator.velocity_square_integral(y, v, w, applied)
          : 0.0;
  const Vec3 y_before = y, v_before = v;
  group.propagator.advance(y, v, w, applied);
  const Vec3 moved = y - y_before + w * step_s;
  if (group.friction > 0 && v.dot(v_before) < 0) v.setZero();
  return viscous - friction_force.dot(moved);
}

}  // namespace

ClosedLoopDevice::ClosedLoopDevice(const ClosedLoopModel& model, double tick_s)
    : model_(model), tick_s_(tick_s) {
  const HandModel& hand = model.hand;
  const DeviceModel& device = model.device;
  // Translation and rotation are independent: each is cut into substeps
  // only when it has Coulomb friction.
  translation_substeps_ = device.friction_n > 0 ? kFrictionSubsteps : 1;
  rotation_substeps_ = device.friction_nm > 0 ? kFrictionSubsteps : 1;
  translation_ = AxisPropagator::make(hand.mass_kg + device.mass_kg, hand.k_t, hand.b_t, device.b_t,
                                      tick_s / translation_substeps_);
  rotation_ = AxisPropagator::make(hand.inertia_kgm2 + device.inertia_kgm2, hand.k_r, hand.b_r,
                                   device.b_r, tick_s / rotation_substeps_);
  filter_keep_ = device.velocity_filter_hz > 0
                     ? std::exp(-2 * std::numbers::pi * device.velocity_filter_hz * tick_s)
                     : 0.0;
}

bool ClosedLoopDevice::well_defined() const {
  return translation_.phi.allFinite() && translation_.gamma.allFinite() &&
         rotation_.phi.allFinite() && rotation_.gamma.allFinite();
}

void ClosedLoopDevice::reset(const Pose& intent) {
  pose_ = intent;
  pose_.q.normalize();
  velocity_.setZero();
  angular_velocity_.setZero();
  reported_ = encoder_reading(pose_, model_.device);
  previous_reported_ = reported_;
  estimated_velocity_.setZero();
  estimated_angular_velocity_.setZero();
  dissipated_j_ = 0;
}

double ClosedLoopDevice::absorbed_energy_j() const {
  const DeviceModel& device = model_.device;
  return 0.5 * device.mass_kg * velocity_.squaredNorm() +
         0.5 * device.inertia_kgm2 * angular_velocity_.squaredNorm() + dissipated_j_;
}

void ClosedLoopDevice::advance(const Wrench& wrench, const Pose& intent_now,
                               const Pose& intent_next) {
  const HandModel& hand = model_.hand;
  const DeviceModel& device = model_.device;
  // Offsets from the intent, and the intent's velocities over the tick.
  Vec3 y = pose_.p - intent_now.p;
  const Vec3 w = (intent_next.p - intent_now.p) / tick_s_;
  Vec3 y_r = rotation_vector(pose_.q * intent_now.q.conjugate());
  const Vec3 w_r = rotation_vector(intent_next.q * intent_now.q.conjugate()) / tick_s_;
  const AxisGroup translation{translation_, hand.k_t, hand.b_t, device.b_t, device.friction_n};
  const AxisGroup rotation{rotation_, hand.k_r, hand.b_r, device.b_r, device.friction_nm};
  for (int i = 0; i < translation_substeps_; ++i)
    dissipated_j_ +=
        advance_axes(translation, tick_s_ / translation_substeps_, y, velocity_, w, wrench.force);
  for (int i = 0; i < rotation_substeps_; ++i)
    dissipated_j_ += advance_axes(rotation, tick_s_ / rotation_substeps_, y_r, angular_velocity_,
                                  w_r, wrench.torque);
  pose_.p = intent_next.p + y;
  pose_.q = (quat_from_rotation_vector(y_r) * intent_next.q).normalized();
  sense();
}

void ClosedLoopDevice::sense() {
  previous_reported_ = reported_;
  reported_ = encoder_reading(pose_, model_.device);
  const Vec3 difference = (reported_.p - previous_reported_.p) / tick_s_;
  const Vec3 angular_difference =
      rotation_vector(reported_.q * previous_reported_.q.conjugate()) / tick_s_;
  estimated_velocity_ = filter_keep_ * estimated_velocity_ + (1 - filter_keep_) * difference;
  estimated_angular_velocity_ =
      filter_keep_ * estimated_angular_velocity_ + (1 - filter_keep_) * angular_difference;
}

DeviceSample ClosedLoopDevice::report(int64_t tick) const {
  DeviceSample sample;
  sample.tick = tick;
  sample.t_ns = tick * 1'000'000;
  sample.pose = reported_;
  sample.twist.v = estimated_velocity_;
  sample.twist.w = estimated_angular_velocity_;
  return sample;
}

}  // namespace hb
