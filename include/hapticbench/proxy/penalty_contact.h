// A linearised point contact for penalty-based proxies: a point fixed on
// the tool against a plane fixed in the world. Every penalty algorithm
// reduces its contacts to these, so they share one force law and one set
// of Jacobians for implicit integration (lecture notes, Otaduy & Lin:
// F_p = −kN(x + Rr − p₀) − kdn − bN(v + ω × r), T_p = (Rr) × F_p, N = n nᵀ):
//   depth d = n·(p₀ − (x + R r))
//   F = max(0, k d − b (n·v_r)) n,  v_r = v + ω × (R r),  torque (R r) × F about the COM
// applied only while d > 0. The clamp: a contact can only push; a point
// leaving the surface faster than k d / b is not pulled back (the unclamped
// law made contacts sticky on fast release).
#pragma once

#include <span>
#include <vector>

#include "hapticbench/pose.h"
#include "hapticbench/proxy/force_model.h"
#include "hapticbench/proxy/rigid_body.h"

namespace hb {

/// One tool point against one plane.
struct ContactPlane {
  Vec3 tool_point = Vec3::Zero();   ///< r: m, body (tool) axes, relative to the centre of mass
  Vec3 plane_point = Vec3::Zero();  ///< p₀: m, world frame, on the surface
  Vec3 normal = Vec3::UnitZ();      ///< n: world frame, unit length, pushes the tool out
};

/// Penalty gains shared by the contacts of one algorithm.
struct PenaltyGains {
  double stiffness = 3000;  ///< k, N/m
  double damping = 2;       ///< b, N·s/m
};

/// Penetration depth d = n·(p₀ − (x + R r)) of the tool point (m); > 0 when penetrating.
double contact_depth(const ContactPlane& plane, const RigidBodyState& state);

/// World position x + R r of the contact's tool point (m).
Vec3 contact_tool_point_world(const ContactPlane& plane, const RigidBodyState& state);

/// Penalty wrench of one contact about the centre of mass and, when asked,
/// its Jacobians (force_model.h coordinates). Zero when d ≤ 0 or when the
/// normal force k d − b n·v_r would pull (≤ 0).
ForceEvaluation evaluate_penalty_contact(const ContactPlane& plane, const PenaltyGains& gains,
                                         const RigidBodyState& state, bool with_jacobians);

/// k d − b n·v_r of the contact as the linearised implicit step applies it
/// at the step's end, from `state` moved by `displacement` (δx, δθ: m, rad,
/// world) with velocities changed by `velocity_change` (δv, δω). Negative:
/// the unclamped, linearised law pulls over that step.
double linearised_normal_force(const ContactPlane& plane, const PenaltyGains& gains,
                               const RigidBodyState& state, const Vec6& displacement,
                               const Vec6& velocity_change);

/// The penalty contacts of a set of planes as a force model for the
/// proxy's integrator, with the clamp kept over implicit steps: a contact
/// whose linearised force would pull at the step's end is released for the
/// rest of the step (release_pulling), the contacts that acted in the last
/// evaluation being the ones its linearisation holds. Given its planes by
/// use() before each step (kept by a renderer, so that its storage is
/// reused from tick to tick).
class PenaltyPlaneForces : public ForceModel {
 public:
  /// The planes (kept by the caller until the step is done) and gains of the
  /// next step; nothing released.
  void use(std::span<const ContactPlane> planes, const PenaltyGains& gains) {
    planes_ = planes;
    gains_ = gains;
    released_.assign(planes.size(), 0);
    acting_.assign(planes.size(), 0);
  }
  ForceEvaluation evaluate(const RigidBodyState& state, bool with_jacobians) override;
  bool release_pulling(const RigidBodyState& state, const Vec6& displacement,
                       const Vec6& velocity_change) override;

 private:
  std::span<const ContactPlane> planes_;
  PenaltyGains gains_;
  std::vector<char> released_;  ///< per plane: left out for the rest of the step
  std::vector<char> acting_;    ///< per plane: acted in the last evaluation
};

}  // namespace hb
