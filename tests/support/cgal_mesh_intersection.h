// Test support: whether two triangle meshes intersect, decided by CGAL's
// exact predicates on the double coordinates (CGAL stays inside
// cgal_mesh_intersection.cpp, which only the tests that need it compile).
#pragma once

#include <memory>

#include "hapticbench/pose.h"
#include "hapticbench/triangle_mesh.h"

namespace hb::test {

/// A static mesh (world frame, m) with CGAL's AABB tree over its triangles,
/// queried with a moving mesh placed at a pose.
class CgalMeshIntersection {
 public:
  explicit CgalMeshIntersection(const TriangleMesh& scene_world);
  ~CgalMeshIntersection();
  CgalMeshIntersection(const CgalMeshIntersection&) = delete;
  CgalMeshIntersection& operator=(const CgalMeshIntersection&) = delete;

  /// Some closed triangle of `mesh`, its vertices placed by `pose` (the
  /// placed coordinates rounded to double), meets some closed triangle of
  /// the scene: the surfaces touch or cross. Exact on those doubles.
  bool intersects(const TriangleMesh& mesh, const Pose& pose) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hb::test
