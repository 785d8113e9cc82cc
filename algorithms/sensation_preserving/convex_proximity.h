// Proximity of two convex polytopes: penetration depth, normal and contact
// point by GJK/EPA (libccd, kept inside convex_proximity.cpp), and the
// Euclidean distance of separated polytopes by GJK with Johnson's
// sub-distance search (libccd 2.1 has no distance query).
#pragma once

#include <span>

#include "hapticbench/pose.h"

namespace hb {

/// The convex hull of `vertices` (body frame, m) placed in the world by
/// `pose`. Only the hull matters: interior points and repeated vertices are
/// allowed; at least one vertex.
struct PlacedConvex {
  std::span<const Vec3> vertices;
  Pose pose;
};

/// How a polytope b lies against a polytope a.
struct ConvexProximity {
  /// They overlap, or are apart by less than the margin asked for.
  bool in_contact = false;
  /// m: the penetration depth (> 0) when they overlap, minus their gap
  /// (< 0) when they are apart: translating b by signed_depth · normal makes
  /// them touch. Set only when in_contact.
  double signed_depth = 0;
  /// World, unit: the direction that moves b out of a (for overlap, that of
  /// the smallest separating translation; apart, from a's closest point to
  /// b's). Set only when in_contact.
  Vec3 normal = Vec3::Zero();
  /// World, m: on the plane midway between a's extreme face, edge or vertex
  /// along +normal and b's along -normal, at the centre of where the two
  /// overlap seen along the normal. Set only when in_contact.
  Vec3 point = Vec3::Zero();
};

/// Penetration of b into a, or their gap when it is below margin_m (m, ≥ 0;
/// 0: only overlapping polytopes are in contact). Polytopes that exactly
/// touch may be reported either way.
ConvexProximity convex_proximity(const PlacedConvex& a, const PlacedConvex& b, double margin_m = 0);

/// True when the polytopes are proved apart by more than margin_m (m, ≥ 0):
/// GJK stopped at the first support plane that shows it. Cheaper than
/// convex_proximity for pairs that are apart.
/// When they are, and `axis` is given, it receives a unit direction (world,
/// from a towards b) along which they were found apart.
bool convex_apart(const PlacedConvex& a, const PlacedConvex& b, double margin_m = 0,
                  Vec3* axis = nullptr);

/// How far apart the polytopes are along the unit direction `axis` (world,
/// m): b's least height along it less a's greatest; positive only for a
/// plane between them, and then at most their distance.
double separation_along(const PlacedConvex& a, const PlacedConvex& b, const Vec3& axis);

/// Euclidean distance (m) between the two polytopes; 0 when they overlap.
double convex_distance(const PlacedConvex& a, const PlacedConvex& b);

}  // namespace hb
