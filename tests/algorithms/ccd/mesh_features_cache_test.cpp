// Tests for algorithms/ccd/mesh_features_cache.cpp: a cache hit gives the
// structure a fresh build gives, array for array and bit for bit; a
// damaged file is rebuilt; the input checks are made on a hit too.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "algorithms/ccd/mesh_features.h"
#include "algorithms/core/input_error.h"
#include "algorithms/core/shapes.h"
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

}  // namespace
}  // namespace hb::ccd_detail
