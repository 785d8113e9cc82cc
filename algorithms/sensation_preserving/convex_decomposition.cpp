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

// Per triangle: unit normal (zero when degenerate), centroid (m), area (m²).
struct TriangleFrames {
  std::vector<Vec3> normal, centroid;
  std::vector<double> area;
};

TriangleFrames triangle_frames(const TriangleMesh& mesh) {
  const std::size_t triangle_count = mesh.triangles.size();
  TriangleFrames frames;
  frames.normal.resize(triangle_count);
  frames.centroid.resize(triangle_count);
  frames.area.resize(triangle_count);
  for (std::size_t t = 0; t < triangle_count; ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(tri[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(tri[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(tri[2])];
    const Vec3 cross = (b - a).cross(c - a);
    frames.area[t] = 0.5 * cross.norm();
    frames.normal[t] = frames.area[t] > 0 ? Vec3(cross / cross.norm()) : Vec3::Zero();
    frames.centroid[t] = (a + b + c) / 3.0;
  }
  return frames;
}

// What growing the patches shares: the mesh and its triangles' frames and
// adjacency, the convexity test's constants, and the marks left by the
// patches so far.
struct PatchGrowth {
  PatchGrowth(const TriangleMesh& mesh, const TriangleFrames& frames,
              const EdgeAdjacency& adjacency, double sin_tolerance, double rounding)
      : mesh(mesh),
        frames(frames),
        adjacency(adjacency),
        sin_tolerance(sin_tolerance),
        rounding(rounding),
        patch_of(mesh.triangles.size(), -1),
        vertex_stamp(mesh.vertices.size(), -1),
        tried_stamp(mesh.triangles.size(), -1) {}

  const TriangleMesh& mesh;
  const TriangleFrames& frames;
  const EdgeAdjacency& adjacency;
  double sin_tolerance;
  double rounding;                  // m
  std::vector<int> patch_of;        // patch holding the triangle, −1 while none
  std::vector<int> vertex_stamp;    // patch holding the vertex
  std::vector<int> tried_stamp;     // patch that queued the triangle
  std::vector<int> patch_vertices;  // vertices of the patch being grown
  std::deque<int> queue;            // triangles the patch being grown may take
};

// Whether vertex v (m) lies behind triangle t's plane within the tolerance.
bool behind(const PatchGrowth& g, const Vec3& v, std::size_t t) {
  const Vec3 offset = v - g.frames.centroid[t];
  return g.frames.normal[t].dot(offset) <= g.sin_tolerance * offset.norm() + g.rounding;
}

// Adds triangle t to patch `id` (whose triangles are `faces`) and queues its
// edge neighbours that no patch holds and this one has not queued.
void add_to_patch(PatchGrowth& g, int id, int t, std::vector<int>& faces) {
  g.patch_of[static_cast<std::size_t>(t)] = id;
  faces.push_back(t);
  for (const int v : g.mesh.triangles[static_cast<std::size_t>(t)]) {
    if (g.vertex_stamp[static_cast<std::size_t>(v)] == id) continue;
    g.vertex_stamp[static_cast<std::size_t>(v)] = id;
    g.patch_vertices.push_back(v);
  }
  for (int k = g.adjacency.offset[static_cast<std::size_t>(t)];
       k < g.adjacency.offset[static_cast<std::size_t>(t) + 1]; ++k) {
    const int u = g.adjacency.neighbour[static_cast<std::size_t>(k)];
    if (g.patch_of[static_cast<std::size_t>(u)] >= 0 ||
        g.tried_stamp[static_cast<std::size_t>(u)] == id)
      continue;
    g.tried_stamp[static_cast<std::size_t>(u)] = id;
    g.queue.push_back(u);
  }
}

// Whether patch `id` (triangles `faces`) stays convex with t: t's new
// vertices behind every patch triangle, every patch vertex behind t. (A
// triangle rejected once stays rejected: the patch only gains constraints.)
bool keeps_convex(const PatchGrowth& g, int id, int t, const std::vector<int>& faces) {
  const std::size_t ut = static_cast<std::size_t>(t);
  for (const int w : g.mesh.triangles[ut]) {
    if (g.vertex_stamp[static_cast<std::size_t>(w)] == id) continue;
    const Vec3& point = g.mesh.vertices[static_cast<std::size_t>(w)];
    for (const int f : faces)
      if (!behind(g, point, static_cast<std::size_t>(f))) return false;
  }
  for (const int v : g.patch_vertices)
    if (!behind(g, g.mesh.vertices[static_cast<std::size_t>(v)], ut)) return false;
  return true;
}

// Grows patch `id` breadth-first across shared edges from `seed`; returns
// its triangles in the order they joined.
std::vector<int> grow_patch(PatchGrowth& g, int id, int seed) {
  std::vector<int> faces;
  g.patch_vertices.clear();
  add_to_patch(g, id, seed, faces);
  while (!g.queue.empty()) {
    const int t = g.queue.front();
    g.queue.pop_front();
    if (g.patch_of[static_cast<std::size_t>(t)] >= 0) continue;
    if (keeps_convex(g, id, t, faces)) add_to_patch(g, id, t, faces);
  }
  return faces;
}

}  // namespace

std::vector<std::vector<int>> convex_surface_patches(const TriangleMesh& mesh,
                                                     double tolerance_rad) {
  const std::size_t triangle_count = mesh.triangles.size();
  const Eigen::AlignedBox3d bounds = mesh.bounds();
  const TriangleFrames frames = triangle_frames(mesh);
  const EdgeAdjacency adjacency = edge_adjacency(mesh);
  std::vector<int> seeds(triangle_count);
  std::iota(seeds.begin(), seeds.end(), 0);
  std::stable_sort(seeds.begin(), seeds.end(), [&](int x, int y) {
    return frames.area[static_cast<std::size_t>(x)] > frames.area[static_cast<std::size_t>(y)];
  });

  PatchGrowth growth(mesh, frames, adjacency, std::sin(tolerance_rad),
                     1e-12 * (bounds.isEmpty() ? 1.0 : bounds.diagonal().norm()));
  std::vector<std::vector<int>> patches;
  for (const int seed : seeds) {
    if (growth.patch_of[static_cast<std::size_t>(seed)] >= 0) continue;
    const int id = static_cast<int>(patches.size());
    patches.push_back(grow_patch(growth, id, seed));
  }
  return patches;
}

}  // namespace hb
