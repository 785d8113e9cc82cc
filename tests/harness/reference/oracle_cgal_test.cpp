// Tests for harness/reference/oracle_cgal.cpp against closed forms: the
// exact box (shape_signed_distance, shape_closest_surface_point) for
// inside/outside, distances, closest points and normals; products of
// overlaps and cut-corner formulas for intersection volumes; edge and vertex
// counts worked out by hand for defective meshes. Units m, m³; quaternions
// (qw,qx,qy,qz).
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "hapticbench/input_error.h"
#include "hapticbench/shapes.h"
#include "harness/reference/oracle.h"
#include "tests/support/shape_fixtures.h"

namespace hb {
namespace {

using test::box_shape;

SceneObject box_object(const std::string& name, const Vec3& size, const Pose& pose) {
  SceneObject object;
  object.name = name;
  object.pose = pose;
  object.shape = box_shape(size);
  object.mesh = shape_mesh(*object.shape);
  return object;
}

SceneObject mesh_object(const std::string& name, TriangleMesh mesh) {
  SceneObject object;
  object.name = name;
  object.mesh = std::move(mesh);
  return object;
}

TriangleMesh posed_box_mesh(const Vec3& size, const Pose& pose) {
  return transformed(shape_mesh(box_shape(size)), pose);
}

// Both meshes' triangles in one mesh (b's indices shifted past a's vertices).
TriangleMesh merged(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh result = a;
  const int offset = static_cast<int>(a.vertices.size());
  result.vertices.insert(result.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& [i, j, k] : b.triangles)
    result.triangles.push_back({i + offset, j + offset, k + offset});
  return result;
}

// Like merged(), but vertices at exactly equal coordinates become one vertex,
// so the two meshes share the vertices (and edges) they have in common.
TriangleMesh welded(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh result = a;
  for (const auto& triangle : b.triangles) {
    std::array<int, 3> welded_triangle{};
    for (int corner = 0; corner < 3; ++corner) {
      const Vec3& v = b.vertices[triangle[corner]];
      const auto found = std::find(result.vertices.begin(), result.vertices.end(), v);
      welded_triangle[corner] = static_cast<int>(found - result.vertices.begin());
      if (found == result.vertices.end()) result.vertices.push_back(v);
    }
    result.triangles.push_back(welded_triangle);
  }
  return result;
}

template <typename F>
InputError input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error;
  }
  FAIL("expected an InputError");
  return InputError("", "", "");
}

// Uniform random points in an axis-aligned box (fixed seed: reproducible).
std::vector<Vec3> random_points(const Eigen::AlignedBox3d& box, int count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Vec3> points(static_cast<std::size_t>(count));
  for (Vec3& p : points)
    p = box.min() + box.sizes().cwiseProduct(Vec3(unit(rng), unit(rng), unit(rng)));
  return points;
}

PointQueryResult query(const Oracle& oracle, const std::vector<Vec3>& points, bool want_inside,
                       bool want_closest) {
  PointQueryResult result;
  oracle.query_points({.points = points, .want_inside = want_inside, .want_closest = want_closest},
                      result);
  return result;
}

const Pose kBoxPose{Vec3(0.05, -0.02, 0.1), quat_from_rotation_vector(Vec3(0.3, -0.5, 0.7))};
const Vec3 kBoxSize(0.3, 0.2, 0.1);

TEST_CASE("CGAL oracle matches the exact posed box: inside, distance, closest point, normal") {
  const SceneObject box = box_object("box", kBoxSize, kBoxPose);
  const Shape& shape = *box.shape;
  const auto oracle = make_cgal_oracle({box});
  CHECK(oracle->name() == "cgal");
  CHECK(oracle->distance_only_objects().empty());

  // Points in a box frame region twice the box's size, mapped to the world.
  const Eigen::AlignedBox3d local_region(-kBoxSize, kBoxSize);
  std::vector<Vec3> points;
  for (const Vec3& local : random_points(local_region, 3000, 17))
    points.push_back(kBoxPose.transform_point(local));
  const PointQueryResult result = query(*oracle, points, true, true);
  REQUIRE(result.inside.size() == points.size());
  REQUIRE(result.distance.size() == points.size());

  int inside = 0, normals_checked = 0;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const Vec3 local = kBoxPose.inverse_transform_point(points[k]);
    const SurfacePoint exact = shape_closest_surface_point(shape, local);
    const double signed_distance = shape_signed_distance(shape, local);
    INFO("point " << k << " local (" << local.transpose() << "), signed distance "
                  << signed_distance);
    CHECK(static_cast<bool>(result.inside[k]) == (signed_distance < 0));
    inside += result.inside[k];
    CHECK(std::abs(result.distance[k] - std::abs(signed_distance)) < 1e-12);
    CHECK((result.closest[k] - kBoxPose.transform_point(exact.point)).norm() < 1e-12);
    CHECK(result.object[k] == 0);
    // The nearest triangle is unambiguous when the closest point lies inside
    // one face, away from its edges: then its normal is that face's normal.
    int on_face_axis = -1, interior_axes = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double gap = 0.5 * kBoxSize[axis] - std::abs(exact.point[axis]);
      if (gap < 1e-12) on_face_axis = axis;
      if (gap > 1e-6) ++interior_axes;
    }
    if (on_face_axis >= 0 && interior_axes == 2) {
      const Vec3 face_normal =
          std::copysign(1.0, exact.point[on_face_axis]) * Vec3::Unit(on_face_axis);
      CHECK((result.normal[k] - kBoxPose.q * face_normal).norm() < 1e-12);
      ++normals_checked;
    }
  }
  // The box fills 1/8 of the sampled region; a fixed seed, so no flakiness.
  CHECK(inside > 250);
  CHECK(inside < 500);
  CHECK(normals_checked > 1000);
}

TEST_CASE("CGAL oracle counts a point on the surface as inside") {
  const auto unit_box = make_cgal_oracle({box_object("unit", Vec3::Ones(), Pose{})});
  const double just_out = std::nextafter(0.5, 1.0);
  const std::vector<Vec3> points = {Vec3(0.5, 0.1, -0.2),       // on a face
                                    Vec3(0.5, 0.5, 0.1),        // on an edge
                                    Vec3(-0.5, 0.5, -0.5),      // a corner
                                    Vec3(just_out, 0.1, -0.2),  // the next double outward
                                    Vec3(0.1, -0.2, -just_out)};
  const PointQueryResult result = query(*unit_box, points, true, true);
  CHECK(result.inside == std::vector<uint8_t>{1, 1, 1, 0, 0});
  for (int k = 0; k < 5; ++k) CHECK(result.distance[k] < 1e-15);

  // A posed box's own world-frame vertices are on its surface, exactly.
  const SceneObject posed = box_object("posed", kBoxSize, kBoxPose);
  const TriangleMesh world = transformed(posed.mesh, posed.pose);
  const PointQueryResult corners = query(*make_cgal_oracle({posed}), world.vertices, true, false);
  CHECK(std::count(corners.inside.begin(), corners.inside.end(), 1) ==
        static_cast<long>(world.vertices.size()));
}

TEST_CASE("CGAL oracle computes only what the request asks for") {
  const auto oracle = make_cgal_oracle({box_object("box", kBoxSize, kBoxPose)});
  const std::vector<Vec3> points = {kBoxPose.p, kBoxPose.p + Vec3(1, 0, 0)};
  const PointQueryResult inside_only = query(*oracle, points, true, false);
  CHECK(inside_only.inside == std::vector<uint8_t>{1, 0});
  CHECK(inside_only.distance.empty());
  CHECK(inside_only.closest.empty());
  CHECK(inside_only.normal.empty());
  CHECK(inside_only.object.empty());
  const PointQueryResult closest_only = query(*oracle, points, false, true);
  CHECK(closest_only.inside.empty());
  CHECK(closest_only.distance.size() == 2);
  CHECK(closest_only.distance[0] == Approx(0.05).epsilon(1e-12));  // half the smallest side
}

TEST_CASE("CGAL oracle over two objects: the nearest object and the union's inside") {
  const SceneObject left = box_object("left", Vec3(0.1, 0.1, 0.1), Pose{Vec3(-0.2, 0, 0)});
  const SceneObject right = box_object("right", Vec3(0.1, 0.2, 0.1), Pose{Vec3(0.2, 0, 0)});
  const auto oracle = make_cgal_oracle({left, right});
  const std::vector<Vec3> points = {Vec3(-0.2, 0, 0.01), Vec3(0.21, 0.05, 0), Vec3(0.01, 0, 0),
                                    Vec3(-0.01, 0, 0), Vec3(0.2, 0, 0.3)};
  const PointQueryResult result = query(*oracle, points, true, true);
  CHECK(result.inside == std::vector<uint8_t>{1, 1, 0, 0, 0});
  CHECK(result.object == std::vector<int32_t>{0, 1, 1, 0, 1});
  CHECK(result.distance[0] == Approx(0.04).epsilon(1e-12));  // to the top face of left
  CHECK(result.distance[1] == Approx(0.04).epsilon(1e-12));  // to right's +x face
  CHECK(result.distance[2] == Approx(0.14).epsilon(1e-12));  // to right's -x face at 0.15
  CHECK(result.distance[3] == Approx(0.14).epsilon(1e-12));  // to left's +x face at -0.15
  CHECK(result.distance[4] == Approx(0.25).epsilon(1e-12));  // above right's top at 0.05
  CHECK((result.normal[4] - Vec3::UnitZ()).norm() < 1e-15);
  const Eigen::AlignedBox3d bounds = oracle->bounds();
  CHECK((bounds.min() - Vec3(-0.25, -0.1, -0.05)).norm() < 1e-15);
  CHECK((bounds.max() - Vec3(0.25, 0.1, 0.05)).norm() < 1e-15);
}

TEST_CASE("CGAL intersection volume of overlapping axis-aligned boxes is the product of overlaps") {
  const SceneObject scene = box_object("scene", Vec3(0.4, 0.3, 0.2), Pose{Vec3(0.01, 0.02, 0.03)});
  const auto oracle = make_cgal_oracle({scene});
  const Eigen::AlignedBox3d scene_box = transformed(scene.mesh, scene.pose).bounds();
  // Overlaps in x, y, z are all partial; in y the tool's face is coplanar
  // with none of the scene's, in the last case two faces are coplanar.
  for (const auto& [size, centre] :
       std::vector<std::pair<Vec3, Vec3>>{{Vec3(0.1, 0.25, 0.12), Vec3(0.17, -0.05, 0.11)},
                                          {Vec3(0.05, 0.05, 0.05), Vec3(-0.2, 0.18, -0.09)},
                                          {Vec3(0.1, 0.1, 0.1), Vec3(0.26, 0.02, 0.03)}}) {
    const TriangleMesh tool = posed_box_mesh(size, Pose{centre});
    const Eigen::AlignedBox3d overlap = tool.bounds().intersection(scene_box);
    const double expected = overlap.sizes().prod();
    INFO("tool size " << size.transpose() << " at " << centre.transpose());
    const std::optional<double> volume = oracle->intersection_volume(tool);
    REQUIRE(volume);
    CHECK(std::abs(*volume - expected) <= 1e-12 * expected);
  }
}

TEST_CASE("CGAL intersection volume of rotated boxes matches the cut-corner formulas") {
  // Scene: a slab whose top face is the plane z = 0.
  const auto oracle =
      make_cgal_oracle({box_object("slab", Vec3(0.4, 0.4, 0.2), Pose{Vec3(0, 0, -0.1)})});
  const double side = 0.1;
  const Vec3 cube(side, side, side);

  SECTION("a cube edge-down: a triangular prism, volume d² times the edge length") {
    const double depth = 0.02;
    const Quat edge_down(Eigen::AngleAxisd(std::numbers::pi / 4, Vec3::UnitY()));
    const Pose pose{Vec3(0.03, -0.04, side / std::sqrt(2.0) - depth), edge_down};
    const std::optional<double> volume = oracle->intersection_volume(posed_box_mesh(cube, pose));
    REQUIRE(volume);
    const double expected = depth * depth * side;
    CHECK(std::abs(*volume - expected) <= 1e-12 * expected);
  }
  SECTION("a cube corner-down: a tetrahedron, volume (sqrt(3)/2) d³") {
    // The body diagonal (1, 1, 1) points up, so the corner (-1, -1, -1) is lowest.
    const double depth = 0.03;  // below side / sqrt(3), where the cut reaches other corners
    const Quat corner_down = Quat::FromTwoVectors(Vec3(1, 1, 1), Vec3::UnitZ());
    const Pose pose{Vec3(-0.02, 0.05, 0.5 * side * std::sqrt(3.0) - depth), corner_down};
    const std::optional<double> volume = oracle->intersection_volume(posed_box_mesh(cube, pose));
    REQUIRE(volume);
    const double expected = std::sqrt(3.0) / 2 * depth * depth * depth;
    CHECK(std::abs(*volume - expected) <= 1e-12 * expected);
  }
  SECTION("a rotated cube wholly inside: its own volume") {
    const Pose pose{Vec3(0.01, 0.02, -0.1), quat_from_rotation_vector(Vec3(0.2, 0.4, -0.3))};
    const std::optional<double> volume = oracle->intersection_volume(posed_box_mesh(cube, pose));
    REQUIRE(volume);
    CHECK(std::abs(*volume - side * side * side) <= 1e-12 * side * side * side);
  }
}

TEST_CASE("CGAL intersection volume of disjoint meshes is zero") {
  // Scene box [0, 0.1]³.
  const auto oracle =
      make_cgal_oracle({box_object("corner", Vec3(0.1, 0.1, 0.1), Pose{Vec3(0.05, 0.05, 0.05)})});
  const Vec3 cube(0.1, 0.1, 0.1);
  SECTION("bounding boxes apart") {
    CHECK(oracle->intersection_volume(posed_box_mesh(cube, Pose{Vec3(1, 1, 1)})) == 0.0);
  }
  SECTION("bounding boxes overlap, the solids do not") {
    // Turned 45° about z, the tool's near side runs along x + y = 0.32 -
    // 0.1/sqrt(2) = 0.249, past the scene's corner at x + y = 0.2, while
    // its bounding box reaches down to x = y = 0.089.
    const Pose pose{Vec3(0.16, 0.16, 0.05),
                    Quat(Eigen::AngleAxisd(std::numbers::pi / 4, Vec3::UnitZ()))};
    const TriangleMesh tool = posed_box_mesh(cube, pose);
    REQUIRE(tool.bounds().intersects(oracle->bounds()));
    const std::optional<double> volume = oracle->intersection_volume(tool);
    REQUIRE(volume);
    CHECK(*volume == 0.0);
  }
}

TEST_CASE("A box tool resting face-down at depth d: penetration d, volume footprint times d") {
  // Scene top face at z = 0; the tool, turned about z (still face-down),
  // has its bottom face at z = -d, well inside the top face's footprint.
  const auto oracle =
      make_cgal_oracle({box_object("slab", Vec3(0.4, 0.4, 0.2), Pose{Vec3(0, 0, -0.1)})});
  const double depth = 0.002;
  const Vec3 tool_size(0.06, 0.04, 0.03);
  const Pose tool_pose{Vec3(0.01, -0.02, 0.5 * tool_size.z() - depth),
                       Quat(Eigen::AngleAxisd(0.4, Vec3::UnitZ()))};
  const TriangleMesh tool_local = shape_mesh(box_shape(tool_size));
  const TriangleMesh tool = transformed(tool_local, tool_pose);

  const long bottom_vertices = std::count_if(tool_local.vertices.begin(), tool_local.vertices.end(),
                                             [&](const Vec3& v) { return v.z() < 0; });
  const PenetrationResult penetration = oracle->penetration(tool.vertices);
  CHECK(penetration.points == static_cast<int64_t>(tool.vertices.size()));
  CHECK(penetration.inside == bottom_vertices);
  CHECK(std::abs(penetration.max_depth_m - depth) < 1e-12);
  CHECK(std::abs(penetration.rms_depth_m - depth) < 1e-12);

  const std::optional<double> volume = oracle->intersection_volume(tool);
  REQUIRE(volume);
  const double expected = tool_size.x() * tool_size.y() * depth;
  CHECK(std::abs(*volume - expected) <= 1e-12 * expected);
}

TEST_CASE("inside_outside_defect accepts closed solids") {
  CHECK_FALSE(inside_outside_defect(shape_mesh(box_shape(kBoxSize))));
  Shape sphere;
  sphere.type = ShapeType::kSphere;
  sphere.radius = 0.05;
  sphere.subdivisions = 3;
  CHECK_FALSE(inside_outside_defect(shape_mesh(sphere)));
  Shape capsule;
  capsule.type = ShapeType::kCapsule;
  capsule.radius = 0.01;
  capsule.length = 0.05;
  CHECK_FALSE(inside_outside_defect(shape_mesh(capsule)));
}

TEST_CASE("inside_outside_defect names what is wrong") {
  const TriangleMesh box = shape_mesh(box_shape(Vec3(0.1, 0.1, 0.1)));
  SECTION("one triangle missing: its three edges are border edges") {
    TriangleMesh open = box;
    open.triangles.pop_back();
    CHECK(inside_outside_defect(open) == "open boundary (3 border edges)");
  }
  SECTION("one triangle flipped: its three edges are traversed twice the same way") {
    TriangleMesh flipped = box;
    std::swap(flipped.triangles[4][1], flipped.triangles[4][2]);
    CHECK(inside_outside_defect(flipped).value_or("").starts_with(
        "inconsistently oriented (3 edges"));
  }
  SECTION("every triangle flipped: inside-out") {
    TriangleMesh inverted = box;
    for (auto& triangle : inverted.triangles) std::swap(triangle[1], triangle[2]);
    CHECK(inside_outside_defect(inverted).value_or("").starts_with("inside-out"));
  }
  SECTION("two cubes sharing one edge: that edge has four triangles") {
    const TriangleMesh other = transformed(box, Pose{Vec3(0.1, 0.1, 0)});
    CHECK(inside_outside_defect(welded(box, other)) ==
          "non-manifold (1 edge shared by more than two triangles)");
  }
  SECTION("two cubes sharing one corner: a non-manifold vertex") {
    const TriangleMesh other = transformed(box, Pose{Vec3(0.1, 0.1, 0.1)});
    CHECK(inside_outside_defect(welded(box, other)) ==
          "non-manifold (1 vertex where separate sheets of surface touch)");
  }
  SECTION("two interpenetrating cubes in one mesh") {
    const TriangleMesh other = transformed(box, Pose{Vec3(0.05, 0.04, 0.03)});
    const std::optional<std::string> defect = inside_outside_defect(merged(box, other));
    REQUIRE(defect);
    CHECK(defect->starts_with("self-intersecting ("));
  }
}

TEST_CASE("CGAL oracle refuses an open mesh, naming the object") {
  TriangleMesh open = shape_mesh(box_shape(Vec3(0.1, 0.1, 0.1)));
  open.triangles.pop_back();
  const std::vector<SceneObject> scene = {box_object("floor", Vec3(1, 1, 0.1), Pose{}),
                                          mesh_object("open_box.off", open)};
  const InputError error = input_error_of([&] { make_cgal_oracle(scene); });
  CHECK(error.source() == "open_box.off");
  CHECK(error.location() == "/scene/1");
  CHECK(error.message() ==
        "open boundary (3 border edges); inside/outside would be meaningless (mark the object "
        "\"distance_only\": true to use it for distances only)");
}

TEST_CASE("CGAL oracle: a self-intersecting mesh is refused, or used for distances only") {
  const Vec3 size(0.1, 0.1, 0.1);
  const Pose second_pose{Vec3(0.05, 0.04, 0.03)};
  const TriangleMesh first_cube = shape_mesh(box_shape(size));
  const TriangleMesh two_cubes = merged(first_cube, transformed(first_cube, second_pose));
  SceneObject object = mesh_object("two_cubes.obj", two_cubes);

  const InputError error = input_error_of([&] { make_cgal_oracle({object}); });
  CHECK(error.source() == "two_cubes.obj");
  CHECK(error.location() == "/scene/0");
  CHECK(error.message().find("self-intersecting") != std::string::npos);
  CHECK(error.message().find("\"distance_only\": true") != std::string::npos);

  object.distance_only = true;
  const auto oracle = make_cgal_oracle({object});
  CHECK(oracle->distance_only_objects() == std::vector<std::string>{"two_cubes.obj"});
  const Shape cube = box_shape(size);
  const std::vector<Vec3> points =
      random_points(Eigen::AlignedBox3d(Vec3::Constant(-0.1), Vec3::Constant(0.15)), 2000, 5);
  const PointQueryResult result = query(*oracle, points, true, true);
  CHECK(std::count(result.inside.begin(), result.inside.end(), 1) == 0);  // never inside
  for (std::size_t k = 0; k < points.size(); ++k) {
    // The surface is both cubes' surfaces: the nearer of the two.
    const double expected = std::min(
        std::abs(shape_signed_distance(cube, points[k])),
        std::abs(shape_signed_distance(cube, second_pose.inverse_transform_point(points[k]))));
    INFO("point " << k << " (" << points[k].transpose() << ")");
    CHECK(std::abs(result.distance[k] - expected) < 1e-12);
  }
  // No volume next to a distance-only object; zero far from it.
  CHECK_FALSE(oracle->intersection_volume(posed_box_mesh(size, Pose{Vec3(0.1, 0, 0)})));
  CHECK(oracle->intersection_volume(posed_box_mesh(size, Pose{Vec3(1, 0, 0)})) == 0.0);
}

TEST_CASE("CGAL oracle answers a non-finite point with NaN, not a crash") {
  const auto oracle = make_cgal_oracle({box_object("box", kBoxSize, kBoxPose)});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Vec3> points = {Vec3(nan, 0, 0), kBoxPose.p,
                                    Vec3(0, std::numeric_limits<double>::infinity(), 0)};
  const PointQueryResult result = query(*oracle, points, true, true);
  CHECK(result.inside == std::vector<uint8_t>{0, 1, 0});
  CHECK(std::isnan(result.distance[0]));
  CHECK(std::isnan(result.distance[2]));
  CHECK(result.object == std::vector<int32_t>{-1, 0, -1});
  CHECK(result.distance[1] == Approx(0.05).epsilon(1e-12));

  TriangleMesh tool = posed_box_mesh(Vec3(0.1, 0.1, 0.1), kBoxPose);
  tool.vertices[3].x() = nan;
  CHECK_FALSE(oracle->intersection_volume(tool));
}

TEST_CASE("CGAL intersection volume of an open tool is unavailable, not a crash") {
  const auto oracle =
      make_cgal_oracle({box_object("slab", Vec3(0.4, 0.4, 0.2), Pose{Vec3(0, 0, -0.1)})});
  TriangleMesh open_tool = posed_box_mesh(Vec3(0.1, 0.1, 0.1), Pose{Vec3(0, 0, 0.02)});
  open_tool.triangles.pop_back();
  CHECK_FALSE(oracle->intersection_volume(open_tool));
}

}  // namespace
}  // namespace hb
