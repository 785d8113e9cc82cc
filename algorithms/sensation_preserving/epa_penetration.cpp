#include "algorithms/sensation_preserving/epa_penetration.h"

#include <ccd/ccd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace hb::convex_detail {

namespace {

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

/// separating_translation(a, b, u) when it is below `bound`, else some
/// number at least `bound`. The vertices `a_first` and `b_first` (indices,
/// those nearest the extremes along a nearby direction) are tried first:
/// the translation is at least what any of a's vertices and b's give, and
/// floating-point sums are monotone, so a bound reached with them is
/// reached by the full sums too; otherwise the full sums are taken.
double separating_translation_below(const Body& a, const Body& b, const Vec3& u, double bound,
                                    const std::vector<int>& a_first,
                                    const std::vector<int>& b_first) {
  const Vec3 ua = a.rotation.transpose() * u, ub = b.rotation.transpose() * u;
  double a_max = -std::numeric_limits<double>::infinity();
  double b_min = std::numeric_limits<double>::infinity();
  for (const int i : a_first) a_max = std::max(a_max, ua.dot(a.vertices[i]));
  for (const int i : b_first) b_min = std::min(b_min, ub.dot(b.vertices[i]));
  const double lower = a_max + u.dot(a.translation) - b_min - u.dot(b.translation);
  if (!(lower < bound)) return lower;
  return separating_translation(a, b, u);
}

/// The vertices of `body` whose height along `u` (sign +1) or `-u` (sign
/// -1) is within `band` of the extreme: the nearest kPolishVertices of them
/// (the highest first, equal heights by index), their world positions in
/// `out` and their indices in `indices`. `heights` is scratch.
void near_extreme(const Body& body, const Vec3& u, double sign, double band,
                  std::vector<std::pair<double, int>>& heights, std::vector<Vec3>& out,
                  std::vector<int>& indices) {
  heights.clear();
  for (std::size_t i = 0; i < body.vertices.size(); ++i)
    heights.emplace_back(sign * u.dot(body.world(i)), static_cast<int>(i));
  // Highest first, equal heights in index order: the order a stable sort by
  // height gives, for the first kPolishVertices only.
  const auto higher = [](const std::pair<double, int>& p, const std::pair<double, int>& q) {
    return p.first > q.first || (!(q.first > p.first) && p.second < q.second);
  };
  const std::size_t kept = std::min(kPolishVertices, heights.size());
  std::partial_sort(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(kept),
                    heights.end(), higher);
  out.clear();
  indices.clear();
  if (heights.empty()) return;
  const double top = heights.front().first;
  for (std::size_t k = 0; k < kept; ++k) {
    if (heights[k].first < top - band) break;
    out.push_back(body.world(static_cast<std::size_t>(heights[k].second)));
    indices.push_back(heights[k].second);
  }
}

/// What polish_normal() fills each round, kept between calls (per thread)
/// so that a warm query allocates nothing: the slow loop polishes
/// thousands of normals an update.
struct PolishScratch {
  std::vector<std::pair<double, int>> heights;
  std::vector<Vec3> pa, pb;  ///< world positions of a's and b's vertices near the extremes
  std::vector<int> ia, ib;   ///< their indices
};
thread_local PolishScratch polish_scratch;

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
    PolishScratch& scratch = polish_scratch;
    near_extreme(a, n, +1, kPolishBand * scale, scratch.heights, scratch.pa, scratch.ia);
    near_extreme(b, n, -1, kPolishBand * scale, scratch.heights, scratch.pb, scratch.ib);
    const std::vector<Vec3>& pa = scratch.pa;
    const std::vector<Vec3>& pb = scratch.pb;
    const std::vector<int>& ia = scratch.ia;
    const std::vector<int>& ib = scratch.ib;
    const Vec3 reference = n;
    const auto consider = [&](const Vec3& axis) {
      const double length = axis.norm();
      if (!(length > 1e-12 * scale * scale)) return;
      Vec3 u = axis / length;
      if (u.dot(reference) < 0) u = -u;
      const double value = separating_translation_below(a, b, u, best, ia, ib);
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

// ---------------------------------------------------------------- EPA

/// The expanding polytope algorithm on b - a, started from GJK's simplex
/// (blown up to a tetrahedron around the origin when smaller). ok is false
/// when b - a is flat or the polytope degenerates.
struct EpaResult {
  bool ok = false;
  Vec3 normal = Vec3::Zero();  ///< unit, moves b out of a
  double lower_bound = 0;      ///< m, the polytope's depth: at most the true depth
};

/// A face of EPA's polytope: vertices (indices into its points, outward
/// counter-clockwise), unit outward normal, distance from the origin.
struct EpaFace {
  std::array<int, 3> v;
  Vec3 n;
  double d;
  bool alive;
};

/// EPA's polytope and edge lists, kept between calls (per thread) as
/// PolishScratch is.
struct EpaScratch {
  std::vector<DifferencePoint> points;
  std::vector<EpaFace> faces;
  std::vector<std::pair<int, int>> edges, horizon;
};
thread_local EpaScratch epa_scratch;

// Whether w (m) lies off the span of the polytope's points so far (none to
// three) by more than `tiny` (m).
bool independent(const std::vector<DifferencePoint>& points, const Vec3& w, double tiny) {
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
}

// Adds the support point of b - a along d while the polytope has fewer than
// four points, when it is independent of them.
void add_support(const Body& a, const Body& b, const Vec3& d, double tiny,
                 std::vector<DifferencePoint>& points) {
  if (points.size() >= 4) return;
  const DifferencePoint p = difference_support(a, b, d);
  if (independent(points, p.w, tiny)) points.push_back(p);
}

// Fills `points` with four independent points of b - a: GJK's simplex, then
// support points along the axes, around a segment and off a triangle.
// Returns false when b - a is flat (coplanar pieces).
bool seed_tetrahedron(const Body& a, const Body& b, const GjkResult& start, double tiny,
                      std::vector<DifferencePoint>& points) {
  points.clear();
  for (int i = 0; i < start.size; ++i)
    if (points.size() < 4 &&
        independent(points, start.simplex[static_cast<std::size_t>(i)].w, tiny))
      points.push_back(start.simplex[static_cast<std::size_t>(i)]);
  for (const Vec3& d : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1),
                        Vec3(0, 0, -1)})
    if (points.size() < 2) add_support(a, b, d, tiny, points);
  if (points.size() == 2) {
    const Vec3 axis = (points[1].w - points[0].w).normalized();
    const Vec3 helper = std::abs(axis.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 e1 = axis.cross(helper).normalized(), e2 = axis.cross(e1);
    for (int k = 0; k < 6 && points.size() < 3; ++k)
      add_support(a, b,
                  std::cos(k * std::numbers::pi / 3) * e1 + std::sin(k * std::numbers::pi / 3) * e2,
                  tiny, points);
  }
  if (points.size() == 3) {
    const Vec3 n = (points[1].w - points[0].w).cross(points[2].w - points[0].w);
    add_support(a, b, n, tiny, points);
    add_support(a, b, -n, tiny, points);
  }
  return points.size() >= 4;
}

// Appends the face (i, j, k) of the polytope, turned outward (away from
// `interior`, m); false when it is degenerate (|(w_j − w_i) × (w_k − w_i)|
// at most `tiny`², m²).
[[gnu::always_inline]] inline bool add_face(const std::vector<DifferencePoint>& points,
                                            const Vec3& interior, double tiny, int i, int j, int k,
                                            std::vector<EpaFace>& faces) {
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
  faces.push_back(EpaFace{{i, j, k}, n, n.dot(wi), true});
  return true;
}

// The live face nearest the origin (the first of equals), nullptr when none is left.
const EpaFace* nearest_face(const std::vector<EpaFace>& faces) {
  const EpaFace* nearest = nullptr;
  for (const EpaFace& f : faces)
    if (f.alive && (nearest == nullptr || f.d < nearest->d)) nearest = &f;
  return nearest;
}

// Removes the live faces that the new point w (m) sees and lists their
// edges in `edges`; then the horizon, the edges whose reverse is not listed,
// in `horizon`.
void remove_visible(const std::vector<DifferencePoint>& points, const Vec3& w,
                    std::vector<EpaFace>& faces, std::vector<std::pair<int, int>>& edges,
                    std::vector<std::pair<int, int>>& horizon) {
  edges.clear();
  for (EpaFace& f : faces) {
    if (!f.alive || f.n.dot(w - points[static_cast<std::size_t>(f.v[0])].w) <= 0) continue;
    f.alive = false;
    for (int e = 0; e < 3; ++e)
      edges.emplace_back(f.v[static_cast<std::size_t>(e)],
                         f.v[static_cast<std::size_t>((e + 1) % 3)]);
  }
  horizon.clear();
  for (const auto& [i, j] : edges)
    if (std::find(edges.begin(), edges.end(), std::make_pair(j, i)) == edges.end())
      horizon.emplace_back(i, j);
}

EpaResult epa(const Body& a, const Body& b, const GjkResult& start, double scale) {
  const double tiny = kDegenerateTolerance * scale;
  EpaScratch& scratch = epa_scratch;
  std::vector<DifferencePoint>& points = scratch.points;
  if (!seed_tetrahedron(a, b, start, tiny, points)) return {};  // b - a is flat: coplanar pieces

  std::vector<EpaFace>& faces = scratch.faces;
  faces.clear();
  const Vec3 interior = 0.25 * (points[0].w + points[1].w + points[2].w + points[3].w);
  if (!add_face(points, interior, tiny, 0, 1, 2, faces) ||
      !add_face(points, interior, tiny, 0, 1, 3, faces) ||
      !add_face(points, interior, tiny, 0, 2, 3, faces) ||
      !add_face(points, interior, tiny, 1, 2, 3, faces))
    return {};
  for (int iteration = 0; iteration < 256; ++iteration) {
    const EpaFace* nearest = nearest_face(faces);
    if (nearest == nullptr) return {};
    const Vec3 n = nearest->n;
    const double d = nearest->d;
    const DifferencePoint p = difference_support(a, b, n);
    if (n.dot(p.w) - d <= kEpaGap * scale) return EpaResult{true, -n, d};
    const int m = static_cast<int>(points.size());
    points.push_back(p);
    remove_visible(points, p.w, faces, scratch.edges, scratch.horizon);
    for (const auto& [i, j] : scratch.horizon)
      if (!add_face(points, interior, tiny, i, j, m, faces)) return {};
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
}  // namespace

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

}  // namespace hb::convex_detail
