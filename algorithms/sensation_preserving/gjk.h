// GJK on the difference of two convex pieces: distance, closest points,
// and the simplex that holds the origin when they overlap.
#pragma once

#include <array>
#include <limits>

#include "algorithms/sensation_preserving/convex_body.h"

namespace hb::convex_detail {

/// A point of the difference b - a with the two vertices it comes from.
struct DifferencePoint {
  Vec3 w, on_a, on_b;
};

/// The support point of b - a along d.
DifferencePoint difference_support(const Body& a, const Body& b, const Vec3& d);

/// GJK on b - a: the distance (m, 0 when they overlap), the closest points
/// when they are apart, and the final simplex (a tetrahedron holding the
/// origin, or a smaller simplex the origin lies on, when they overlap).
/// With a finite `stop_beyond` (m), GJK stops as soon as a support plane
/// proves the distance larger than it; distance is then that lower bound
/// (> stop_beyond) and the closest points are not computed.
struct GjkResult {
  double distance = 0;
  Vec3 on_a = Vec3::Zero(), on_b = Vec3::Zero();
  /// The last search direction: the point of b - a nearest the origin found
  /// (world, m; a direction from a towards b when they are apart).
  Vec3 direction = Vec3::Zero();
  std::array<DifferencePoint, 4> simplex;
  int size = 0;
};

GjkResult gjk(const Body& a, const Body& b, double scale,
              double stop_beyond = std::numeric_limits<double>::infinity());

}  // namespace hb::convex_detail
