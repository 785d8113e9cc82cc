// What an integrator asks of the world around the proxy: the total wrench
// about the proxy's centre of mass at a given state and, for implicit
// integration, how that wrench changes with the state.
#pragma once

#include "hapticbench/pose.h"
#include "hapticbench/proxy/rigid_body.h"

namespace hb {

/// A wrench on the proxy and its linearisation about the evaluated state.
/// Coordinates of a state perturbation, all world frame:
///   position δx of the centre of mass (m), rotation δθ with q' = exp(δθ)·q (rad),
///   linear velocity δv of the centre of mass (m/s), angular velocity δω (rad/s).
struct ForceEvaluation {
  Wrench wrench;                  ///< N, and N·m about the centre of mass, world frame
  Mat6 stiffness = Mat6::Zero();  ///< K = ∂(F, τ)/∂(δx, δθ); rows F then τ
  Mat6 damping = Mat6::Zero();    ///< D = ∂(F, τ)/∂(δv, δω)

  /// Adds another evaluation (forces superpose; so do their Jacobians).
  ForceEvaluation& operator+=(const ForceEvaluation& other) {
    wrench.force += other.wrench.force;
    wrench.torque += other.wrench.torque;
    stiffness += other.stiffness;
    damping += other.damping;
    return *this;
  }
};

/// Source of the forces acting on a proxy (coupling, contacts, ...).
class ForceModel {
 public:
  virtual ~ForceModel() = default;
  /// Wrench about the centre of mass at `state`. The Jacobians are filled
  /// only when `with_jacobians` is true (explicit integration skips them).
  virtual ForceEvaluation evaluate(const RigidBodyState& state, bool with_jacobians) = 0;

  /// For unilateral forces (penalty contacts only push): the linearised
  /// implicit step (integrator.h) applies each force as linearised at the
  /// step's end; after a solve it hands over the step from `state` (δx, δθ:
  /// m, rad, world; δv, δω: m/s, rad/s). A model whose contact would pull
  /// there leaves that contact out of its later evaluations in this step
  /// and returns true, and the integrator solves again. Models without
  /// unilateral forces keep the default.
  virtual bool release_pulling(const RigidBodyState& /*state*/, const Vec6& /*displacement*/,
                               const Vec6& /*velocity_change*/) {
    return false;
  }
};

}  // namespace hb
