// Where two convex pieces touch, seen along the contact normal: each
// piece's extreme feature as a 2-D polygon, segment or point, and the
// centre of their overlap.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace hb::convex_detail {

using Vec2 = Eigen::Vector2d;

/// A 2-D convex feature: a polygon, or (when thinner than the tolerance) the
/// segment between its two farthest points, possibly a single point.
struct Feature2 {
  std::vector<Vec2> polygon;  // counter-clockwise; empty for a segment or point
  Vec2 from, to;              // the segment (from == to for a point)
};

/// The feature the points span, with `tolerance` (m) deciding thinness,
/// into `feature` (its polygon's storage reused).
void make_feature(const std::vector<Vec2>& points, double tolerance, Feature2& feature);

/// The overlap's centre with exact boundaries; when rounding leaves the
/// features just apart (they touch along the normal), with boundaries
/// widened by `tolerance`. False when they do not overlap even then.
bool overlap_centre(const Feature2& fa, const Feature2& fb, double tolerance, Vec2& centre);

}  // namespace hb::convex_detail
