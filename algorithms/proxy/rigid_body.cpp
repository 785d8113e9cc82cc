#include "hapticbench/proxy/rigid_body.h"

namespace hb {

Mat3 world_inertia(const RigidBody& body, const Quat& q) {
  const Mat3 r = q.toRotationMatrix();
  return r * body.inertia_body * r.transpose();
}

Vec3 com_to_tool_origin(const RigidBody& body, const Quat& q) { return -(q * body.centre_of_mass); }

Pose tool_pose(const RigidBody& body, const RigidBodyState& state) {
  return Pose{state.x + com_to_tool_origin(body, state.q), state.q};
}

Twist tool_twist(const RigidBody& body, const RigidBodyState& state) {
  return Twist{state.v + state.w.cross(com_to_tool_origin(body, state.q)), state.w};
}

RigidBodyState state_at_rest(const RigidBody& body, const Pose& pose) {
  RigidBodyState state;
  state.q = pose.q.normalized();
  state.x = pose.p + state.q * body.centre_of_mass;
  return state;
}

RigidBodyState state_moving_with(const RigidBody& body, const Pose& pose, const Twist& twist) {
  RigidBodyState state = state_at_rest(body, pose);
  state.w = twist.w;
  state.v = twist.v - twist.w.cross(com_to_tool_origin(body, state.q));
  return state;
}

Vec3 gyroscopic_torque(const Mat3& world_inertia, const Vec3& w) {
  return w.cross(world_inertia * w);
}

Mat3 gyroscopic_torque_jacobian(const Mat3& world_inertia, const Vec3& w) {
  return skew(w) * world_inertia - skew(world_inertia * w);
}

double kinetic_energy(const RigidBody& body, const RigidBodyState& state) {
  return 0.5 * body.mass_kg * state.v.squaredNorm() +
         0.5 * state.w.dot(world_inertia(body, state.q) * state.w);
}

bool is_finite(const RigidBodyState& state) {
  return state.x.allFinite() && state.q.coeffs().allFinite() && state.v.allFinite() &&
         state.w.allFinite();
}

}  // namespace hb
