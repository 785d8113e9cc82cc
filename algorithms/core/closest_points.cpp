#include "hapticbench/closest_points.h"

namespace hb {

SegmentClosestPoints closest_points_of_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                                const Vec3& q1) {
  const SegmentParameters st = closest_segment_parameters(p0, p1, q0, q1);
  return {p0 + st.s * (p1 - p0), q0 + st.t * (q1 - q0)};
}

Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length_sq = ab.squaredNorm();
  if (!(length_sq > 0)) return a;
  return a + std::clamp((p - a).dot(ab) / length_sq, 0.0, 1.0) * ab;
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double n2 = ab.cross(ac).squaredNorm();
  if (!(n2 > 1e-24 * ab.squaredNorm() * ac.squaredNorm())) {
    // Degenerate: the nearest point of its three edges.
    Vec3 best = closest_point_on_segment(p, a, b);
    for (const Vec3& candidate :
         {closest_point_on_segment(p, b, c), closest_point_on_segment(p, c, a)})
      if ((candidate - p).squaredNorm() < (best - p).squaredNorm()) best = candidate;
    return best;
  }
  // Voronoi regions of the vertices, then of the edges, else the face.
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  // Barycentric areas (scaled) opposite each vertex.
  const double area_c = d1 * d4 - d3 * d2;
  if (area_c <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const double area_b = d5 * d2 - d1 * d6;
  if (area_b <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double area_a = d3 * d6 - d5 * d4;
  if (area_a <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denominator = area_a + area_b + area_c;
  return a + (area_b / denominator) * ab + (area_c / denominator) * ac;
}

}  // namespace hb
