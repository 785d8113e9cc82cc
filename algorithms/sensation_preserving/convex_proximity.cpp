#include "algorithms/sensation_preserving/convex_proximity.h"

#include <ccd/ccd.h>

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "algorithms/core/input_error.h"

namespace hb {

namespace {

using Vec2 = Eigen::Vector2d;

// Relative tolerances, scaled by the larger polytope's extent (m).
constexpr double kEpaTolerance = 1e-7;          // libccd's EPA and MPR stop
constexpr double kPolishBand = 1e-3;            // vertices near the extreme tried in polishing
constexpr std::size_t kPolishVertices = 8;      // most such vertices per polytope
constexpr double kCertifyTolerance = 1e-9;      // EPA's bounds this close: its normal is exact
constexpr double kEpaGap = 1e-12;               // own EPA stops when the support gains less
constexpr double kDegenerateTolerance = 1e-10;  // lengths below this are degenerate
constexpr double kFeatureTolerance = 1e-7;      // vertices this close to the extreme plane
constexpr double kPlanarTolerance = 1e-9;       // lengths in the contact plane
constexpr double kTouchTolerance = 1e-12;       // GJK: the origin is on the difference

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

Vec3 from_ccd(const ccd_vec3_t& v) { return Vec3(v.v[0], v.v[1], v.v[2]); }

void to_ccd(const Vec3& v, ccd_vec3_t* out) {
  out->v[0] = v.x();
  out->v[1] = v.y();
  out->v[2] = v.z();
}

void ccd_support(const void* object, const ccd_vec3_t* direction, ccd_vec3_t* out) {
  to_ccd(static_cast<const Body*>(object)->support(from_ccd(*direction)), out);
}

void ccd_centre(const void* object, ccd_vec3_t* out) {
  to_ccd(static_cast<const Body*>(object)->centre(), out);
}

void ccd_first_direction(const void* object1, const void* object2, ccd_vec3_t* out) {
  Vec3 d =
      static_cast<const Body*>(object2)->centre() - static_cast<const Body*>(object1)->centre();
  if (d.squaredNorm() == 0) d = Vec3::UnitX();
  to_ccd(d, out);
}

bool usable_direction(const Vec3& d) {
  return d.allFinite() && std::abs(d.squaredNorm() - 1) < 1e-6;
}

// ---------------------------------------------------------------- polishing

/// Translation along unit u that separates b from a: h_a(u) + h_b(-u).
double separating_translation(const Body& a, const Body& b, const Vec3& u) {
  const Vec3 ua = a.rotation.transpose() * u, ub = b.rotation.transpose() * u;
  double a_max = -std::numeric_limits<double>::infinity();
  double b_min = std::numeric_limits<double>::infinity();
  for (const Vec3& v : a.vertices) a_max = std::max(a_max, ua.dot(v));
  for (const Vec3& v : b.vertices) b_min = std::min(b_min, ub.dot(v));
  return a_max + u.dot(a.translation) - b_min - u.dot(b.translation);
}

/// World positions of the vertices of `body` whose height along `u` (sign
/// +1) or `-u` (sign -1) is within `band` of the extreme: the nearest
/// kPolishVertices of them.
std::vector<Vec3> near_extreme(const Body& body, const Vec3& u, double sign, double band) {
  std::vector<std::pair<double, Vec3>> heights;
  for (std::size_t i = 0; i < body.vertices.size(); ++i) {
    const Vec3 x = body.world(i);
    heights.emplace_back(sign * u.dot(x), x);
  }
  const double top =
      std::max_element(heights.begin(), heights.end(), [](const auto& p, const auto& q) {
        return p.first < q.first;
      })->first;
  std::stable_sort(heights.begin(), heights.end(),
                   [](const auto& p, const auto& q) { return p.first > q.first; });
  std::vector<Vec3> out;
  for (const auto& [height, x] : heights) {
    if (height < top - band || out.size() == kPolishVertices) break;
    out.push_back(x);
  }
  return out;
}

/// The penetration depth is least along the normal of the face of a - b
/// nearest the origin: a face normal of a or of b, or the cross product of
/// an edge of each. EPA stops within its tolerance of that face; the
/// polytopes' vertices near the extremes along its normal span it, so the
/// candidates they give (every triple of one side, every pair of each)
/// contain the exact normal. Keeps the one needing the least translation;
/// never worse than the normal given.
Vec3 polish_normal(const Body& a, const Body& b, Vec3 n, double scale) {
  double best = separating_translation(a, b, n);
  for (int round = 0; round < 3; ++round) {
    const double before = best;
    const std::vector<Vec3> pa = near_extreme(a, n, +1, kPolishBand * scale);
    const std::vector<Vec3> pb = near_extreme(b, n, -1, kPolishBand * scale);
    const Vec3 reference = n;
    const auto consider = [&](const Vec3& axis) {
      const double length = axis.norm();
      if (!(length > 1e-12 * scale * scale)) return;
      Vec3 u = axis / length;
      if (u.dot(reference) < 0) u = -u;
      const double value = separating_translation(a, b, u);
      if (value < best) {
        best = value;
        n = u;
      }
    };
    for (const std::vector<Vec3>* side : {&pa, &pb})
      for (std::size_t i = 0; i < side->size(); ++i)
        for (std::size_t j = i + 1; j < side->size(); ++j)
          for (std::size_t k = j + 1; k < side->size(); ++k)
            consider(((*side)[j] - (*side)[i]).cross((*side)[k] - (*side)[i]));
    for (std::size_t i = 0; i < pa.size(); ++i)
      for (std::size_t j = i + 1; j < pa.size(); ++j)
        for (std::size_t k = 0; k < pb.size(); ++k)
          for (std::size_t l = k + 1; l < pb.size(); ++l)
            consider((pa[j] - pa[i]).cross(pb[l] - pb[k]));
    if (!(best < before)) break;
  }
  return n;
}

// ---------------------------------------------------------------- GJK distance

/// A point of the difference b - a with the two vertices it comes from.
struct DifferencePoint {
  Vec3 w, on_a, on_b;
};

DifferencePoint difference_support(const Body& a, const Body& b, const Vec3& d) {
  DifferencePoint p;
  p.on_b = b.support(d);
  p.on_a = a.support(-d);
  p.w = p.on_b - p.on_a;
  return p;
}

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

/// GJK on b - a: the distance (m, 0 when they overlap), the closest points
/// when they are apart, and the final simplex (a tetrahedron holding the
/// origin, or a smaller simplex the origin lies on, when they overlap).
/// With a finite `stop_beyond` (m), GJK stops as soon as a support plane
/// proves the distance larger than it; distance is then that lower bound
/// (> stop_beyond) and the closest points are not computed.
struct GjkResult {
  double distance = 0;
  Vec3 on_a = Vec3::Zero(), on_b = Vec3::Zero();
  std::array<DifferencePoint, 4> simplex;
  int size = 0;
};

GjkResult gjk(const Body& a, const Body& b, double scale,
              double stop_beyond = std::numeric_limits<double>::infinity()) {
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
  return r;
}

// ---------------------------------------------------------------- EPA

/// The expanding polytope algorithm on b - a, started from GJK's simplex
/// (blown up to a tetrahedron around the origin when smaller). ok is false
/// when b - a is flat or the polytope degenerates.
struct EpaResult {
  bool ok = false;
  Vec3 normal = Vec3::Zero();  ///< unit, moves b out of a
  double lower_bound = 0;      ///< m, the polytope's depth: at most the true depth
};

EpaResult epa(const Body& a, const Body& b, const GjkResult& start, double scale) {
  const double tiny = kDegenerateTolerance * scale;
  std::vector<DifferencePoint> points;
  const auto independent = [&](const Vec3& w) {
    if (points.empty()) return true;
    const Vec3 e1 = points.size() > 1 ? Vec3(points[1].w - points[0].w) : Vec3::Zero();
    switch (points.size()) {
      case 1:
        return (w - points[0].w).norm() > tiny;
      case 2:
        return e1.cross(w - points[0].w).norm() > tiny * e1.norm();
      default: {
        const Vec3 n = e1.cross(points[2].w - points[0].w);
        return std::abs(n.dot(w - points[0].w)) > tiny * n.norm();
      }
    }
  };
  const auto add_support = [&](const Vec3& d) {
    if (points.size() >= 4) return;
    const DifferencePoint p = difference_support(a, b, d);
    if (independent(p.w)) points.push_back(p);
  };
  for (int i = 0; i < start.size; ++i)
    if (points.size() < 4 && independent(start.simplex[static_cast<std::size_t>(i)].w))
      points.push_back(start.simplex[static_cast<std::size_t>(i)]);
  for (const Vec3& d : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1),
                        Vec3(0, 0, -1)})
    if (points.size() < 2) add_support(d);
  if (points.size() == 2) {
    const Vec3 axis = (points[1].w - points[0].w).normalized();
    const Vec3 helper = std::abs(axis.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 e1 = axis.cross(helper).normalized(), e2 = axis.cross(e1);
    for (int k = 0; k < 6 && points.size() < 3; ++k)
      add_support(std::cos(k * std::numbers::pi / 3) * e1 +
                  std::sin(k * std::numbers::pi / 3) * e2);
  }
  if (points.size() == 3) {
    const Vec3 n = (points[1].w - points[0].w).cross(points[2].w - points[0].w);
    add_support(n);
    add_support(-n);
  }
  if (points.size() < 4) return {};  // b - a is flat: coplanar pieces

  struct Face {
    std::array<int, 3> v;
    Vec3 n;
    double d;
    bool alive;
  };
  std::vector<Face> faces;
  const Vec3 interior = 0.25 * (points[0].w + points[1].w + points[2].w + points[3].w);
  const auto add_face = [&](int i, int j, int k) {
    const Vec3& wi = points[static_cast<std::size_t>(i)].w;
    Vec3 n = (points[static_cast<std::size_t>(j)].w - wi)
                 .cross(points[static_cast<std::size_t>(k)].w - wi);
    const double length = n.norm();
    if (!(length > tiny * tiny)) return false;
    n /= length;
    if (n.dot(wi - interior) < 0) {
      n = -n;
      std::swap(j, k);
    }
    faces.push_back(Face{{i, j, k}, n, n.dot(wi), true});
    return true;
  };
  if (!add_face(0, 1, 2) || !add_face(0, 1, 3) || !add_face(0, 2, 3) || !add_face(1, 2, 3))
    return {};
  std::vector<std::pair<int, int>> edges, horizon;
  for (int iteration = 0; iteration < 256; ++iteration) {
    const Face* nearest = nullptr;
    for (const Face& f : faces)
      if (f.alive && (nearest == nullptr || f.d < nearest->d)) nearest = &f;
    if (nearest == nullptr) return {};
    const Vec3 n = nearest->n;
    const double d = nearest->d;
    const DifferencePoint p = difference_support(a, b, n);
    if (n.dot(p.w) - d <= kEpaGap * scale) return EpaResult{true, -n, d};
    const int m = static_cast<int>(points.size());
    points.push_back(p);
    edges.clear();
    for (Face& f : faces) {
      if (!f.alive || f.n.dot(p.w - points[static_cast<std::size_t>(f.v[0])].w) <= 0) continue;
      f.alive = false;
      for (int e = 0; e < 3; ++e)
        edges.emplace_back(f.v[static_cast<std::size_t>(e)],
                           f.v[static_cast<std::size_t>((e + 1) % 3)]);
    }
    horizon.clear();
    for (const auto& [i, j] : edges)
      if (std::find(edges.begin(), edges.end(), std::make_pair(j, i)) == edges.end())
        horizon.emplace_back(i, j);
    for (const auto& [i, j] : horizon)
      if (!add_face(i, j, m)) return {};
  }
  return {};
}

// ---------------------------------------------------------------- penetration

/// The direction in which b, overlapping a, leaves it by the least
/// translation. Candidates, each polished, the one needing the least
/// translation winning: own EPA from GJK's simplex (done when its lower
/// bound certifies it), then libccd's GJK/EPA and its Minkowski portal
/// refinement (libccd moves its second object along the direction it
/// returns). libccd alone is not enough: on the thin, nearly flat pieces
/// of a surface decomposition its GJK misses overlaps and its EPA stops on
/// wrong faces.
Vec3 penetration_normal(const Body& a, const Body& b, const GjkResult& overlap, double scale) {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.first_dir = ccd_first_direction;
  ccd.support1 = ccd_support;
  ccd.support2 = ccd_support;
  ccd.center1 = ccd_centre;
  ccd.center2 = ccd_centre;
  ccd.max_iterations = 1000;
  // libccd compares squared distances of the next support point from the
  // nearest triangle against epa_tolerance: it is an area (m²). Much
  // tighter than this, EPA can cycle on nearly coplanar support points;
  // polish_normal() finishes the job exactly.
  ccd.epa_tolerance = (kEpaTolerance * scale) * (kEpaTolerance * scale);
  ccd.mpr_tolerance = kEpaTolerance * scale;

  Vec3 best = Vec3::Zero();
  double best_translation = std::numeric_limits<double>::infinity();
  const auto consider = [&](const Vec3& candidate) {
    const Vec3 n = polish_normal(a, b, candidate, scale);
    const double translation = separating_translation(a, b, n);
    if (translation < best_translation) {
      best_translation = translation;
      best = n;
    }
  };
  const EpaResult own = epa(a, b, overlap, scale);
  if (own.ok) {
    consider(own.normal);
    // EPA's polytope lies inside the difference: its depth bounds the answer below.
    if (best_translation - own.lower_bound <= kCertifyTolerance * scale) return best;
  }
  ccd_real_t depth = 0;
  ccd_vec3_t direction, position;
  if (ccdGJKPenetration(&a, &b, &ccd, &depth, &direction, &position) == 0 && std::isfinite(depth) &&
      usable_direction(from_ccd(direction)))
    consider(from_ccd(direction).normalized());
  if (ccdMPRPenetration(&a, &b, &ccd, &depth, &direction, &position) == 0 && std::isfinite(depth) &&
      usable_direction(from_ccd(direction)))
    consider(from_ccd(direction).normalized());
  if (!(best_translation < std::numeric_limits<double>::infinity())) {
    Vec3 d = b.centre() - a.centre();
    consider(d.squaredNorm() > 0 ? d.normalized() : Vec3::UnitZ());
  }
  return best;
}

// ---------------------------------------------------------------- contact point

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Convex hull (counter-clockwise, no collinear vertices) of 2-D points.
std::vector<Vec2> hull_2d(std::vector<Vec2> points) {
  std::sort(points.begin(), points.end(), [](const Vec2& p, const Vec2& q) {
    return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<Vec2> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross2(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross2(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

/// A 2-D convex feature: a polygon, or (when thinner than the tolerance) the
/// segment between its two farthest points, possibly a single point.
struct Feature2 {
  std::vector<Vec2> polygon;  // counter-clockwise; empty for a segment or point
  Vec2 from, to;              // the segment (from == to for a point)
};

Feature2 make_feature(const std::vector<Vec2>& points, double tolerance) {
  const std::vector<Vec2> hull = hull_2d(points);
  Feature2 f;
  f.from = f.to = hull[0];
  double diameter = 0;
  for (std::size_t i = 0; i < hull.size(); ++i)
    for (std::size_t j = i + 1; j < hull.size(); ++j)
      if ((hull[i] - hull[j]).norm() > diameter) {
        diameter = (hull[i] - hull[j]).norm();
        f.from = hull[i];
        f.to = hull[j];
      }
  if (diameter <= tolerance || hull.size() < 3) return f;
  const Vec2 axis = (f.to - f.from) / diameter;
  double width = 0;
  for (const Vec2& p : hull) width = std::max(width, std::abs(cross2(axis, p - f.from)));
  if (width > tolerance) f.polygon = hull;
  return f;
}

/// Signed distance of p to the left of the directed edge (e0, e1).
double left_of(const Vec2& e0, const Vec2& e1, const Vec2& p) {
  const Vec2 e = e1 - e0;
  return cross2(e, p - e0) / e.norm();
}

/// The part of `subject` inside the convex polygon `clip` (Sutherland–Hodgman),
/// points within `tolerance` of it counting as inside.
std::vector<Vec2> clip_polygon(const std::vector<Vec2>& subject, const std::vector<Vec2>& clip,
                               double tolerance) {
  std::vector<Vec2> out = subject;
  for (std::size_t i = 0; i < clip.size() && !out.empty(); ++i) {
    const Vec2& e0 = clip[i];
    const Vec2& e1 = clip[(i + 1) % clip.size()];
    std::vector<Vec2> in = std::move(out);
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
  return out;
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

/// Midpoint of the closest points of two segments (points when degenerate);
/// the middle of their overlap when they are parallel and overlap.
Vec2 segments_middle(const Vec2& p1, const Vec2& q1, const Vec2& p2, const Vec2& q2,
                     double tolerance) {
  const Vec2 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
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
  // Closest points of two segments (clamped least squares).
  double s = 0, t = 0;
  const double f = d2.dot(r);
  if (a <= tolerance * tolerance && e <= tolerance * tolerance) {
    s = t = 0;
  } else if (a <= tolerance * tolerance) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= tolerance * tolerance) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denominator = a * e - b * b;
      s = denominator > 0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return 0.5 * ((p1 + s * d1) + (p2 + t * d2));
}

/// Centre (2-D) of the overlap of two features seen along the normal, with
/// boundaries widened by `tolerance`.
bool overlap_centre_within(const Feature2& fa, const Feature2& fb, double tolerance, Vec2& centre) {
  const bool a_area = !fa.polygon.empty(), b_area = !fb.polygon.empty();
  if (a_area && b_area) {
    const std::vector<Vec2> common = clip_polygon(fa.polygon, fb.polygon, tolerance);
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

/// The overlap's centre with exact boundaries; when rounding leaves the
/// features just apart (they touch along the normal), with widened ones.
bool overlap_centre(const Feature2& fa, const Feature2& fb, double tolerance, Vec2& centre) {
  return overlap_centre_within(fa, fb, 0, centre) ||
         overlap_centre_within(fa, fb, tolerance, centre);
}

/// Fills the contact's depth and point from its normal: a's extreme
/// feature along +n, b's along -n.
void fill_contact(const Body& a, const Body& b, const Vec3& n, double scale,
                  ConvexProximity& result) {
  const Vec3 na = a.rotation.transpose() * n, nb = b.rotation.transpose() * n;
  const double offset_a = n.dot(a.translation), offset_b = n.dot(b.translation);
  double a_max = -std::numeric_limits<double>::infinity();
  double b_min = std::numeric_limits<double>::infinity();
  for (const Vec3& v : a.vertices) a_max = std::max(a_max, na.dot(v) + offset_a);
  for (const Vec3& v : b.vertices) b_min = std::min(b_min, nb.dot(v) + offset_b);

  // An orthonormal basis (u, w) of the plane perpendicular to n.
  const Vec3 helper = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 u = n.cross(helper).normalized();
  const Vec3 w = n.cross(u);
  const double feature_tolerance = kFeatureTolerance * scale;
  std::vector<Vec2> pa, pb;
  Vec3 mean_a = Vec3::Zero(), mean_b = Vec3::Zero();
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    if (na.dot(a.vertices[i]) + offset_a < a_max - feature_tolerance) continue;
    const Vec3 x = a.world(i);
    pa.emplace_back(u.dot(x), w.dot(x));
    mean_a += x;
  }
  for (std::size_t i = 0; i < b.vertices.size(); ++i) {
    if (nb.dot(b.vertices[i]) + offset_b > b_min + feature_tolerance) continue;
    const Vec3 x = b.world(i);
    pb.emplace_back(u.dot(x), w.dot(x));
    mean_b += x;
  }
  const double planar_tolerance = kPlanarTolerance * scale;
  Vec2 centre;
  if (!overlap_centre(make_feature(pa, planar_tolerance), make_feature(pb, planar_tolerance),
                      planar_tolerance, centre)) {
    const Vec3 mid =
        0.5 * (mean_a / static_cast<double>(pa.size()) + mean_b / static_cast<double>(pb.size()));
    centre = Vec2(u.dot(mid), w.dot(mid));
  }
  result.in_contact = true;
  result.normal = n;
  result.signed_depth = a_max - b_min;
  result.point = centre.x() * u + centre.y() * w + 0.5 * (a_max + b_min) * n;
}

void check_piece(const PlacedConvex& c, const char* name) {
  if (c.vertices.empty()) throw InputError("", name, "a convex piece needs at least one vertex");
  for (const Vec3& v : c.vertices)
    if (!v.allFinite()) throw InputError("", name, "non-finite vertex coordinate");
  if (!is_finite(c.pose)) throw InputError("", name, "non-finite pose");
}

double common_scale(const Body& a, const Body& b) {
  return std::max({a.extent(), b.extent(), std::numeric_limits<double>::min()});
}

}  // namespace

ConvexProximity convex_proximity(const PlacedConvex& a, const PlacedConvex& b, double margin_m) {
  check_piece(a, "convex piece a");
  check_piece(b, "convex piece b");
  if (!(margin_m >= 0) || !std::isfinite(margin_m))
    throw InputError("", "contact margin", "expected a finite margin >= 0 m");
  const Body body_a(a), body_b(b);
  const double scale = common_scale(body_a, body_b);
  ConvexProximity result;
  // Own GJK decides overlap (libccd's GJK misses some overlaps of thin
  // pieces) and measures the gap of separated pieces.
  const GjkResult g = gjk(body_a, body_b, scale, margin_m);
  if (g.distance > 0) {
    if (g.distance < margin_m)
      fill_contact(body_a, body_b, (g.on_b - g.on_a) / g.distance, scale, result);
    return result;
  }
  fill_contact(body_a, body_b, penetration_normal(body_a, body_b, g, scale), scale, result);
  return result;
}

bool convex_apart(const PlacedConvex& a, const PlacedConvex& b, double margin_m) {
  const Body body_a(a), body_b(b);
  return gjk(body_a, body_b, common_scale(body_a, body_b), margin_m).distance > margin_m;
}

double convex_distance(const PlacedConvex& a, const PlacedConvex& b) {
  check_piece(a, "convex piece a");
  check_piece(b, "convex piece b");
  const Body body_a(a), body_b(b);
  return gjk(body_a, body_b, common_scale(body_a, body_b)).distance;
}

}  // namespace hb
