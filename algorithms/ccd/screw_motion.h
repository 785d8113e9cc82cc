// The in-between motion of a rigid body over one step (Redon et al.): its
// reference point moves on a straight line at constant speed while it turns
// at constant rate about a fixed axis,
//   T(t) = c0 + t (c1 − c0),
//   R(t) = cos(ωt)(I − uuᵀ)R0 + sin(ωt)[u]× R0 + uuᵀR0,
// for t ∈ [0, 1], with ω ∈ [0, π] the angle and u the unit axis of R1 R0ᵀ;
// a body point r is at p(t) = T(t) + R(t) r. Besides plain evaluation it
// gives interval enclosures of point paths over an interval of t, which the
// screw-motion CCD kernels bisect.
#pragma once

#include "algorithms/ccd/interval.h"
#include "hapticbench/pose.h"

namespace hb {

/// Everything a point path needs at one interval of t, computed once and
/// shared by all the body's points.
struct ScrewMotionSample {
  Interval t;           ///< the interval of t (unitless)
  IntervalVec3 origin;  ///< T(t), world frame, m
  Interval cos_wt;      ///< cos(ωt)
  Interval sin_wt;      ///< sin(ωt)
};

/// The path p(t) − T(t) = R(t) v of a body vector v (a point relative to the
/// reference point, or a difference of two body points), stored as
/// R(t) v = cos(ωt) a + sin(ωt) b + k with a = (I − uuᵀ)R0 v,
/// b = u × R0 v, k = uuᵀR0 v enclosed in intervals (world frame, m).
struct ScrewVectorPath {
  IntervalVec3 a, b, k;

  /// Encloses R(t) v over the sample's interval of t.
  IntervalVec3 rotated(const ScrewMotionSample& s) const {
    return (s.cos_wt * a + s.sin_wt * b) + k;
  }
  /// Encloses T(t) + R(t) v: the world position of the body point v.
  IntervalVec3 position(const ScrewMotionSample& s) const { return s.origin + rotated(s); }
};

/// Screw motion between two poses of a body frame. The frame's origin is
/// the reference point that moves on a straight line: pass poses of a frame
/// at the centre of mass to interpolate about it.
class ScrewMotion {
 public:
  /// start: pose at t = 0, end: pose at t = 1 (world frame, m). The
  /// rotation takes the shorter way (ω <= π).
  ScrewMotion(const Pose& start, const Pose& end);

  /// c0 and c1 (m, world), R0, the unit axis u and the angle ω (rad); the
  /// motion is exactly the formula of this file with these doubles, which
  /// reproduces `end` to rounding. When ω = 0, u is the x axis.
  const Vec3& start_origin() const { return start_origin_; }
  const Vec3& end_origin() const { return end_origin_; }
  const Mat3& start_rotation() const { return start_rotation_; }
  const Vec3& axis() const { return axis_; }
  double angle() const { return angle_; }

  /// R(t), and the world position (m) of body point r at time t.
  Mat3 rotation_at(double t) const;
  Vec3 point_at(const Vec3& body_point, double t) const;

  /// The path of a body point or vector given in body coordinates (m),
  /// enclosed with interval arithmetic from this motion's doubles.
  ScrewVectorPath path(const IntervalVec3& body_vector) const;
  ScrewVectorPath path(const Vec3& body_point) const;

  /// Encloses, over the sample's interval of t, the body coordinates (m) of
  /// a static world point (m): R(t)ᵀ (x − T(t)), with
  /// R(t)ᵀ = R0ᵀ (cos(ωt)(I − uuᵀ) − sin(ωt)[u]× + uuᵀ). Lets a kernel
  /// work in the body frame, where the body's own primitive stands still.
  IntervalVec3 body_coordinates(const Vec3& world_point, const ScrewMotionSample& s) const;

  /// T(t), cos(ωt) and sin(ωt) enclosed over an interval of t ⊆ [0, 1].
  ScrewMotionSample sample(const Interval& t) const;

  /// Every number of the motion is finite and at most `limit` in magnitude.
  bool within(double limit) const;

 private:
  Vec3 start_origin_, end_origin_;
  Mat3 start_rotation_;
  Vec3 axis_ = Vec3::UnitX();
  double angle_ = 0;
};

}  // namespace hb
