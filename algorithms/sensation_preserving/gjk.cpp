#include "algorithms/sensation_preserving/gjk.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace hb::convex_detail {

DifferencePoint difference_support(const Body& a, const Body& b, const Vec3& d) {
  DifferencePoint p;
  p.on_b = b.support(d);
  p.on_a = a.support(-d);
  p.w = p.on_b - p.on_a;
  return p;
}

namespace {

/// Affine coordinates μ of the origin's projection onto the face spanned
/// by base + edges[0..m) (m = 1, 2 or 3): the Gram system
/// (EᵀE) μ = −Eᵀ base, solved in closed form. False for a degenerate face
/// (Gram determinant ≤ 1e-12 of the product of its diagonal).
bool solve_face_projection(const std::array<Vec3, 3>& edges, int m, const Vec3& base,
                           std::array<double, 3>& mu) {
  if (m == 1) {
    const double g = edges[0].squaredNorm();
    if (!(g > 0)) return false;
    mu[0] = -edges[0].dot(base) / g;
    return true;
  }
  if (m == 2) {
    const double g00 = edges[0].squaredNorm(), g11 = edges[1].squaredNorm();
    const double g01 = edges[0].dot(edges[1]);
    const double det = g00 * g11 - g01 * g01;
    if (!(det > 1e-12 * g00 * g11)) return false;
    const double r0 = -edges[0].dot(base), r1 = -edges[1].dot(base);
    mu[0] = (r0 * g11 - r1 * g01) / det;
    mu[1] = (r1 * g00 - r0 * g01) / det;
    return true;
  }
  Mat3 e;
  e << edges[0], edges[1], edges[2];
  const Mat3 gram = e.transpose() * e;
  const double det = gram.determinant();
  if (!(det > 1e-12 * gram.diagonal().prod())) return false;
  const Vec3 solution = gram.inverse() * (-e.transpose() * base);
  mu = {solution.x(), solution.y(), solution.z()};
  return true;
}

/// The point of the simplex's hull closest to the origin, by trying every
/// face of it (Johnson's sub-distance search): the answer lies inside the
/// face whose affine projection of the origin has non-negative barycentric
/// coordinates and the least norm. Reduces the simplex to that face.
Vec3 closest_on_simplex(std::array<DifferencePoint, 4>& simplex, int& size,
                        std::array<double, 4>& weights) {
  double best_norm = std::numeric_limits<double>::infinity();
  int best_mask = 1;
  std::array<double, 4> best_weights{1, 0, 0, 0};
  for (int mask = 1; mask < (1 << size); ++mask) {
    std::array<int, 4> members{};
    int count = 0;
    for (int i = 0; i < size; ++i)
      if (mask & (1 << i)) members[static_cast<std::size_t>(count++)] = i;
    std::array<double, 4> lambda{};
    const Vec3& base = simplex[static_cast<std::size_t>(members[0])].w;
    if (count == 1) {
      lambda[0] = 1;
    } else {
      const int m = count - 1;
      std::array<Vec3, 3> edges;
      for (int j = 0; j < m; ++j)
        edges[static_cast<std::size_t>(j)] =
            simplex[static_cast<std::size_t>(members[static_cast<std::size_t>(j + 1)])].w - base;
      std::array<double, 3> mu{};
      if (!solve_face_projection(edges, m, base, mu)) continue;  // degenerate face
      double rest = 1;
      bool inside = true;
      for (int j = 0; j < m; ++j) {
        const double mu_j = mu[static_cast<std::size_t>(j)];
        lambda[static_cast<std::size_t>(j + 1)] = mu_j;
        rest -= mu_j;
        if (mu_j < 0) inside = false;
      }
      lambda[0] = rest;
      if (rest < 0 || !inside) continue;
    }
    Vec3 point = Vec3::Zero();
    for (int j = 0; j < count; ++j)
      point += lambda[static_cast<std::size_t>(j)] *
               simplex[static_cast<std::size_t>(members[static_cast<std::size_t>(j)])].w;
    const double norm = point.squaredNorm();
    if (norm < best_norm) {
      best_norm = norm;
      best_mask = mask;
      best_weights = lambda;
    }
  }
  std::array<DifferencePoint, 4> reduced;
  int count = 0;
  Vec3 point = Vec3::Zero();
  for (int i = 0; i < size; ++i) {
    if (!(best_mask & (1 << i))) continue;
    reduced[static_cast<std::size_t>(count)] = simplex[static_cast<std::size_t>(i)];
    weights[static_cast<std::size_t>(count)] = best_weights[static_cast<std::size_t>(count)];
    point += weights[static_cast<std::size_t>(count)] * simplex[static_cast<std::size_t>(i)].w;
    ++count;
  }
  simplex = reduced;
  size = count;
  return point;
}

}  // namespace

GjkResult gjk(const Body& a, const Body& b, double scale, double stop_beyond) {
  Vec3 d = b.centre() - a.centre();
  if (d.squaredNorm() == 0) d = Vec3::UnitX();
  GjkResult r;
  std::array<double, 4> weights{1, 0, 0, 0};
  r.simplex[0] = difference_support(a, b, -d);
  r.size = 1;
  Vec3 v = r.simplex[0].w;
  const double touch = kTouchTolerance * scale;
  for (int iteration = 0; iteration < 128; ++iteration) {
    const double vv = v.squaredNorm();
    if (vv <= touch * touch) return r;
    const DifferencePoint p = difference_support(a, b, -v);
    // Every point x of b - a has v·x ≥ v·w: the distance is at least v·w/|v|.
    const double separation = v.dot(p.w);
    if (separation > 0 && separation * separation > stop_beyond * stop_beyond * vv) {
      r.distance = separation / std::sqrt(vv);
      r.direction = v;
      return r;
    }
    // v·w is a lower bound of |v|·distance: stop once it is within rounding.
    if (vv - v.dot(p.w) <= 1e-13 * vv) break;
    bool repeated = false;
    for (int i = 0; i < r.size; ++i)
      repeated = repeated || r.simplex[static_cast<std::size_t>(i)].w == p.w;
    if (repeated) break;
    std::array<DifferencePoint, 4> grown = r.simplex;
    std::array<double, 4> grown_weights = weights;
    int grown_size = r.size;
    grown[static_cast<std::size_t>(grown_size++)] = p;
    const Vec3 next = closest_on_simplex(grown, grown_size, grown_weights);
    if (next.squaredNorm() >= vv) break;  // no progress left in double precision
    r.simplex = grown;
    weights = grown_weights;
    r.size = grown_size;
    v = next;
    if (r.size == 4) return r;  // the origin is inside a tetrahedron of b - a
  }
  for (int i = 0; i < r.size; ++i) {
    r.on_a += weights[static_cast<std::size_t>(i)] * r.simplex[static_cast<std::size_t>(i)].on_a;
    r.on_b += weights[static_cast<std::size_t>(i)] * r.simplex[static_cast<std::size_t>(i)].on_b;
  }
  r.distance = v.norm();
  r.direction = v;
  return r;
}

}  // namespace hb::convex_detail
