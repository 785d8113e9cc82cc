#include "algorithms/sensation_preserving/contact_features.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "hapticbench/closest_points.h"

namespace hb::convex_detail {

namespace {

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Convex hull (counter-clockwise, no collinear vertices) of 2-D points,
/// into `hull`; `sorted` is scratch.
void hull_2d(const std::vector<Vec2>& points, std::vector<Vec2>& sorted, std::vector<Vec2>& hull) {
  sorted.assign(points.begin(), points.end());
  std::sort(sorted.begin(), sorted.end(), [](const Vec2& p, const Vec2& q) {
    return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
  });
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  if (sorted.size() < 3) {
    hull.assign(sorted.begin(), sorted.end());
    return;
  }
  hull.resize(2 * sorted.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    while (k >= 2 && cross2(hull[k - 1] - hull[k - 2], sorted[i] - hull[k - 2]) <= 0) --k;
    hull[k++] = sorted[i];
  }
  for (std::size_t i = sorted.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 1] - hull[k - 2], sorted[i] - hull[k - 2]) <= 0) --k;
    hull[k++] = sorted[i];
  }
  hull.resize(k - 1);
}

/// The buffers make_feature() and overlap_centre() fill, kept between calls
/// (per thread) so that a warm contact query allocates nothing.
struct FeatureScratch {
  std::vector<Vec2> sorted, hull;  ///< make_feature()'s
  std::vector<Vec2> clipped, in;   ///< clip_polygon()'s
};
thread_local FeatureScratch feature_scratch;

}  // namespace

void make_feature(const std::vector<Vec2>& points, double tolerance, Feature2& f) {
  std::vector<Vec2>& hull = feature_scratch.hull;
  hull_2d(points, feature_scratch.sorted, hull);
  f.polygon.clear();
  f.from = f.to = hull[0];
  double diameter = 0;
  for (std::size_t i = 0; i < hull.size(); ++i)
    for (std::size_t j = i + 1; j < hull.size(); ++j)
      if ((hull[i] - hull[j]).norm() > diameter) {
        diameter = (hull[i] - hull[j]).norm();
        f.from = hull[i];
        f.to = hull[j];
      }
  if (diameter <= tolerance || hull.size() < 3) return;
  const Vec2 axis = (f.to - f.from) / diameter;
  double width = 0;
  for (const Vec2& p : hull) width = std::max(width, std::abs(cross2(axis, p - f.from)));
  if (width > tolerance) f.polygon.assign(hull.begin(), hull.end());
}

namespace {

/// Signed distance of p to the left of the directed edge (e0, e1).
double left_of(const Vec2& e0, const Vec2& e1, const Vec2& p) {
  const Vec2 e = e1 - e0;
  return cross2(e, p - e0) / e.norm();
}

/// The part of `subject` inside the convex polygon `clip` (Sutherland–Hodgman),
/// points within `tolerance` of it counting as inside, into `out`; `in` is
/// scratch.
void clip_polygon(const std::vector<Vec2>& subject, const std::vector<Vec2>& clip, double tolerance,
                  std::vector<Vec2>& out, std::vector<Vec2>& in) {
  out.assign(subject.begin(), subject.end());
  for (std::size_t i = 0; i < clip.size() && !out.empty(); ++i) {
    const Vec2& e0 = clip[i];
    const Vec2& e1 = clip[(i + 1) % clip.size()];
    in.swap(out);
    out.clear();
    for (std::size_t j = 0; j < in.size(); ++j) {
      const Vec2& p = in[j];
      const Vec2& q = in[(j + 1) % in.size()];
      const double dp = left_of(e0, e1, p) + tolerance;
      const double dq = left_of(e0, e1, q) + tolerance;
      if (dp >= 0) out.push_back(p);
      if ((dp >= 0) != (dq >= 0)) out.push_back(p + (q - p) * (dp / (dp - dq)));
    }
  }
}

/// Area centroid of a polygon; the mean of its vertices when it has no area.
Vec2 polygon_centre(const std::vector<Vec2>& polygon) {
  double area = 0;
  Vec2 moment = Vec2::Zero();
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    const Vec2 e1 = polygon[i] - polygon[0];
    const Vec2 e2 = polygon[i + 1] - polygon[0];
    const double twice = cross2(e1, e2);
    area += twice;
    moment += twice * (e1 + e2) / 3;
  }
  double perimeter = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
    perimeter += (polygon[(i + 1) % polygon.size()] - polygon[i]).norm();
  if (std::abs(area) > 1e-9 * perimeter * perimeter) return polygon[0] + moment / area;
  Vec2 mean = Vec2::Zero();
  for (const Vec2& p : polygon) mean += p;
  return mean / static_cast<double>(polygon.size());
}

/// The part of segment (from, to) inside a convex polygon (Cyrus–Beck),
/// as parameters [t0, t1] of from + t (to - from); false when empty.
bool clip_segment(const Vec2& from, const Vec2& to, const std::vector<Vec2>& clip, double tolerance,
                  double& t0, double& t1) {
  t0 = 0;
  t1 = 1;
  for (std::size_t i = 0; i < clip.size(); ++i) {
    const Vec2& e0 = clip[i];
    const Vec2& e1 = clip[(i + 1) % clip.size()];
    const double start = left_of(e0, e1, from) + tolerance;
    const double slope = left_of(e0, e1, to) + tolerance - start;
    if (std::abs(slope) < 1e-300) {
      if (start < 0) return false;
      continue;
    }
    const double t = -start / slope;
    if (slope > 0)
      t0 = std::max(t0, t);
    else
      t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  return true;
}

/// Midpoint of the closest points of two segments (closest_points.h rules);
/// the middle of their overlap when they are parallel and overlap.
Vec2 segments_middle(const Vec2& p1, const Vec2& q1, const Vec2& p2, const Vec2& q2,
                     double tolerance) {
  const Vec2 d1 = q1 - p1, d2 = q2 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm();
  if (a > tolerance * tolerance && e > tolerance * tolerance &&
      std::abs(cross2(d1, d2)) <= 1e-9 * std::sqrt(a * e)) {
    const Vec2 axis = d1 / std::sqrt(a);
    const double lo1 = std::min(0.0, axis.dot(d1)), hi1 = std::max(0.0, axis.dot(d1));
    const double lo2 = std::min(axis.dot(p2 - p1), axis.dot(q2 - p1));
    const double hi2 = std::max(axis.dot(p2 - p1), axis.dot(q2 - p1));
    const double overlap_lo = std::max(lo1, lo2), overlap_hi = std::min(hi1, hi2);
    if (overlap_lo <= overlap_hi + tolerance) {
      const Vec2 on1 = p1 + 0.5 * (overlap_lo + overlap_hi) * axis;
      const Vec2 on2 = p2 + axis.dot(on1 - p2) * axis;
      return 0.5 * (on1 + on2);
    }
  }
  const SegmentParameters st = closest_segment_parameters(p1, q1, p2, q2);
  return 0.5 * ((p1 + st.s * d1) + (p2 + st.t * d2));
}

/// Centre (2-D) of the overlap of two features seen along the normal, with
/// boundaries widened by `tolerance`.
bool overlap_centre_within(const Feature2& fa, const Feature2& fb, double tolerance, Vec2& centre) {
  const bool a_area = !fa.polygon.empty(), b_area = !fb.polygon.empty();
  if (a_area && b_area) {
    std::vector<Vec2>& common = feature_scratch.clipped;
    clip_polygon(fa.polygon, fb.polygon, tolerance, common, feature_scratch.in);
    if (common.empty()) return false;
    centre = polygon_centre(common);
    return true;
  }
  if (a_area || b_area) {
    const Feature2& area = a_area ? fa : fb;
    const Feature2& thin = a_area ? fb : fa;
    double t0 = 0, t1 = 1;
    if (!clip_segment(thin.from, thin.to, area.polygon, tolerance, t0, t1)) return false;
    centre = thin.from + 0.5 * (t0 + t1) * (thin.to - thin.from);
    return true;
  }
  centre = segments_middle(fa.from, fa.to, fb.from, fb.to, tolerance);
  return true;
}

}  // namespace

/// The overlap's centre with exact boundaries; when rounding leaves the
/// features just apart (they touch along the normal), with widened ones.
bool overlap_centre(const Feature2& fa, const Feature2& fb, double tolerance, Vec2& centre) {
  return overlap_centre_within(fa, fb, 0, centre) ||
         overlap_centre_within(fa, fb, tolerance, centre);
}

/// Fills the contact's depth and point from its normal: a's extreme
/// feature along +n, b's along -n.
}  // namespace hb::convex_detail
