// The tool's clearance along a trace against closed forms: a box tool
// above, touching and inside a box scene, and a distance taken by vertices.
#include "harness/reference/trace_clearance.h"

#include <catch2/catch.hpp>
#include <vector>

#include "hapticbench/shapes.h"

namespace {

hb::SceneObject box_object(const hb::Vec3& size, const hb::Vec3& centre) {
  hb::SceneObject object;
  object.name = "floor";
  object.shape = hb::Shape{hb::ShapeType::kBox, size};
  object.mesh = hb::shape_mesh(*object.shape);
  object.pose.p = centre;
  return object;
}

}  // namespace

TEST_CASE("the clearance along a trace is the gap of the lowest vertex, negative inside") {
  // A floor whose top face is z = 0, and a 2 cm cube tool (its corners are
  // its lowest points, 1 cm below its centre).
  const std::vector<hb::SceneObject> scene = {box_object({0.4, 0.4, 0.02}, {0, 0, -0.01})};
  const hb::TriangleMesh tool = hb::shape_mesh(hb::Shape{hb::ShapeType::kBox, {0.02, 0.02, 0.02}});
  std::vector<hb::Pose> poses(3);
  poses[0].p = {0, 0, 0.05};    // 4 cm above
  poses[1].p = {0, 0, 0.007};   // 3 mm inside
  poses[2].p = {0.1, 0, 0.02};  // 1 cm above
  const hb::TraceClearance clearance = hb::trace_clearance(scene, tool, poses);
  CHECK(clearance.poses == 3);
  CHECK(clearance.vertices == tool.vertices.size());
  CHECK(clearance.first.gap_m == Approx(0.04).margin(1e-9));
  CHECK(clearance.closest.pose_index == 1);
  CHECK(clearance.closest.gap_m == Approx(-0.003).margin(1e-9));
  CHECK(clearance.last.pose_index == 2);
  CHECK(clearance.last.gap_m == Approx(0.01).margin(1e-9));

  // Fewer vertices than the tool has: every k-th, never more than asked.
  const hb::TraceClearance sparse = hb::trace_clearance(scene, tool, poses, 3);
  CHECK(sparse.vertices <= 3);
  CHECK(sparse.closest.gap_m >= clearance.closest.gap_m);
}
