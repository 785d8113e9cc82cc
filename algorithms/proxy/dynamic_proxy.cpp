#include "hapticbench/proxy/dynamic_proxy.h"

#include <algorithm>

#include "hapticbench/proxy/device_output.h"
#include "hapticbench/proxy/virtual_coupling.h"

namespace hb {

namespace {
// A jump to the device that changes the coupling spring's force by no more
// than this is made whatever the device did (N).
constexpr double kUnfeltJumpForceN = 0.005;

bool exerts_nothing(const ForceEvaluation& f) {
  return f.wrench.force.isZero() && f.wrench.torque.isZero();
}
}  // namespace

DynamicProxy::DynamicProxy(const RigidBody& body, const CouplingGains& gains,
                           IntegratorKind integrator, double dt_s)
    : body_(body), gains_(gains), integrator_(integrator), dt_s_(dt_s) {}

void DynamicProxy::follow_device_in_free_space(const FreeSpaceFollowing& limits) {
  if (body_.gravity.isZero()) following_ = limits;
}

void DynamicProxy::reset(const Pose& pose) {
  state_ = state_at_rest(body_, pose);
  last_device_.reset();
  at_device_now_ = false;
}

// How far the farthest tool point moves from one state to the other (m):
// |Δx| + |Δθ| r, a bound.
double DynamicProxy::point_step(const RigidBodyState& from, const RigidBodyState& to) const {
  return (to.x - from.x).norm() +
         rotation_vector(to.q * from.q.conjugate()).norm() * following_->tool_radius_m;
}

// Free where the proxy is and where the device is, and near enough.
bool DynamicProxy::free_to_jump(const RigidBodyState& from, const RigidBodyState& at_device,
                                ForceModel* contacts) const {
  if (point_step(from, at_device) > following_->max_point_step_m) return false;
  return !contacts || (exerts_nothing(contacts->evaluate(from, false)) &&
                       exerts_nothing(contacts->evaluate(at_device, false)));
}

bool display_allows_jump_to_device(const CouplingGains& gains, const Wrench& display,
                                   const Pose& device, const Pose& last_device,
                                   double tool_radius_m) {
  const double force_allowed =
      std::max(kUnfeltJumpForceN, gains.k_t * (device.p - last_device.p).norm());
  const double torque_allowed =
      std::max(kUnfeltJumpForceN * tool_radius_m,
               gains.k_r * rotation_vector(device.q * last_device.q.conjugate()).norm());
  return display.force.norm() <= force_allowed && display.torque.norm() <= torque_allowed;
}

Wrench DynamicProxy::advance(const DeviceSample& device, ForceModel* contacts, uint32_t& flags) {
  if (!is_finite(device)) {
    flags |= kFlagNonFiniteZeroed;
    return Wrench{};
  }
  std::optional<RigidBodyState> at_device;
  if (following_) at_device = state_moving_with(body_, device.pose, device.twist);
  // A proxy that is the device stays it while nothing touches.
  if (at_device && at_device_now_ && free_to_jump(state_, *at_device, contacts)) {
    state_ = *at_device;
    last_device_ = device.pose;
    return evaluate_coupling(gains_, body_, state_, device.pose, device.twist, false).display;
  }
  at_device_now_ = false;
  // The display is the reaction to the coupling force the step applied:
  // explicit Euler applies it at the state before the step, implicit Euler
  // (linearised, exact for the translational spring) at the state after it.
  // Displaying anything else would lag the proxy by a tick against the
  // device and show a spurious k_T·v·Δt in steady motion.
  Wrench display;
  if (integrator_ == IntegratorKind::kExplicitEuler)
    display = evaluate_coupling(gains_, body_, state_, device.pose, device.twist, false).display;
  CouplingWithContacts forces(CouplingForce(gains_, body_, device.pose, device.twist), contacts);
  const RigidBodyState before = state_;
  state_ = integrate_step(integrator_, body_, state_, forces, dt_s_);
  const bool reset = reset_non_finite_proxy(body_, device.pose, state_, flags);
  if (integrator_ == IntegratorKind::kImplicitEuler || reset)
    display = evaluate_coupling(gains_, body_, state_, device.pose, device.twist, false).display;
  // A proxy leaving contact becomes the device once its dynamics have
  // brought it near enough.
  if (at_device && last_device_ && !reset &&
      display_allows_jump_to_device(gains_, display, device.pose, *last_device_,
                                    following_->tool_radius_m) &&
      free_to_jump(before, *at_device, contacts)) {
    state_ = *at_device;
    at_device_now_ = true;
    display = evaluate_coupling(gains_, body_, state_, device.pose, device.twist, false).display;
  }
  if (following_) last_device_ = device.pose;
  return display;
}

}  // namespace hb
