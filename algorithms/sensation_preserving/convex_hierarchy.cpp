#include "algorithms/sensation_preserving/convex_hierarchy.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/core/build_progress.h"
#include "algorithms/sensation_preserving/convex_decomposition.h"
#include "algorithms/sensation_preserving/convex_hull.h"
#include "algorithms/sensation_preserving/hull_simplification.h"
#include "hapticbench/closest_points.h"
#include "hapticbench/input_error.h"

namespace hb {

namespace {

std::size_t at(int i) { return static_cast<std::size_t>(i); }

// Among merges of equal deviation (flat regions) the smaller piece goes
// first: cost = deviation + kSizeWeight · bounding radius.
constexpr double kSizeWeight = 1e-3;
// A level whose adjacent merges leave more than this fraction of its pieces
// also merges pieces that are near each other without touching.
constexpr double kStalledFraction = 0.75;

struct Plane {
  Vec3 normal;
  double offset;
};

// A patch: the original triangles in one or two lists.
using Patch = std::array<std::span<const int>, 2>;

std::vector<Plane> face_planes(const ConvexPolytope& piece) {
  std::vector<Plane> planes;
  planes.reserve(piece.triangles.size());
  for (const auto& t : piece.triangles) {
    const Vec3& a = piece.vertices[at(t[0])];
    const Vec3 cross = (piece.vertices[at(t[1])] - a).cross(piece.vertices[at(t[2])] - a);
    if (!(cross.norm() > 0)) continue;
    const Vec3 n = cross.normalized();
    planes.push_back({n, n.dot(a)});
  }
  return planes;
}

// A piece with what it stands for: its deviation and bounding sphere.
struct Piece {
  ConvexPolytope polytope;
  double deviation_m = 0;
  Vec3 centre = Vec3::Zero();
  double radius = 0;
  double cost() const { return deviation_m + kSizeWeight * radius; }
};

// Bound on the largest distance from a point of the patch (mesh triangles)
// to the surface of a convex piece that encloses it. Inside the piece that
// distance is f(p) = min_f (h_f − n_f·p), a concave function, so on a
// triangle it is at most U = min_f max_{vertices} (h_f − n_f·v). Branch and
// bound: f at the patch's vertices gives a lower bound L of the largest
// distance; a triangle whose U exceeds (1 + kRelativeGap)·L + slack is cut
// into four (up to kMaxSubdivision times), f at the new points raising L.
// The result, the largest U accepted, bounds the distance from above and
// is within the gap of it where the subdivision resolves it.
class DeviationBound {
 public:
  DeviationBound(const std::vector<Plane>& planes, double slack) : planes_(planes), slack_(slack) {}

  void add_point(const Vec3& p) {
    double best = depth(hint_, p);
    if (best <= lower_) return;
    for (std::size_t f = 0; f < planes_.size(); ++f) {
      const double d = depth(f, p);
      if (d < best) {
        best = d;
        hint_ = f;
        if (best <= lower_) return;
      }
    }
    lower_ = best;
  }

  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, int subdivision = 0) {
    const double threshold = std::max(upper_, (1 + kRelativeGap) * lower_ + slack_);
    const double bound = triangle_bound(a, b, c, threshold);
    if (bound <= threshold || subdivision == kMaxSubdivision) {
      upper_ = std::max(upper_, bound);
      return;
    }
    const Vec3 ab = (a + b) / 2, bc = (b + c) / 2, ca = (c + a) / 2;
    for (const Vec3* p : {&ab, &bc, &ca}) add_point(*p);
    add_triangle(a, ab, ca, subdivision + 1);
    add_triangle(ab, b, bc, subdivision + 1);
    add_triangle(ca, bc, c, subdivision + 1);
    add_triangle(ab, bc, ca, subdivision + 1);
  }

  double bound() const { return std::max(lower_, upper_); }

 private:
  static constexpr double kRelativeGap = 0.05;
  static constexpr int kMaxSubdivision = 5;

  double depth(std::size_t f, const Vec3& p) const {
    return planes_[f].offset - planes_[f].normal.dot(p);
  }

  // Smallest U over the faces, or the first value found ≤ threshold (also
  // an upper bound for the triangle).
  double triangle_bound(const Vec3& a, const Vec3& b, const Vec3& c, double threshold) {
    auto value = [&](std::size_t f) { return std::max({depth(f, a), depth(f, b), depth(f, c)}); };
    double best = value(hint_);
    if (best <= threshold) return best;
    for (std::size_t f = 0; f < planes_.size(); ++f) {
      const double v = value(f);
      if (v < best) {
        best = v;
        hint_ = f;
        if (best <= threshold) return best;
      }
    }
    return best;
  }

  const std::vector<Plane>& planes_;
  double slack_;
  std::size_t hint_ = 0;
  double lower_ = 0;  // largest distance found at a point
  double upper_ = 0;  // largest bound accepted for a (sub)triangle
};

// The bound of DeviationBound for the patch `faces`, with slack (m) below
// which the gap is not narrowed. Piece surfaces of dimension ≤ 1 (segment,
// point): the distance is convex in p, so its largest value on a triangle
// is at a vertex.
double deviation_bound(const ConvexPolytope& piece, const std::vector<Plane>& planes,
                       const TriangleMesh& mesh, const Patch& patch, double slack) {
  if (planes.empty()) {
    double worst = 0;
    for (const auto faces : patch)
      for (const int t : faces)
        for (const int v : mesh.triangles[at(t)]) {
          const Vec3& p = mesh.vertices[at(v)];
          const double d =
              piece.vertices.size() >= 2
                  ? (p - closest_point_on_segment(p, piece.vertices[0], piece.vertices[1])).norm()
                  : (p - piece.vertices[0]).norm();
          worst = std::max(worst, d);
        }
    return worst;
  }
  DeviationBound bound(planes, slack);
  for (const auto faces : patch)
    for (const int t : faces)
      for (const int v : mesh.triangles[at(t)]) bound.add_point(mesh.vertices[at(v)]);
  for (const auto faces : patch)
    for (const int t : faces) {
      const auto& tri = mesh.triangles[at(t)];
      bound.add_triangle(mesh.vertices[at(tri[0])], mesh.vertices[at(tri[1])],
                         mesh.vertices[at(tri[2])]);
    }
  return bound.bound();
}

// Rounding allowance (m) added to computed deviations: plane offsets and
// depths are rounded at about 1e-16 of the coordinates' magnitude.
double rounding_allowance(const Vec3& centre, double radius) {
  return 1e-12 * (centre.cwiseAbs().maxCoeff() + radius);
}

Piece make_piece(ConvexPolytope polytope, const TriangleMesh& mesh, const Patch& patch) {
  Piece piece;
  piece.polytope = std::move(polytope);
  Eigen::AlignedBox3d box;
  for (const Vec3& v : piece.polytope.vertices) box.extend(v);
  piece.centre = box.center();
  double radius2 = 0;
  for (const Vec3& v : piece.polytope.vertices)
    radius2 = std::max(radius2, (v - piece.centre).squaredNorm());
  for (const auto faces : patch)
    for (const int t : faces)
      for (const int v : mesh.triangles[at(t)])
        radius2 = std::max(radius2, (mesh.vertices[at(v)] - piece.centre).squaredNorm());
  piece.radius = std::sqrt(radius2) * (1 + 1e-12);  // rounded up
  const std::vector<Plane> planes = face_planes(piece.polytope);
  piece.deviation_m = deviation_bound(piece.polytope, planes, mesh, patch, 1e-6 * piece.radius) +
                      rounding_allowance(piece.centre, piece.radius);
  return piece;
}

// Interleaved bits of a point's cell in a 2^20 grid over the box.
uint64_t morton_code(const Vec3& p, const Eigen::AlignedBox3d& box) {
  const Vec3 size = box.sizes().cwiseMax(1e-300);
  uint64_t code = 0;
  std::array<uint64_t, 3> cell{};
  for (int axis = 0; axis < 3; ++axis) {
    const double unit = std::clamp((p[axis] - box.min()[axis]) / size[axis], 0.0, 1.0);
    cell[at(axis)] = static_cast<uint64_t>(unit * ((1 << 20) - 1));
  }
  for (int bit = 19; bit >= 0; --bit)
    for (int axis = 0; axis < 3; ++axis) code = (code << 1) | ((cell[at(axis)] >> bit) & 1);
  return code;
}

void validate(const TriangleMesh& mesh, const ConvexHierarchySettings& settings) {
  if (mesh.triangles.empty() || mesh.vertices.empty())
    throw InputError("", "mesh", "a convex hierarchy needs at least one triangle");
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (!mesh.vertices[v].allFinite())
      throw InputError("", "vertex " + std::to_string(v), "coordinates must be finite");
  const int count = static_cast<int>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const int v : mesh.triangles[t])
      if (v < 0 || v >= count)
        throw InputError("", "triangle " + std::to_string(t),
                         "vertex index " + std::to_string(v) + " out of range [0, " +
                             std::to_string(count) + ")");
  if (!(settings.convexity_tolerance_rad >= 0 &&
        settings.convexity_tolerance_rad < std::numbers::pi / 2))
    throw InputError("", "convexity_tolerance_rad", "must be in [0, pi/2) rad");
  if (settings.max_piece_vertices < 4)
    throw InputError("", "max_piece_vertices", "must be at least 4");
}

class HierarchyBuilder {
 public:
  HierarchyBuilder(const TriangleMesh& mesh, const ConvexHierarchySettings& settings)
      : mesh_(mesh), settings_(settings) {}

  ConvexHierarchy build() {
    make_leaves();
    alive_.resize(hierarchy_.nodes.size());
    std::iota(alive_.begin(), alive_.end(), 0);
    hierarchy_.pieces_per_level.push_back(static_cast<int>(alive_.size()));
    const std::size_t merges = alive_.size() - 1;  // each merge joins two pieces into one
    merges_total_ = merges;
    for (int level = 1; alive_.size() > 1; ++level) {
      merge_level(level);
      std::vector<int> next;
      for (std::size_t n = 0; n < hierarchy_.nodes.size(); ++n)
        if (is_alive_[n]) next.push_back(static_cast<int>(n));
      alive_ = std::move(next);
      hierarchy_.pieces_per_level.push_back(static_cast<int>(alive_.size()));
      announce_build_progress(merges + 1 - alive_.size(), merges);
    }
    hierarchy_.root = alive_.front();
    return std::move(hierarchy_);
  }

 private:
  struct Candidate {
    int a, b;
    Piece piece;
  };

  void make_leaves() {
    const std::vector<std::vector<int>> patches =
        convex_surface_patches(mesh_, settings_.convexity_tolerance_rad);
    std::vector<int> vertex_stamp(mesh_.vertices.size(), -1);
    // Patches sharing a vertex are neighbours.
    std::vector<std::vector<int>> patches_at(mesh_.vertices.size());
    for (std::size_t p = 0; p < patches.size(); ++p) {
      std::vector<Vec3> points;
      for (const int t : patches[p])
        for (const int v : mesh_.triangles[at(t)]) {
          if (vertex_stamp[at(v)] == static_cast<int>(p)) continue;
          vertex_stamp[at(v)] = static_cast<int>(p);
          points.push_back(mesh_.vertices[at(v)]);
          patches_at[at(v)].push_back(static_cast<int>(p));
        }
      Piece piece = make_piece(convex_hull(points), mesh_, Patch{patches[p], {}});
      std::vector<Vec3> proxy = merge_proxy(piece.polytope);
      ConvexNode node = node_of(std::move(piece), 0);
      node.faces = patches[p];
      add_node(std::move(node), patches[p], std::move(proxy));
    }
    for (const auto& list : patches_at)
      for (const int p : list)
        for (const int q : list)
          if (p != q) neighbours_[at(p)].push_back(q);
    for (auto& list : neighbours_) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
  }

  ConvexNode node_of(Piece piece, int level) const {
    ConvexNode node;
    node.vertices = std::move(piece.polytope.vertices);
    node.triangles = std::move(piece.polytope.triangles);
    node.centre = piece.centre;
    node.radius = piece.radius;
    node.deviation_m = piece.deviation_m;
    node.level = level;
    return node;
  }

  int add_node(ConvexNode node, std::vector<int> covered, std::vector<Vec3> proxy) {
    const int id = static_cast<int>(hierarchy_.nodes.size());
    hierarchy_.nodes.push_back(std::move(node));
    proxy_.push_back(std::move(proxy));
    covered_.push_back(std::move(covered));
    neighbours_.emplace_back();
    is_alive_.push_back(true);
    ++alive_count_;
    return id;
  }

  // A piece with more than max_piece_vertices vertices (a leaf) enters
  // merges as its enclosing simplification (vertices), others as they are
  // (empty).
  std::vector<Vec3> merge_proxy(const ConvexPolytope& piece) const {
    if (static_cast<int>(piece.vertices.size()) <= settings_.max_piece_vertices) return {};
    return simplify_enclosing(piece, settings_.max_piece_vertices).vertices;
  }

  const std::vector<Vec3>& merge_points(int n) const {
    return proxy_[at(n)].empty() ? hierarchy_.nodes[at(n)].vertices : proxy_[at(n)];
  }

  // The merge of a and b ranked by its hull before simplification.
  Candidate evaluate(int a, int b) const {
    std::vector<Vec3> points = merge_points(a);
    const std::vector<Vec3>& more = merge_points(b);
    points.insert(points.end(), more.begin(), more.end());
    return Candidate{
        a, b, make_piece(convex_hull(points), mesh_, Patch{covered_[at(a)], covered_[at(b)]})};
  }

  // Pairs of the given nodes that are near in Morton order of their centres.
  std::vector<std::pair<int, int>> proximity_pairs(std::vector<int> nodes) const {
    Eigen::AlignedBox3d box;
    for (const int n : nodes) box.extend(hierarchy_.nodes[at(n)].centre);
    std::vector<std::pair<uint64_t, int>> order;
    for (const int n : nodes)
      order.emplace_back(morton_code(hierarchy_.nodes[at(n)].centre, box), n);
    std::sort(order.begin(), order.end());
    std::vector<std::pair<int, int>> pairs;
    for (std::size_t i = 0; i < order.size(); ++i)
      for (std::size_t j = i + 1; j < std::min(order.size(), i + 3); ++j)
        pairs.emplace_back(std::min(order[i].second, order[j].second),
                           std::max(order[i].second, order[j].second));
    return pairs;
  }

  // Greedy matching of the candidates, cheapest first, until the alive
  // count reaches target.
  void merge_candidates(const std::vector<std::pair<int, int>>& pairs, int level,
                        std::vector<bool>& merged, std::size_t target) {
    std::vector<Candidate> candidates;
    candidates.reserve(pairs.size());
    for (const auto& [a, b] : pairs) {
      check_build_stop();  // 50k triangles take minutes: a signal ends them
      candidates.push_back(evaluate(a, b));
    }
    std::vector<std::size_t> order(candidates.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
      const double cx = candidates[x].piece.cost(), cy = candidates[y].piece.cost();
      if (cx != cy) return cx < cy;
      return std::pair(candidates[x].a, candidates[x].b) <
             std::pair(candidates[y].a, candidates[y].b);
    });
    for (const std::size_t k : order) {
      if (alive_count_ <= target) break;
      Candidate& c = candidates[k];
      if (merged[at(c.a)] || merged[at(c.b)]) continue;
      check_build_stop();
      merge(c, level, merged);
      // Progress within the level, not only at its end.
      announce_build_progress(++merges_done_, merges_total_);
    }
  }

  void merge(Candidate& candidate, int level, std::vector<bool>& merged) {
    const int a = candidate.a, b = candidate.b;
    std::vector<int> covered = std::move(covered_[at(a)]);
    covered.insert(covered.end(), covered_[at(b)].begin(), covered_[at(b)].end());
    Piece piece = std::move(candidate.piece);
    if (static_cast<int>(piece.polytope.vertices.size()) > settings_.max_piece_vertices)
      piece = make_piece(simplify_enclosing(piece.polytope, settings_.max_piece_vertices), mesh_,
                         Patch{covered, {}});
    std::vector<Vec3> proxy = merge_proxy(piece.polytope);
    ConvexNode node = node_of(std::move(piece), level);
    node.children = {a, b};
    covered_[at(b)].clear();
    covered_[at(b)].shrink_to_fit();
    proxy_[at(a)].clear();
    proxy_[at(b)].clear();
    const int id = add_node(std::move(node), std::move(covered), std::move(proxy));
    merged.resize(at(id) + 1, false);
    merged[at(a)] = merged[at(b)] = merged[at(id)] = true;
    std::vector<int> around;
    for (const int child : {a, b})
      for (const int n : neighbours_[at(child)])
        if (n != a && n != b) around.push_back(n);
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    for (const int n : around) {
      auto& list = neighbours_[at(n)];
      list.erase(std::remove_if(list.begin(), list.end(), [&](int x) { return x == a || x == b; }),
                 list.end());
      list.insert(std::lower_bound(list.begin(), list.end(), id), id);
    }
    neighbours_[at(id)] = std::move(around);
    neighbours_[at(a)].clear();
    neighbours_[at(b)].clear();
    is_alive_[at(a)] = is_alive_[at(b)] = false;
    alive_count_ -= 2;
  }

  void merge_level(int level) {
    const std::size_t start = alive_.size();
    const std::size_t target = (start + 1) / 2;
    std::vector<bool> merged(hierarchy_.nodes.size(), false);
    std::vector<std::pair<int, int>> pairs;
    for (const int a : alive_)
      for (const int b : neighbours_[at(a)])
        if (a < b) pairs.emplace_back(a, b);
    merge_candidates(pairs, level, merged, target);
    if (alive_count_ > target &&
        static_cast<double>(alive_count_) > kStalledFraction * static_cast<double>(start)) {
      std::vector<int> waiting;
      for (const int n : alive_)
        if (!merged[at(n)]) waiting.push_back(n);
      merge_candidates(proximity_pairs(waiting), level, merged, target);
    }
  }

  const TriangleMesh& mesh_;
  const ConvexHierarchySettings& settings_;
  ConvexHierarchy hierarchy_;
  std::vector<int> alive_;      // nodes without a parent at the level's start
  std::vector<bool> is_alive_;  // per node: has no parent yet
  std::size_t alive_count_ = 0;
  std::size_t merges_done_ = 0, merges_total_ = 0;  // for progress
  std::vector<std::vector<int>> covered_;           // triangles under each alive node
  std::vector<std::vector<int>> neighbours_;        // alive nodes whose patches touch
  std::vector<std::vector<Vec3>> proxy_;            // see merge_proxy
};

}  // namespace

ConvexHierarchy build_convex_hierarchy(const TriangleMesh& mesh,
                                       const ConvexHierarchySettings& settings) {
  validate(mesh, settings);
  return HierarchyBuilder(mesh, settings).build();
}

}  // namespace hb
