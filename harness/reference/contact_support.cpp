#include "harness/reference/contact_support.h"

#include <algorithm>
#include <cmath>

#include "algorithms/contact/frictional_contact_solver.h"  // perpendicular_unit

namespace hb {
namespace {

constexpr double kSameNormal = 1e-9;    // |n_i − n_j|
constexpr double kSamePlaneM = 1e-10;   // |n·(c_i − c_j)|
constexpr double kBoundSlackM = 1e-12;  // a bound this far above the interpolation is implied

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// Corners of the convex hull of `points` (indices into it), counter-
// clockwise, points on an edge left out (Andrew's monotone chain).
std::vector<std::size_t> hull_corners(const std::vector<Vec2>& points) {
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return points[a].x() < points[b].x() ||
           (points[a].x() == points[b].x() && points[a].y() < points[b].y());
  });
  const auto turns_left = [&](std::size_t o, std::size_t a, std::size_t b) {
    const double scale = (points[a] - points[o]).norm() * (points[b] - points[o]).norm();
    return cross(points[o], points[a], points[b]) > 1e-12 * scale;
  };
  std::vector<std::size_t> hull(2 * order.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    while (k >= 2 && !turns_left(hull[k - 2], hull[k - 1], order[i])) --k;
    hull[k++] = order[i];
  }
  for (std::size_t i = order.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && !turns_left(hull[k - 2], hull[k - 1], order[i])) --k;
    hull[k++] = order[i];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

// The highest bound that the corners' rows imply at x: the largest
// interpolation over the triangles (or, for two corners, the segment) of
// corners that contain it; −∞ where none does.
double implied_bound(const Vec2& x, const std::vector<Vec2>& corner,
                     const std::vector<double>& bound) {
  double best = -INFINITY;
  const std::size_t h = corner.size();
  if (h == 2) {
    const Vec2 d = corner[1] - corner[0];
    const double t = d.dot(x - corner[0]) / d.squaredNorm();
    const double off = std::abs(cross(corner[0], corner[1], x)) / d.norm();
    if (t >= -1e-12 && t <= 1 + 1e-12 && off <= 1e-12) best = bound[0] + t * (bound[1] - bound[0]);
    return best;
  }
  for (std::size_t i = 0; i < h; ++i)
    for (std::size_t j = i + 1; j < h; ++j)
      for (std::size_t k = j + 1; k < h; ++k) {
        const double area = cross(corner[i], corner[j], corner[k]);
        if (std::abs(area) <= 0) continue;
        const double wi = cross(x, corner[j], corner[k]) / area;
        const double wj = cross(corner[i], x, corner[k]) / area;
        const double wk = 1 - wi - wj;
        if (wi < -1e-12 || wj < -1e-12 || wk < -1e-12) continue;
        best = std::max(best, wi * bound[i] + wj * bound[j] + wk * bound[k]);
      }
  return best;
}

}  // namespace

std::vector<std::size_t> supporting_rows(std::span<const ContactRowGeometry> rows) {
  std::vector<char> grouped(rows.size(), 0), kept(rows.size(), 1);
  std::vector<std::size_t> group;
  std::vector<Vec2> points, corner_points;
  std::vector<double> corner_bounds;
  for (std::size_t first = 0; first < rows.size(); ++first) {
    if (grouped[first]) continue;
    const ContactRowGeometry& seed = rows[first];
    group.clear();
    for (std::size_t j = first; j < rows.size(); ++j) {
      const ContactRowGeometry& row = rows[j];
      if (grouped[j] || row.friction != seed.friction ||
          (row.normal - seed.normal).norm() > kSameNormal ||
          std::abs(seed.normal.dot(row.point - seed.point)) > kSamePlaneM)
        continue;
      grouped[j] = 1;
      group.push_back(j);
    }
    const Vec3 u = perpendicular_unit(seed.normal), v = seed.normal.cross(u);
    points.clear();
    for (std::size_t j : group) points.push_back(Vec2(u.dot(rows[j].point), v.dot(rows[j].point)));
    // Rows at one point (a sample over the edge two coplanar triangles
    // share): the highest bound implies the others.
    for (std::size_t m = 0; m < group.size(); ++m)
      for (std::size_t l = 0; l < m && kept[group[m]]; ++l)
        if (kept[group[l]] && (points[m] - points[l]).norm() <= kSamePlaneM) {
          const bool m_higher = rows[group[m]].bound > rows[group[l]].bound;
          kept[group[m_higher ? l : m]] = 0;
        }
    std::size_t distinct = 0;
    for (std::size_t m = 0; m < group.size(); ++m) {
      if (!kept[group[m]]) continue;
      group[distinct] = group[m];
      points[distinct++] = points[m];
    }
    group.resize(distinct);
    points.resize(distinct);
    if (group.size() < 3) continue;
    const std::vector<std::size_t> corners = hull_corners(points);
    if (corners.size() > kMaxSupportCorners || corners.size() < 2) continue;
    corner_points.clear();
    corner_bounds.clear();
    std::vector<char> is_corner(group.size(), 0);
    for (std::size_t c : corners) {
      is_corner[c] = 1;
      corner_points.push_back(points[c]);
      corner_bounds.push_back(rows[group[c]].bound);
    }
    for (std::size_t m = 0; m < group.size(); ++m)
      if (!is_corner[m] && implied_bound(points[m], corner_points, corner_bounds) >=
                               rows[group[m]].bound - kBoundSlackM)
        kept[group[m]] = 0;
  }
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (kept[i]) out.push_back(i);
  return out;
}

}  // namespace hb
