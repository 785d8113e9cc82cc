#include "hapticbench/proxy/dynamic_proxy.h"

#include "hapticbench/proxy/device_output.h"
#include "hapticbench/proxy/virtual_coupling.h"

namespace hb {

DynamicProxy::DynamicProxy(const RigidBody& body, const CouplingGains& gains,
                           IntegratorKind integrator, double dt_s)
    : body_(body), gains_(gains), integrator_(integrator), dt_s_(dt_s) {}

void DynamicProxy::reset(const Pose& pose) { state_ = state_at_rest(body_, pose); }

Wrench DynamicProxy::advance(const DeviceSample& device, ForceModel* contacts, uint32_t& flags) {
  if (!is_finite(device)) {
    flags |= kFlagNonFiniteZeroed;
    return Wrench{};
  }
  // The display is the reaction to the coupling force the step applied:
  // explicit Euler applies it at the state before the step, implicit Euler
  // (linearised, exact for the translational spring) at the state after it.
  // Displaying anything else would lag the proxy by a tick against the
  // device and show a spurious k_T·v·Δt in steady motion.
  Wrench display;
  if (integrator_ == IntegratorKind::kExplicitEuler)
    display = evaluate_coupling(gains_, body_, state_, device.pose, device.twist, false).display;
  CouplingWithContacts forces(CouplingForce(gains_, body_, device.pose, device.twist), contacts);
  state_ = integrate_step(integrator_, body_, state_, forces, dt_s_);
  const bool reset = reset_non_finite_proxy(body_, device.pose, state_, flags);
  if (integrator_ == IntegratorKind::kImplicitEuler || reset)
    display = evaluate_coupling(gains_, body_, state_, device.pose, device.twist, false).display;
  return display;
}

}  // namespace hb
