// Bounding-sphere trees: every node's sphere holds every vertex of its
// triangles (checked in long double), leaves hold 1..4 triangles, every
// triangle is in exactly one leaf, and degenerate input still builds.
#include "algorithms/ccd/sphere_tree.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

namespace hb {
namespace {

/// The triangles under a node.
std::vector<int> triangles_under(const SphereTree& tree, int node) {
  std::vector<int> found, stack{node};
  while (!stack.empty()) {
    const SphereTreeNode& n = tree.nodes()[static_cast<std::size_t>(stack.back())];
    stack.pop_back();
    if (n.is_leaf()) {
      for (const int t : tree.leaf_triangles(n)) found.push_back(t);
    } else {
      stack.push_back(n.first);
      stack.push_back(n.first + 1);
    }
  }
  return found;
}

void check_tree(const std::vector<Vec3>& vertices,
                const std::vector<std::array<int, 3>>& triangles) {
  const SphereTree tree(vertices, triangles);
  REQUIRE_FALSE(tree.empty());
  std::vector<int> seen(triangles.size(), 0);
  for (std::size_t i = 0; i < tree.nodes().size(); ++i) {
    const SphereTreeNode& n = tree.nodes()[i];
    if (n.is_leaf()) {
      REQUIRE(n.count <= SphereTree::kMaxLeafTriangles);
      for (const int t : tree.leaf_triangles(n)) ++seen[static_cast<std::size_t>(t)];
    } else {
      REQUIRE(static_cast<std::size_t>(n.first) > i);
      REQUIRE(static_cast<std::size_t>(n.first) + 1 < tree.nodes().size());
    }
    // Every vertex of every triangle under the node is inside its sphere.
    for (const int t : triangles_under(tree, static_cast<int>(i)))
      for (const int v : triangles[static_cast<std::size_t>(t)]) {
        long double squared = 0;
        for (int k = 0; k < 3; ++k) {
          const long double d = static_cast<long double>(vertices[static_cast<std::size_t>(v)][k]) -
                                static_cast<long double>(n.centre[k]);
          squared += d * d;
        }
        REQUIRE(std::sqrt(squared) <= static_cast<long double>(n.radius));
      }
  }
  // Every triangle in exactly one leaf.
  for (const int s : seen) REQUIRE(s == 1);
  CHECK(triangles_under(tree, 0).size() == triangles.size());
  CHECK(tree.memory_bytes() > 0);
}

TEST_CASE("every node's sphere holds its triangles' vertices", "[sphere_tree]") {
  std::mt19937 rng(5);
  for (const double offset : {0.0, 1e3, -7.5}) {
    for (const double scale : {1e-3, 1.0, 200.0}) {
      std::uniform_real_distribution<double> coordinate(-scale, scale);
      std::vector<Vec3> vertices;
      for (int i = 0; i < 600; ++i)
        vertices.emplace_back(offset + coordinate(rng), coordinate(rng), offset + coordinate(rng));
      std::uniform_int_distribution<int> index(0, 599);
      std::vector<std::array<int, 3>> triangles;
      for (int i = 0; i < 1000; ++i) triangles.push_back({index(rng), index(rng), index(rng)});
      INFO("offset " << offset << " scale " << scale);
      check_tree(vertices, triangles);
    }
  }
}

TEST_CASE("degenerate input builds: one triangle, coincident centroids, no triangles",
          "[sphere_tree]") {
  const std::vector<Vec3> vertices{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  check_tree(vertices, {{0, 1, 2}});
  // The same triangle 37 times: every split has equal centroids.
  check_tree(vertices, std::vector<std::array<int, 3>>(37, {0, 1, 2}));
  // A single point as a triangle: radius zero is still an upper bound.
  const SphereTree point(vertices, std::vector<std::array<int, 3>>{{1, 1, 1}});
  CHECK(point.nodes()[0].radius >= 0);
  CHECK((point.nodes()[0].centre - vertices[1]).norm() == 0);
  CHECK(SphereTree(vertices, {}).empty());
}

}  // namespace
}  // namespace hb
