// Tests for algorithms/ccd/mesh_features_cache.cpp: a cache hit gives the
// structure a fresh build gives, array for array and bit for bit; a
// damaged file is rebuilt; the input checks are made on a hit too.
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "algorithms/ccd/mesh_features.h"
#include "hapticbench/disk_cache.h"
#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"
#include "tests/support/scratch_dir.h"

namespace hb::ccd_detail {
namespace {

namespace fs = std::filesystem;

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void check_same(const MeshFeatures& a, const MeshFeatures& b) {
  CHECK(same_bytes(a.vertices, b.vertices));
  CHECK(same_bytes(a.triangles, b.triangles));
  CHECK(same_bytes(a.edges, b.edges));
  CHECK(same_bytes(a.triangle_edges, b.triangle_edges));
  CHECK(same_bytes(a.edge_face_begin, b.edge_face_begin));
  CHECK(same_bytes(a.edge_faces, b.edge_faces));
  CHECK(same_bytes(a.face_normals, b.face_normals));
  CHECK(same_bytes(a.planes, b.planes));
  CHECK(same_bytes(a.tree.nodes(), b.tree.nodes()));
  CHECK(same_bytes(a.tree.triangle_order(), b.tree.triangle_order()));
  CHECK(same_bytes(a.slabs, b.slabs));
  CHECK(same_bytes(a.leaf_slot, b.leaf_slot));
  CHECK(same_bytes(a.leaves, b.leaves));
}

struct CacheFolder {
  test::ScratchDir dir{"mesh_features_cache"};
  CacheFolder() { ::setenv("HAPTICBENCH_CACHE_DIR", dir.path().c_str(), 1); }
  ~CacheFolder() { ::unsetenv("HAPTICBENCH_CACHE_DIR"); }
};

TriangleMesh sphere_mesh() {
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = 0.02;
  sphere.subdivisions = 3;
  return shape_mesh(sphere);
}

TEST_CASE("a cached mesh-features structure equals a fresh build, bit for bit") {
  const CacheFolder cache;
  const TriangleMesh mesh = sphere_mesh();
  const MeshFeatures built = build_mesh_features(mesh.vertices, mesh.triangles, "tool");
  bool hit = true;
  const MeshFeatures first = cached_mesh_features(mesh.vertices, mesh.triangles, "tool", &hit);
  CHECK_FALSE(hit);  // empty cache: built and stored
  check_same(first, built);
  const MeshFeatures second = cached_mesh_features(mesh.vertices, mesh.triangles, "tool", &hit);
  CHECK(hit);
  check_same(second, built);

  // Other vertices are another key: a miss.
  std::vector<Vec3> moved = mesh.vertices;
  moved[0].x() += 1e-9;
  cached_mesh_features(moved, mesh.triangles, "tool", &hit);
  CHECK_FALSE(hit);
}

TEST_CASE("a damaged mesh-features file is rebuilt, and input is checked on a hit") {
  const CacheFolder cache;
  const TriangleMesh mesh = sphere_mesh();
  bool hit = false;
  cached_mesh_features(mesh.vertices, mesh.triangles, "tool", &hit);
  for (const auto& entry : fs::directory_iterator(cache.dir.path())) {
    std::fstream f(entry.path(), std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(entry.path()) / 2));
    f.put('\x5a');
  }
  const MeshFeatures rebuilt = cached_mesh_features(mesh.vertices, mesh.triangles, "tool", &hit);
  CHECK_FALSE(hit);
  check_same(rebuilt, build_mesh_features(mesh.vertices, mesh.triangles, "tool"));

  std::vector<std::array<int, 3>> bad = mesh.triangles;
  bad[3][1] = static_cast<int>(mesh.vertices.size());
  CHECK_THROWS_AS(cached_mesh_features(mesh.vertices, bad, "tool", &hit), InputError);
}

// The one cache file of `folder`, split into its key and payload.
struct CacheFile {
  std::string key, payload;
};
CacheFile read_cache_file(const fs::path& folder) {
  fs::path path;
  for (const auto& entry : fs::directory_iterator(folder)) path = entry.path();
  const std::string bytes = test::read_text_file(path);
  const std::size_t magic_end = bytes.find('\n');
  const std::size_t sizes_end = bytes.find('\n', magic_end + 1);
  std::size_t key_bytes = 0, payload_bytes = 0;
  std::sscanf(bytes.c_str() + magic_end + 1, "%zu %zu", &key_bytes, &payload_bytes);
  return {bytes.substr(sizes_end + 1, key_bytes), bytes.substr(sizes_end + 1 + key_bytes)};
}

// The offset in a features payload of its tree's first node: the arrays
// before it (each a 64-bit count, then its elements) skipped.
std::size_t first_node_offset(const std::string& payload) {
  const std::size_t element_bytes[] = {sizeof(std::array<int, 2>),
                                       sizeof(std::array<int, 3>),
                                       sizeof(int),
                                       sizeof(int),
                                       sizeof(Vec3),
                                       sizeof(FacePlane)};
  std::size_t at = 0;
  for (const std::size_t bytes : element_bytes) {
    std::uint64_t count = 0;
    std::memcpy(&count, payload.data() + at, sizeof count);
    at += sizeof count + count * bytes;
  }
  return at + sizeof(std::uint64_t);
}

TEST_CASE("a crafted mesh-features file that passes its checksum is rebuilt, not followed") {
  // The checksum only catches accidents: anyone can recompute it. A tree
  // whose root is its own child (an endless search), whose child lies past
  // the last node (a read out of bounds), or whose root shares a child with
  // another node (children 2 and 3, node 3 being node 1's child too: a DAG,
  // whose search is exponential in its depth) is rebuilt.
  const TriangleMesh mesh = sphere_mesh();
  const MeshFeatures fresh = build_mesh_features(mesh.vertices, mesh.triangles, "tool");
  for (const int root_child : {0, 1 << 20, 2}) {
    INFO("root's first child " << root_child);
    const CacheFolder cache;
    bool hit = false;
    cached_mesh_features(mesh.vertices, mesh.triangles, "tool", &hit);
    CacheFile file = read_cache_file(cache.dir.path());
    SphereTreeNode root;
    const std::size_t at = first_node_offset(file.payload);
    std::memcpy(static_cast<void*>(&root), file.payload.data() + at, sizeof root);
    REQUIRE(root.count == 0);  // an inner node
    root.first = root_child;
    std::memcpy(file.payload.data() + at, static_cast<const void*>(&root), sizeof root);
    REQUIRE(DiskCache(cache.dir.path(), "mesh_features").write(file.key, file.payload).empty());
    const MeshFeatures rebuilt = cached_mesh_features(mesh.vertices, mesh.triangles, "tool", &hit);
    CHECK_FALSE(hit);
    check_same(rebuilt, fresh);
  }
}

}  // namespace
}  // namespace hb::ccd_detail
