// Rigid-body kinematic types shared by every algorithm and the harness.
// Quaternions are written and read in the order qw,qx,qy,qz everywhere in
// hapticbench files; Eigen's constructor takes (w,x,y,z) but stores x,y,z,w.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace hb {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// Rigid transform from a body's own coordinates to the world frame.
/// p: translation in metres, world frame. q: unit quaternion (qw,qx,qy,qz).
struct Pose {
  Vec3 p = Vec3::Zero();
  Quat q = Quat::Identity();

  /// Maps a point given in body coordinates (m) to world coordinates (m).
  Vec3 transform_point(const Vec3& body_point) const { return p + q * body_point; }
  /// Maps a world point (m) into body coordinates (m).
  Vec3 inverse_transform_point(const Vec3& world_point) const {
    return q.conjugate() * (world_point - p);
  }
  /// Composition: (a * b) maps b's body coordinates through b then a.
  Pose operator*(const Pose& b) const { return Pose{p + q * b.p, (q * b.q).normalized()}; }
  Pose inverse() const { return Pose{-(q.conjugate() * p), q.conjugate()}; }
};

/// Spatial velocity, world frame: v linear velocity of the body frame's
/// origin (m/s), w angular velocity (rad/s).
struct Twist {
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
};

/// Force (N) and torque (N·m) in world coordinates; the torque is taken
/// about the point the context names (the tool frame's origin for a
/// displayed wrench, the centre of mass for proxy dynamics).
struct Wrench {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
};

/// Cross-product matrix: skew(a) * b == a.cross(b).
inline Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

/// Rotation vector (axis * angle, rad, angle in [0, pi]) of a unit quaternion.
Vec3 rotation_vector(const Quat& q);

/// Unit quaternion of a rotation vector (axis * angle, rad).
Quat quat_from_rotation_vector(const Vec3& theta);

/// Inverse of the right Jacobian of SO(3) at theta: for small delta,
/// log(exp(theta) * exp(delta)) ~= theta + right_jacobian_inverse(theta) * delta.
Mat3 right_jacobian_inverse(const Vec3& theta);

/// Inverse of the left Jacobian of SO(3) at theta: for small delta,
/// log(exp(delta) * exp(theta)) ~= theta + left_jacobian_inverse(theta) * delta.
Mat3 left_jacobian_inverse(const Vec3& theta);

/// True when every coefficient is finite.
inline bool is_finite(const Vec3& v) { return v.allFinite(); }
inline bool is_finite(const Wrench& w) { return w.force.allFinite() && w.torque.allFinite(); }
inline bool is_finite(const Pose& x) { return x.p.allFinite() && x.q.coeffs().allFinite(); }

}  // namespace hb
