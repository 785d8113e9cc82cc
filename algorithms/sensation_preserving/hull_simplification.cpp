#include "algorithms/sensation_preserving/hull_simplification.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <queue>
#include <unordered_map>
#include <utility>
#include <vector>

namespace hb {

namespace {

std::size_t at(int i) { return static_cast<std::size_t>(i); }

// Rounding allowance (m) of plane tests on a polytope of these vertices.
double rounding_of(const std::vector<Vec3>& vertices) {
  Eigen::AlignedBox3d box;
  for (const Vec3& v : vertices) box.extend(v);
  const double reach = box.min().cwiseAbs().maxCoeff() + box.max().cwiseAbs().maxCoeff();
  return 1e-12 * (box.diagonal().norm() + reach);
}

// ---- Flat polygons ---------------------------------------------------------

ConvexPolytope simplify_polygon(const ConvexPolytope& hull, int max_vertices) {
  std::vector<Vec3> polygon = hull.vertices;
  const std::vector<Vec3>& p0 = hull.vertices;
  const Vec3 normal = (p0[1] - p0[0]).cross(p0[2] - p0[0]).normalized();
  while (static_cast<int>(polygon.size()) > max_vertices) {
    const std::size_t n = polygon.size();
    double best_cost = std::numeric_limits<double>::infinity();
    std::size_t best_edge = n;
    Vec3 best_point = Vec3::Zero();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& before = polygon[(i + n - 1) % n];
      const Vec3& p = polygon[i];
      const Vec3& q = polygon[(i + 1) % n];
      const Vec3& after = polygon[(i + 2) % n];
      // p + s·(p − before) = q + t·(q − after), s, t > 0.
      const Vec3 d1 = p - before, d2 = q - after, e = q - p;
      const double denominator = d1.cross(d2).dot(normal);
      if (!(std::abs(denominator) > 0)) continue;
      const double s = e.cross(d2).dot(normal) / denominator;
      const double t = e.cross(d1).dot(normal) / denominator;
      if (!(s > 0 && t > 0) || !std::isfinite(s) || !std::isfinite(t)) continue;
      const Vec3 point = p + s * d1;
      const double length = e.norm();
      if (!(length > 0)) continue;
      const double cost = e.cross(point - p).norm() / length;
      if (cost < best_cost) {
        best_cost = cost;
        best_edge = i;
        best_point = point;
      }
    }
    if (best_edge == n) break;
    polygon[best_edge] = best_point;
    polygon.erase(polygon.begin() + static_cast<std::ptrdiff_t>((best_edge + 1) % n));
  }
  ConvexPolytope result;
  result.dimension = 2;
  result.vertices = std::move(polygon);
  const int count = static_cast<int>(result.vertices.size());
  for (int i = 1; i + 1 < count; ++i) result.triangles.push_back({0, i, i + 1});
  for (int i = 1; i + 1 < count; ++i) result.triangles.push_back({0, i + 1, i});
  return result;
}

// ---- Solids ----------------------------------------------------------------

struct Plane {
  Vec3 normal;  // unit, outward
  double offset;
};

class SolidSimplifier {
 public:
  explicit SolidSimplifier(const ConvexPolytope& hull)
      : position_(hull.vertices),
        alive_vertex_(hull.vertices.size(), true),
        stamp_(hull.vertices.size(), 0),
        incident_(hull.vertices.size()),
        tolerance_(rounding_of(hull.vertices)) {
    Eigen::AlignedBox3d box;
    for (const Vec3& v : hull.vertices) box.extend(v);
    min_double_area_ = 1e-14 * box.diagonal().squaredNorm();
    for (const auto& t : hull.triangles) add_triangle(t);
    alive_count_ = static_cast<int>(position_.size());
  }

  void run(int max_vertices) {
    for (int v = 0; v < static_cast<int>(position_.size()); ++v)
      for (const int w : neighbours(v))
        if (v < w) push_candidate(v, w);
    // Lazy: an edge whose surroundings changed since its point was chosen
    // is re-evaluated only when it reaches the front of the queue.
    while (alive_count_ > max_vertices && !queue_.empty()) {
      const Candidate candidate = queue_.top();
      queue_.pop();
      const int a = candidate.a, b = candidate.b;
      if (!alive_vertex_[at(a)] || !alive_vertex_[at(b)]) continue;
      if (candidate.evaluated && stamp_[at(a)] == candidate.stamp_a &&
          stamp_[at(b)] == candidate.stamp_b) {
        collapse_if_valid(candidate);
        continue;
      }
      const auto last = evaluated_at_.find(edge_key(a, b));
      if (last != evaluated_at_.end() && last->second == stamps_of(a, b)) continue;
      const std::vector<int> around = neighbours(a);
      if (std::binary_search(around.begin(), around.end(), b)) push_candidate(a, b);
    }
  }

  ConvexPolytope result() const {
    ConvexPolytope out;
    out.dimension = 3;
    std::vector<int> index(position_.size(), -1);
    for (std::size_t v = 0; v < position_.size(); ++v) {
      if (!alive_vertex_[v]) continue;
      index[v] = static_cast<int>(out.vertices.size());
      out.vertices.push_back(position_[v]);
    }
    for (std::size_t t = 0; t < triangle_.size(); ++t) {
      if (!alive_triangle_[t]) continue;
      const auto& tri = triangle_[t];
      out.triangles.push_back({index[at(tri[0])], index[at(tri[1])], index[at(tri[2])]});
    }
    return out;
  }

 private:
  struct Candidate {
    double cost;
    int a, b;
    unsigned stamp_a, stamp_b;
    Vec3 point;
    bool evaluated;
    bool operator<(const Candidate& other) const { return cost > other.cost; }  // min-heap
  };

  void add_triangle(const std::array<int, 3>& t) {
    const int id = static_cast<int>(triangle_.size());
    triangle_.push_back(t);
    alive_triangle_.push_back(true);
    plane_.push_back(plane_of(t));
    area_.push_back(0.5 * (position_[at(t[1])] - position_[at(t[0])])
                              .cross(position_[at(t[2])] - position_[at(t[0])])
                              .norm());
    for (const int v : t) incident_[at(v)].push_back(id);
  }

  Plane plane_of(const std::array<int, 3>& t) const {
    const Vec3& a = position_[at(t[0])];
    const Vec3 n = (position_[at(t[1])] - a).cross(position_[at(t[2])] - a).normalized();
    return Plane{n, n.dot(a)};
  }

  std::vector<int> neighbours(int v) const {
    std::vector<int> out;
    for (const int t : incident_[at(v)])
      for (const int w : triangle_[at(t)])
        if (w != v) out.push_back(w);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  // Triangles around a or b, sorted, into `out`.
  void star(int a, int b, std::vector<int>& out) const {
    out = incident_[at(a)];
    out.insert(out.end(), incident_[at(b)].begin(), incident_[at(b)].end());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  // The best collapse point of edge (a, b), if any: the vertex of the
  // region outside all star planes that minimises the area-weighted height.
  void push_candidate(int a, int b) {
    std::vector<int>& faces = star_scratch_;
    star(a, b, faces);
    std::vector<Plane>& planes = plane_scratch_;
    planes.clear();
    Vec3 weight = Vec3::Zero();
    for (const int t : faces) {
      const Plane& p = plane_[at(t)];
      weight += area_[at(t)] * p.normal;
      bool repeated = false;
      for (const Plane& q : planes)
        if (p.normal.dot(q.normal) > 1 - 1e-12 && std::abs(p.offset - q.offset) <= tolerance_)
          repeated = true;
      if (!repeated) planes.push_back(p);
    }
    const std::size_t n = planes.size();
    evaluated_at_[edge_key(a, b)] = stamps_of(a, b);
    if (n < 3) return;
    // The optimum is the vertex of three planes that is primal feasible
    // (outside every star plane) and dual feasible (the weight is a
    // non-negative combination of the three normals): the first such triple.
    const double dual_tolerance = 1e-12 * weight.norm();
    bool found = false;
    Vec3 best = Vec3::Zero();
    for (std::size_t i = 0; i < n && !found; ++i)
      for (std::size_t j = i + 1; j < n && !found; ++j) {
        const Vec3 ij = planes[i].normal.cross(planes[j].normal);
        for (std::size_t k = j + 1; k < n; ++k) {
          const double det = ij.dot(planes[k].normal);
          if (std::abs(det) < 1e-6) continue;
          const Vec3 jk = planes[j].normal.cross(planes[k].normal);
          const Vec3 ki = planes[k].normal.cross(planes[i].normal);
          if (weight.dot(jk) / det < -dual_tolerance || weight.dot(ki) / det < -dual_tolerance ||
              weight.dot(ij) / det < -dual_tolerance)
            continue;
          const Vec3 c =
              (planes[i].offset * jk + planes[j].offset * ki + planes[k].offset * ij) / det;
          bool outside = true;
          for (const Plane& p : planes)
            if (p.normal.dot(c) < p.offset - tolerance_) {
              outside = false;
              break;
            }
          if (!outside) continue;
          best = c;
          found = true;
          break;
        }
      }
    if (!found) return;
    double height = 0;
    for (const Plane& p : planes) height = std::max(height, p.normal.dot(best) - p.offset);
    queue_.push(Candidate{height, a, b, stamp_[at(a)], stamp_[at(b)], best, true});
  }

  // A collapse of edge (a, b) being checked: the triangles around a or b
  // (sorted), the edge's two and their apexes, and the star's other
  // triangles as they become with a and b replaced by the new vertex.
  struct Collapse {
    int a = 0, b = 0;
    int c_index = 0;  // the new vertex
    std::vector<int> faces;
    std::vector<int> edge_faces, apexes;
    std::vector<std::pair<int, std::array<int, 3>>> changed;
    std::vector<Plane> changed_planes;
  };

  // Collapses the candidate's edge to its point when the result stays a
  // closed manifold with every vertex on or behind every face.
  void collapse_if_valid(const Candidate& candidate) {
    Collapse collapse;
    collapse.a = candidate.a;
    collapse.b = candidate.b;
    const Vec3& c = candidate.point;
    star(collapse.a, collapse.b, collapse.faces);
    if (!link_holds(collapse)) return;
    collapse.c_index = static_cast<int>(position_.size());
    position_.push_back(c);  // provisional; removed again on rejection
    if (!changed_faces_hold(collapse) || !kept_faces_hold(c, collapse.faces)) {
      position_.pop_back();
      return;
    }
    commit(collapse);
    requeue_around(collapse.c_index, candidate.cost);
  }

  // Finds the edge's two triangles and their apexes; whether the link
  // condition holds (two triangles, distinct apexes, two common neighbours).
  bool link_holds(Collapse& collapse) const {
    const int a = collapse.a, b = collapse.b;
    for (const int t : collapse.faces) {
      const auto& tri = triangle_[at(t)];
      const bool has_a = std::find(tri.begin(), tri.end(), a) != tri.end();
      const bool has_b = std::find(tri.begin(), tri.end(), b) != tri.end();
      if (has_a && has_b) {
        collapse.edge_faces.push_back(t);
        for (const int v : tri)
          if (v != a && v != b) collapse.apexes.push_back(v);
      }
    }
    if (collapse.edge_faces.size() != 2 || collapse.apexes[0] == collapse.apexes[1]) return false;
    const std::vector<int> na = neighbours(a), nb = neighbours(b);
    std::vector<int> common;
    std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
    return common.size() == 2;
  }

  // The star's other triangles with a, b replaced by the new vertex (already
  // in position_): whether each is non-degenerate with every vertex (a and b
  // included) on or behind it. Lists them with their planes.
  bool changed_faces_hold(Collapse& collapse) const {
    for (const int t : collapse.faces) {
      if (t == collapse.edge_faces[0] || t == collapse.edge_faces[1]) continue;
      std::array<int, 3> tri = triangle_[at(t)];
      for (int& v : tri)
        if (v == collapse.a || v == collapse.b) v = collapse.c_index;
      const Vec3& p = position_[at(tri[0])];
      const Vec3 cross = (position_[at(tri[1])] - p).cross(position_[at(tri[2])] - p);
      if (!(cross.norm() > min_double_area_)) return false;
      const Vec3 normal = cross.normalized();
      const Plane plane{normal, normal.dot(p)};
      for (std::size_t v = 0; v + 1 < position_.size(); ++v)
        if (alive_vertex_[v] && plane.normal.dot(position_[v]) > plane.offset + tolerance_)
          return false;
      collapse.changed.emplace_back(t, tri);
      collapse.changed_planes.push_back(plane);
    }
    return true;
  }

  // Whether c (m) lies on or behind every live face outside the star
  // (`faces`, sorted): those keep their planes.
  bool kept_faces_hold(const Vec3& c, const std::vector<int>& faces) const {
    for (std::size_t t = 0; t < triangle_.size(); ++t) {
      if (!alive_triangle_[t] ||
          std::binary_search(faces.begin(), faces.end(), static_cast<int>(t)))
        continue;
      if (plane_[t].normal.dot(c) > plane_[t].offset + tolerance_) return false;
    }
    return true;
  }

  // Replaces a and b with the new vertex: drops the edge's two triangles and
  // rewrites the others of the star.
  void commit(const Collapse& collapse) {
    const int a = collapse.a, b = collapse.b, c_index = collapse.c_index;
    alive_vertex_.push_back(true);
    stamp_.push_back(0);
    incident_.emplace_back();
    alive_vertex_[at(a)] = alive_vertex_[at(b)] = false;
    incident_[at(a)].clear();
    incident_[at(b)].clear();
    for (const int t : collapse.edge_faces) {
      alive_triangle_[at(t)] = false;
      for (const int v : triangle_[at(t)]) {
        auto& list = incident_[at(v)];
        list.erase(std::remove(list.begin(), list.end(), t), list.end());
      }
    }
    for (std::size_t k = 0; k < collapse.changed.size(); ++k) {
      const int t = collapse.changed[k].first;
      triangle_[at(t)] = collapse.changed[k].second;
      plane_[at(t)] = collapse.changed_planes[k];
      const auto& tri = triangle_[at(t)];
      area_[at(t)] = 0.5 * (position_[at(tri[1])] - position_[at(tri[0])])
                               .cross(position_[at(tri[2])] - position_[at(tri[0])])
                               .norm();
      incident_[at(c_index)].push_back(t);
    }
    --alive_count_;
  }

  // Marks the ring around the new vertex changed and queues every edge
  // touching the ring for evaluation, at the collapse's cost.
  void requeue_around(int c_index, double cost) {
    const std::vector<int> ring = neighbours(c_index);
    for (const int v : ring) ++stamp_[at(v)];
    std::vector<std::pair<int, int>> edges;
    for (const int v : ring)
      for (const int w : neighbours(v)) edges.emplace_back(std::min(v, w), std::max(v, w));
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    for (const auto& [v, w] : edges) queue_.push(Candidate{cost, v, w, 0, 0, Vec3::Zero(), false});
  }

  static uint64_t edge_key(int a, int b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
  }
  uint64_t stamps_of(int a, int b) const {
    if (a > b) std::swap(a, b);
    return (static_cast<uint64_t>(stamp_[at(a)]) << 32) | stamp_[at(b)];
  }

  std::vector<Vec3> position_;
  std::vector<bool> alive_vertex_;
  std::vector<unsigned> stamp_;
  std::vector<std::vector<int>> incident_;
  std::vector<std::array<int, 3>> triangle_;
  std::vector<bool> alive_triangle_;
  std::vector<Plane> plane_;
  std::vector<double> area_;
  std::priority_queue<Candidate> queue_;
  std::vector<int> star_scratch_;
  std::vector<Plane> plane_scratch_;
  std::unordered_map<uint64_t, uint64_t> evaluated_at_;  // edge -> its stamps when last evaluated
  int alive_count_ = 0;
  double tolerance_;
  double min_double_area_ = 0;
};

}  // namespace

ConvexPolytope simplify_enclosing(const ConvexPolytope& hull, int max_vertices) {
  if (static_cast<int>(hull.vertices.size()) <= max_vertices) return hull;
  if (hull.dimension == 2) return simplify_polygon(hull, max_vertices);
  if (hull.dimension != 3) return hull;
  SolidSimplifier simplifier(hull);
  simplifier.run(max_vertices);
  return simplifier.result();
}

}  // namespace hb
