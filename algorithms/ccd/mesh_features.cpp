#include "algorithms/ccd/mesh_features.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "algorithms/ccd/ccd_settings.h"
#include "algorithms/ccd/interval.h"
#include "algorithms/core/build_progress.h"
#include "hapticbench/input_error.h"

namespace hb::ccd_detail {

namespace {

IntervalVec3 point_interval(const Vec3& v) {
  return {Interval(v.x()), Interval(v.y()), Interval(v.z())};
}

std::string number_text(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

/// Adds `id` to the first `count` of `ids` unless there, marking `bit` in
/// its mask; returns its index.
int add_distinct(int* ids, std::uint8_t* masks, int& count, int id, std::uint8_t bit) {
  for (int i = 0; i < count; ++i)
    if (ids[i] == id) {
      masks[i] = static_cast<std::uint8_t>(masks[i] | bit);
      return i;
    }
  ids[count] = id;
  masks[count] = bit;
  return count++;
}

LeafFeatures leaf_features(const MeshFeatures& mesh, std::span<const int> leaf) {
  LeafFeatures f;
  f.triangle_count = static_cast<int>(leaf.size());
  for (int k = 0; k < f.triangle_count; ++k) {
    const int t = leaf[static_cast<std::size_t>(k)];
    f.triangles[k] = t;
    const auto bit = static_cast<std::uint8_t>(1u << k);
    for (int c = 0; c < 3; ++c) {
      f.corner[k][c] = add_distinct(f.vertices, f.vertex_triangles, f.vertex_count,
                                    mesh.triangle(t)[static_cast<std::size_t>(c)], bit);
      add_distinct(f.edges, f.edge_triangles, f.edge_count,
                   mesh.triangle_edges[static_cast<std::size_t>(t)][static_cast<std::size_t>(c)],
                   bit);
    }
  }
  return f;
}

void check_input(const std::vector<Vec3>& vertices,
                 const std::vector<std::array<int, 3>>& triangles, const std::string& name) {
  for (std::size_t v = 0; v < vertices.size(); ++v)
    for (int k = 0; k < 3; ++k)
      if (!(std::abs(vertices[v][k]) <= kMaxCcdCoordinate))
        throw InputError("", name + " vertex " + std::to_string(v),
                         "expected finite coordinates of magnitude at most " +
                             number_text(kMaxCcdCoordinate) + " m, got " +
                             number_text(vertices[v][k]));
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (const int v : triangles[t])
      if (v < 0 || static_cast<std::size_t>(v) >= vertices.size())
        throw InputError("", name + " triangle " + std::to_string(t),
                         "vertex index " + std::to_string(v) + " out of range [0, " +
                             std::to_string(vertices.size()) + ")");
}

/// Unique edges: the 3n half-edges sorted by their undirected key.
void build_edges(MeshFeatures& mesh) {
  struct HalfEdge {
    int a, b, triangle, slot;
  };
  const std::size_t n = mesh.triangles.size();
  std::vector<HalfEdge> halves;
  halves.reserve(3 * n);
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.triangles[t][static_cast<std::size_t>(k)];
      const int b = mesh.triangles[t][static_cast<std::size_t>((k + 1) % 3)];
      halves.push_back({std::min(a, b), std::max(a, b), static_cast<int>(t), k});
    }
  std::sort(halves.begin(), halves.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.a != y.a ? x.a < y.a : (x.b != y.b ? x.b < y.b : x.triangle < y.triangle);
  });
  mesh.triangle_edges.resize(n);
  mesh.edge_faces.reserve(halves.size());
  for (std::size_t i = 0; i < halves.size(); ++i) {
    if (i == 0 || halves[i].a != halves[i - 1].a || halves[i].b != halves[i - 1].b) {
      mesh.edges.push_back({halves[i].a, halves[i].b});
      mesh.edge_face_begin.push_back(static_cast<int>(mesh.edge_faces.size()));
    }
    mesh.triangle_edges[static_cast<std::size_t>(halves[i].triangle)]
                       [static_cast<std::size_t>(halves[i].slot)] =
        static_cast<int>(mesh.edges.size()) - 1;
    mesh.edge_faces.push_back(halves[i].triangle);
  }
  mesh.edge_face_begin.push_back(static_cast<int>(mesh.edge_faces.size()));
}

void build_planes(MeshFeatures& mesh) {
  const std::size_t n = mesh.triangles.size();
  mesh.face_normals.resize(n);
  mesh.planes.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const Vec3 &a = mesh.vertex(mesh.triangles[t][0]), &b = mesh.vertex(mesh.triangles[t][1]),
               &c = mesh.vertex(mesh.triangles[t][2]);
    const Vec3 normal = (b - a).cross(c - a);
    const double length = normal.norm();
    mesh.face_normals[t] = length > 0 ? Vec3(normal / length) : Vec3::Zero();
    FacePlane& plane = mesh.planes[t];
    plane.normal = normal;
    plane.anchor = a;
    const IntervalVec3 n_box = point_interval(normal), a_box = point_interval(a);
    const Interval sb = dot(n_box, point_interval(b) - a_box);
    const Interval sc = dot(n_box, point_interval(c) - a_box);
    plane.lo = std::min({0.0, sb.lo, sc.lo});
    plane.hi = std::max({0.0, sb.hi, sc.hi});
  }
}

/// Leaves' features, and every node's slab. Each node's triangles are a
/// contiguous range of the tree's order (children follow their parent, the
/// first child's range first).
void build_node_data(MeshFeatures& mesh) {
  const auto& nodes = mesh.tree.nodes();
  const auto& order = mesh.tree.triangle_order();
  mesh.leaf_slot.assign(nodes.size(), -1);
  std::vector<std::array<int, 2>> ranges(nodes.size());
  for (std::size_t i = nodes.size(); i-- > 0;) {
    if (nodes[i].is_leaf()) {
      ranges[i] = {nodes[i].first, nodes[i].first + nodes[i].count};
    } else {
      const auto child = static_cast<std::size_t>(nodes[i].first);
      ranges[i] = {ranges[child][0], ranges[child + 1][1]};
    }
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (!nodes[i].is_leaf()) continue;
    mesh.leaf_slot[i] = static_cast<int>(mesh.leaves.size());
    mesh.leaves.push_back(leaf_features(mesh, mesh.tree.leaf_triangles(nodes[i])));
  }
  mesh.slabs.resize(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    Vec3 normal = Vec3::Zero();
    for (int k = ranges[i][0]; k < ranges[i][1]; ++k)
      normal += mesh.plane(order[static_cast<std::size_t>(k)]).normal;
    if (!(normal.norm() > 0)) continue;
    NodeSlab slab;
    slab.normal = normal.normalized();
    // Bounds of n · (v − c) with the stored n, exact up to outward rounding.
    const IntervalVec3 n = point_interval(slab.normal), c = point_interval(nodes[i].centre);
    slab.lo = std::numeric_limits<double>::infinity();
    slab.hi = -slab.lo;
    for (int k = ranges[i][0]; k < ranges[i][1]; ++k)
      for (const int v : mesh.triangle(order[static_cast<std::size_t>(k)])) {
        const Interval side = dot(n, point_interval(mesh.vertex(v)) - c);
        slab.lo = std::min(slab.lo, side.lo);
        slab.hi = std::max(slab.hi, side.hi);
      }
    if (slab.hi - slab.lo < 1.8 * nodes[i].radius) mesh.slabs[i] = slab;
  }
}

}  // namespace

Vec3 MeshFeatures::edge_normal_sum(int e) const {
  Vec3 sum = Vec3::Zero();
  for (int k = edge_face_begin[static_cast<std::size_t>(e)];
       k < edge_face_begin[static_cast<std::size_t>(e) + 1]; ++k)
    sum += face_normals[static_cast<std::size_t>(edge_faces[static_cast<std::size_t>(k)])];
  return sum;
}

std::size_t MeshFeatures::memory_bytes() const {
  return vertices.capacity() * sizeof(Vec3) + triangles.capacity() * sizeof(std::array<int, 3>) +
         edges.capacity() * sizeof(std::array<int, 2>) +
         triangle_edges.capacity() * sizeof(std::array<int, 3>) +
         (edge_face_begin.capacity() + edge_faces.capacity()) * sizeof(int) +
         face_normals.capacity() * sizeof(Vec3) + planes.capacity() * sizeof(FacePlane) +
         tree.memory_bytes() + slabs.capacity() * sizeof(NodeSlab) +
         leaf_slot.capacity() * sizeof(int) + leaves.capacity() * sizeof(LeafFeatures);
}

void check_mesh_features_input(const std::vector<Vec3>& vertices,
                               const std::vector<std::array<int, 3>>& triangles,
                               const std::string& name) {
  check_input(vertices, triangles, name);
}

MeshFeatures build_mesh_features(std::vector<Vec3> vertices,
                                 std::vector<std::array<int, 3>> triangles,
                                 const std::string& name) {
  check_input(vertices, triangles, name);
  MeshFeatures mesh;
  mesh.vertices = std::move(vertices);
  mesh.triangles = std::move(triangles);
  // Each stage takes well under a second on the largest meshes: a stop
  // request is honoured between them.
  build_edges(mesh);
  check_build_stop();
  build_planes(mesh);
  check_build_stop();
  mesh.tree = SphereTree(mesh.vertices, mesh.triangles);
  check_build_stop();
  build_node_data(mesh);
  return mesh;
}

}  // namespace hb::ccd_detail
