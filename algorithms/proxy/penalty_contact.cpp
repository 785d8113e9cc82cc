#include "hapticbench/proxy/penalty_contact.h"

namespace hb {

double contact_depth(const ContactPlane& plane, const RigidBodyState& state) {
  return plane.normal.dot(plane.plane_point - contact_tool_point_world(plane, state));
}

Vec3 contact_tool_point_world(const ContactPlane& plane, const RigidBodyState& state) {
  return state.x + state.q * plane.tool_point;
}

ForceEvaluation evaluate_penalty_contact(const ContactPlane& plane, const PenaltyGains& gains,
                                         const RigidBodyState& state, bool with_jacobians) {
  ForceEvaluation result;
  const Vec3 lever = state.q * plane.tool_point;  // R r
  const Vec3& n = plane.normal;
  const double depth = n.dot(plane.plane_point - (state.x + lever));
  if (!(depth > 0)) return result;

  const Vec3 point_velocity = state.v + state.w.cross(lever);
  // A contact can only push: separating faster than k d / b, the damping
  // would pull the tool into the surface (sticky contact); then nothing acts.
  const double magnitude = gains.stiffness * depth - gains.damping * n.dot(point_velocity);
  if (!(magnitude > 0)) return result;
  const Vec3 force = magnitude * n;
  result.wrench = Wrench{force, lever.cross(force)};
  if (!with_jacobians) return result;

  // Perturbations (force_model.h): lever' = exp(δθ) lever  =>  ∂lever/∂δθ = −[s]×, s = R r;
  // ∂d/∂x = −nᵀ, ∂d/∂δθ = nᵀ[s]×; ∂v_r/∂δθ = −[ω]×[s]×, ∂v_r/∂ω = −[s]×.
  const Mat3 nn = n * n.transpose();
  const Mat3 skew_s = skew(lever);
  const Mat3 dforce_dx = -gains.stiffness * nn;
  const Mat3 dforce_dtheta =
      gains.stiffness * nn * skew_s + gains.damping * nn * skew(state.w) * skew_s;
  const Mat3 dforce_dv = -gains.damping * nn;
  const Mat3 dforce_dw = gains.damping * nn * skew_s;

  Mat6& k = result.stiffness;
  k.block<3, 3>(0, 0) = dforce_dx;
  k.block<3, 3>(0, 3) = dforce_dtheta;
  k.block<3, 3>(3, 0) = skew_s * dforce_dx;
  k.block<3, 3>(3, 3) = skew_s * dforce_dtheta + skew(force) * skew_s;
  Mat6& d = result.damping;
  d.block<3, 3>(0, 0) = dforce_dv;
  d.block<3, 3>(0, 3) = dforce_dw;
  d.block<3, 3>(3, 0) = skew_s * dforce_dv;
  d.block<3, 3>(3, 3) = skew_s * dforce_dw;
  return result;
}

double linearised_normal_force(const ContactPlane& plane, const PenaltyGains& gains,
                               const RigidBodyState& state, const Vec6& displacement,
                               const Vec6& velocity_change) {
  const Vec3 lever = state.q * plane.tool_point;  // s = R r
  const Vec3& n = plane.normal;
  const Vec3 dx = displacement.head<3>(), dtheta = displacement.tail<3>();
  const Vec3 dv = velocity_change.head<3>(), dw = velocity_change.tail<3>();
  // d' = d − n·(δx + δθ × s);  v_r' = v_r + δv + δω × s + ω × (δθ × s).
  const double depth =
      n.dot(plane.plane_point - (state.x + lever)) - n.dot(dx + dtheta.cross(lever));
  const Vec3 point_velocity =
      state.v + state.w.cross(lever) + dv + dw.cross(lever) + state.w.cross(dtheta.cross(lever));
  return gains.stiffness * depth - gains.damping * n.dot(point_velocity);
}

ForceEvaluation PenaltyPlaneForces::evaluate(const RigidBodyState& state, bool with_jacobians) {
  ForceEvaluation total;
  for (std::size_t k = 0; k < planes_.size(); ++k) {
    acting_[k] = 0;
    if (released_[k]) continue;
    const ForceEvaluation contact =
        evaluate_penalty_contact(planes_[k], gains_, state, with_jacobians);
    if (contact.wrench.force.squaredNorm() == 0) continue;
    acting_[k] = 1;
    total += contact;
  }
  return total;
}

bool PenaltyPlaneForces::release_pulling(const RigidBodyState& state, const Vec6& displacement,
                                         const Vec6& velocity_change) {
  bool released = false;
  for (std::size_t k = 0; k < planes_.size(); ++k) {
    // Only contacts that acted in the solve's evaluation are in its linearisation.
    if (!acting_[k]) continue;
    if (linearised_normal_force(planes_[k], gains_, state, displacement, velocity_change) < 0) {
      released_[k] = 1;
      released = true;
    }
  }
  return released;
}

}  // namespace hb
