#include "hapticbench/proxy/virtual_coupling.h"

namespace hb {

CouplingEvaluation evaluate_coupling(const CouplingGains& gains, const RigidBody& body,
                                     const RigidBodyState& state, const Pose& device_pose,
                                     const Twist& device_twist, bool with_jacobians) {
  // a: lever from the centre of mass to the tool-frame origin, where the spring acts.
  const Vec3 a = com_to_tool_origin(body, state.q);
  const Vec3 origin = state.x + a;
  const Vec3 origin_velocity = state.v + state.w.cross(a);
  const Vec3 theta = rotation_vector(device_pose.q * state.q.conjugate());

  const Vec3 force =
      gains.k_t * (device_pose.p - origin) + gains.b_t * (device_twist.v - origin_velocity);
  const Vec3 couple = gains.k_r * theta + gains.b_r * (device_twist.w - state.w);

  CouplingEvaluation result;
  result.display = Wrench{-force, -couple};
  result.on_proxy.wrench = Wrench{force, couple + a.cross(force)};
  if (!with_jacobians) return result;

  // Perturbations (force_model.h): a' = exp(δθ) a  =>  ∂a/∂δθ = −[a]×;
  // v_origin = v + ω × a  =>  ∂/∂δθ = −[ω]×[a]×, ∂/∂ω = −[a]×;
  // θ = log(exp(θ) exp(−δθ))  =>  ∂θ/∂δθ = −J_r⁻¹(θ).
  const Mat3 identity = Mat3::Identity();
  const Mat3 skew_a = skew(a);
  const Mat3 dforce_dx = -gains.k_t * identity;
  const Mat3 dforce_dtheta = gains.k_t * skew_a + gains.b_t * skew(state.w) * skew_a;
  const Mat3 dforce_dv = -gains.b_t * identity;
  const Mat3 dforce_dw = gains.b_t * skew_a;
  const Mat3 dcouple_dtheta = -gains.k_r * right_jacobian_inverse(theta);
  const Mat3 dcouple_dw = -gains.b_r * identity;

  // τ_com = τ_c + a × F: the lever turns with the body too (∂(a × F)/∂a · ∂a/∂δθ = [F]×[a]×).
  Mat6& k = result.on_proxy.stiffness;
  k.block<3, 3>(0, 0) = dforce_dx;
  k.block<3, 3>(0, 3) = dforce_dtheta;
  k.block<3, 3>(3, 0) = skew_a * dforce_dx;
  k.block<3, 3>(3, 3) = dcouple_dtheta + skew_a * dforce_dtheta + skew(force) * skew_a;
  Mat6& d = result.on_proxy.damping;
  d.block<3, 3>(0, 0) = dforce_dv;
  d.block<3, 3>(0, 3) = dforce_dw;
  d.block<3, 3>(3, 0) = skew_a * dforce_dv;
  d.block<3, 3>(3, 3) = dcouple_dw + skew_a * dforce_dw;
  return result;
}

}  // namespace hb
