// The proxy as a rigid body: mass properties about its centre of mass and a
// state written about that centre. The body's axes are the tool frame's
// axes; the tool frame's origin sits at -centre_of_mass in body terms, so the
// pose the device and the oracle see is derived, never stored.
// Quaternions are qw,qx,qy,qz (Eigen's Quat).
#pragma once

#include "hapticbench/pose.h"

namespace hb {

/// Inertial description of a proxy.
struct RigidBody {
  double mass_kg = 1;                    ///< kg, > 0
  Mat3 inertia_body = Mat3::Identity();  ///< kg·m², about the centre of mass, tool-frame axes
  Vec3 centre_of_mass = Vec3::Zero();    ///< m, tool coordinates
  Vec3 gravity = Vec3::Zero();           ///< m/s², world frame; acts as m·g at the COM
};

/// Dynamic state of a proxy, world frame, about its centre of mass.
struct RigidBodyState {
  Vec3 x = Vec3::Zero();      ///< centre of mass position, m
  Quat q = Quat::Identity();  ///< orientation of the tool frame (= body axes)
  Vec3 v = Vec3::Zero();      ///< centre of mass velocity, m/s
  Vec3 w = Vec3::Zero();      ///< angular velocity, rad/s
};

/// Inertia about the centre of mass in world axes, I = R I_body Rᵀ (kg·m²).
Mat3 world_inertia(const RigidBody& body, const Quat& q);

/// Vector from the centre of mass to the tool frame's origin, world frame (m): -R c.
Vec3 com_to_tool_origin(const RigidBody& body, const Quat& q);

/// Pose of the tool frame (what the device holds and the oracle checks).
Pose tool_pose(const RigidBody& body, const RigidBodyState& state);

/// Velocity of the tool frame's origin, v + ω × (origin − COM), and ω; world frame.
Twist tool_twist(const RigidBody& body, const RigidBodyState& state);

/// State of a body whose tool frame is at `pose`, at rest.
RigidBodyState state_at_rest(const RigidBody& body, const Pose& pose);

/// State of a body whose tool frame is at `pose` and moves with `twist`
/// (velocity of the tool frame's origin and angular velocity, world frame).
RigidBodyState state_moving_with(const RigidBody& body, const Pose& pose, const Twist& twist);

/// Gyroscopic torque ω × (I ω) in world axes (N·m), with I the world inertia.
Vec3 gyroscopic_torque(const Mat3& world_inertia, const Vec3& w);

/// ∂(ω × I ω)/∂ω = skew(ω) I − skew(I ω), I held fixed (world axes).
Mat3 gyroscopic_torque_jacobian(const Mat3& world_inertia, const Vec3& w);

/// Kinetic energy ½ m v·v + ½ ω·I ω (J).
double kinetic_energy(const RigidBody& body, const RigidBodyState& state);

/// True when every coefficient of the state is finite.
bool is_finite(const RigidBodyState& state);

}  // namespace hb
