// Closest points of two triangles that do not intersect, in double: the
// nearest of their six vertex–face and nine edge–edge pairs (for disjoint
// triangles the closest points always lie on one such pair). Whether two
// triangles intersect is decided exactly elsewhere
// (triangles_intersect(), oracle.h); this answers only for disjoint ones.
// Coordinates are in any one frame (m); the results are in that frame.
#pragma once

#include <array>

#include "hapticbench/pose.h"

namespace hb {

/// A triangle by its three corners (m).
using TriangleCorners = std::array<Vec3, 3>;

/// The closest points of two triangles: on_a on the first, on_b on the second.
struct TrianglePairClosest {
  Vec3 on_a = Vec3::Zero();
  Vec3 on_b = Vec3::Zero();
  double distance = 0;  ///< m, |on_a − on_b|
};

/// Closest points of the closed triangles a and b, assuming they do not
/// intersect (for intersecting triangles the result is the nearest pair of
/// boundary features, not 0). Degenerate triangles follow closest_points.h.
TrianglePairClosest closest_points_of_disjoint_triangles(const TriangleCorners& a,
                                                         const TriangleCorners& b);

}  // namespace hb
