// Closest points between points, segments and triangles, with one rule for
// degenerate input used everywhere (CCD, the god-object's contact features,
// the sensation-preserving contact features, the Embree oracle, tests):
// - a segment of zero length is its first end point;
// - two segments are parallel when a·e − b² ≤ 1e-14·a·e (a, e their squared
//   lengths, b the dot product of their directions); the closest points are
//   then taken with s = 0 on the first, clamped on the second and back;
// - a triangle is degenerate when |ab × ac|² ≤ 1e-24·|ab|²·|ac|²; it is then
//   the union of its three edges.
// Formulas after Ericson, Real-Time Collision Detection, 5.1.2, 5.1.5 and
// 5.1.9. Coordinates are in any one frame; the results are in that frame.
#pragma once

#include <Eigen/Core>
#include <algorithm>

#include "hapticbench/pose.h"

namespace hb {

/// Parameters of the closest points of two segments: p0 + s (p1 − p0) and
/// q0 + t (q1 − q0), s and t in [0, 1].
struct SegmentParameters {
  double s = 0;
  double t = 0;
};

/// Relative threshold below which two segments count as parallel.
inline constexpr double kParallelSegmentsTolerance = 1e-14;

/// Closest points of segments [p0, p1] and [q0, q1], in 2-D or 3-D.
template <class Vector>
SegmentParameters closest_segment_parameters(const Vector& p0, const Vector& p1, const Vector& q0,
                                             const Vector& q1) {
  const Vector d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  SegmentParameters out;
  if (a == 0 && e == 0) return out;
  if (a == 0) {
    out.t = std::clamp(f / e, 0.0, 1.0);
    return out;
  }
  const double c = d1.dot(r);
  if (e == 0) {
    out.s = std::clamp(-c / a, 0.0, 1.0);
    return out;
  }
  // Minimise over s with t following, then clamp t and re-minimise s.
  const double b = d1.dot(d2), denominator = a * e - b * b;
  out.s = denominator > kParallelSegmentsTolerance * a * e
              ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0)
              : 0.0;
  out.t = (b * out.s + f) / e;
  if (out.t < 0) {
    out.t = 0;
    out.s = std::clamp(-c / a, 0.0, 1.0);
  } else if (out.t > 1) {
    out.t = 1;
    out.s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return out;
}

/// The closest points themselves: on_p on [p0, p1], on_q on [q0, q1].
struct SegmentClosestPoints {
  Vec3 on_p;
  Vec3 on_q;
  double distance() const { return (on_p - on_q).norm(); }
};
SegmentClosestPoints closest_points_of_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                                const Vec3& q1);

/// Closest point of segment [a, b] to p (a when the segment has zero length).
Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b);

/// Closest point of the closed triangle (a, b, c) to p.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace hb
