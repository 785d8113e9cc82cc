// The oracle's tunnelling detector on the paths the closed-form box detector
// is tested on (tests/support/tunnelling_paths.h): a 2 mm plate as a mesh,
// through both oracles, and an open sheet marked distance_only. Units m.
#include "harness/reference/tunnelling.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "hapticbench/shapes.h"
#include "harness/reference/oracle.h"
#include "tests/support/tunnelling_paths.h"

namespace hb {
namespace {

SceneObject plate(const Pose& pose) {
  SceneObject object;
  object.name = "plate";
  Shape shape;
  shape.type = ShapeType::kBox;
  shape.size = Vec3(0.2, 0.2, 0.002);
  object.shape = shape;
  object.mesh = shape_mesh(shape);
  object.pose = pose;
  return object;
}

// A square sheet of two triangles in the plane z = 0 (open: distance only).
SceneObject sheet() {
  SceneObject object;
  object.name = "sheet";
  object.mesh.vertices = {{-0.1, -0.1, 0}, {0.1, -0.1, 0}, {0.1, 0.1, 0}, {-0.1, 0.1, 0}};
  object.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  object.distance_only = true;
  return object;
}

int count_passes(const Oracle& oracle, const Pose& frame, const std::vector<Vec3>& path) {
  OracleTunnellingDetector detector(oracle);
  int passes = 0;
  for (const Vec3& p : path) passes += detector.update(frame.transform_point(p));
  return passes;
}

TEST_CASE("the oracle's tunnelling detector counts passes through a plate, not round it") {
  Pose frame;  // turned and moved, so nothing lines up with the axes
  frame.p = Vec3(0.3, -0.2, 0.1);
  frame.q = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  const std::vector<SceneObject> scene = {plate(frame)};
  for (const auto make : {make_embree_oracle, make_cgal_oracle}) {
    const std::unique_ptr<Oracle> oracle = make(scene);
    INFO(std::string(oracle->name()));
    for (const hb::test::TunnellingPath& path : hb::test::plate_tunnelling_paths()) {
      INFO(path.what);
      CHECK(count_passes(*oracle, frame, path.points) == path.passes);
    }
  }
}

TEST_CASE("a rod whose far end passes through the plate while its origin goes round it counts") {
  // A 5 cm rod (0.2 × 0.2 mm section) whose tool frame is at one end, moved
  // down past the plate's edge in 4 mm steps: the origin passes 2 cm
  // beyond the edge, the far end 3 cm inside it, through the plate. The
  // origin's detector alone sees nothing; the tool's points see one tick.
  Pose frame;
  frame.p = Vec3(0.3, -0.2, 0.1);
  frame.q = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  const std::vector<SceneObject> scene = {plate(frame)};
  Shape rod;
  rod.type = ShapeType::kBox;
  rod.size = Vec3(0.05, 0.0002, 0.0002);
  TriangleMesh rod_mesh = shape_mesh(rod);
  for (Vec3& vertex : rod_mesh.vertices) vertex.x() -= 0.025;  // from x = −5 cm to the origin
  const std::vector<Vec3> followed = tunnelling_points(rod_mesh);
  CHECK(followed.size() == 9);  // the origin and the rod's eight corners
  for (const auto make : {make_embree_oracle, make_cgal_oracle}) {
    const std::unique_ptr<Oracle> oracle = make(scene);
    INFO(std::string(oracle->name()));
    ToolTunnelling tool(followed,
                        [&] { return std::make_unique<OracleTunnellingDetector>(*oracle); });
    OracleTunnellingDetector origin_only(*oracle);
    int tool_ticks = 0, origin_passes = 0;
    for (double z = 0.0103; z > -0.011; z -= 0.004) {
      const Pose pose{frame.transform_point(Vec3(0.12, 0, z)), frame.q};
      tool_ticks += tool.update(pose);
      origin_passes += origin_only.update(pose.p);
    }
    CHECK(origin_passes == 0);
    CHECK(tool_ticks == 1);
  }
}

TEST_CASE("crossing an open sheet counts as passing through it") {
  const std::vector<SceneObject> scene = {sheet()};
  const std::unique_ptr<Oracle> oracle = make_embree_oracle(scene);
  const Pose identity;
  CHECK(count_passes(*oracle, identity, {{0, 0, 0.002}, {0, 0, -0.002}}) == 1);
  CHECK(count_passes(*oracle, identity, {{0.1001, 0, 0.002}, {0.1001, 0, -0.002}}) == 0);
  CHECK(count_passes(*oracle, identity, {{0, 0, 0.002}, {0, 0, 0.0001}, {0, 0, 0.002}}) == 0);
}

TEST_CASE("a path meets the surface exactly when it reaches it") {
  const std::vector<SceneObject> scene = {plate(Pose{})};
  const std::unique_ptr<Oracle> oracle = make_embree_oracle(scene);
  CHECK(path_meets_surface(*oracle, Vec3(0, 0, 0.01), Vec3(0, 0, 0.0011)) == false);
  CHECK(path_meets_surface(*oracle, Vec3(0, 0, 0.01), Vec3(0, 0, 0.0009)));
  // Parallel to the top face, 10 µm above it, over 5 cm: no contact.
  CHECK(path_meets_surface(*oracle, Vec3(-0.02, 0, 0.00101), Vec3(0.03, 0, 0.00101)) == false);
}

}  // namespace
}  // namespace hb
