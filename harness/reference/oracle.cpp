#include "harness/reference/oracle.h"

#include <cmath>

namespace hb {

PenetrationResult Oracle::penetration(std::span<const Vec3> points) const {
  PenetrationResult result;
  result.points = static_cast<int64_t>(points.size());
  if (points.empty()) return result;

  PointQueryRequest inside_request;
  inside_request.points = points;
  inside_request.want_inside = true;
  PointQueryResult inside;
  query_points(inside_request, inside);

  // Distances only for the points found inside: usually a small share.
  std::vector<Vec3> inside_points;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (inside.inside[i]) inside_points.push_back(points[i]);
  result.inside = static_cast<int64_t>(inside_points.size());
  if (inside_points.empty()) return result;

  PointQueryRequest distance_request;
  distance_request.points = inside_points;
  distance_request.want_inside = false;
  distance_request.want_closest = true;
  PointQueryResult closest;
  query_points(distance_request, closest);
  double sum_sq = 0;
  for (double d : closest.distance) {
    result.max_depth_m = std::max(result.max_depth_m, d);
    sum_sq += d * d;
  }
  result.rms_depth_m = std::sqrt(sum_sq / static_cast<double>(inside_points.size()));
  return result;
}

}  // namespace hb
