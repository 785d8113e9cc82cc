// Motions of a constrained-contact proxy (the god-object's, in its
// slow-loop update and its haptic-rate solve, and constrained dynamics'):
// poses of the frame at the tool's centre of mass, and generalised
// displacements (centre-of-mass displacement, rotation vector) between them
// with how far they move the tool's points.
#pragma once

#include "algorithms/ccd/screw_motion.h"
#include "hapticbench/pose.h"

namespace hb {

/// The tool frame and the frame at its centre of mass (same axes), in
/// which a constrained-contact proxy moves and the CCD sees the tool.
struct ProxyFrames {
  Vec3 centre_of_mass = Vec3::Zero();  ///< tool coordinates, m

  Pose com_frame(const Pose& tool_pose) const {
    return Pose{tool_pose.transform_point(centre_of_mass), tool_pose.q};
  }
  Pose tool_frame(const Pose& com_pose) const {
    return Pose{com_pose.p - com_pose.q * centre_of_mass, com_pose.q};
  }
};

/// Generalised displacement (centre of mass m, rotation vector rad, world)
/// that carries the pose `from` onto `to`, both frames at the centre of mass.
inline Vec6 displacement(const Pose& from, const Pose& to) {
  Vec6 d;
  d.head<3>() = to.p - from.p;
  d.tail<3>() = rotation_vector(to.q * from.q.conjugate());
  return d;
}

/// The pose `from` moved by the displacement d.
inline Pose displaced(const Pose& from, const Vec6& d) {
  return Pose{from.p + d.head<3>(), (quat_from_rotation_vector(d.tail<3>()) * from.q).normalized()};
}

/// The pose at time t (unitless, in [0, 1]) of the frame `motion` moves.
inline Pose pose_on(const ScrewMotion& motion, double t) {
  return Pose{motion.point_at(Vec3::Zero(), t), Quat(motion.rotation_at(t)).normalized()};
}

/// Bound (m) on how far any point within `radius` of the centre of mass
/// moves under d: |Δc| + |φ| radius.
inline double point_reach(const Vec6& d, double radius) {
  return d.head<3>().norm() + d.tail<3>().norm() * radius;
}

/// The largest fraction f in [0, 1] (to 2⁻³⁰) of the step d from `start`
/// that keeps the proxy within `reach` (m, point_reach with `radius`) of
/// `anchor`; 0 when `start` itself is not within it. The reach bound is
/// continuous in f, so bisection finds the boundary.
inline double fraction_within_reach(const Pose& anchor, const Pose& start, const Vec6& d,
                                    double radius, double reach) {
  auto within = [&](double f) {
    return point_reach(displacement(anchor, displaced(start, f * d)), radius) <= reach;
  };
  if (within(1.0)) return 1.0;
  if (!within(0.0)) return 0.0;
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (lo + hi);
    (within(mid) ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace hb
