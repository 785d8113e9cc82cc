#include "algorithms/sensation_preserving/convex_decomposition.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <deque>
#include <numeric>
#include <utility>

namespace hb {

namespace {

// Triangles sharing an edge, as compressed rows: neighbours of t are
// neighbour[offset[t] .. offset[t + 1]).
struct EdgeAdjacency {
  std::vector<int> offset;
  std::vector<int> neighbour;
};

EdgeAdjacency edge_adjacency(const TriangleMesh& mesh) {
  struct EdgeUse {
    int low, high, triangle;
  };
  std::vector<EdgeUse> uses;
  uses.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int e = 0; e < 3; ++e) {
      const int a = tri[static_cast<std::size_t>(e)],
                b = tri[static_cast<std::size_t>((e + 1) % 3)];
      if (a == b) continue;
      uses.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t)});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.low, x.high, x.triangle) < std::tie(y.low, y.high, y.triangle);
  });
  std::vector<std::pair<int, int>> pairs;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].low == uses[i].low && uses[j].high == uses[i].high) ++j;
    for (std::size_t p = i; p < j; ++p)
      for (std::size_t q = i; q < j; ++q)
        if (uses[p].triangle != uses[q].triangle)
          pairs.emplace_back(uses[p].triangle, uses[q].triangle);
    i = j;
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  EdgeAdjacency adjacency;
  adjacency.offset.assign(mesh.triangles.size() + 1, 0);
  for (const auto& [t, u] : pairs) ++adjacency.offset[static_cast<std::size_t>(t) + 1];
  std::partial_sum(adjacency.offset.begin(), adjacency.offset.end(), adjacency.offset.begin());
  adjacency.neighbour.reserve(pairs.size());
  for (const auto& [t, u] : pairs) adjacency.neighbour.push_back(u);
  return adjacency;
}

}  // namespace

std::vector<std::vector<int>> convex_surface_patches(const TriangleMesh& mesh,
                                                     double tolerance_rad) {
  const std::size_t triangle_count = mesh.triangles.size();
  const double sin_tolerance = std::sin(tolerance_rad);
  const Eigen::AlignedBox3d bounds = mesh.bounds();
  const double rounding = 1e-12 * (bounds.isEmpty() ? 1.0 : bounds.diagonal().norm());

  std::vector<Vec3> normal(triangle_count), centroid(triangle_count);
  std::vector<double> area(triangle_count);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(tri[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(tri[2])];
    const Vec3 cross = (b - a).cross(c - a);
    area[t] = 0.5 * cross.norm();
    normal[t] = area[t] > 0 ? Vec3(cross / cross.norm()) : Vec3::Zero();
    centroid[t] = (a + b + c) / 3.0;
  }
  // Whether vertex v lies behind triangle t's plane within the tolerance.
  auto behind = [&](const Vec3& v, std::size_t t) {
    const Vec3 offset = v - centroid[t];
    return normal[t].dot(offset) <= sin_tolerance * offset.norm() + rounding;
  };

  const EdgeAdjacency adjacency = edge_adjacency(mesh);
  std::vector<int> seeds(triangle_count);
  std::iota(seeds.begin(), seeds.end(), 0);
  std::stable_sort(seeds.begin(), seeds.end(), [&](int x, int y) {
    return area[static_cast<std::size_t>(x)] > area[static_cast<std::size_t>(y)];
  });

  std::vector<int> patch_of(triangle_count, -1);
  std::vector<int> vertex_stamp(mesh.vertices.size(), -1);  // patch holding the vertex
  std::vector<int> tried_stamp(triangle_count, -1);         // patch that queued the triangle
  std::vector<std::vector<int>> patches;
  std::vector<int> patch_vertices;
  std::deque<int> queue;
  for (const int seed : seeds) {
    if (patch_of[static_cast<std::size_t>(seed)] >= 0) continue;
    const int id = static_cast<int>(patches.size());
    std::vector<int> faces;
    patch_vertices.clear();
    auto add = [&](int t) {
      patch_of[static_cast<std::size_t>(t)] = id;
      faces.push_back(t);
      for (const int v : mesh.triangles[static_cast<std::size_t>(t)]) {
        if (vertex_stamp[static_cast<std::size_t>(v)] == id) continue;
        vertex_stamp[static_cast<std::size_t>(v)] = id;
        patch_vertices.push_back(v);
      }
      for (int k = adjacency.offset[static_cast<std::size_t>(t)];
           k < adjacency.offset[static_cast<std::size_t>(t) + 1]; ++k) {
        const int u = adjacency.neighbour[static_cast<std::size_t>(k)];
        if (patch_of[static_cast<std::size_t>(u)] >= 0 ||
            tried_stamp[static_cast<std::size_t>(u)] == id)
          continue;
        tried_stamp[static_cast<std::size_t>(u)] = id;
        queue.push_back(u);
      }
    };
    // The patch stays convex with t: t's new vertices behind every patch
    // triangle, every patch vertex behind t. (A triangle rejected once
    // stays rejected: the patch only gains constraints.)
    auto keeps_convex = [&](int t) {
      const std::size_t ut = static_cast<std::size_t>(t);
      for (const int w : mesh.triangles[ut]) {
        if (vertex_stamp[static_cast<std::size_t>(w)] == id) continue;
        const Vec3& point = mesh.vertices[static_cast<std::size_t>(w)];
        for (const int f : faces)
          if (!behind(point, static_cast<std::size_t>(f))) return false;
      }
      for (const int v : patch_vertices)
        if (!behind(mesh.vertices[static_cast<std::size_t>(v)], ut)) return false;
      return true;
    };
    add(seed);
    while (!queue.empty()) {
      const int t = queue.front();
      queue.pop_front();
      if (patch_of[static_cast<std::size_t>(t)] >= 0) continue;
      if (keeps_convex(t)) add(t);
    }
    patches.push_back(std::move(faces));
  }
  return patches;
}

}  // namespace hb
