// The convex hierarchy of sensation-preserving simplification (algorithms/
// sensation_preserving/convex_hierarchy.cpp and its helpers) against ground
// truth: pieces convex and enclosing by plane tests on every vertex, leaf
// patches partitioning the triangles, bounding spheres checked in long
// double, surface deviations against CGAL's AABB-tree distances from points
// sampled on the patches, closed forms for a box and a sphere, and the
// on-disk cache. Units m.
#include "algorithms/sensation_preserving/convex_hierarchy.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <stdlib.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "algorithms/sensation_preserving/convex_hull.h"
#include "algorithms/sensation_preserving/hull_simplification.h"
#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"
#include "harness/mesh_io/mesh_io.h"
#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

std::size_t at(int i) { return static_cast<std::size_t>(i); }
Point point(const Vec3& v) { return Point(v.x(), v.y(), v.z()); }

/// CGAL's distance from points to a triangle surface (AABB tree).
class SurfaceDistance {
 public:
  SurfaceDistance(const std::vector<Vec3>& vertices,
                  const std::vector<std::array<int, 3>>& triangles) {
    for (const auto& t : triangles) {
      Triangle triangle(point(vertices[at(t[0])]), point(vertices[at(t[1])]),
                        point(vertices[at(t[2])]));
      if (!triangle.is_degenerate()) triangles_.push_back(triangle);
    }
    tree_.insert(triangles_.begin(), triangles_.end());
    tree_.accelerate_distance_queries();
  }
  bool empty() const { return triangles_.empty(); }
  double operator()(const Vec3& p) const { return std::sqrt(tree_.squared_distance(point(p))); }

 private:
  std::vector<Triangle> triangles_;
  Tree tree_;
};

/// Largest height (m) of any of `points` above any face plane of the piece
/// (≤ 0: all inside or on it).
double largest_height(const std::vector<Vec3>& vertices,
                      const std::vector<std::array<int, 3>>& triangles,
                      const std::vector<Vec3>& points) {
  double worst = -std::numeric_limits<double>::infinity();
  for (const auto& t : triangles) {
    const Vec3& a = vertices[at(t[0])];
    const Vec3 cross = (vertices[at(t[1])] - a).cross(vertices[at(t[2])] - a);
    if (!(cross.norm() > 0)) continue;
    const Vec3 n = cross.normalized();
    for (const Vec3& p : points) worst = std::max(worst, n.dot(p - a));
  }
  return worst;
}

/// All vertices within tolerance of the plane of the first non-degenerate face.
bool is_flat(const ConvexNode& node, double tolerance) {
  for (const auto& t : node.triangles) {
    const Vec3& a = node.vertices[at(t[0])];
    const Vec3 cross = (node.vertices[at(t[1])] - a).cross(node.vertices[at(t[2])] - a);
    if (!(cross.norm() > 0)) continue;
    const Vec3 n = cross.normalized();
    for (const Vec3& v : node.vertices)
      if (std::abs(n.dot(v - a)) > tolerance) return false;
    return true;
  }
  return true;
}

/// The original triangles under a node (from its leaves).
std::vector<int> faces_under(const ConvexHierarchy& h, int node) {
  std::vector<int> found, stack{node};
  while (!stack.empty()) {
    const ConvexNode& n = h.nodes[at(stack.back())];
    stack.pop_back();
    if (n.children[0] < 0) {
      found.insert(found.end(), n.faces.begin(), n.faces.end());
    } else {
      stack.push_back(n.children[0]);
      stack.push_back(n.children[1]);
    }
  }
  return found;
}

std::vector<Vec3> patch_vertices(const TriangleMesh& mesh, const std::vector<int>& faces) {
  std::vector<Vec3> points;
  for (const int f : faces)
    for (const int v : mesh.triangles[at(f)]) points.push_back(mesh.vertices[at(v)]);
  return points;
}

std::vector<int> parents_of(const ConvexHierarchy& h) {
  std::vector<int> parent(h.nodes.size(), -1);
  for (std::size_t n = 0; n < h.nodes.size(); ++n)
    for (const int c : h.nodes[n].children)
      if (c >= 0) parent[at(c)] = static_cast<int>(n);
  return parent;
}

double mesh_size(const TriangleMesh& mesh) { return mesh.bounds().diagonal().norm(); }

/// Everything the hierarchy promises, checked on a mesh. Returns, per
/// non-leaf node, the largest sampled patch-to-piece distance.
std::vector<std::pair<double, double>> check_hierarchy(const TriangleMesh& mesh,
                                                       const ConvexHierarchy& h,
                                                       const ConvexHierarchySettings& settings) {
  const double tolerance = 1e-9 * mesh_size(mesh);
  REQUIRE(!h.nodes.empty());
  REQUIRE(h.root == static_cast<int>(h.nodes.size()) - 1);
  const std::vector<int> parent = parents_of(h);

  // Leaf patches partition the triangles; the root covers all of them.
  std::vector<int> seen(mesh.triangles.size(), 0);
  for (const ConvexNode& node : h.nodes) {
    if (node.children[0] >= 0) {
      CHECK(node.faces.empty());
      continue;
    }
    CHECK(node.level == 0);
    for (const int f : node.faces) ++seen[at(f)];
  }
  for (const int s : seen) REQUIRE(s == 1);
  std::vector<int> under_root = faces_under(h, h.root);
  std::sort(under_root.begin(), under_root.end());
  std::vector<int> all(mesh.triangles.size());
  std::iota(all.begin(), all.end(), 0);
  CHECK(under_root == all);
  CHECK(parent[at(h.root)] == -1);
  for (std::size_t n = 0; n + 1 < h.nodes.size(); ++n) REQUIRE(parent[n] >= 0);

  std::vector<std::pair<double, double>> deviations;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0, 1);
  for (std::size_t n = 0; n < h.nodes.size(); ++n) {
    const ConvexNode& node = h.nodes[n];
    INFO("node " << n << " level " << node.level << ", " << node.vertices.size() << " vertices");
    // Convex: every vertex on or behind every face plane.
    CHECK(largest_height(node.vertices, node.triangles, node.vertices) <= tolerance);
    const std::vector<int> faces = faces_under(h, static_cast<int>(n));
    const std::vector<Vec3> patch = patch_vertices(mesh, faces);
    // The piece encloses its patch and its children's pieces.
    const bool flat = is_flat(node, tolerance);
    const SurfaceDistance to_piece(node.vertices, node.triangles);
    auto check_inside = [&](const std::vector<Vec3>& points) {
      if (node.triangles.empty()) return;
      CHECK(largest_height(node.vertices, node.triangles, points) <= tolerance);
      if (flat)
        for (const Vec3& p : points) REQUIRE(to_piece(p) <= tolerance);
    };
    check_inside(patch);
    if (node.children[0] >= 0) {
      REQUIRE(static_cast<int>(node.vertices.size()) <= settings.max_piece_vertices);
      for (const int c : node.children) {
        REQUIRE(c < static_cast<int>(n));
        CHECK(h.nodes[at(c)].level < node.level);
        check_inside(h.nodes[at(c)].vertices);
      }
    }
    // The bounding sphere holds the piece and the patch (long double).
    for (const auto* points : {&node.vertices, &patch})
      for (const Vec3& p : *points) {
        long double squared = 0;
        for (int k = 0; k < 3; ++k) {
          const long double d =
              static_cast<long double>(p[k]) - static_cast<long double>(node.centre[k]);
          squared += d * d;
        }
        REQUIRE(std::sqrt(squared) <= static_cast<long double>(node.radius));
      }
    // Deviation: CGAL's distance from points on the patch to the piece's
    // surface never exceeds it.
    if (to_piece.empty()) continue;
    double sampled = 0;
    for (const int f : faces) {
      const auto& t = mesh.triangles[at(f)];
      const Vec3& a = mesh.vertices[at(t[0])];
      const Vec3& b = mesh.vertices[at(t[1])];
      const Vec3& c = mesh.vertices[at(t[2])];
      std::vector<Vec3> samples{a, b, c, (a + b + c) / 3, (a + b) / 2, (b + c) / 2, (c + a) / 2};
      for (int k = 0; k < 3; ++k) {
        double u = unit(random), v = unit(random);
        if (u + v > 1) u = 1 - u, v = 1 - v;
        samples.push_back(a + u * (b - a) + v * (c - a));
      }
      for (const Vec3& p : samples) sampled = std::max(sampled, to_piece(p));
    }
    REQUIRE(sampled <= node.deviation_m + tolerance);
    if (node.children[0] >= 0) deviations.emplace_back(sampled, node.deviation_m);
  }

  // Levels: each is the set of nodes with level ≤ l whose parent has level
  // > l; its size is pieces_per_level[l]; each level halves the previous
  // one or comes close.
  const auto& counts = h.pieces_per_level;
  REQUIRE(!counts.empty());
  CHECK(counts.back() == 1);
  for (std::size_t l = 0; l < counts.size(); ++l) {
    int cut = 0;
    for (std::size_t n = 0; n < h.nodes.size(); ++n)
      if (h.nodes[n].level <= static_cast<int>(l) &&
          (parent[n] < 0 || h.nodes[at(parent[n])].level > static_cast<int>(l)))
        ++cut;
    CHECK(cut == counts[l]);
    if (l == 0) continue;
    CHECK(counts[l] >= (counts[l - 1] + 1) / 2);
    CHECK(counts[l] <= 0.75 * counts[l - 1] + 1);
  }
  return deviations;
}

TriangleMesh model(const std::string& name, double scale) {
  const std::string path = std::string(HAPTICBENCH_SOURCE_DIR) + "/models/" + name;
  if (!std::filesystem::exists(path))
    FAIL(path << " is missing: run scripts/extract-models (CMake's configure step runs it)");
  return read_mesh_file(path, scale);
}

TEST_CASE("a box is one convex patch: one leaf, its hull the box", "[sensation_preserving]") {
  Shape box;
  box.type = ShapeType::kBox;
  box.size = Vec3(0.04, 0.02, 0.03);
  const TriangleMesh mesh = shape_mesh(box);
  const ConvexHierarchySettings settings;
  const ConvexHierarchy h = build_convex_hierarchy(mesh, settings);
  check_hierarchy(mesh, h, settings);
  REQUIRE(h.nodes.size() == 1);
  CHECK(h.root == 0);
  CHECK(h.pieces_per_level == std::vector<int>{1});
  CHECK(h.nodes[0].faces.size() == mesh.triangles.size());
  CHECK(h.nodes[0].vertices.size() == 8);
  CHECK(h.nodes[0].deviation_m <= 1e-12);  // rounding allowance only
  // The sphere holds the corners: radius at least the half diagonal.
  CHECK(h.nodes[0].radius >= 0.5 * box.size.norm() * (1 - 1e-12));
}

TEST_CASE("an icosphere is one convex patch", "[sensation_preserving]") {
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = 0.05;
  sphere.subdivisions = 3;
  const TriangleMesh mesh = shape_mesh(sphere);
  const ConvexHierarchySettings settings;
  const ConvexHierarchy h = build_convex_hierarchy(mesh, settings);
  check_hierarchy(mesh, h, settings);
  REQUIRE(h.nodes.size() == 1);
  CHECK(h.nodes[0].vertices.size() == mesh.vertices.size());
  CHECK(h.nodes[0].deviation_m <= 1e-12);
  CHECK(h.nodes[0].radius == Approx(0.05).epsilon(1e-9));
}

TEST_CASE("a box with a through-hole: concave edges split patches, the root covers all",
          "[sensation_preserving]") {
  Shape shape;
  shape.type = ShapeType::kBoxWithHole;
  shape.size = Vec3(0.1, 0.1, 0.04);
  shape.hole_size = Vec3(0.04, 0.03, 0);
  const TriangleMesh mesh = shape_mesh(shape);
  const ConvexHierarchySettings settings;
  const ConvexHierarchy h = build_convex_hierarchy(mesh, settings);
  check_hierarchy(mesh, h, settings);
  CHECK(h.pieces_per_level.front() > 1);
  // The root is the block's hull: its 8 corners, and no vertex off the
  // block's faces (the hull also keeps the hole's rims, which lie in the top
  // and bottom faces: redundant, not wrong). The hole's walls at mid-height
  // are 2 cm from the top and bottom faces and farther from the sides.
  const ConvexNode& root = h.nodes[at(h.root)];
  int corners = 0;
  for (const Vec3& v : root.vertices) {
    const Vec3 on_face = v.cwiseAbs() - Vec3(0.05, 0.05, 0.02);
    CHECK(on_face.maxCoeff() == Approx(0).margin(1e-12));
    if (on_face.cwiseAbs().maxCoeff() <= 1e-12) ++corners;
  }
  CHECK(corners == 8);
  CHECK(root.deviation_m >= 0.02 - 1e-12);
}

TEST_CASE("separate boxes merge into one root that encloses both", "[sensation_preserving]") {
  Shape box;
  box.type = ShapeType::kBox;
  box.size = Vec3(0.02, 0.02, 0.02);
  TriangleMesh mesh = shape_mesh(box);
  const TriangleMesh other = transformed(mesh, Pose{Vec3(0.1, 0.03, 0), Quat::Identity()});
  const int offset = static_cast<int>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (auto t : other.triangles)
    mesh.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const ConvexHierarchySettings settings;
  const ConvexHierarchy h = build_convex_hierarchy(mesh, settings);
  check_hierarchy(mesh, h, settings);
  CHECK(h.pieces_per_level == std::vector<int>{2, 1});
  CHECK(h.nodes.size() == 3);
}

TEST_CASE("knot: convex pieces, enclosing parents, deviations bound CGAL's distances",
          "[sensation_preserving]") {
  const TriangleMesh mesh = model("knot1.off", 0.05);
  for (const int max_vertices : {32, 12}) {
    ConvexHierarchySettings settings;
    settings.max_piece_vertices = max_vertices;
    const ConvexHierarchy h = build_convex_hierarchy(mesh, settings);
    INFO("max_piece_vertices " << max_vertices);
    const auto deviations = check_hierarchy(mesh, h, settings);
    CHECK(h.pieces_per_level.front() > 100);
    CHECK(h.pieces_per_level.size() >= 8);
    // The bound is not vacuous: within 1.5 times the largest sampled
    // distance for nearly all merged nodes, within 3 times for all.
    int tight = 0;
    const double slack = 1e-9 * mesh_size(mesh);
    for (const auto& [sampled, bound] : deviations) {
      if (bound <= 1.5 * sampled + slack) ++tight;
      CHECK(bound <= 3 * sampled + slack);
    }
    CHECK(tight >= 0.95 * static_cast<double>(deviations.size()));
    // Coarser levels deviate more: the root more than the median leaf.
    CHECK(h.nodes[at(h.root)].deviation_m > 0.01 * mesh_size(mesh));
  }
}

TEST_CASE("hull simplification stays convex, encloses, and reaches the vertex budget",
          "[sensation_preserving]") {
  std::mt19937 random(3);
  std::normal_distribution<double> normal(0, 1);
  std::vector<Vec3> points;
  for (int i = 0; i < 300; ++i) {
    const Vec3 d = Vec3(normal(random), normal(random), normal(random)).normalized();
    points.push_back(Vec3(0.03 * d.x(), 0.01 * d.y() + 0.2, 0.02 * d.z()));
  }
  const ConvexPolytope hull = convex_hull(points);
  REQUIRE(hull.dimension == 3);
  REQUIRE(hull.vertices.size() == points.size());  // all on an ellipsoid
  CHECK(hull.triangles.size() == 2 * hull.vertices.size() - 4);
  CHECK(largest_height(hull.vertices, hull.triangles, points) <= 1e-15);
  for (const int budget : {64, 16, 6}) {
    const ConvexPolytope simple = simplify_enclosing(hull, budget);
    INFO("budget " << budget);
    CHECK(static_cast<int>(simple.vertices.size()) <= budget);
    CHECK(simple.triangles.size() == 2 * simple.vertices.size() - 4);
    CHECK(largest_height(simple.vertices, simple.triangles, simple.vertices) <= 1e-14);
    CHECK(largest_height(simple.vertices, simple.triangles, points) <= 1e-14);
  }

  // A flat polygon: exactly coplanar points in the tilted plane x = y.
  const Vec3 u = Vec3(1, 1, 0).normalized(), v(0, 0, 1);
  std::vector<Vec3> flat;
  for (int i = 0; i < 40; ++i) {
    const double angle = 2 * std::numbers::pi * i / 40;
    const double s = 0.1 + 0.02 * std::cos(angle);
    flat.push_back(Vec3(s, s, 0.01 * std::sin(angle)));
  }
  const ConvexPolytope polygon = convex_hull(flat);
  REQUIRE(polygon.dimension == 2);
  CHECK(polygon.vertices.size() == 40);
  const ConvexPolytope simple_polygon = simplify_enclosing(polygon, 8);
  CHECK(simple_polygon.vertices.size() == 8);
  CHECK(largest_height(simple_polygon.vertices, simple_polygon.triangles, flat) <= 1e-15);
  // In-plane: every point inside the polygon (left of every edge).
  const Vec3 n = u.cross(v);
  const auto& p = simple_polygon.vertices;
  const double turn = (p[1] - p[0]).cross(p[2] - p[1]).dot(n) > 0 ? 1.0 : -1.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 edge = p[(i + 1) % p.size()] - p[i];
    for (std::size_t k = 0; k < p.size(); ++k)
      CHECK(turn * edge.cross(p[k] - p[i]).dot(n) >= -1e-15);
    for (const Vec3& q : flat) CHECK(turn * edge.cross(q - p[i]).dot(n) >= -1e-15);
  }

  // Lower dimensions.
  CHECK(convex_hull(std::vector<Vec3>{Vec3(1, 2, 3), Vec3(1, 2, 3)}).dimension == 0);
  const ConvexPolytope segment =
      convex_hull(std::vector<Vec3>{Vec3(0, 0, 0), Vec3(2, 2, 2), Vec3(1, 1, 1), Vec3(-1, -1, -1)});
  CHECK(segment.dimension == 1);
  CHECK(segment.vertices.size() == 2);
  CHECK(segment.triangles.empty());
  CHECK(convex_hull(std::vector<Vec3>{}).dimension == -1);
}

TEST_CASE("the second call loads the cache, a damaged cache file is rebuilt",
          "[sensation_preserving]") {
  test::ScratchDir dir("convex_hierarchy_cache");
  ::setenv("HAPTICBENCH_CACHE_DIR", dir.path().c_str(), 1);
  Shape shape;
  shape.type = ShapeType::kBoxWithHole;
  shape.size = Vec3(0.1, 0.1, 0.04);
  shape.hole_size = Vec3(0.04, 0.03, 0);
  const TriangleMesh mesh = shape_mesh(shape);
  const ConvexHierarchySettings settings;
  const ConvexHierarchy built = build_convex_hierarchy(mesh, settings);
  auto same = [&](const ConvexHierarchy& h) {
    REQUIRE(h.nodes.size() == built.nodes.size());
    CHECK(h.root == built.root);
    CHECK(h.pieces_per_level == built.pieces_per_level);
    for (std::size_t n = 0; n < h.nodes.size(); ++n) {
      const ConvexNode& a = h.nodes[n];
      const ConvexNode& b = built.nodes[n];
      REQUIRE(a.vertices == b.vertices);
      REQUIRE(a.triangles == b.triangles);
      REQUIRE(a.centre == b.centre);
      REQUIRE(a.radius == b.radius);
      REQUIRE(a.deviation_m == b.deviation_m);
      REQUIRE(a.level == b.level);
      REQUIRE(a.children == b.children);
      REQUIRE(a.faces == b.faces);
    }
  };
  auto cache_files = [&] {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
      files.push_back(entry.path());
    return files;
  };

  bool hit = true;
  const ConvexHierarchy first = cached_convex_hierarchy(mesh, "box with hole", settings, &hit);
  CHECK_FALSE(hit);
  same(first);
  CHECK_FALSE(first.key.empty());
  REQUIRE(cache_files().size() == 1);  // no temporary left behind
  const std::filesystem::path file = cache_files().front();
  const ConvexHierarchy second = cached_convex_hierarchy(mesh, "box with hole", settings, &hit);
  CHECK(hit);
  same(second);
  CHECK(second.key == first.key);

  // Other settings, content hash or geometry: another key, built afresh.
  ConvexHierarchySettings other = settings;
  other.max_piece_vertices = 8;
  cached_convex_hierarchy(mesh, "box with hole", other, &hit);
  CHECK_FALSE(hit);
  cached_convex_hierarchy(mesh, "another hash", settings, &hit);
  CHECK_FALSE(hit);
  TriangleMesh moved = mesh;
  moved.vertices[0].x() += 1e-6;
  cached_convex_hierarchy(moved, "box with hole", settings, &hit);
  CHECK_FALSE(hit);

  // A flipped byte in the payload: rebuilt (to the same hierarchy), then
  // written again.
  const auto size = std::filesystem::file_size(file);
  {
    std::fstream io(file, std::ios::binary | std::ios::in | std::ios::out);
    io.seekg(static_cast<std::streamoff>(size - 20));
    char byte = 0;
    io.read(&byte, 1);
    byte = static_cast<char>(byte ^ 0x10);
    io.seekp(static_cast<std::streamoff>(size - 20));
    io.write(&byte, 1);
  }
  same(cached_convex_hierarchy(mesh, "box with hole", settings, &hit));
  CHECK_FALSE(hit);
  cached_convex_hierarchy(mesh, "box with hole", settings, &hit);
  CHECK(hit);
  // Truncated, and garbage: the same.
  std::filesystem::resize_file(file, size / 2);
  same(cached_convex_hierarchy(mesh, "box with hole", settings, &hit));
  CHECK_FALSE(hit);
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out << "not a cache file";
  }
  same(cached_convex_hierarchy(mesh, "box with hole", settings, &hit));
  CHECK_FALSE(hit);
  CHECK(std::filesystem::file_size(file) == size);
  ::unsetenv("HAPTICBENCH_CACHE_DIR");
}

TEST_CASE("bad meshes and settings are input errors", "[sensation_preserving]") {
  const ConvexHierarchySettings settings;
  CHECK_THROWS_AS(build_convex_hierarchy(TriangleMesh{}, settings), InputError);
  Shape box;
  box.type = ShapeType::kBox;
  box.size = Vec3(0.02, 0.02, 0.02);
  TriangleMesh mesh = shape_mesh(box);
  ConvexHierarchySettings few = settings;
  few.max_piece_vertices = 3;
  CHECK_THROWS_AS(build_convex_hierarchy(mesh, few), InputError);
  ConvexHierarchySettings folded = settings;
  folded.convexity_tolerance_rad = -0.1;
  CHECK_THROWS_AS(build_convex_hierarchy(mesh, folded), InputError);
  TriangleMesh out_of_range = mesh;
  out_of_range.triangles[3][1] = 99;
  CHECK_THROWS_AS(build_convex_hierarchy(out_of_range, settings), InputError);
  mesh.vertices[2].y() = std::nan("");
  try {
    build_convex_hierarchy(mesh, settings);
    FAIL("no InputError");
  } catch (const InputError& e) {
    CHECK(e.location() == "vertex 2");
  }
}

}  // namespace
}  // namespace hb
