// A placed convex piece prepared for support queries, and the tolerances
// the convex proximity code shares (internal to convex_proximity.cpp, gjk,
// epa_penetration and contact_features).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

#include "algorithms/sensation_preserving/convex_proximity.h"

namespace hb::convex_detail {

using Vec2 = Eigen::Vector2d;

// Relative tolerances, scaled by the larger polytope's extent (m).
inline constexpr double kEpaTolerance = 1e-7;      // libccd's EPA and MPR stop
inline constexpr double kPolishBand = 1e-3;        // vertices near the extreme tried in polishing
inline constexpr std::size_t kPolishVertices = 8;  // most such vertices per polytope
inline constexpr double kCertifyTolerance = 1e-9;  // EPA's bounds this close: its normal is exact
inline constexpr double kEpaGap = 1e-12;           // own EPA stops when the support gains less
inline constexpr double kDegenerateTolerance = 1e-10;  // lengths below this are degenerate
inline constexpr double kFeatureTolerance = 1e-7;      // vertices this close to the extreme plane
inline constexpr double kPlanarTolerance = 1e-9;       // lengths in the contact plane
inline constexpr double kTouchTolerance = 1e-12;       // GJK: the origin is on the difference

/// A placed polytope prepared for support queries.
struct Body {
  explicit Body(const PlacedConvex& c)
      : vertices(c.vertices),
        rotation(c.pose.q.normalized().toRotationMatrix()),
        translation(c.pose.p) {}

  Vec3 world(std::size_t i) const { return rotation * vertices[i] + translation; }

  /// A vertex farthest along the world direction d (the first one on ties).
  Vec3 support(const Vec3& d) const {
    const Vec3 local = rotation.transpose() * d;
    std::size_t best = 0;
    double best_value = local.dot(vertices[0]);
    for (std::size_t i = 1; i < vertices.size(); ++i) {
      const double value = local.dot(vertices[i]);
      if (value > best_value) {
        best_value = value;
        best = i;
      }
    }
    return world(best);
  }

  Vec3 centre() const {
    Vec3 sum = Vec3::Zero();
    for (const Vec3& v : vertices) sum += v;
    return rotation * (sum / static_cast<double>(vertices.size())) + translation;
  }

  /// Largest distance of a vertex from the first (m): the size of the piece.
  double extent() const {
    double largest = 0;
    for (const Vec3& v : vertices) largest = std::max(largest, (v - vertices[0]).squaredNorm());
    return std::sqrt(largest);
  }

  std::span<const Vec3> vertices;
  Mat3 rotation;
  Vec3 translation;
};

/// Translation (m) along the unit direction u that separates b from a:
/// h_a(u) + h_b(−u), a's greatest height along u less b's least; negative
/// when a plane normal to u lies between them (minus their gap along u).
inline double separating_translation(const Body& a, const Body& b, const Vec3& u) {
  const Vec3 ua = a.rotation.transpose() * u, ub = b.rotation.transpose() * u;
  double a_max = -std::numeric_limits<double>::infinity();
  double b_min = std::numeric_limits<double>::infinity();
  for (const Vec3& v : a.vertices) a_max = std::max(a_max, ua.dot(v));
  for (const Vec3& v : b.vertices) b_min = std::min(b_min, ub.dot(v));
  return a_max + u.dot(a.translation) - b_min - u.dot(b.translation);
}

}  // namespace hb::convex_detail
