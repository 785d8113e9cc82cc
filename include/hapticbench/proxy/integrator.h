// Time integration of the proxy with mass (lecture notes, "Dynamic Proxy
// Simulation"): m a = F + m g,  I α + ω × I ω = τ, with F and τ (about the
// centre of mass) from a ForceModel.
//
// Explicit Euler, y⁺ = y + Δt ẏ(y), on the notes' state y = (x, q, P = m v, L = I ω):
//   x⁺ = x + Δt v          (the old velocity)
//   q⁺ = exp(Δt ω) q
//   P⁺ = P + Δt (F + m g)
//   L⁺ = L + Δt τ          (dL/dt = τ in world axes; the gyroscopic term is
//                           what I α picks up from the rotating inertia)
//   v⁺ = P⁺ / m,  ω⁺ = I(q⁺)⁻¹ L⁺.
//
// Linearised implicit Euler, (I − Δt ∂ẏ/∂y)(y⁺ − y) = Δt ẏ, written in
// velocity form. With u = (v, ω), M = diag(m 1, I), the generalised force
// f = (F + m g, τ − ω × I ω), K = ∂f/∂(x, δθ) and D = ∂f/∂u (the force
// model's Jacobians plus −∂(ω × I ω)/∂ω), backward Euler u⁺ = u + Δt M⁻¹ f(y⁺)
// linearised about y with Δ(x, δθ) = Δt u⁺ gives
//   (M − Δt D − Δt² K) Δu = Δt (f + Δt K u),   u⁺ = u + Δu,
//   x⁺ = x + Δt v⁺,   q⁺ = exp(Δt ω⁺) q.
// For a linear spring-damper this is exactly backward Euler, which is
// unconditionally stable and dissipative.
#pragma once

#include "hapticbench/proxy/force_model.h"
#include "hapticbench/proxy/rigid_body.h"

namespace hb {

enum class IntegratorKind { kExplicitEuler, kImplicitEuler };

/// One explicit Euler step of length dt_s (s).
RigidBodyState explicit_euler_step(const RigidBody& body, const RigidBodyState& state,
                                   ForceModel& forces, double dt_s);

/// The linear system of one linearised implicit Euler step,
/// matrix · Δu = rhs with matrix = M − Δt D − Δt² K (the effective mass) and
/// rhs = Δt (f + Δt K u), for the forces `f` evaluated with their Jacobians
/// at `state`.
struct ImplicitStepSystem {
  Mat6 matrix;
  Vec6 rhs;
};
ImplicitStepSystem implicit_step_system(const RigidBody& body, const RigidBodyState& state,
                                        const ForceEvaluation& f, double dt_s);

/// Solves of one implicit step at most: a step whose contacts would pull
/// is solved again without them (ForceModel::release_pulling).
inline constexpr int kMaxReleasePasses = 8;

/// One linearised implicit Euler step of length dt_s (s).
RigidBodyState implicit_euler_step(const RigidBody& body, const RigidBodyState& state,
                                   ForceModel& forces, double dt_s);

/// Dispatches on kind.
RigidBodyState integrate_step(IntegratorKind kind, const RigidBody& body,
                              const RigidBodyState& state, ForceModel& forces, double dt_s);

}  // namespace hb
