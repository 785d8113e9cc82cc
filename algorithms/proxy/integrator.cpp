#include "hapticbench/proxy/integrator.h"

#include <Eigen/Dense>

namespace hb {

namespace {
Quat rotated(const Quat& q, const Vec3& rotation_vector_world) {
  return (quat_from_rotation_vector(rotation_vector_world) * q).normalized();
}
}  // namespace

RigidBodyState explicit_euler_step(const RigidBody& body, const RigidBodyState& state,
                                   ForceModel& forces, double dt_s) {
  const ForceEvaluation f = forces.evaluate(state, false);
  const Vec3 momentum =
      body.mass_kg * state.v + dt_s * (f.wrench.force + body.mass_kg * body.gravity);
  const Vec3 angular_momentum = world_inertia(body, state.q) * state.w + dt_s * f.wrench.torque;

  RigidBodyState next;
  next.x = state.x + dt_s * state.v;
  next.q = rotated(state.q, dt_s * state.w);
  next.v = momentum / body.mass_kg;
  next.w = world_inertia(body, next.q).ldlt().solve(angular_momentum);
  return next;
}

ImplicitStepSystem implicit_step_system(const RigidBody& body, const RigidBodyState& state,
                                        const ForceEvaluation& f, double dt_s) {
  const Mat3 inertia = world_inertia(body, state.q);
  Vec6 generalised_force;
  generalised_force << f.wrench.force + body.mass_kg * body.gravity,
      f.wrench.torque - gyroscopic_torque(inertia, state.w);
  Mat6 damping = f.damping;
  damping.block<3, 3>(3, 3) -= gyroscopic_torque_jacobian(inertia, state.w);

  Mat6 mass = Mat6::Zero();
  mass.block<3, 3>(0, 0) = body.mass_kg * Mat3::Identity();
  mass.block<3, 3>(3, 3) = inertia;

  Vec6 velocity;
  velocity << state.v, state.w;
  return {mass - dt_s * damping - dt_s * dt_s * f.stiffness,
          dt_s * (generalised_force + dt_s * f.stiffness * velocity)};
}

RigidBodyState implicit_euler_step(const RigidBody& body, const RigidBodyState& state,
                                   ForceModel& forces, double dt_s) {
  RigidBodyState next;
  // A unilateral force that the linearisation would turn into a pull by the
  // step's end is released and the step solved again (force_model.h); each
  // pass releases at least one, so the passes are bounded.
  for (int pass = 0; pass < kMaxReleasePasses; ++pass) {
    const ImplicitStepSystem system =
        implicit_step_system(body, state, forces.evaluate(state, true), dt_s);
    // The system is not symmetric in general (contact levers, rotation), so use LU.
    const Vec6 delta = system.matrix.partialPivLu().solve(system.rhs);
    next.v = state.v + delta.head<3>();
    next.w = state.w + delta.tail<3>();
    next.x = state.x + dt_s * next.v;
    next.q = rotated(state.q, dt_s * next.w);
    Vec6 displacement;
    displacement << dt_s * next.v, dt_s * next.w;
    if (!forces.release_pulling(state, displacement, delta)) break;
  }
  return next;
}

RigidBodyState integrate_step(IntegratorKind kind, const RigidBody& body,
                              const RigidBodyState& state, ForceModel& forces, double dt_s) {
  return kind == IntegratorKind::kExplicitEuler ? explicit_euler_step(body, state, forces, dt_s)
                                                : implicit_euler_step(body, state, forces, dt_s);
}

}  // namespace hb
