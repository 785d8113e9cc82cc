// MeshFeatures on disk: every part is an array of plain values, written in
// one payload (hapticbench/disk_cache.h adds key, length and checksum).
// The key holds the vertices' and triangles' bytes' hash and a hash of this
// folder's sources (HB_BUILDER_SOURCES_HASH, from CMake), so a structure
// built by other code or from other input never matches.
#include <cmath>
#include <cstring>
#include <optional>
#include <string_view>
#include <type_traits>
#include <vector>

#include "algorithms/ccd/mesh_features.h"
#include "algorithms/core/build_progress.h"
#include "algorithms/core/payload_bytes.h"
#include "hapticbench/cache_directory.h"
#include "hapticbench/content_hash.h"
#include "hapticbench/disk_cache.h"

namespace hb::ccd_detail {

namespace {

constexpr int kPayloadLayout = 1;  // bump when the payload's layout changes

// Each part is an array of plain numbers (doubles and ints in structs,
// Eigen's fixed-size vectors among them: byte-copyable though the trait
// says otherwise), so its bytes are its value.
template <class T>
std::string_view bytes_of(const std::vector<T>& values) {
  static_assert(std::is_standard_layout_v<T>);
  return {reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)};
}

std::string features_key(const std::vector<Vec3>& vertices,
                         const std::vector<std::array<int, 3>>& triangles) {
  return "mesh features layout " + std::to_string(kPayloadLayout) +
         "\nbuilder " HB_BUILDER_SOURCES_HASH "\nvertices " + std::to_string(vertices.size()) +
         " " + ContentHash().add(bytes_of(vertices)).hex() + "\ntriangles " +
         std::to_string(triangles.size()) + " " + ContentHash().add(bytes_of(triangles)).hex() +
         "\n";
}

std::string payload_of(const MeshFeatures& mesh) {
  PayloadWriter out;
  out.put_array(mesh.edges);
  out.put_array(mesh.triangle_edges);
  out.put_array(mesh.edge_face_begin);
  out.put_array(mesh.edge_faces);
  out.put_array(mesh.face_normals);
  out.put_array(mesh.planes);
  out.put_array(mesh.tree.nodes());
  out.put_array(mesh.tree.triangle_order());
  out.put_array(mesh.slabs);
  out.put_array(mesh.leaf_slot);
  out.put_array(mesh.leaves);
  return std::move(out.bytes());
}

// The stored parts around the given vertices and triangles, when they fit
// them (sizes and indices in range); the checksum has ruled out damage.
// A payload that passes its checksum is still untrusted input (the checksum
// can be recomputed by anyone): every index the queries follow is checked
// here, so that a crafted file is rebuilt instead of crashing a query or
// sending the tree search round a cycle. Children follow their parent
// (first > the node's index), so every descent ends, and every node but the
// root has exactly one parent, so that it is a tree: nodes sharing children
// (a DAG) would make a descent exponential in the depth.
bool valid_structure(const MeshFeatures& mesh, const std::vector<SphereTreeNode>& nodes,
                     const std::vector<int>& order, std::size_t n_vertices,
                     std::size_t n_triangles) {
  const auto in_range = [](long long value, std::size_t size) {
    return value >= 0 && static_cast<unsigned long long>(value) < size;
  };
  const std::size_t n_edges = mesh.edges.size();
  for (const auto& edge : mesh.edges)
    for (const int v : edge)
      if (!in_range(v, n_vertices)) return false;
  for (const auto& edges : mesh.triangle_edges)
    for (const int e : edges)
      if (!in_range(e, n_edges)) return false;
  if (mesh.edge_face_begin.front() != 0 ||
      mesh.edge_face_begin.back() != static_cast<long long>(mesh.edge_faces.size()))
    return false;
  for (std::size_t e = 0; e < n_edges; ++e)
    if (mesh.edge_face_begin[e] > mesh.edge_face_begin[e + 1]) return false;
  for (const int t : mesh.edge_faces)
    if (!in_range(t, n_triangles)) return false;
  std::vector<char> seen(n_triangles, 0);
  for (const int t : order) {
    if (!in_range(t, n_triangles) || seen[static_cast<std::size_t>(t)]) return false;
    seen[static_cast<std::size_t>(t)] = 1;
  }
  if (n_triangles > 0 && nodes.empty()) return false;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const SphereTreeNode& node = nodes[i];
    if (!node.centre.allFinite() || !std::isfinite(node.radius) || node.radius < 0) return false;
    if (node.count == 0) {  // inner: two children after it
      if (node.first <= static_cast<long long>(i) || !in_range(node.first + 1LL, nodes.size()) ||
          mesh.leaf_slot[i] != -1)
        return false;
    } else if (node.count < 0 || node.count > SphereTree::kMaxLeafTriangles || node.first < 0 ||
               static_cast<std::size_t>(node.first) + static_cast<std::size_t>(node.count) >
                   n_triangles ||
               !in_range(mesh.leaf_slot[i], mesh.leaves.size())) {
      return false;
    }
  }
  std::vector<unsigned char> parents(nodes.size(), 0);
  for (const SphereTreeNode& node : nodes)
    if (node.count == 0)
      for (const long long child : {static_cast<long long>(node.first), node.first + 1LL})
        if (++parents[static_cast<std::size_t>(child)] > 1) return false;
  for (std::size_t i = 1; i < nodes.size(); ++i)
    if (parents[i] != 1) return false;
  for (const LeafFeatures& leaf : mesh.leaves) {
    if (leaf.triangle_count < 1 || leaf.triangle_count > LeafFeatures::kMaxTriangles ||
        leaf.vertex_count < 0 || leaf.vertex_count > LeafFeatures::kMaxVertices ||
        leaf.edge_count < 0 || leaf.edge_count > LeafFeatures::kMaxVertices)
      return false;
    for (int k = 0; k < leaf.triangle_count; ++k) {
      if (!in_range(leaf.triangles[k], n_triangles)) return false;
      for (const int corner : leaf.corner[k])
        if (!in_range(corner, static_cast<std::size_t>(leaf.vertex_count))) return false;
    }
    for (int k = 0; k < leaf.vertex_count; ++k)
      if (!in_range(leaf.vertices[k], n_vertices)) return false;
    for (int k = 0; k < leaf.edge_count; ++k)
      if (!in_range(leaf.edges[k], n_edges)) return false;
  }
  return true;
}

std::optional<MeshFeatures> parse_payload(std::string_view payload, std::vector<Vec3>& vertices,
                                          std::vector<std::array<int, 3>>& triangles) {
  PayloadReader in(payload);
  MeshFeatures mesh;
  std::vector<SphereTreeNode> nodes;
  std::vector<int> order;
  if (!in.get_array(mesh.edges) || !in.get_array(mesh.triangle_edges) ||
      !in.get_array(mesh.edge_face_begin) || !in.get_array(mesh.edge_faces) ||
      !in.get_array(mesh.face_normals) || !in.get_array(mesh.planes) || !in.get_array(nodes) ||
      !in.get_array(order) || !in.get_array(mesh.slabs) || !in.get_array(mesh.leaf_slot) ||
      !in.get_array(mesh.leaves) || !in.at_end())
    return std::nullopt;
  const std::size_t n_triangles = triangles.size();
  if (mesh.triangle_edges.size() != n_triangles || mesh.planes.size() != n_triangles ||
      mesh.face_normals.size() != n_triangles || order.size() != n_triangles ||
      mesh.edge_face_begin.size() != mesh.edges.size() + 1 || mesh.slabs.size() != nodes.size() ||
      mesh.leaf_slot.size() != nodes.size())
    return std::nullopt;
  if (!valid_structure(mesh, nodes, order, vertices.size(), n_triangles)) return std::nullopt;
  mesh.vertices = std::move(vertices);
  mesh.triangles = std::move(triangles);
  mesh.tree = SphereTree(std::move(nodes), std::move(order));
  return mesh;
}

}  // namespace

MeshFeatures cached_mesh_features(std::vector<Vec3> vertices,
                                  std::vector<std::array<int, 3>> triangles,
                                  const std::string& name, bool* cache_hit) {
  if (cache_hit != nullptr) *cache_hit = false;
  check_mesh_features_input(vertices, triangles, name);
  const std::string key = features_key(vertices, triangles);
  const DiskCache cache(default_cache_directory(), "mesh_features");
  if (const DiskCache::Lookup lookup = cache.read(key); lookup.payload) {
    if (std::optional<MeshFeatures> cached = parse_payload(*lookup.payload, vertices, triangles)) {
      if (cache_hit != nullptr) *cache_hit = true;
      announce_cached_build("feature trees of " + name, true);
      return std::move(*cached);
    }
  }
  announce_cached_build("feature trees of " + name, false);
  MeshFeatures mesh = build_mesh_features(std::move(vertices), std::move(triangles), name);
  cache.write(key, payload_of(mesh));
  return mesh;
}

}  // namespace hb::ccd_detail
