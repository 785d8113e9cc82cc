// Test support: the exact distance between the convex hulls of two point
// sets, by CGAL's Polytope_distance_d (a quadratic program solved in exact
// arithmetic on the double coordinates; CGAL stays inside cgal_convex.cpp,
// which only the tests that need it compile).
#pragma once

#include <vector>

#include "hapticbench/pose.h"

namespace hb::test {

/// The squared distance (m²) between conv(p) and conv(q), world frame,
/// computed exactly and rounded to double at the end.
double cgal_hull_squared_distance(const std::vector<Vec3>& p, const std::vector<Vec3>& q);

/// conv(p) and conv(q) share a point (exact: the squared distance is 0).
bool cgal_hulls_intersect(const std::vector<Vec3>& p, const std::vector<Vec3>& q);

}  // namespace hb::test
