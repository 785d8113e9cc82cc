// Convex hulls of point sets, decided by CGAL's exact predicates on the
// double coordinates (CGAL stays inside convex_hull.cpp). A hull's vertices
// are exact copies of input points; no coordinate is constructed.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

/// A convex polytope as a closed triangle surface (same frame and unit as
/// the points it came from). A flat polytope (all vertices in one plane) is
/// a convex polygon whose triangles are listed once on each side, so every
/// triangle's plane still has the whole polytope on or behind it.
struct ConvexPolytope {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;  ///< counter-clockwise seen from outside
  /// 3: a solid; 2: a flat polygon (vertices in boundary order, counter-
  /// clockwise about the first triangle's normal); 1: a segment (two
  /// vertices, no triangles); 0: one point; -1: no points.
  int dimension = -1;
};

/// The convex hull of the points (any number, repeats allowed).
ConvexPolytope convex_hull(std::span<const Vec3> points);

}  // namespace hb
