#include "harness/reference/triangle_pair_distance.h"

#include <cmath>
#include <limits>

#include "hapticbench/closest_points.h"

namespace hb {

TrianglePairClosest closest_points_of_disjoint_triangles(const TriangleCorners& a,
                                                         const TriangleCorners& b) {
  TrianglePairClosest best;
  double best_sq = std::numeric_limits<double>::infinity();
  const auto offer = [&](const Vec3& on_a, const Vec3& on_b) {
    const double d_sq = (on_a - on_b).squaredNorm();
    if (d_sq < best_sq) {
      best_sq = d_sq;
      best.on_a = on_a;
      best.on_b = on_b;
    }
  };
  // Each vertex of one against the other's face.
  for (const Vec3& v : a) offer(v, closest_point_on_triangle(v, b[0], b[1], b[2]));
  for (const Vec3& v : b) offer(closest_point_on_triangle(v, a[0], a[1], a[2]), v);
  // Each edge of one against each edge of the other.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const SegmentClosestPoints edges =
          closest_points_of_segments(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]);
      offer(edges.on_p, edges.on_q);
    }
  }
  best.distance = std::sqrt(best_sq);
  return best;
}

}  // namespace hb
