#include "harness/reference/oracle.h"

#include <algorithm>
#include <cmath>

namespace hb {

PenetrationResult penetration_of_inside_points(const Oracle& oracle, std::span<const Vec3> points,
                                               const std::vector<uint8_t>& inside) {
  PenetrationResult result;
  result.points = static_cast<int64_t>(points.size());
  // Distances only for the points found inside: usually a small share.
  std::vector<Vec3> inside_points;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (inside[i]) inside_points.push_back(points[i]);
  result.inside = static_cast<int64_t>(inside_points.size());
  if (inside_points.empty()) return result;

  PointQueryResult closest;
  oracle.query_points({.points = inside_points, .want_inside = false, .want_closest = true},
                      closest);
  double sum_sq = 0;
  for (double d : closest.distance) {
    result.max_depth_m = std::max(result.max_depth_m, d);
    sum_sq += d * d;
  }
  result.rms_depth_m = std::sqrt(sum_sq / static_cast<double>(inside_points.size()));
  return result;
}

PenetrationResult Oracle::penetration(std::span<const Vec3> points) const {
  if (points.empty()) return PenetrationResult{};
  PointQueryRequest request;
  request.points = points;
  request.want_inside = true;
  PointQueryResult inside;
  query_points(request, inside);
  return penetration_of_inside_points(*this, points, inside.inside);
}

std::span<const OracleBackendEntry> oracle_backends() {
  static const OracleBackendEntry backends[] = {
      {"embree", &make_embree_oracle, false, false},
      {"cgal", &make_cgal_oracle, true, true},
  };
  return backends;
}

std::optional<std::size_t> oracle_backend_index(std::string_view name) {
  const auto backends = oracle_backends();
  for (std::size_t i = 0; i < backends.size(); ++i)
    if (backends[i].name == name) return i;
  return std::nullopt;
}

}  // namespace hb
