// The on-disk cache of convex hierarchies, in the shared disk cache
// (hapticbench/disk_cache.h, kind "convex_hierarchy"). The payload, in
// native byte order, lists the root, the pieces per level and every node.
// The key spells out the caller's content hash, a hash of the mesh's
// coordinates and triangles as stored, and the exact settings. A file whose
// header, key, length, checksum or structure does not match is rebuilt.
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <vector>

#include "algorithms/core/build_progress.h"
#include "algorithms/core/payload_bytes.h"
#include "algorithms/sensation_preserving/convex_hierarchy.h"
#include "hapticbench/cache_directory.h"
#include "hapticbench/content_hash.h"
#include "hapticbench/disk_cache.h"

namespace hb {

namespace {

// Bump when the payload's layout changes; how the hierarchy is built is in
// the key through HB_BUILDER_SOURCES_HASH (a hash of this folder's sources,
// set by CMake).
constexpr uint32_t kFormatVersion = 1;

std::string hierarchy_key(const TriangleMesh& mesh, const std::string& content_hash,
                          const ConvexHierarchySettings& settings) {
  return "convex hierarchy format " + std::to_string(kFormatVersion) +
         "\nbuilder " HB_BUILDER_SOURCES_HASH "\ncontent " + content_hash + "\nmesh " +
         mesh_geometry_hash(mesh) + " " + std::to_string(mesh.vertices.size()) + " " +
         std::to_string(mesh.triangles.size()) + "\nconvexity_tolerance_rad " +
         exact_key_text(settings.convexity_tolerance_rad) + "\nmax_piece_vertices " +
         std::to_string(settings.max_piece_vertices) + "\n";
}

std::string payload_of(const ConvexHierarchy& hierarchy) {
  PayloadWriter out;
  out.put(static_cast<int32_t>(hierarchy.root));
  out.put_array(hierarchy.pieces_per_level);
  out.put(static_cast<uint64_t>(hierarchy.nodes.size()));
  for (const ConvexNode& node : hierarchy.nodes) {
    out.put_array(node.vertices);
    out.put_array(node.triangles);
    out.put(node.centre);
    out.put(node.radius);
    out.put(node.deviation_m);
    out.put(static_cast<int32_t>(node.level));
    out.put(node.children);
    out.put_array(node.faces);
  }
  return std::move(out.bytes());
}

// The hierarchy in a payload, if it is complete and consistent with a mesh
// of triangle_count triangles.
std::optional<ConvexHierarchy> parse_payload(std::string_view payload, std::size_t triangle_count) {
  PayloadReader in(payload);
  ConvexHierarchy hierarchy;
  int32_t root = -1;
  uint64_t node_count = 0;
  if (!in.get(root) || !in.get_array(hierarchy.pieces_per_level) || !in.get(node_count))
    return std::nullopt;
  // A node takes at least its fixed fields and three array counts: the
  // count is bounded by what the bytes can hold, and nodes are added as
  // they are read, so that memory follows the payload's real size (a
  // crafted count once cost 128 times the file's size up front).
  constexpr std::size_t kMinNodeBytes = 3 * sizeof(uint64_t) + sizeof(Vec3) + 2 * sizeof(double) +
                                        sizeof(int32_t) + sizeof(ConvexNode::children);
  if (node_count == 0 || node_count > in.remaining() / kMinNodeBytes || root < 0 ||
      static_cast<uint64_t>(root) >= node_count)
    return std::nullopt;
  hierarchy.root = root;
  hierarchy.nodes.reserve(static_cast<std::size_t>(node_count));
  // Every node but the root must be the child of exactly one node: a tree.
  // Nodes sharing children (a DAG) would make a descent exponential.
  std::vector<unsigned char> parents(static_cast<std::size_t>(node_count), 0);
  for (std::size_t n = 0; n < static_cast<std::size_t>(node_count); ++n) {
    ConvexNode& node = hierarchy.nodes.emplace_back();
    int32_t level = 0;
    if (!in.get_array(node.vertices) || !in.get_array(node.triangles) || !in.get(node.centre) ||
        !in.get(node.radius) || !in.get(node.deviation_m) || !in.get(level) ||
        !in.get(node.children) || !in.get_array(node.faces))
      return std::nullopt;
    node.level = level;
    const int vertex_count = static_cast<int>(node.vertices.size());
    for (const Vec3& v : node.vertices)
      if (!v.allFinite()) return std::nullopt;
    for (const auto& t : node.triangles)
      for (const int v : t)
        if (v < 0 || v >= vertex_count) return std::nullopt;
    if (!node.centre.allFinite() || !std::isfinite(node.radius) || !(node.radius >= 0) ||
        !std::isfinite(node.deviation_m) || !(node.deviation_m >= 0) || level < 0)
      return std::nullopt;
    const bool leaf = node.children[0] < 0 && node.children[1] < 0;
    for (const int child : node.children) {
      if (leaf) continue;
      if (child < 0 || child >= static_cast<int>(n)) return std::nullopt;
      if (++parents[static_cast<std::size_t>(child)] > 1) return std::nullopt;
    }
    for (const int f : node.faces)
      if (f < 0 || static_cast<std::size_t>(f) >= triangle_count) return std::nullopt;
  }
  for (std::size_t n = 0; n < parents.size(); ++n)
    if (parents[n] != (static_cast<int32_t>(n) == root ? 0 : 1)) return std::nullopt;
  if (in.remaining() != 0) return std::nullopt;
  return hierarchy;
}

}  // namespace

ConvexHierarchy cached_convex_hierarchy(const TriangleMesh& mesh, const std::string& content_hash,
                                        const ConvexHierarchySettings& settings, bool* cache_hit,
                                        const std::string& name) {
  if (cache_hit != nullptr) *cache_hit = false;
  const std::string key = hierarchy_key(mesh, content_hash, settings);
  const DiskCache cache(default_cache_directory(), "convex_hierarchy");
  if (const DiskCache::Lookup lookup = cache.read(key); lookup.payload) {
    if (std::optional<ConvexHierarchy> cached =
            parse_payload(*lookup.payload, mesh.triangles.size())) {
      cached->key = key;
      if (cache_hit != nullptr) *cache_hit = true;
      announce_cached_build("convex hierarchy of " + name, true);
      return std::move(*cached);
    }
  }
  announce_cached_build("convex hierarchy of " + name, false);
  ConvexHierarchy hierarchy = build_convex_hierarchy(mesh, settings);
  hierarchy.key = key;
  cache.write(key, payload_of(hierarchy));
  return hierarchy;
}

}  // namespace hb
