#include "algorithms/ccd/screw_motion.h"

#include <cmath>

#include "algorithms/ccd/interval_trig.h"

namespace hb {

namespace {

IntervalVec3 point_interval(const Vec3& v) {
  return {Interval(v.x()), Interval(v.y()), Interval(v.z())};
}

}  // namespace

ScrewMotion::ScrewMotion(const Pose& start, const Pose& end)
    : start_origin_(start.p),
      end_origin_(end.p),
      start_rotation_(start.q.normalized().toRotationMatrix()) {
  // R1 R0ᵀ as a quaternion; rotation_vector takes the shorter way round.
  const Vec3 theta = rotation_vector((end.q.normalized() * start.q.normalized().conjugate()));
  angle_ = theta.norm();
  if (angle_ > 0) axis_ = theta / angle_;
}

Mat3 ScrewMotion::rotation_at(double t) const {
  const Mat3 uut = axis_ * axis_.transpose();
  const double wt = angle_ * t;
  return std::cos(wt) * (Mat3::Identity() - uut) * start_rotation_ +
         std::sin(wt) * skew(axis_) * start_rotation_ + uut * start_rotation_;
}

Vec3 ScrewMotion::point_at(const Vec3& body_point, double t) const {
  return start_origin_ + t * (end_origin_ - start_origin_) + rotation_at(t) * body_point;
}

ScrewVectorPath ScrewMotion::path(const IntervalVec3& body_vector) const {
  // r0 = R0 v, then its parts along and across the axis.
  IntervalVec3 rotated;
  Interval* rows[3] = {&rotated.x, &rotated.y, &rotated.z};
  for (int i = 0; i < 3; ++i)
    *rows[i] = body_vector.x * start_rotation_(i, 0) + body_vector.y * start_rotation_(i, 1) +
               body_vector.z * start_rotation_(i, 2);
  const IntervalVec3 u = point_interval(axis_);
  const Interval along = dot(u, rotated);
  ScrewVectorPath path;
  path.k = along * u;
  path.a = rotated - path.k;
  path.b = cross(u, rotated);
  return path;
}

ScrewVectorPath ScrewMotion::path(const Vec3& body_point) const {
  return path(point_interval(body_point));
}

IntervalVec3 ScrewMotion::body_coordinates(const Vec3& world_point,
                                           const ScrewMotionSample& s) const {
  const IntervalVec3 w = point_interval(world_point) - s.origin;
  const IntervalVec3 u = point_interval(axis_);
  const IntervalVec3 k = dot(u, w) * u;
  // Turned back about the axis by ωt, then R0ᵀ.
  const IntervalVec3 turned = (s.cos_wt * (w - k) - s.sin_wt * cross(u, w)) + k;
  IntervalVec3 body;
  Interval* rows[3] = {&body.x, &body.y, &body.z};
  for (int i = 0; i < 3; ++i)
    *rows[i] = turned.x * start_rotation_(0, i) + turned.y * start_rotation_(1, i) +
               turned.z * start_rotation_(2, i);
  return body;
}

ScrewMotionSample ScrewMotion::sample(const Interval& t) const {
  ScrewMotionSample s;
  s.t = t;
  const IntervalVec3 c0 = point_interval(start_origin_);
  s.origin = c0 + t * (point_interval(end_origin_) - c0);
  const Interval wt = t * angle_;
  s.cos_wt = interval_cos(wt);
  s.sin_wt = interval_sin(wt);
  return s;
}

bool ScrewMotion::within(double limit) const {
  auto ok = [limit](double x) { return std::abs(x) <= limit; };
  for (int i = 0; i < 3; ++i) {
    if (!ok(start_origin_[i]) || !ok(end_origin_[i]) || !ok(axis_[i])) return false;
    for (int j = 0; j < 3; ++j)
      if (!ok(start_rotation_(i, j))) return false;
  }
  return ok(angle_);
}

}  // namespace hb
