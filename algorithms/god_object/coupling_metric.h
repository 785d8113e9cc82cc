// The god-object's metric on its proxy's generalised displacements
// (centre-of-mass displacement, rotation vector; proxy_motion.h): the
// coupling energy's Hessian, used by its slow-loop update and its
// haptic-rate solve in place of the mass matrix a massless proxy lacks.
#pragma once

#include <algorithm>

#include "hapticbench/pose.h"
#include "hapticbench/scene.h"

namespace hb {

/// The coupling energy's Hessian in (centre-of-mass displacement, rotation
/// vector) for a tool whose centre of mass is at `centre_of_mass` (tool
/// coordinates) with orientation q: the tool-frame origin moves by
/// δc − [a]× δφ with a = origin − COM, so K = Jᵀ diag(k_t I, k_r I) J,
/// J = [[I, −[a]×], [0, I]]. A zero rotational stiffness is replaced by a
/// tiny one (relative to k_t radius²) so K stays positive definite.
inline Mat6 coupling_metric(const CouplingGains& gains, const Vec3& centre_of_mass, const Quat& q,
                            double radius) {
  const Vec3 arm = -(q * centre_of_mass);
  const double r = std::max(radius, 1e-3);
  const double k_r = std::max(gains.k_r, 1e-6 * gains.k_t * r * r);
  Mat6 jacobian = Mat6::Identity();
  jacobian.block<3, 3>(0, 3) = -skew(arm);
  Vec6 stiffness;
  stiffness << Vec3::Constant(gains.k_t), Vec3::Constant(k_r);
  return jacobian.transpose() * stiffness.asDiagonal() * jacobian;
}

}  // namespace hb
