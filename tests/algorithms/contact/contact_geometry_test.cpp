// The contact geometry shared by the constrained-contact renderers: the
// tool's centre of mass and the scene's friction as given, and the start
// escape against closed forms (a cube sunk into a slab comes up onto its
// face, a point inside it leaves through the nearer face, a free start is
// kept).
#include "algorithms/contact/contact_geometry.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <vector>

#include "hapticbench/shapes.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

constexpr double kCube = 0.04;  // cube tool edge (m)

// A 0.4 × 0.4 × 0.02 m slab whose top face is the plane z = 0, with its mesh.
std::vector<SceneObject> slab_scene() {
  SceneObject slab =
      test::box_object(Vec3(0.4, 0.4, 0.02), Pose{Vec3(0, 0, -0.01), Quat::Identity()});
  slab.mesh = shape_mesh(*slab.shape);
  return {slab};
}

Tool cube_tool() { return test::meshed_box_tool(Vec3::Constant(kCube)); }

// Lowest z of the tool's vertices at a tool-frame pose (m).
double lowest_vertex_z(const Tool& tool, const Pose& pose) {
  return test::lowest_vertex_z(tool.mesh, pose);
}

Pose at(const Vec3& p, const Quat& q = Quat::Identity()) { return Pose{p, q}; }

TEST_CASE("the geometry gives the tool's centre of mass and each scene object's friction") {
  Tool tool = cube_tool();
  tool.mass.centre_of_mass = Vec3(0.001, -0.002, 0.003);
  std::vector<SceneObject> scene = slab_scene();
  scene.push_back(scene.front());
  scene.back().pose.p.x() = 1.0;
  scene.front().friction = 0.3;
  scene.back().friction = 0.7;
  ContactSettings settings;
  const ContactGeometry geometry(tool, scene, settings);
  CHECK(geometry.centre_of_mass() == tool.mass.centre_of_mass);
  CHECK(geometry.frames().centre_of_mass == tool.mass.centre_of_mass);
  CHECK(geometry.friction() == std::vector<double>{0.3, 0.7});
  CHECK(geometry.ccd().tool_radius() > 0.5 * kCube);

  settings.point_tool = true;
  const ContactGeometry point(tool, scene, settings);
  CHECK(point.centre_of_mass() == Vec3::Zero());
  CHECK(point.friction() == std::vector<double>{0.3, 0.7});
}

TEST_CASE("a start inside the scene is moved out the shortest way, a free one is kept") {
  const Tool tool = cube_tool();
  const std::vector<SceneObject> scene = slab_scene();
  ContactSettings settings;
  const double above = 0.5 * kCube;  // tool-frame height when resting on z = 0
  // The paths come from half a metre away: the CCD's time tolerance (1e-6
  // of the path) leaves up to 0.5 µm beyond the standoff.
  const double farthest = settings.standoff_m + 1e-6;

  SECTION("a cube sunk 3 mm into the face comes up onto it") {
    const ContactGeometry geometry(tool, scene, settings);
    const StartEscape escape = geometry.escape(at(Vec3(0.01, 0.02, above - 0.003)));
    CHECK(escape.escaped);
    const double gap = lowest_vertex_z(tool, escape.pose);
    CHECK(gap >= 0.0);
    CHECK(gap <= farthest);
    CHECK(escape.distance_m == Approx(0.003 + gap).margin(1e-9));
    CHECK(escape.pose.p.x() == Approx(0.01).margin(1e-12));
    CHECK(escape.pose.p.y() == Approx(0.02).margin(1e-12));
  }
  SECTION("a point inside the slab leaves through the nearer face") {
    settings.point_tool = true;
    const ContactGeometry geometry(tool, scene, settings);
    // 4 mm below the top face (z = 0), 16 mm above the bottom (z = −0.02).
    const StartEscape up = geometry.escape(at(Vec3(0.05, -0.03, -0.004)));
    CHECK(up.escaped);
    CHECK(up.pose.p.z() >= 0.0);
    CHECK(up.pose.p.z() <= farthest);
    CHECK(up.distance_m == Approx(0.004 + up.pose.p.z()).margin(1e-9));
    // 3 mm above the bottom face.
    const StartEscape down = geometry.escape(at(Vec3(0.05, -0.03, -0.017)));
    CHECK(down.escaped);
    CHECK(down.pose.p.z() <= -0.02);
    CHECK(down.pose.p.z() >= -0.02 - farthest);
    CHECK(down.pose.p.x() == Approx(0.05).margin(1e-12));
  }
  SECTION("a free start stays where it is") {
    const ContactGeometry geometry(tool, scene, settings);
    const Pose start = at(Vec3(0.01, 0.02, above + 0.001));
    const StartEscape escape = geometry.escape(start);
    CHECK_FALSE(escape.escaped);
    CHECK(escape.distance_m == 0.0);
    CHECK(escape.pose.p == start.p);
  }
}

}  // namespace
}  // namespace hb
