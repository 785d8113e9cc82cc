#include "hapticbench/pose.h"

#include <cmath>

namespace hb {

Vec3 rotation_vector(const Quat& q_in) {
  // Shortest rotation: take the hemisphere with w >= 0.
  Quat q = q_in.w() < 0 ? Quat(-q_in.w(), -q_in.x(), -q_in.y(), -q_in.z()) : q_in;
  const Vec3 xyz = q.vec();
  const double s = xyz.norm();
  if (s < 1e-12) return 2.0 * xyz / (q.w() > 0 ? q.w() : 1.0);  // small angle: sin(a/2)~a/2
  const double angle = 2.0 * std::atan2(s, q.w());
  return xyz * (angle / s);
}

Quat quat_from_rotation_vector(const Vec3& theta) {
  const double angle = theta.norm();
  if (angle < 1e-12) {
    Quat q(1.0, 0.5 * theta.x(), 0.5 * theta.y(), 0.5 * theta.z());
    return q.normalized();
  }
  const Vec3 axis = theta / angle;
  const double s = std::sin(0.5 * angle);
  return Quat(std::cos(0.5 * angle), axis.x() * s, axis.y() * s, axis.z() * s);
}

namespace {
// Coefficient of skew(theta)^2 in the inverse SO(3) Jacobians.
double jacobian_inverse_quadratic_coefficient(double angle) {
  if (angle < 1e-4) return 1.0 / 12.0 + angle * angle / 720.0;
  return 1.0 / (angle * angle) - (1.0 + std::cos(angle)) / (2.0 * angle * std::sin(angle));
}
}  // namespace

Mat3 right_jacobian_inverse(const Vec3& theta) {
  const Mat3 s = skew(theta);
  return Mat3::Identity() + 0.5 * s + jacobian_inverse_quadratic_coefficient(theta.norm()) * s * s;
}

Mat3 left_jacobian_inverse(const Vec3& theta) {
  const Mat3 s = skew(theta);
  return Mat3::Identity() - 0.5 * s + jacobian_inverse_quadratic_coefficient(theta.norm()) * s * s;
}

}  // namespace hb
