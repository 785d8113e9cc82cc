#include "tests/support/cgal_mesh_intersection.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace hb::test {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

Point point(const Vec3& v) { return Point(v.x(), v.y(), v.z()); }

}  // namespace

struct CgalMeshIntersection::Impl {
  std::vector<Triangle> triangles;
  Tree tree;
};

CgalMeshIntersection::CgalMeshIntersection(const TriangleMesh& scene_world)
    : impl_(std::make_unique<Impl>()) {
  for (std::size_t i = 0; i < scene_world.triangles.size(); ++i) {
    const auto& t = scene_world.triangles[i];
    impl_->triangles.emplace_back(point(scene_world.vertices[static_cast<std::size_t>(t[0])]),
                                  point(scene_world.vertices[static_cast<std::size_t>(t[1])]),
                                  point(scene_world.vertices[static_cast<std::size_t>(t[2])]));
    if (impl_->triangles.back().is_degenerate())
      throw std::invalid_argument("degenerate scene triangle " + std::to_string(i));
  }
  impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  impl_->tree.build();
}

CgalMeshIntersection::~CgalMeshIntersection() = default;

bool CgalMeshIntersection::intersects(const TriangleMesh& mesh, const Pose& pose) const {
  std::vector<Point> placed;
  placed.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) placed.push_back(point(pose.transform_point(v)));
  const CGAL::Bbox_3 scene_box = impl_->tree.bbox();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const Triangle triangle(placed[static_cast<std::size_t>(t[0])],
                            placed[static_cast<std::size_t>(t[1])],
                            placed[static_cast<std::size_t>(t[2])]);
    if (!CGAL::do_overlap(triangle.bbox(), scene_box)) continue;
    if (triangle.is_degenerate())
      throw std::invalid_argument("degenerate placed triangle " + std::to_string(i));
    if (impl_->tree.do_intersect(triangle)) return true;
  }
  return false;
}

}  // namespace hb::test
